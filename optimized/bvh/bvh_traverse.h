/* What the BVH kernels share (kernel side, one copy per instruction set):
 * the packet walk of traverse_packet.c, which the frusta kernel also uses
 * for the packets whose rays share no origin. */
#ifndef RTT_BVH_TRAVERSE_H
#define RTT_BVH_TRAVERSE_H

#include "bvh_isa.h"
#include "bvh_kernels.h"
#include "bvh_packet.h"

/* The lanes `live` of packet p through the tree: closest hits lowered in
 * `hits` (cleared by the caller), or with hits NULL the occluded lanes into
 * *occluded. */
void bvh_trace_packet(const bvh_tree *tree, const bvh_packet *p, uint32_t live, bvh_hits *hits, uint32_t *occluded,
                      bvh_counters *counters);

#endif

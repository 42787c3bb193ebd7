/* Cone-bounded soft shadows (Thesis 4.1.6 - 4.1.9, Figure 4.5, Table 4.6):
 * the N sample rays from one shading point to a sphere light traced
 * together under one proxy, a cone (cone:N) or a pyramid frustum
 * (pyramid:N), with the interval traversals of traverse_cone.c and
 * traverse_frustum.c and the packet intersection of every proxy kernel. */
#ifndef RTT_OPTIMIZED_SHADOW_CONE_H
#define RTT_OPTIMIZED_SHADOW_CONE_H

#include <stdint.h>

#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"
#include "rtt/render.h"

/* Packets needed for the groups: sum over groups of ceil(rays / 4). */
uint32_t sc_group_packets(const uint32_t *group_first, uint32_t groups);

/* Occlusion of rays grouped by shading point and light: group g is rays
 * [group_first[g], group_first[g+1]) (at most 4 * KD_BLOCK_MAX_PACKETS),
 * traced as one block of packets under one proxy: the group's cone
 * (cone:N) when `pyramid` is NULL, else through the frustum kernel
 * `pyramid` (pyramid:N).  `packets` and `lane_masks` are scratch of
 * sc_group_packets(...) entries; occluded[i] = 1 when ray i is blocked.
 * The result of every ray is exactly the occlusion kernels' (the proxies
 * are conservative, the triangle test the same), so cone:N and pyramid:N
 * see the same samples as multi:N. */
void sc_trace_groups(const kd_tree *tree, const kd_kernel *pyramid, const rtt_ray *rays, const uint32_t *group_first,
                     uint32_t groups, ray_packet4 *packets, uint8_t *lane_masks, uint8_t *occluded, int leaf_culling,
                     kd_counters *counters);

#endif

/* Blocks of packets under proxies: the state the frustum, MFT and cone
 * kernels share (Thesis 2.3.2, 4.1.3 - 4.1.9, Figure 3.2).
 *
 * A block is up to KD_BLOCK_MAX_PACKETS 2x2 packets traced together.  Its
 * packets are partitioned into up to four groups, each bounded by one proxy
 * (a frustum, frustum.h, or a cone, cone.h): one group for the
 * single-frustum and single-cone kernels, four quadrants for MFT and
 * MFT-cone, and the four lanes of one packet when a block is too incoherent
 * for a proxy to pay (then every "proxy" is one ray and the traversal is an
 * omni-directional packet traversal with per-lane intervals, Listing 4.1).
 *
 * Exactness, for arbitrary rays.  A proxy interval [near, far] only ever
 * contains, conservatively, the parameters at which any ray of its group can
 * be inside the current cell.  A hit found in a leaf is kept whatever cell it
 * lies in (closest wins); a subtree is dropped only when its near lies past
 * the farthest current best hit of every live ray of the group ("max best").
 * So the result is the closest hit in (tnear, tfar) whatever order leaves are
 * visited in; front-to-back order only makes it fast.  Bounds are widened by
 * KD_WIDEN (relative) and the leaf boxes by kd_tree_margin, so rounding
 * never drops a cell a ray touches. */
#ifndef RTT_OPTIMIZED_BLOCK_H
#define RTT_OPTIMIZED_BLOCK_H

#include "kernel_isa.h"

#include <immintrin.h>
#include <stdint.h>

#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"
#include "simd4.h"

#define KD_WIDEN (1.0f / 65536.0f)   /* relative widening of proxy distances */

typedef enum kd_units { KD_UNITS_RAY = 0, KD_UNITS_CONE_AXIS = 1 } kd_units;

struct kd_frustum4;

typedef struct kd_block {
    const kd_tree *tree;
    const ray_packet4 *packets;
    hit_packet4 *hits;                   /* closest hit, or NULL */
    uint8_t *occluded;                   /* occlusion lane masks, or NULL */
    kd_counters *counters;
    int leaf_culling;
    uint32_t packet_count;
    float margin;                        /* leaf boxes grow by this (world units) */
    uint64_t *isect_ns;                  /* stats: time in leaf intersection, or NULL */
    /* groups: packets order[group_first[g] .. group_first[g+1]) */
    uint32_t group_count;
    int lane_groups;                     /* group g = lane g of packet lane_packet */
    uint32_t lane_packet;
    kd_units units;
    /* The groups' frusta (lane g = group g), or NULL (cones): a leaf visit
     * first tests the leaf box against them, one test per group instead of
     * one slab test per packet. */
    const struct kd_frustum4 *leaf_frusta;
    float cone_apex[4][3], cone_axis[4][3];
    uint16_t group_first[5];
    uint16_t order[KD_BLOCK_MAX_PACKETS];
    __m128 live[KD_BLOCK_MAX_PACKETS];   /* lanes still traced */
    /* Per packet, the largest best (upper end of the search, block units)
     * over its live lanes: -inf when none is live, +inf until a leaf visit
     * computes it.  A leaf whose group interval starts past it cannot hold
     * a closer hit for the packet (the exactness argument above), so the
     * visit skips the packet with one compare instead of a slab test. */
    float packet_best[KD_BLOCK_MAX_PACKETS];
    __m128 root_entry[KD_BLOCK_MAX_PACKETS], root_exit[KD_BLOCK_MAX_PACKETS]; /* kd_block_root_interval */
} kd_block;

/* Marks live lanes (finite ray, nonzero direction,
 * tnear < tfar, touching the root box) and puts every packet in group 0.
 * Closest-hit results are not cleared: like every kernel (kernels.h) the
 * block only lowers the hits it is given (callers clear them); occlusion
 * masks are written.  Returns the number of packets with a live lane. */
uint32_t kd_block_init(kd_block *block, const kd_tree *tree, const ray_packet4 *packets, uint32_t packet_count,
                       hit_packet4 *hits, uint8_t *occluded, int leaf_culling, kd_counters *counters);
/* Splits the packets into four groups: quadrants of the square of quads
 * when packet_count is a square with even side, else four runs. */
void kd_block_group_quadrants(kd_block *block);
/* Restricts the block to packet `index` with one group per lane. */
void kd_block_group_lanes(kd_block *block, uint32_t index);

/* Per-ray clipped interval [entry, exit] of packet p in the root box
 * (computed once by kd_block_init). */
static inline void kd_block_root_interval(const kd_block *block, uint32_t p, __m128 *entry, __m128 *exit)
{
    *entry = block->root_entry[p];
    *exit = block->root_exit[p];
}

/* Visits a leaf for the groups in lane_mask (bit g = group g), whose
 * interval in the leaf's cell starts at near[g]: culls the groups' packets
 * against the leaf box (when leaf culling is on; packets whose every live
 * ray has its best before near[g] without a slab test), intersects the
 * survivors and writes each visited group's new max best (in the block's
 * units; -inf when the group is finished) into max_best[g]. */
void kd_block_visit_leaf(kd_block *block, const kd_leaf *leaf, uint32_t lane_mask, const float near[4],
                         float max_best[4]);

/* Omni-directional per-lane traversal of every packet, one at a time (the
 * fallback for incoherent blocks): each lane is its own exact frustum. */
void kd_block_trace_packets(kd_block *block);

/* One block through one proxy kind (traverse_*.c); the kernels of the
 * frustum family are these over blocks of at most KD_BLOCK_MAX_PACKETS. */
void kd_block_trace_frustum(kd_block *block);
void kd_block_trace_mft(kd_block *block);
void kd_block_trace_cone(kd_block *block);
void kd_block_trace_mft_cone(kd_block *block);

/* A query cut into blocks of at most KD_BLOCK_MAX_PACKETS packets, each
 * traced by `trace` (one of the four above): the frustum family's entry. */
void kd_blocks_trace(const kd_tree *tree, const kd_query *q, void (*trace)(kd_block *));

#endif

/* Blocks of packets under proxies: the state the frustum, MFT and cone
 * kernels share (Thesis 2.3.2, 4.1.3 - 4.1.9, Figure 3.2).
 *
 * A block is up to KD_BLOCK_MAX_PACKETS 2x2 packets traced together.  Its
 * packets are partitioned into up to four groups, each bounded by one proxy
 * (a frustum or a cone): one group for the single-frustum and single-cone
 * kernels, four quadrants for MFT and MFT-cone, and the four lanes of one
 * packet when a block is too incoherent for a proxy to pay (then every
 * "proxy" is one ray and the traversal is an omni-directional packet
 * traversal with per-lane intervals, Listing 4.1).
 *
 * Exactness, for arbitrary rays.  A proxy interval [near, far] only ever
 * contains, conservatively, the parameters at which any ray of its group can
 * be inside the current cell.  A hit found in a leaf is kept whatever cell it
 * lies in (closest wins); a subtree is dropped only when its near lies past
 * the farthest current best hit of every live ray of the group ("max best").
 * So the result is the closest hit in (tnear, tfar) whatever order leaves are
 * visited in; front-to-back order only makes it fast.  Bounds are widened by
 * KD_WIDEN (relative) and the leaf boxes by a margin relative to the scene
 * size, so rounding never drops a cell a ray touches. */
#ifndef RTT_OPTIMIZED_FRUSTUM_H
#define RTT_OPTIMIZED_FRUSTUM_H

#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"

#define KD_BLOCK_MAX_PACKETS 256u    /* a 32x32 tile */
#define KD_STACK_MAX 256u            /* deeper than any tree the builder makes */
#define KD_WIDEN (1.0f / 65536.0f)   /* relative widening of proxy distances */

/* Horizontal minimum and maximum of the four lanes. */
static inline float kd_hmin4(__m128 v)
{
    v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(v);
}

static inline float kd_hmax4(__m128 v)
{
    v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(v);
}

typedef enum kd_units { KD_UNITS_RAY = 0, KD_UNITS_CONE_AXIS = 1 } kd_units;

/* Conservative interval-arithmetic frustum of a group of rays (the
 * generalisation of the thesis' corner rays to arbitrary origins): origin
 * box, and per axis the range of positive and of |negative| reciprocal
 * directions.  A ray whose direction component has its sign bit clear counts
 * as positive (+0 gives +inf), set as negative.  Sentinels: pos_lo = +inf
 * when no positive ray (then has_pos = 0).  104 bytes, scalar: the
 * single-frustum traversal reads it per node. */
typedef struct kd_frustum {
    float org_lo[3], org_hi[3];
    float pos_lo[3], pos_hi[3];      /* 1/dir over rays with dir >= +0 */
    float neg_lo[3], neg_hi[3];      /* |1/dir| over rays with dir <= -0 */
    uint32_t has_pos[3], has_neg[3];
    float near, far;                 /* root interval, near > far when empty */
} kd_frustum;
_Static_assert(sizeof(kd_frustum) == 104, "kd_frustum is 26 floats");

/* Four frusta in SSE lanes (MFT, 4.1.5); masks are all-ones lanes. */
typedef struct kd_frustum4 {
    __m128 org_lo[3], org_hi[3];
    __m128 pos_lo[3], pos_hi[3];
    __m128 neg_lo[3], neg_hi[3];
    __m128 has_pos[3], has_neg[3];
    __m128 near, far;
} kd_frustum4;

/* A cone (4.1.7): apex, unit axis, tan of the half angle and the per-axis
 * reciprocal denominators of Equation 4.8 (Listing 4.4).  near/far are in
 * tau units. */
typedef struct kd_cone {
    float apex[3], axis[3];
    float tan_angle;
    float pre[2][3];
    float near, far;
} kd_cone;

typedef struct kd_cone4 {
    __m128 apex[3];
    __m128 pre0[3], pre1[3];
    __m128 near, far;
} kd_cone4;

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
     * a closer hit for the packet (frustum.h's exactness argument), so the
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
void kd_block_root_interval(const kd_block *block, uint32_t p, __m128 *entry, __m128 *exit);

/* Frustum of group g; false when the group has no live ray. */
int kd_frustum_build(const kd_block *block, uint32_t g, kd_frustum *out);
/* True when a frustum would bound its rays too loosely to pay: origins
 * spread over more than a hundredth of the scene, or mixed direction signs
 * on all three axes (random rays). */
int kd_frustum_is_incoherent(const kd_block *block, const kd_frustum *f);
void kd_frustum4_pack(const kd_frustum f[4], const int present[4], kd_frustum4 *out);

/* Cone of group g (apex behind all origins, half angle covering every
 * direction).  Returns 1 when built (and records the tau conversion in the
 * block), 0 when the group has no live ray, -1 when no cone narrower than
 * ~80 degrees bounds it or a ray starts before t = 0 (then the block is
 * traced packet by packet). */
int kd_cone_build(kd_block *block, uint32_t g, kd_cone *out);
void kd_cone4_pack(const kd_cone c[4], const int present[4], kd_cone4 *out);

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

/* One block through one proxy kind (traverse_*.c); the kernels above
 * are these over blocks of at most KD_BLOCK_MAX_PACKETS packets. */
void kd_block_trace_frustum(kd_block *block);
void kd_block_trace_mft(kd_block *block);
void kd_block_trace_cone(kd_block *block);
void kd_block_trace_mft_cone(kd_block *block);

/* A query cut into blocks of at most KD_BLOCK_MAX_PACKETS packets, each
 * traced by `trace` (one of the four above): the frustum family's entry. */
void kd_blocks_trace(const kd_tree *tree, const kd_query *q, void (*trace)(kd_block *));

/* The four-lane interval traversal (MFT, 4.1.5), in traverse_mft.c. */
void kd_traverse4_frusta(kd_block *block, const kd_frustum4 *frusta);

/* Relative widening that keeps infinities (x - |x| w would give NaN). */
static inline float kd_widen_lo(float x)
{
    float a = x * (1.0f - KD_WIDEN), b = x * (1.0f + KD_WIDEN);
    return a < b ? a : b; /* not fminf: a libm call without -ffast-math */
}
static inline float kd_widen_hi(float x)
{
    float a = x * (1.0f - KD_WIDEN), b = x * (1.0f + KD_WIDEN);
    return a > b ? a : b;
}
static inline __m128 kd_widen_lo4(__m128 x)
{
    return _mm_min_ps(_mm_mul_ps(x, _mm_set1_ps(1.0f - KD_WIDEN)), _mm_mul_ps(x, _mm_set1_ps(1.0f + KD_WIDEN)));
}
static inline __m128 kd_widen_hi4(__m128 x)
{
    return _mm_max_ps(_mm_mul_ps(x, _mm_set1_ps(1.0f - KD_WIDEN)), _mm_mul_ps(x, _mm_set1_ps(1.0f + KD_WIDEN)));
}

#endif

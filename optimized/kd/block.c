/* Blocks of packets under proxies (block.h, whose header states the
 * exactness argument): set-up, grouping, and the leaf visit every proxy
 * kernel ends in (Figure 3.2: "cull packets against the leaf box,
 * intersect the rest"; packet/leaf culling, Thesis 4.1.4), and the per-lane
 * fallback for blocks no proxy bounds usefully.  Trades: a block keeps per
 * packet its live lanes, root interval and best so that a leaf visit skips
 * finished packets with one compare; that state costs a pass over the
 * block at set-up. */
#include <math.h>

#include "block.h"
#include "engine/clock.h"
#include "frustum.h"
#include "isect_leaf.h"

/* Slab test of a packet against box [lo - margin, hi + margin]: per-lane
 * entry and exit clipped to [tnear, tfar], widened relatively (which also
 * covers an inv_dir that is a refined reciprocal rather than 1/dir). */
static inline __attribute__((always_inline)) void slab4(const ray_packet4 *r, const float lo[3], const float hi[3], float margin, __m128 tfar,
                  __m128 *entry, __m128 *exit)
{
    const float grown_lo[3] = {lo[0] - margin, lo[1] - margin, lo[2] - margin};
    const float grown_hi[3] = {hi[0] + margin, hi[1] + margin, hi[2] + margin};
    __m128 t0, t1;
    ray_packet4_slab(r, grown_lo, grown_hi, r->tnear, tfar, &t0, &t1);
    *entry = kd_widen_lo4(t0, KD_WIDEN);
    *exit = kd_widen_hi4(t1, KD_WIDEN);
}

uint32_t kd_block_init(kd_block *b, const kd_tree *tree, const ray_packet4 *packets, uint32_t packet_count,
                       hit_packet4 *hits, uint8_t *occluded, int leaf_culling, kd_counters *counters)
{
    b->tree = tree;
    b->packets = packets;
    b->hits = hits;
    b->occluded = occluded;
    b->counters = counters;
    b->leaf_culling = leaf_culling;
    b->packet_count = packet_count;
    b->lane_groups = 0;
    b->lane_packet = 0;
    b->units = KD_UNITS_RAY;
    b->leaf_frusta = NULL;
    b->isect_ns = NULL;
    b->margin = kd_tree_margin(tree);
    const rtt_bounds *bb = &tree->bounds;
    const float lo[3] = {bb->lo.x, bb->lo.y, bb->lo.z}, hi[3] = {bb->hi.x, bb->hi.y, bb->hi.z};

    uint32_t traced = 0;
    for (uint32_t p = 0; p < packet_count; p++) {
        if (occluded) occluded[p] = 0;
        __m128 valid = ray_packet4_valid(&packets[p]);
        if (_mm_movemask_ps(valid)) traced++;
        __m128 entry, exit;
        slab4(&packets[p], lo, hi, b->margin, packets[p].tfar, &entry, &exit);
        b->root_entry[p] = entry;
        b->root_exit[p] = exit;
        b->live[p] = _mm_and_ps(valid, _mm_cmple_ps(entry, exit));
        b->packet_best[p] = _mm_movemask_ps(b->live[p]) ? INFINITY : -INFINITY;
        b->order[p] = (uint16_t)p;
    }
    b->group_count = 1;
    b->group_first[0] = 0;
    b->group_first[1] = (uint16_t)packet_count;
    if (counters) counters->packets += traced;
    return traced;
}

void kd_block_group_quadrants(kd_block *b)
{
    uint32_t n = b->packet_count, side = (uint32_t)sqrtf((float)n);
    uint32_t count[4] = {0, 0, 0, 0};
    uint8_t quadrant[KD_BLOCK_MAX_PACKETS];
    int square = side * side == n && side % 2 == 0;
    if (square) {
        for (uint32_t y = 0, p = 0; y < side; y++)
            for (uint32_t x = 0; x < side; x++, p++)
                quadrant[p] = (uint8_t)((y >= side / 2 ? 2u : 0u) + (x >= side / 2 ? 1u : 0u));
        for (uint32_t g = 0; g < 4; g++) count[g] = n / 4;
    } else {
        for (uint32_t p = 0; p < n; p++) {
            uint32_t q = (uint32_t)(((uint64_t)p * 4u) / n);
            quadrant[p] = (uint8_t)q;
            count[q]++;
        }
    }
    uint32_t next[4];
    b->group_first[0] = 0;
    for (uint32_t g = 0; g < 4; g++) {
        b->group_first[g + 1] = (uint16_t)(b->group_first[g] + count[g]);
        next[g] = b->group_first[g];
    }
    for (uint32_t p = 0; p < n; p++) b->order[next[quadrant[p]]++] = (uint16_t)p;
    b->group_count = 4;
}

void kd_block_group_lanes(kd_block *b, uint32_t index)
{
    b->lane_groups = 1;
    b->lane_packet = index;
    b->group_count = 4;
    b->units = KD_UNITS_RAY;
}

/* Lanes of packet r that may meet the leaf box before their current best:
 * packet/leaf culling (4.1.4). */
static __m128 leaf_overlap(const kd_block *b, const ray_packet4 *r, const kd_leaf *leaf, __m128 best)
{
    __m128 entry, exit;
    slab4(r, leaf->lo, leaf->hi, b->margin, best, &entry, &exit);
    return _mm_cmple_ps(entry, exit);
}

/* The best (upper end of the search) of each lane in the block's units. */
static __m128 lane_best(const kd_block *b, uint32_t g, uint32_t p)
{
    const ray_packet4 *r = &b->packets[p];
    __m128 t = b->hits ? _mm_min_ps(b->hits[p].t, r->tfar) : r->tfar;
    if (b->units == KD_UNITS_RAY) return t;
    const float *apex = b->cone_apex[g], *axis = b->cone_axis[g];
    __m128 offset = _mm_setzero_ps(), speed = _mm_setzero_ps();
    for (int a = 0; a < 3; a++) {
        offset = _mm_add_ps(offset, _mm_mul_ps(_mm_sub_ps(r->org[a], _mm_set1_ps(apex[a])), _mm_set1_ps(axis[a])));
        speed = _mm_add_ps(speed, _mm_mul_ps(r->dir[a], _mm_set1_ps(axis[a])));
    }
    /* speed > 0 for every live ray of a cone; t = +inf gives +inf */
    return _mm_add_ps(offset, _mm_mul_ps(t, speed));
}

/* Culls packet p against the leaf and intersects what is left; false when
 * it was culled (its hits and live lanes are then unchanged). */
static inline __attribute__((always_inline)) bool visit_packet(kd_block *b, const kd_leaf *leaf, uint32_t p,
                                                               __m128 mask)
{
    const ray_packet4 *r = &b->packets[p];
    if (b->leaf_culling) {
        __m128 best = b->hits ? _mm_min_ps(b->hits[p].t, r->tfar) : r->tfar;
        mask = _mm_and_ps(mask, leaf_overlap(b, r, leaf, best));
        if (!_mm_movemask_ps(mask)) return false;
    }
    if (b->hits) {
        isect4_leaf(b->tree, leaf, r, &b->hits[p], mask, b->counters);
    } else {
        __m128 hit = occluded4_leaf(b->tree, leaf, r, mask, b->counters);
        hit = _mm_and_ps(hit, mask);
        b->occluded[p] |= (uint8_t)_mm_movemask_ps(hit);
        b->live[p] = _mm_andnot_ps(hit, b->live[p]);
    }
    return true;
}

/* The packet's largest best over its live lanes (packet_best). */
static float packet_best(const kd_block *b, uint32_t g, uint32_t p)
{
    return kd_hmax4(_mm_blendv_ps(_mm_set1_ps(-INFINITY), lane_best(b, g, p), b->live[p]));
}

/* Interval arithmetic over each frustum's origin box and reciprocal
 * direction ranges: the groups (lanes) some ray of which may meet the leaf
 * box (grown by the margin) between the group's root near and its current
 * max best.  A ray's parameter in the box is at least the largest, over
 * axes, of its smallest possible slab entry, and at most the smallest of
 * its largest possible slab exit; both are widened as the slab tests are.
 * 0 * inf (an origin on a slab face, a zero direction) constrains nothing. */
static int frusta_meet_box(const kd_frustum4 *f, const kd_leaf *leaf, float margin, const float max_best[4])
{
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY), zero = _mm_setzero_ps();
    __m128 enter = f->near, leave = _mm_min_ps(f->far, _mm_loadu_ps(max_best));
    for (int a = 0; a < 3; a++) {
        __m128 lo = _mm_set1_ps(leaf->lo[a] - margin), hi = _mm_set1_ps(leaf->hi[a] + margin);
        __m128 d_enter = _mm_sub_ps(lo, f->org_hi[a]), d_leave = _mm_sub_ps(hi, f->org_lo[a]);
        __m128 e_pos = _mm_mul_ps(d_enter, _mm_blendv_ps(f->pos_hi[a], f->pos_lo[a], _mm_cmpgt_ps(d_enter, zero)));
        __m128 x_pos = _mm_mul_ps(d_leave, _mm_blendv_ps(f->pos_lo[a], f->pos_hi[a], _mm_cmpgt_ps(d_leave, zero)));
        __m128 n_enter = _mm_sub_ps(f->org_lo[a], hi), n_leave = _mm_sub_ps(f->org_hi[a], lo);
        __m128 e_neg = _mm_mul_ps(n_enter, _mm_blendv_ps(f->neg_hi[a], f->neg_lo[a], _mm_cmpgt_ps(n_enter, zero)));
        __m128 x_neg = _mm_mul_ps(n_leave, _mm_blendv_ps(f->neg_lo[a], f->neg_hi[a], _mm_cmpgt_ps(n_leave, zero)));
        e_pos = _mm_blendv_ps(pinf, _mm_blendv_ps(e_pos, ninf, _mm_cmpunord_ps(e_pos, e_pos)), f->has_pos[a]);
        e_neg = _mm_blendv_ps(pinf, _mm_blendv_ps(e_neg, ninf, _mm_cmpunord_ps(e_neg, e_neg)), f->has_neg[a]);
        x_pos = _mm_blendv_ps(ninf, _mm_blendv_ps(x_pos, pinf, _mm_cmpunord_ps(x_pos, x_pos)), f->has_pos[a]);
        x_neg = _mm_blendv_ps(ninf, _mm_blendv_ps(x_neg, pinf, _mm_cmpunord_ps(x_neg, x_neg)), f->has_neg[a]);
        enter = _mm_max_ps(enter, _mm_min_ps(e_pos, e_neg));
        leave = _mm_min_ps(leave, _mm_max_ps(x_pos, x_neg));
    }
    return _mm_movemask_ps(_mm_cmple_ps(kd_widen_lo4(enter, KD_WIDEN), kd_widen_hi4(leave, KD_WIDEN)));
}

/* The group test costs about as much as two packet slab tests and culls
 * little where leaf boxes fill their cells (dense meshes: bunny00), so it
 * runs only when more packets than this wait behind it (measured: callgrind,
 * kernel-tuning.md). */
#define LEAF_GROUP_TEST_MIN_PACKETS 8u

void kd_block_visit_leaf(kd_block *b, const kd_leaf *leaf, uint32_t lane_mask, const float near[4],
                         float max_best[4])
{
    if (leaf->count == 0) return;
    /* groups culled as a whole keep their max best: their hits did not change */
    if (b->leaf_culling && b->leaf_frusta) {
        uint32_t candidates = b->lane_groups ? LEAF_GROUP_TEST_MIN_PACKETS + 1 : 0u;
        for (uint32_t g = 0; g < 4 && !b->lane_groups; g++)
            if (lane_mask >> g & 1u) candidates += b->group_first[g + 1] - b->group_first[g];
        if (candidates > LEAF_GROUP_TEST_MIN_PACKETS)
            lane_mask &= (uint32_t)frusta_meet_box(b->leaf_frusta, leaf, b->margin, max_best);
    }
    if (!lane_mask) return;
    uint64_t start = b->isect_ns ? rtt_clock_ns() : 0;
    const __m128 ninf = _mm_set1_ps(-INFINITY);
    for (uint32_t g = 0; g < b->group_count; g++) {
        if (!(lane_mask >> g & 1u)) continue;
        if (b->lane_groups) {
            __m128 group_best = ninf;
            uint32_t p = b->lane_packet;
            int32_t bits[4] = {0, 0, 0, 0};
            bits[g] = -1;
            __m128 lane = _mm_castsi128_ps(_mm_loadu_si128((const __m128i *)bits));
            __m128 mask = _mm_and_ps(b->live[p], lane);
            if (_mm_movemask_ps(mask)) {
                visit_packet(b, leaf, p, mask);
                group_best = _mm_blendv_ps(ninf, lane_best(b, g, p), _mm_and_ps(b->live[p], lane));
            }
            b->packet_best[p] = INFINITY;
            max_best[g] = kd_widen_hi(kd_hmax4(group_best), KD_WIDEN);
            continue;
        }
        /* Without leaf culling every live packet is intersected (Table 4.2's
         * "off"); with it, packets done before the interval are skipped. */
        const float skip_below = b->leaf_culling ? near[g] : -INFINITY;
        float group_best = -INFINITY;
        for (uint32_t i = b->group_first[g]; i < b->group_first[g + 1]; i++) {
            uint32_t p = b->order[i];
            float best = b->packet_best[p];
            if (best == -INFINITY) continue;
            if (best >= skip_below && (visit_packet(b, leaf, p, b->live[p]) || best == INFINITY))
                best = b->packet_best[p] = packet_best(b, g, p);
            group_best = best > group_best ? best : group_best;
        }
        max_best[g] = kd_widen_hi(group_best, KD_WIDEN);
    }
    if (b->isect_ns) *b->isect_ns += rtt_clock_ns() - start;
}

void kd_block_trace_packets(kd_block *b)
{
    for (uint32_t p = 0; p < b->packet_count; p++) {
        if (!_mm_movemask_ps(b->live[p])) continue;
        kd_block_group_lanes(b, p);
        kd_frustum4 f;
        kd_frustum4_of_lanes(b, p, &f);
        b->leaf_frusta = &f;
        kd_traverse4_frusta(b, &f);
        b->leaf_frusta = NULL;
    }
    b->lane_groups = 0;
}

void kd_blocks_trace(const kd_tree *tree, const kd_query *q, void (*trace)(kd_block *))
{
    kd_block b;
    for (uint32_t first = 0; first < q->packet_count; first += KD_BLOCK_MAX_PACKETS) {
        uint32_t n = q->packet_count - first < KD_BLOCK_MAX_PACKETS ? q->packet_count - first : KD_BLOCK_MAX_PACKETS;
        if (!kd_block_init(&b, tree, q->packets + first, n, q->hits ? q->hits + first : NULL,
                           q->occluded ? q->occluded + first : NULL, q->leaf_culling, q->counters))
            continue;
        b.isect_ns = q->isect_ns;
        trace(&b);
    }
}

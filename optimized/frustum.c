/* Blocks, frusta and leaf visits shared by the frustum, MFT and cone kernels
 * (Thesis 2.3.2 frustums, 4.1.3 - 4.1.5, Figure 3.2 "cull packets against
 * the leaf box, intersect the rest").  See frustum.h for the exactness
 * argument.
 *
 * Frustum construction, generalised from the thesis' corner rays: the
 * thesis builds the interval frustum from the four corner rays of a primary
 * tile, which assumes one origin.  Here a group of arbitrary rays is bounded
 * by interval arithmetic instead: the origin box and, per axis, the ranges
 * of positive and of negative reciprocal directions.  For a common origin
 * and equal signs this gives exactly the corner-ray distances; for mixed
 * signs it gives the omni-directional rule of Listing 4.2 (a ray going away
 * from the plane never crosses it: distance +inf). */
#include <float.h>
#include <math.h>
#include <string.h>
#include <time.h>

#include "frustum.h"
#include "isect_projected_bary.h"

static inline __m128 is_finite4(__m128 x) { return _mm_cmpeq_ps(_mm_sub_ps(x, x), _mm_setzero_ps()); }

/* Lanes carrying a ray that can hit: finite origin and direction, nonzero
 * direction, tnear < tfar (both not NaN). */
static __m128 valid_lanes(const ray_packet4 *r)
{
    __m128 ok = _mm_cmplt_ps(r->tnear, r->tfar);
    __m128 nonzero = _mm_setzero_ps();
    for (int a = 0; a < 3; a++) {
        ok = _mm_and_ps(ok, _mm_and_ps(is_finite4(r->org[a]), is_finite4(r->dir[a])));
        nonzero = _mm_or_ps(nonzero, _mm_cmpneq_ps(r->dir[a], _mm_setzero_ps()));
    }
    return _mm_and_ps(ok, nonzero);
}

/* Slab test of a packet against box [lo - margin, hi + margin]: per-lane
 * entry and exit clipped to [tnear, tfar], widened relatively (which also
 * covers an inv_dir that is a refined reciprocal rather than 1/dir).  A NaN slab
 * (a ray parallel to a face, its origin exactly on it) drops that axis. */
static void slab4(const ray_packet4 *r, const float lo[3], const float hi[3], float margin, __m128 tfar,
                  __m128 *entry, __m128 *exit)
{
    __m128 t0 = r->tnear, t1 = tfar;
    for (int a = 0; a < 3; a++) {
        __m128 inv = r->inv_dir[a];
        __m128 ta = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(lo[a] - margin), r->org[a]), inv);
        __m128 tb = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(hi[a] + margin), r->org[a]), inv);
        t0 = _mm_max_ps(_mm_min_ps(ta, tb), t0);
        t1 = _mm_min_ps(_mm_max_ps(ta, tb), t1);
    }
    *entry = kd_widen_lo4(t0);
    *exit = kd_widen_hi4(t1);
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
    const rtt_bounds *bb = &tree->bounds;
    float scale = fmaxf(fmaxf(fmaxf(fabsf(bb->lo.x), fabsf(bb->hi.x)), fmaxf(fabsf(bb->lo.y), fabsf(bb->hi.y))),
                        fmaxf(fabsf(bb->lo.z), fabsf(bb->hi.z)));
    b->margin = isfinite(scale) ? scale * 1e-5f + FLT_MIN : 0.0f;
    float lo[3] = {bb->lo.x, bb->lo.y, bb->lo.z}, hi[3] = {bb->hi.x, bb->hi.y, bb->hi.z};

    uint32_t traced = 0;
    for (uint32_t p = 0; p < packet_count; p++) {
        if (occluded) occluded[p] = 0;
        __m128 valid = valid_lanes(&packets[p]);
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

void kd_block_root_interval(const kd_block *b, uint32_t p, __m128 *entry, __m128 *exit)
{
    *entry = b->root_entry[p];
    *exit = b->root_exit[p];
}

/* One pass per axis (eight accumulators stay in registers; all of them at
 * once spilled to the stack on every packet), then the root interval. */
int kd_frustum_build(const kd_block *b, uint32_t g, kd_frustum *f)
{
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY), sign = _mm_set1_ps(-0.0f);
    const uint16_t *first = &b->order[b->group_first[g]], *last = &b->order[b->group_first[g + 1]];
    for (int a = 0; a < 3; a++) {
        __m128 olo = pinf, ohi = ninf, plo = pinf, phi = ninf, nlo = pinf, nhi = ninf;
        __m128 hpos = _mm_setzero_ps(), hneg = _mm_setzero_ps();
        for (const uint16_t *i = first; i < last; i++) {
            __m128 live = b->live[*i];
            const ray_packet4 *r = &b->packets[*i];
            olo = _mm_min_ps(olo, _mm_blendv_ps(pinf, r->org[a], live));
            ohi = _mm_max_ps(ohi, _mm_blendv_ps(ninf, r->org[a], live));
            __m128 neg = _mm_and_ps(_mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(r->dir[a]), 31)), live);
            __m128 pos = _mm_andnot_ps(neg, live);
            /* the packet's reciprocal (1/dir, packet.c); the split distances
             * are widened by KD_WIDEN, far more than a refined rcp's error */
            __m128 mag = _mm_andnot_ps(sign, r->inv_dir[a]);
            plo = _mm_min_ps(plo, _mm_blendv_ps(pinf, mag, pos));
            phi = _mm_max_ps(phi, _mm_blendv_ps(ninf, mag, pos));
            nlo = _mm_min_ps(nlo, _mm_blendv_ps(pinf, mag, neg));
            nhi = _mm_max_ps(nhi, _mm_blendv_ps(ninf, mag, neg));
            hpos = _mm_or_ps(hpos, pos);
            hneg = _mm_or_ps(hneg, neg);
        }
        f->org_lo[a] = kd_hmin4(olo);
        f->org_hi[a] = kd_hmax4(ohi);
        f->pos_lo[a] = kd_hmin4(plo);
        f->pos_hi[a] = kd_hmax4(phi);
        f->neg_lo[a] = kd_hmin4(nlo);
        f->neg_hi[a] = kd_hmax4(nhi);
        f->has_pos[a] = _mm_movemask_ps(hpos) != 0;
        f->has_neg[a] = _mm_movemask_ps(hneg) != 0;
    }
    __m128 near = pinf, far = ninf;
    for (const uint16_t *i = first; i < last; i++) {
        __m128 live = b->live[*i];
        near = _mm_min_ps(near, _mm_blendv_ps(pinf, b->root_entry[*i], live));
        far = _mm_max_ps(far, _mm_blendv_ps(ninf, b->root_exit[*i], live));
    }
    f->near = kd_hmin4(near);
    f->far = kd_hmax4(far);
    return f->near <= f->far;
}

int kd_frustum_is_incoherent(const kd_block *b, const kd_frustum *f)
{
    rtt_vec3 e = rtt_v3_sub(b->tree->bounds.hi, b->tree->bounds.lo);
    float scene = fmaxf(e.x, fmaxf(e.y, e.z));
    int mixed = 0;
    for (int a = 0; a < 3; a++) {
        if (f->org_hi[a] - f->org_lo[a] > 0.01f * scene) return 1;
        mixed += f->has_pos[a] && f->has_neg[a];
    }
    return mixed == 3;
}

void kd_frustum4_pack(const kd_frustum f[4], const int present[4], kd_frustum4 *out)
{
    float v[4];
#define KD_PACK(field, idle)                                                  \
    do {                                                                      \
        for (int l = 0; l < 4; l++) v[l] = present[l] ? (field) : (idle);     \
    } while (0)
    for (int a = 0; a < 3; a++) {
        KD_PACK(f[l].org_lo[a], 0.0f);
        out->org_lo[a] = _mm_loadu_ps(v);
        KD_PACK(f[l].org_hi[a], 0.0f);
        out->org_hi[a] = _mm_loadu_ps(v);
        KD_PACK(f[l].pos_lo[a], 1.0f);
        out->pos_lo[a] = _mm_loadu_ps(v);
        KD_PACK(f[l].pos_hi[a], 1.0f);
        out->pos_hi[a] = _mm_loadu_ps(v);
        KD_PACK(f[l].neg_lo[a], 1.0f);
        out->neg_lo[a] = _mm_loadu_ps(v);
        KD_PACK(f[l].neg_hi[a], 1.0f);
        out->neg_hi[a] = _mm_loadu_ps(v);
        int32_t m[4];
        for (int l = 0; l < 4; l++) m[l] = present[l] && f[l].has_pos[a] ? -1 : 0;
        out->has_pos[a] = _mm_castsi128_ps(_mm_loadu_si128((const __m128i *)m));
        for (int l = 0; l < 4; l++) m[l] = present[l] && f[l].has_neg[a] ? -1 : 0;
        out->has_neg[a] = _mm_castsi128_ps(_mm_loadu_si128((const __m128i *)m));
    }
    KD_PACK(f[l].near, INFINITY);
    out->near = _mm_loadu_ps(v);
    KD_PACK(f[l].far, -INFINITY);
    out->far = _mm_loadu_ps(v);
#undef KD_PACK
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

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
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
    return _mm_movemask_ps(_mm_cmple_ps(kd_widen_lo4(enter), kd_widen_hi4(leave)));
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
    uint64_t start = b->isect_ns ? now_ns() : 0;
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
            max_best[g] = kd_widen_hi(kd_hmax4(group_best));
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
        max_best[g] = kd_widen_hi(group_best);
    }
    if (b->isect_ns) *b->isect_ns += now_ns() - start;
}

void kd_block_trace_packets(kd_block *b)
{
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
    const __m128 sign = _mm_set1_ps(-0.0f), one = _mm_set1_ps(1.0f);
    for (uint32_t p = 0; p < b->packet_count; p++) {
        __m128 live = b->live[p];
        if (!_mm_movemask_ps(live)) continue;
        kd_block_group_lanes(b, p);
        const ray_packet4 *r = &b->packets[p];
        kd_frustum4 f;
        for (int a = 0; a < 3; a++) {
            __m128 org = _mm_and_ps(r->org[a], live);
            __m128 inv = _mm_div_ps(one, r->dir[a]);
            __m128 mag = _mm_blendv_ps(one, _mm_andnot_ps(sign, inv), live);
            __m128 neg = _mm_and_ps(_mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(r->dir[a]), 31)), live);
            __m128 pos = _mm_andnot_ps(neg, live);
            f.org_lo[a] = f.org_hi[a] = org;
            f.pos_lo[a] = _mm_blendv_ps(pinf, mag, pos);
            f.pos_hi[a] = _mm_blendv_ps(ninf, mag, pos);
            f.neg_lo[a] = _mm_blendv_ps(pinf, mag, neg);
            f.neg_hi[a] = _mm_blendv_ps(ninf, mag, neg);
            f.has_pos[a] = pos;
            f.has_neg[a] = neg;
        }
        __m128 entry, exit;
        kd_block_root_interval(b, p, &entry, &exit);
        f.near = _mm_blendv_ps(pinf, entry, live);
        f.far = _mm_blendv_ps(ninf, exit, live);
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

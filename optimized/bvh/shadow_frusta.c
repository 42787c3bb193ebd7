/* Benthin & Wald 2009, 4.4-4.5: soft-shadow frusta (--shadows frusta:N).
 * BVH_W shading points (16 on AVX-512: a 4x4 block of pixels, 8 on AVX2,
 * 4 on SSE4.1) are traced together, one frustum per SIMD lane: the point's
 * N interleaved sample rays towards one light (bvh_kernels.h,
 * bvh_shadow_query).
 *
 *  - A frustum's origin is its point (exact: every sample ray starts there);
 *    its direction box is the box of the four vectors from the point to the
 *    corners of the set's 2D sample bounds on the light (the paper's
 *    "tighter bounds based on the axis-aligned bounds (in 2D) of the random
 *    samples set"), t from 0 to 1.  The map from the light's domain to its
 *    points is affine, so every target lies in that box up to rounding; the
 *    box is grown by 2^-16 of the magnitudes involved, far more than the
 *    rounding of a target or of a ray's unit direction.
 *  - Per node one pass tests both children's boxes against every frustum
 *    (bvh_frusta.h: open-ended interval bounds with the zero fix); the
 *    active-frusta mask travels on the stack.  A box that holds the ends
 *    of the group's corner vectors (group_ends: every frustum reaches
 *    them, on the light) is entered without a test.
 *  - At a leaf, per triangle: the common-origin Pluecker test against every
 *    active frustum at once over the cone of its four corner rays (the
 *    vectors to the 2D bounds' corners: every target is a convex
 *    combination of them; bvh_frusta.h), with a margin for the corners'
 *    rounding, and a plane test for what the edges cannot cull (a point in
 *    the triangle's plane, as on a floor: beside_plane), after a box test
 *    of the leaf against the rays of the frusta that have them (leaf_rays:
 *    a wide frustum's cone passes many small triangles its few rays miss;
 *    armadillo's ray-triangle tests 1945K -> 1004K); then, only for the
 *    survivors (bitscan), the frustum's rays are generated from the point, its light
 *    frame and the set's domain coordinates at its first triangle test
 *    (on demand: a frustum no triangle reaches makes none), kept in the
 *    group with their shears for its later tests, and tested with the
 *    triangle test the tree names (bvh_isect_wide.h: projected or
 *    watertight) in packets of BVH_W, only the samples not yet occluded.
 *    Making them once instead of at every test (with the floor lanes of
 *    bvh_isect_wide.h): oa_dm4 69 -> 107 Mrays/s, czest3ctf 47 -> 63-72,
 *    bunny00 64 -> 75 (bench/results/frusta.md).
 *  - Occlusion bits are packed in a mask per point (N <= 32); a frustum is
 *    terminated as soon as all its rays are occluded.
 *  - Frustum shrinking (the paper's 5.3, "CR"): after a leaf in which some
 *    of a frustum's samples were newly occluded, its corner rays are
 *    recomputed through the corners of the 2D bounds of its samples still
 *    unoccluded, so later triangles are culled against the rays it has
 *    left, and the direction box that steers the traversal is made from
 *    them too (the paper's "FS"; shrink_bounds), for the subtrees it
 *    descends into from then on (those already on the stack keep the
 *    frusta they were entered with).
 *
 * A sample ray is computed with the scalar renderers' operations in their
 * order (shader_proxy.c's shadow_segment: target, difference, length with
 * rtt_v3_length's double fallback, direction by one reciprocal), so its
 * visibility is bit for bit the one bvh-packet gives that ray. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "bvh_frusta.h"
#include "bvh_isa.h"
#include "bvh_isect_wide.h"
#include "bvh_kernels.h"
#include "bvh_traverse.h"

#define SF_FRUSTA BVH_W
/* sample vectors a frustum may have: N <= 32 */
#define SF_VECTORS ((32u + BVH_W - 1u) / BVH_W)

/* One vector of a frustum's sample rays, made at its first triangle test
 * and kept for the group's later tests (a frustum meets 1.4 to 4.5
 * triangles on the bench scenes), with the shears of its live lanes. */
typedef struct sf_rays {
    bvh_packet r;
    bvh_wt_shears shears;
    const bvh_wt_shears *s;         /* &shears, or NULL under the projected test */
} sf_rays;

typedef struct sf_group {
    mft_bounds b;
    vf corner[4][3];                /* per frustum: the vectors to the 2D bounds' corners */
    vf base[3], du[3], dv[3];       /* per frustum: its point's light frame (bvh_shadow_point's), for shrinking */
    vf corner_grow;                 /* how far off they may be per axis (rounding) */
    vf corner_l1;                   /* per frustum: the largest |corner|_1 */
    vf corner_max;                  /* per frustum: the largest |component| of its corners */
    const bvh_shadow_point *point[SF_FRUSTA];
    uint32_t occ[SF_FRUSTA];        /* occluded samples */
    uint32_t live[SF_FRUSTA];       /* samples with a ray, once known */
    uint32_t known;                 /* frusta whose live samples are known (and rays made) */
    sf_rays rays[SF_FRUSTA][SF_VECTORS];
} sf_group;

static inline vm vf_finite(vf x) { return vf_eq(vf_sub(x, x), vf_set1(0.0f)); }

/* Rays of samples v*BVH_W .. of point pt into r; returns the lanes with a ray. */
static uint32_t sample_packet(const bvh_shadow_point *pt, const bvh_shadow_sets *sets, uint32_t v, float eps,
                              bvh_packet *r)
{
    const uint32_t first = v * BVH_W, n = sets->samples - first < BVH_W ? sets->samples - first : BVH_W;
    const vf x = vf_load(&sets->x[pt->set][first]), y = vf_load(&sets->y[pt->set][first]);
    vf to[3];
    for (int k = 0; k < 3; k++) {
        const vf target = vf_add(vf_add(vf_set1(pt->base[k]), vf_mul(vf_set1(pt->du[k]), x)), vf_mul(vf_set1(pt->dv[k]), y));
        to[k] = vf_sub(target, vf_set1(pt->org[k]));
    }
    vf len = vf_sqrt(vf_add(vf_add(vf_mul(to[0], to[0]), vf_mul(to[1], to[1])), vf_mul(to[2], to[2])));
    const uint32_t plain = vm_bits(vm_and(vf_gt(len, vf_set1(1e-18f)), vf_lt(len, vf_set1(1e18f))));
    if ((plain & ((1u << n) - 1u)) != ((1u << n) - 1u)) { /* rtt_v3_length's double fallback */
        float l[BVH_W], t[3][BVH_W];
        vf_store(l, len);
        for (int k = 0; k < 3; k++) vf_store(t[k], to[k]);
        for (uint32_t i = 0; i < n; i++)
            if (!(plain >> i & 1u))
                l[i] = (float)sqrt((double)t[0][i] * t[0][i] + (double)t[1][i] * t[1][i] + (double)t[2][i] * t[2][i]);
        len = vf_load(l);
    }
    const vf inv = vf_div(vf_set1(1.0f), len), e = vf_set1(eps);
    vm ok = vf_gt(len, vf_set1(2.0f * eps));
    for (int k = 0; k < 3; k++) {
        r->org[k] = vf_set1(pt->org[k]);
        r->dir[k] = vf_mul(to[k], inv);
        r->inv_dir[k] = vf_div(vf_set1(1.0f), r->dir[k]);
        ok = vm_and(ok, vm_and(vf_finite(r->dir[k]), vf_finite(r->org[k])));
    }
    r->tnear = e;
    r->tfar = vf_sub(len, e);
    ok = vm_and(ok, vf_le(r->tnear, r->tfar));
    /* lanes without a ray answer nothing (bvh_packet.h's inactive lanes) */
    r->tnear = vf_blend(ok, vf_set1(INFINITY), r->tnear);
    r->tfar = vf_blend(ok, vf_set1(-INFINITY), r->tfar);
    return vm_bits(ok) & ((1u << n) - 1u);
}

/* Frustum f against record rec: its rays not yet occluded; true when all
 * its rays are occluded (the frustum terminates).  Its first test makes
 * every vector of its rays (and learns which samples have one); later tests
 * reuse them: the same rays, so the same answers. */
static bool frustum_rays(const bvh_tree *tree, uint32_t rec, sf_group *g, uint32_t f, const bvh_shadow_sets *sets, float eps)
{
    const uint32_t vecs = (sets->samples + BVH_W - 1u) / BVH_W, lane_bits = BVH_LANES_ALL;
    if (!(g->known >> f & 1u)) {
        for (uint32_t v = 0; v < vecs; v++) {
            sf_rays *made = &g->rays[f][v];
            const uint32_t live = sample_packet(g->point[f], sets, v, eps, &made->r);
            g->live[f] |= live << (v * BVH_W);
            made->s = bvh_record_setup(tree, &made->r, live, &made->shears);
        }
        g->known |= 1u << f;
    }
    for (uint32_t v = 0; v < vecs; v++) {
        const uint32_t shift = v * BVH_W, lanes = (g->live[f] & ~g->occ[f]) >> shift & lane_bits;
        if (!lanes) continue;
        const sf_rays *made = &g->rays[f][v];
        g->occ[f] |= bvh_occluded_record(tree, rec, &made->r, made->s, lanes) << shift;
    }
    return (g->live[f] & ~g->occ[f]) == 0;
}

/* The vectors from the points (origin org, light frame base, du, dv, a
 * lane each) to the light's points at the corners of the 2D rectangles
 * [x0, x1] x [y0, y1] of their domains (corner c: x from x1 when c & 1, y
 * from y1 when c & 2), in the arithmetic of the sample targets, into the
 * lanes `lanes` of corner. */
static void corner_vectors(const vf org[3], const vf base[3], const vf du[3], const vf dv[3], vf x0, vf x1, vf y0,
                           vf y1, vm lanes, vf corner[4][3])
{
    for (int c = 0; c < 4; c++) {
        const vf x = c & 1 ? x1 : x0, y = c & 2 ? y1 : y0;
        for (int k = 0; k < 3; k++) {
            const vf d = vf_sub(vf_add(vf_add(base[k], vf_mul(du[k], x)), vf_mul(dv[k], y)), org[k]);
            corner[c][k] = vf_blend(lanes, corner[c][k], d);
        }
    }
}

/* Per frustum the least and the greatest component k of its four corner
 * vectors (the direction box before its growth). */
static inline void corner_range(const vf corner[4][3], int k, vf *lo, vf *hi)
{
    *lo = *hi = corner[0][k];
    for (int c = 1; c < 4; c++) *lo = vf_min(*lo, corner[c][k]), *hi = vf_max(*hi, corner[c][k]);
}

/* Per frustum its corner vectors' largest |c|_1 (the edge and plane tests'
 * bound on |d|_1) and largest |component| (the edge test's margin). */
static void corner_sizes(sf_group *g)
{
    g->corner_l1 = g->corner_max = vf_set1(0.0f);
    for (int c = 0; c < 4; c++) {
        const vf *d = g->corner[c];
        const vf a0 = vf_abs(d[0]), a1 = vf_abs(d[1]), a2 = vf_abs(d[2]);
        g->corner_l1 = vf_max(g->corner_l1, vf_add(vf_add(a0, a1), a2));
        g->corner_max = vf_max(g->corner_max, vf_max(vf_max(a0, a1), a2));
    }
}

/* The traversal's direction boxes of the frusta `lanes` made again from
 * their (shrunk) corner vectors, grown as group_bounds grows them (the
 * same corner_grow covers the smaller rectangle's corners), within the
 * old boxes (both hold every ray left, so their intersection does; the
 * shrunk corners' own rounding could otherwise reach past an old bound
 * just above zero).  Only for frusta with no interval holding zero: a box
 * inside the old one keeps every axis's sign, so the group's classes
 * (mft_bounds_classify) stand; the ends box too (the shrunk corners end
 * inside the old rectangle). */
static inline void shrink_bounds(sf_group *g, uint32_t lanes)
{
    lanes &= ~(g->b.straddle[0] | g->b.straddle[1] | g->b.straddle[2]);
    if (!lanes) return;
    const vm m = vm_of_bits(lanes);
    const vf one = vf_set1(1.0f), grow = g->corner_grow;
    for (int k = 0; k < 3; k++) {
        vf lo, hi;
        corner_range(g->corner, k, &lo, &hi);
        g->b.dlo[k] = vf_blend(m, g->b.dlo[k], vf_max(vf_sub(lo, grow), g->b.dlo[k]));
        g->b.dhi[k] = vf_blend(m, g->b.dhi[k], vf_min(vf_add(hi, grow), g->b.dhi[k]));
        g->b.rlo[k] = vf_blend(m, g->b.rlo[k], vf_div(one, g->b.dlo[k]));
        g->b.rhi[k] = vf_blend(m, g->b.rhi[k], vf_div(one, g->b.dhi[k]));
    }
}

/* Frustum shrinking by recomputing the corner rays (Benthin & Wald 2009,
 * 5.3, "CR"): for each frustum of `frusta`, the 2D bounds of its samples
 * still unoccluded and the vectors to that rectangle's corners.  Every
 * such sample's target lies in the rectangle, so the new cone still holds
 * every ray the frustum has left to test, and the culling stays exact; the
 * rounding margin (corner_grow) is the full set's, which bounds the
 * smaller rectangle's too.  Then the traversal's direction box
 * (shrink_bounds).  Out of line: after few leaves, and inlined into
 * trace_group with shrink_bounds it cost the maps 5-8% (the loop's code
 * around it, not its own work). */
static __attribute__((noinline)) void shrink_corners(sf_group *g, uint32_t frusta, const bvh_shadow_sets *sets)
{
    const vf inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    const uint32_t vecs = (sets->samples + BVH_W - 1u) / BVH_W;
    vf x0 = inf, x1 = inf, y0 = inf, y1 = inf; /* the lanes of `frusta` are set below */
    for (uint32_t bits = frusta; bits; bits &= bits - 1u) {
        const uint32_t f = (uint32_t)__builtin_ctz(bits);
        const bvh_shadow_point *pt = g->point[f];
        const uint32_t active = g->live[f] & ~g->occ[f];
        vf xlo = inf, xhi = minus_inf, ylo = inf, yhi = minus_inf;
        for (uint32_t v = 0; v < vecs; v++) {
            const vm m = vm_of_bits(active >> (v * BVH_W) & BVH_LANES_ALL);
            const vf x = vf_load(&sets->x[pt->set][v * BVH_W]), y = vf_load(&sets->y[pt->set][v * BVH_W]);
            xlo = vf_min(vf_blend(m, inf, x), xlo), xhi = vf_max(vf_blend(m, minus_inf, x), xhi);
            ylo = vf_min(vf_blend(m, inf, y), ylo), yhi = vf_max(vf_blend(m, minus_inf, y), yhi);
        }
        /* lane f of the rectangles, by blends (a lane of an array stored
         * and the array loaded whole would wait for the store buffer) */
        const vm lane = vm_of_bits(1u << f);
        x0 = vf_blend(lane, x0, vf_set1(vf_hmin(xlo))), x1 = vf_blend(lane, x1, vf_set1(vf_hmax(xhi)));
        y0 = vf_blend(lane, y0, vf_set1(vf_hmin(ylo))), y1 = vf_blend(lane, y1, vf_set1(vf_hmax(yhi)));
    }
    corner_vectors(g->b.org, g->base, g->du, g->dv, x0, x1, y0, y1, vm_of_bits(frusta), g->corner);
    corner_sizes(g);
    shrink_bounds(g, frusta);
}

/* The frusta of `lanes` whose sample rays all stay on one side of the
 * triangle's plane from their tnear = eps on: the case the edge test
 * cannot cull, a point on a floor (in the plane of the floor's triangles,
 * so every edge plane through it is that plane) with the light above it.
 * With N the triangle's normal as computed, h = N.(org - v0) the origin's
 * height over its plane and every sample vector d (a convex combination of
 * the corner vectors, up to corner_grow per axis) climbing at N.d >= lo
 * over |d| <= dmax, a ray's height at t >= eps is at least h + eps lo /
 * dmax; the triangle lies within `thick` of the plane (the larger of its
 * other corners' heights N.(v - v0), N being rounded, and their rounding:
 * the heights are linear, so the triangle, their hull, lies between them)
 * and h is known to 2^-20 of its terms.  A frustum is dropped when
 * that bound clears the slab twice over (the ray meets the plane, if at
 * all, before eps / 2) and eps passes 2^-16 of the corners' distance (the
 * watertight test's t, a weighted mean of the corners' distances along
 * the ray, is off by far less than eps / 2 then); likewise below. */
static inline uint32_t beside_plane(const frusta_tri *t, const sf_group *g, float eps, uint32_t lanes)
{
    const float *n = t->normal, *e1 = t->edge[2], *e2 = t->edge[1]; /* v1 - v0 and v0 - v2 */
    const float n1 = t->area;
    /* the corners' heights over the plane through v0 as computed: the
     * triangle, their hull, lies within the larger (and its rounding) */
    float h1 = 0.0f, h2 = 0.0f, terms = 0.0f;
    for (int k = 0; k < 3; k++) {
        h1 += n[k] * e1[k], h2 += n[k] * e2[k];
        terms += fabsf(n[k] * e1[k]) + fabsf(n[k] * e2[k]);
    }
    const float thick = (fabsf(h1) > fabsf(h2) ? fabsf(h1) : fabsf(h2)) + terms * 0x1p-20f;
    const vf zero = vf_set1(0.0f);
    /* below = -h = N.(v0 - org); reach: the corners' largest distance from
     * the origin per axis (frusta_edges') */
    vf below = zero, below_mag = zero;
    for (int k = 0; k < 3; k++) {
        const vf x = vf_mul(vf_set1(n[k]), t->rel[0][k]);
        below = vf_add(below, x), below_mag = vf_add(below_mag, vf_abs(x));
    }
    const vf reach = t->reach;
    vf lo = vf_set1(INFINITY), hi = vf_set1(-INFINITY);
    for (int c = 0; c < 4; c++) {
        const vf *d = g->corner[c];
        const vf dot = vf_add(vf_add(vf_mul(vf_set1(n[0]), d[0]), vf_mul(vf_set1(n[1]), d[1])), vf_mul(vf_set1(n[2]), d[2]));
        lo = vf_min(lo, dot), hi = vf_max(hi, dot);
    }
    const vf grow = g->corner_grow;
    const vf dmax = vf_add(g->corner_l1, vf_mul(grow, vf_set1(3.0f)));
    const vf slack = vf_mul(vf_set1(n1), vf_add(vf_add(grow, grow), vf_mul(dmax, vf_set1(0x1p-20f))));
    const vf err = vf_add(vf_mul(below_mag, vf_set1(0x1p-20f)), vf_set1(thick));
    const vf e = vf_set1(eps), twice_d = vf_add(dmax, dmax);
    const vf up = vf_sub(lo, slack), down = vf_sub(zero, vf_add(hi, slack));
    const vm rising = vm_and(vf_gt(up, zero), vf_gt(vf_mul(e, up), vf_mul(twice_d, vf_add(err, below))));
    const vm falling = vm_and(vf_gt(down, zero), vf_gt(vf_mul(e, down), vf_mul(twice_d, vf_sub(err, below))));
    const vm near = vf_gt(e, vf_mul(reach, vf_set1(0x1p-16f)));
    return lanes & vm_bits(vm_and(near, vm_or(rising, falling)));
}

/* The frusta of `lanes` worth testing at leaf c: those without rays yet,
 * and those with some ray not yet occluded that enters the leaf's box
 * (bvh-packet's box test, on the same rays: a triangle of the leaf that
 * one of them hits is one it lets through).  A wide frustum's cone passes
 * many small triangles its few rays all miss; one box test per vector
 * drops the leaf for it instead of a ray test per triangle. */
static uint32_t leaf_rays(const bvh_child *c, const sf_group *g, uint32_t lanes, uint32_t vecs, uint64_t *aabb)
{
    uint32_t drop = 0;
    for (uint32_t bits = lanes & g->known & BVH_LANES_ALL; bits; bits &= bits - 1u) {
        const uint32_t f = (uint32_t)__builtin_ctz(bits), left = g->live[f] & ~g->occ[f];
        uint32_t enters = 0;
        for (uint32_t v = 0; v < vecs && !enters; v++) {
            const uint32_t ray_lanes = left >> (v * BVH_W) & BVH_LANES_ALL;
            if (!ray_lanes) continue;
            const bvh_packet *r = &g->rays[f][v].r;
            vf entry;
            ++*aabb;
            enters = vm_bits(bvh_packet_box(c, r, r->tfar, vm_of_bits(ray_lanes), &entry)) & BVH_LANES_ALL;
        }
        drop |= (uint32_t)(enters == 0) << f;
    }
    return lanes & ~drop;
}

static void trace_group(const bvh_tree *tree, sf_group *g, uint32_t frusta, const bvh_shadow_sets *sets, float eps,
                        bvh_counters *counters)
{
    mft_entry stack[BVH_TRAVERSAL_STACK];
    const uint32_t vecs = (sets->samples + BVH_W - 1u) / BVH_W;
    uint32_t top = 0, alive = frusta;
    const vf dist = vf_set1(1.0f);
    stack[top++] = (mft_entry){&tree->root, frusta | (mft_holds_ends(&tree->root, &g->b) ? MFT_HOLDS_ENDS : 0u),
                               MFT_UNTESTED};
    uint64_t aabb = 0;
    const bvh_child *c;
    uint32_t lanes;
    while (alive && (c = mft_next_leaf(tree, &g->b, dist, 0, alive, stack, &top, &aabb, &lanes))) {
        uint32_t newly = 0; /* frusta with a sample newly occluded in this leaf */
        lanes = leaf_rays(c, g, lanes, vecs, &aabb);
        for (uint32_t i = 0; lanes && i < c->count; i++) {
            const uint32_t rec = c->index + i;
            if (counters) counters->triangles += (uint64_t)__builtin_popcount(lanes);
            frusta_tri t;
            frusta_edges(&tree->corners[rec], &g->b, &t);
            uint32_t facing, backing;
            frusta_orientation(&t, &facing, &backing);
            uint32_t survive = frusta_triangle_cone(&t, g->corner, g->corner_max, g->corner_l1, g->corner_grow,
                                                    vm_of_bits(lanes), facing, backing);
            const uint32_t in_plane = survive & ~(facing | backing); /* what the edge test cannot cull */
            if (in_plane) survive &= ~beside_plane(&t, g, eps, in_plane);
            uint32_t done = 0;
            for (survive &= BVH_LANES_ALL; survive; survive &= survive - 1u) {
                const uint32_t f = (uint32_t)__builtin_ctz(survive);
                if (counters) counters->isect_tests++;
                const uint32_t before = g->occ[f];
                const uint32_t over = frustum_rays(tree, rec, g, f, sets, eps); /* the frustum terminates */
                done |= over << f;
                newly |= (uint32_t)(!over && g->occ[f] != before) << f;
            }
            alive &= ~done, lanes &= ~done;
        }
        if ((newly &= alive)) shrink_corners(g, newly, sets);
    }
    if (counters) counters->aabb_tests += aabb;
}

/* Every lane's frustum at once (lane f: point first + f, the lanes from n
 * on dead: origin 0, directions and corners 1, grow 0): the point, the
 * vectors to the corners of its set's 2D bounds (corner_vectors'
 * arithmetic) and their box grown by 2^-16 of the magnitudes involved (see
 * the top) into g->b and g->corner, the grow into g->corner_grow and
 * the points' light frames into g->base, du, dv (for shrinking).
 * The points' fields are gathered into lanes: made per frustum in scalars,
 * written a lane at a time and loaded whole, they waited for the store
 * buffer (bench/results/bvh-mft.md, tenth session: czest3ctf's frusta:16
 * 100 -> 119 Mrays/s, oa_dm4's 204 -> 324 with the traversal's epochs). */
#define SF_POINT_WORDS (sizeof(bvh_shadow_point) / sizeof(float))
_Static_assert(sizeof(bvh_shadow_point) % sizeof(float) == 0, "a shadow point is whole words");
_Static_assert(SF_FRUSTA <= 16, "sf_lane_words has a word offset for 16 lanes");
static const uint32_t sf_lane_words[16] = {
    0 * SF_POINT_WORDS,  1 * SF_POINT_WORDS,  2 * SF_POINT_WORDS,  3 * SF_POINT_WORDS,
    4 * SF_POINT_WORDS,  5 * SF_POINT_WORDS,  6 * SF_POINT_WORDS,  7 * SF_POINT_WORDS,
    8 * SF_POINT_WORDS,  9 * SF_POINT_WORDS,  10 * SF_POINT_WORDS, 11 * SF_POINT_WORDS,
    12 * SF_POINT_WORDS, 13 * SF_POINT_WORDS, 14 * SF_POINT_WORDS, 15 * SF_POINT_WORDS};

static void group_bounds(sf_group *g, const bvh_shadow_point *points, uint32_t n, const bvh_shadow_sets *sets)
{
    const float *words = (const float *)points;
    /* lanes past n read point n - 1 (valid memory) and are blended dead below */
    const vi index = vi_min_s(vi_load(sf_lane_words), vi_set1((n - 1u) * (uint32_t)SF_POINT_WORDS));
    const uint32_t live = (1u << n) - 1u;
    const vm dead = vm_of_bits(BVH_LANES_ALL & ~live);
    const size_t word = sizeof(float), at_org = offsetof(bvh_shadow_point, org) / word;
    const size_t at_base = offsetof(bvh_shadow_point, base) / word, at_du = offsetof(bvh_shadow_point, du) / word;
    const size_t at_dv = offsetof(bvh_shadow_point, dv) / word, at_set = offsetof(bvh_shadow_point, set) / word;
    const vf zero = vf_set1(0.0f), one = vf_set1(1.0f);
    vf org[3], base[3], du[3], dv[3], size = zero;
    for (int k = 0; k < 3; k++) {
        org[k] = vf_gather(words + at_org + k, index), base[k] = vf_gather(words + at_base + k, index);
        du[k] = vf_gather(words + at_du + k, index), dv[k] = vf_gather(words + at_dv + k, index);
        const vf m = vf_add(vf_add(vf_add(vf_abs(base[k]), vf_abs(du[k])), vf_abs(dv[k])), vf_abs(org[k]));
        size = vf_max(m, size);
    }
    const vi set = vf_as_vi(vf_gather(words + at_set, index)), pair = vi_add(set, set); /* lo[set], hi[set] */
    const vf lo[2] = {vf_gather(&sets->lo[0][0], pair), vf_gather(&sets->lo[0][1], pair)};
    const vf hi[2] = {vf_gather(&sets->hi[0][0], pair), vf_gather(&sets->hi[0][1], pair)};
    vf dlo[3], dhi[3];
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 3; k++) g->corner[c][k] = one; /* the dead lanes' */
    corner_vectors(org, base, du, dv, lo[0], hi[0], lo[1], hi[1], vm_of_bits(live), g->corner);
    for (int k = 0; k < 3; k++) {
        corner_range(g->corner, k, &dlo[k], &dhi[k]);
        size = vf_max(vf_max(vf_abs(dlo[k]), vf_abs(dhi[k])), size); /* the largest |corner component| */
    }
    const vf grow = vf_blend(dead, vf_mul(size, vf_set1(0x1p-16f)), zero);
    for (int k = 0; k < 3; k++) {
        g->b.org[k] = vf_blend(dead, org[k], zero);
        g->b.dlo[k] = vf_blend(dead, vf_sub(dlo[k], grow), one);
        g->b.dhi[k] = vf_blend(dead, vf_add(dhi[k], grow), one);
        g->b.rlo[k] = vf_div(one, g->b.dlo[k]), g->b.rhi[k] = vf_div(one, g->b.dhi[k]);
        g->base[k] = base[k], g->du[k] = du[k], g->dv[k] = dv[k];
    }
    g->corner_grow = grow;
}

/* The frusta's ends box (mft_bounds.ends_lo, hi): the points org +
 * corner of the n live frusta (t = 1 = dist on the light), each sum's
 * rounding covered by growing the box by 2^-22 of its largest coordinate
 * (a sum is off by at most 2^-24 of itself). */
static void group_ends(sf_group *g, uint32_t n)
{
    const vm dead = vm_of_bits(BVH_LANES_ALL & ~(uint32_t)((1ull << n) - 1u));
    const vf inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    float size = 0.0f;
    for (int k = 0; k < 3; k++) {
        vf lo, hi; /* org + c is monotone in c, rounding and all: its extremes are org plus the corners' */
        corner_range(g->corner, k, &lo, &hi);
        g->b.ends_lo[k] = vf_hmin(vf_blend(dead, vf_add(g->b.org[k], lo), inf));
        g->b.ends_hi[k] = vf_hmax(vf_blend(dead, vf_add(g->b.org[k], hi), minus_inf));
        const float a = fabsf(g->b.ends_lo[k]), b = fabsf(g->b.ends_hi[k]);
        size = a > size ? a : size, size = b > size ? b : size;
    }
    const float grow = size * 0x1p-22f;
    for (int k = 0; k < 3; k++) g->b.ends_lo[k] -= grow, g->b.ends_hi[k] += grow;
    g->b.ends_known = isfinite(size);
}

/* The points of the group from `first` on (if any) asked for from memory:
 * the points are a stream read once (a 1024^2 frame's are 52 MB), and
 * group_bounds's gathers waited on them (2.7% of armadillo's frusta:16 in
 * perf, their first gather's line).  Issued a group ahead, while the group
 * before is traced: czest3ctf +6%, ctf_inyard +21%, oa_dm4 +23%, armadillo
 * 0 to +3% (bench/results/bvh-mft.md, seventeenth session). */
static inline void prefetch_points(const bvh_shadow_query *q, size_t first)
{
    if (first >= q->count) return;
    const size_t n = q->count - first < SF_FRUSTA ? q->count - first : SF_FRUSTA;
    const char *from = (const char *)&q->points[first], *end = (const char *)&q->points[first + n];
    for (const char *line = from; line < end; line += 64) __builtin_prefetch(line);
    __builtin_prefetch(end - 1); /* the last line, when `from` is not at a line's start */
}

void bvh_shadow_frusta(const bvh_tree *tree, const bvh_shadow_query *q)
{
    const bvh_shadow_sets *sets = q->sets;
    for (size_t first = 0; first < q->count; first += SF_FRUSTA) {
        const uint32_t n = q->count - first < SF_FRUSTA ? (uint32_t)(q->count - first) : SF_FRUSTA;
        sf_group g;
        g.known = 0;
        for (uint32_t f = 0; f < SF_FRUSTA; f++) {
            g.occ[f] = g.live[f] = 0;
            g.point[f] = f < n ? &q->points[first + f] : NULL;
        }
        group_bounds(&g, &q->points[first], n, sets);
        prefetch_points(q, first + SF_FRUSTA);
        corner_sizes(&g);
        g.b.tnear = vf_set1(0.0f);
        g.b.grow = vf_set1(0.0f);
        mft_bounds_classify(&g.b);
        group_ends(&g, n);
        if (q->counters) q->counters->packets += n;
        const uint32_t frusta = (uint32_t)((1ull << n) - 1u);
        if (tree->triangle_count > 0 && sets->samples > 0) trace_group(tree, &g, frusta, sets, q->epsilon, q->counters);
        for (uint32_t f = 0; f < n; f++) q->occluded[first + f] = g.occ[f] & g.live[f];
    }
}

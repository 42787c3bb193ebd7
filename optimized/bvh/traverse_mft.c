/* Benthin & Wald 2009, 4.1-4.3: multi-frusta tracing.  BVH_W frusta of 16
 * rays each (16 on AVX-512: 256 rays, a 16x16-pixel block of 4x4 frusta;
 * 8 on AVX2; 4 on SSE4.1) walk the BVH together, one frustum per SIMD lane:
 *
 *  - per node ONE pass tests both children's boxes against every frustum's
 *    interval bounds (open-ended: no far plane; the entry must not exceed
 *    the largest closest-hit distance of the frustum's rays).  A frustum is
 *    its common origin and the box [dlo, dhi] of its rays' directions; per
 *    axis the slab's entry and exit over every direction of the box are
 *    taken from the reciprocal bounds when the interval keeps one sign, and
 *    when it contains zero (the paper's "zero fix") from the side of the
 *    slab the origin lies on: only directions pointing at the slab can
 *    enter it, at the entry of the steepest one, and nothing bounds the exit;
 *  - the active-frusta mask travels on the stack with the subtree;
 *  - at a leaf, per triangle and for all active frusta at once, the
 *    common-origin Pluecker test: the three edge planes through the origin
 *    (cross products of the origin-relative corners, computed once per
 *    triangle for every frustum) bound n.d over the direction box, and the
 *    triangle's orientation as the origin sees it (the back-face test's
 *    determinant) says which sign they need; a frustum all of whose
 *    directions fall outside one edge is culled.  Then, only for the
 *    survivors (bitscan), the 16-ray triangle test the tree names
 *    (bvh_isect_wide.h: projected or watertight, the watertight shears made
 *    once per packet when the group is loaded) on that frustum's rays;
 *  - frusta are terminated one by one: an occlusion frustum leaves when all
 *    its rays are occluded; a closest-hit frustum's bound shrinks to its
 *    rays' farthest closest hit after every leaf that lowered one.
 *
 * Two entries: bvh_kernel_mft takes any ray stream (engine, conformance,
 * the renderer's anti-aliased samples), loading each frustum's rays;
 * bvh_kernel_mft_camera (the renderer at one sample per pixel, the bench's
 * primary rows) makes primary rays itself from the camera frame's start and
 * delta vectors, the paper's way, never storing them (bottom of the file).
 * A camera frustum whose corner box misses the tree's root box (the
 * traversal's own first test) makes no rays at all; making them only at a
 * frustum's first triangle test was tried and was slower on the maps
 * (bench/results/bvh-mft/s14-lazy-rays-ab.txt).
 * The leaf culling of the camera path is the paper's corner-ray test: the
 * edge planes against the four corner vectors of each 4x4 pixel block,
 * whose cone holds every ray of the block (frusta_pinhole_cull).  What
 * it departs from and why: the stream kernel culls over the direction box
 * instead (exact for any rays sharing an origin; corner rays are exact only
 * for pinhole grids), as does a camera frustum with a ray rtt_camera_ray had
 * to make the slow way (a length outside the fast range).  A group of 16 whose rays do
 * not share one origin is traced by the packet walk instead (bvh_traverse.h).
 * Back-face culling only where the surface allows it: rtt's triangles are
 * two-sided, so elsewhere the orientation only picks the sign the edge
 * tests need; on the camera path the back faces of the solids the eye is
 * outside (../solids.h, bvh_tree.solid) are skipped for every frustum at
 * once, the paper's culling (see mft_group.cull).  Bounds get a relative
 * slack of 2^-20 so that rounding never culls a ray's hit. */
#include <math.h>
#include <string.h>

#include "bvh_frusta.h"
#include "bvh_isect_wide.h"
#include "bvh_traverse.h"
#include "rtt/shade.h"

#define MFT_RAYS 16u                 /* rays per frustum */
#define MFT_VECS (MFT_RAYS / BVH_W)  /* packets per frustum: 1, 2 or 4 */
#define MFT_FRUSTA BVH_W             /* frusta per group: one per lane */

typedef struct mft_group {
    mft_bounds b;                    /* per frustum: origin, direction box, smallest tnear */
    float dist[MFT_FRUSTA];          /* largest min(tfar, closest hit) of its rays */
    bvh_packet rays[MFT_FRUSTA][MFT_VECS];
    uint32_t live[MFT_FRUSTA][MFT_VECS];
    bvh_hits hits[MFT_FRUSTA][MFT_VECS];
    uint32_t occ[MFT_FRUSTA][MFT_VECS];
    bvh_wt_shears shears[MFT_FRUSTA][MFT_VECS]; /* the watertight test's, per packet */
    const bvh_wt_shears *wt[MFT_FRUSTA][MFT_VECS]; /* NULL for the projected test */
    uint32_t unset;                  /* frusta whose wt (and shears) are not made yet: at their first triangle test */
    uint32_t apex;                   /* frusta whose origin is the rays' common end point (hard shadows) */
    uint32_t pinhole;                /* frusta culled over the cone of their corner vectors (camera-made) */
    vf apex_reach;                   /* apex frusta: the largest |component| of their directions */
    mft_cone cone;                   /* those frusta's corner vectors (bvh_frusta.h) */
    /* The camera path's back-face culling (bvh_tree.solid): every ray
     * starts at the eye (t from 0), so a triangle of a solid whose box the
     * eye lies outside, seen from behind, is never a ray's first hit on
     * that solid (an entering face comes first, or ties with it at a
     * silhouette edge) and is skipped for every frustum at once. */
    bool cull;
    float eye[3];
    int32_t solid_seen;              /* the last solid looked at (-1: none yet) and whether the eye is outside its box */
    bool solid_outside;
} mft_group;

/* The side a triangle of solid s (tree->solid[rec] != 0) is culled from:
 * its sign when the eye is outside the solid's box (the frusta that see it
 * from that side drop it: frusta_pinhole_cull), else 0. */
static inline int solid_cull_sign(const bvh_tree *tree, mft_group *g, int32_t s)
{
    const int32_t k = (s > 0 ? s : -s) - 1;
    if (k != g->solid_seen) {
        const float *box = tree->solid_box[k];
        g->solid_seen = k;
        g->solid_outside = g->eye[0] < box[0] || g->eye[1] < box[1] || g->eye[2] < box[2] || g->eye[0] > box[3] ||
                           g->eye[1] > box[4] || g->eye[2] > box[5];
    }
    return g->solid_outside ? (s > 0 ? 1 : -1) : 0;
}

/* The leaf test of apex frusta, whose rays do not start at the frustum's
 * origin: the frusta of `active` whose bounds reach the box of the
 * triangle's corners, and then the common-origin edge test from the apex
 * with the rays' distance from the apex line in its margin.  A ray's point
 * p on the triangle is apex + s d + e, d in the direction box, |e| <= 2
 * grow per axis (the rounding apex_frustum's `grow` bounds, twice over: of
 * d and of the ray's own points); p - apex lies in the triangle's cone from
 * the apex whatever e is, so the edge test holds for the vector s d + e.
 * With R the box's distance from the apex (max norm), s >= (R - 2 grow) /
 * reach, and culling s d + e needs n.d clear of zero by |n|_1 2 grow reach
 * / (R - 2 grow): the slack.  A triangle within 2 grow of the apex keeps
 * the box's answer. */
static inline uint32_t frusta_triangle_apex(const bvh_corners *tri, const mft_bounds *b, vf reach, vf dist, vm active)
{
    bvh_child box = {{tri->v[0][0], tri->v[0][1], tri->v[0][2]}, 0, {tri->v[0][0], tri->v[0][1], tri->v[0][2]}, 0};
    for (int v = 1; v < 3; v++)
        for (int k = 0; k < 3; k++) {
            box.lo[k] = tri->v[v][k] < box.lo[k] ? tri->v[v][k] : box.lo[k];
            box.hi[k] = tri->v[v][k] > box.hi[k] ? tri->v[v][k] : box.hi[k];
        }
    vf entry;
    const uint32_t reached = vm_bits(frusta_box(&box, b, dist, active, &entry));
    if (!reached) return 0;
    const vf zero = vf_set1(0.0f), two_grow = vf_add(b->grow, b->grow);
    vf gap = zero; /* R: the box's distance from the apex, max norm */
    for (int k = 0; k < 3; k++) {
        const vf below = vf_sub(vf_set1(box.lo[k]), b->org[k]), above = vf_sub(b->org[k], vf_set1(box.hi[k]));
        gap = vf_max(gap, vf_max(below, above));
    }
    const vf clear = vf_sub(gap, two_grow);
    const vm far = vf_gt(clear, zero);
    const vf slack = vf_blend(far, vf_set1(INFINITY), vf_div(vf_mul(two_grow, reach), clear));
    const uint32_t near_lanes = reached & ~vm_bits(far);
    return near_lanes | frusta_triangle_bounded(tri, b, slack, vm_of_bits(reached & vm_bits(far)));
}

static float frustum_dist(const mft_group *g, uint32_t f, bool closest)
{
    const vf minus_inf = vf_set1(-INFINITY);
    vf far = minus_inf;
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const vf d = closest ? vf_min(g->hits[f][v].t, g->rays[f][v].tfar) : g->rays[f][v].tfar;
        far = vf_max(vf_blend(vm_of_bits(g->live[f][v]), minus_inf, d), far);
    }
    return vf_hmax(far);
}

static void trace_frusta(const bvh_tree *tree, mft_group *g, uint32_t frusta, bool closest, bvh_counters *counters)
{
    mft_entry stack[BVH_TRAVERSAL_STACK];
    uint32_t top = 0, alive = frusta, epoch = 0; /* epoch: how often dist has been lowered */
    vf dist = vf_load(g->dist);
    stack[top++] = (mft_entry){&tree->root, frusta, MFT_UNTESTED};
    uint64_t aabb = 0;
    const bvh_child *c;
    uint32_t lanes;
    while (alive && (c = mft_next_leaf(tree, &g->b, dist, epoch, alive, stack, &top, &aabb, &lanes))) {
        uint32_t lowered = 0;
        frusta_pinhole_tris pinhole; /* the set-up of triangles i - i % FRUSTA_QUADS on */
        for (uint32_t i = 0; i < c->count && lanes; i++) {
            const uint32_t rec = c->index + i;
            const int32_t s = g->cull ? tree->solid[rec] : 0;
            const int cull = s ? solid_cull_sign(tree, g, s) : 0;
            if (counters) counters->triangles += (uint64_t)__builtin_popcount(lanes);
            const uint32_t boxed = lanes & ~(g->apex | g->pinhole);
            uint32_t survive = boxed ? frusta_triangle(&tree->corners[rec], &g->b, vm_of_bits(boxed)) : 0;
            if (lanes & g->pinhole) { /* (lanes only lose frusta: a set-up's first triangle had some) */
                const uint32_t quad = i % FRUSTA_QUADS;
                if (quad == 0) frusta_pinhole_setup(&tree->corners[rec], c->count - i, &g->cone, &pinhole);
                survive |= frusta_pinhole_cull(&pinhole, quad, &g->cone, cull, lanes & g->pinhole);
            }
            if (lanes & g->apex)
                survive |= frusta_triangle_apex(&tree->corners[rec], &g->b, g->apex_reach, dist, vm_of_bits(lanes & g->apex));
            while (survive) {
                const uint32_t f = (uint32_t)__builtin_ctz(survive);
                survive &= survive - 1u;
                if (counters) counters->isect_tests++;
                if (g->unset >> f & 1u) { /* a frustum that tests no triangle never divides for its shears */
                    g->unset &= ~(1u << f);
                    for (uint32_t v = 0; v < MFT_VECS; v++)
                        g->wt[f][v] = bvh_record_setup(tree, &g->rays[f][v], g->live[f][v], &g->shears[f][v]);
                }
                for (uint32_t v = 0; v < MFT_VECS; v++) {
                    const uint32_t ray_lanes = g->live[f][v] & ~g->occ[f][v];
                    if (!ray_lanes) continue;
                    if (closest) {
                        if (bvh_isect_record(tree, rec, &g->rays[f][v], g->wt[f][v], &g->hits[f][v], ray_lanes))
                            lowered |= 1u << f;
                    } else {
                        g->occ[f][v] |= bvh_occluded_record(tree, rec, &g->rays[f][v], g->wt[f][v], ray_lanes);
                    }
                }
                if (!closest) {
                    bool done = true;
                    for (uint32_t v = 0; v < MFT_VECS; v++) done &= (g->live[f][v] & ~g->occ[f][v]) == 0;
                    if (done) alive &= ~(1u << f), lanes &= ~(1u << f); /* the frustum terminates */
                }
            }
        }
        if (lowered) {
            while (lowered) {
                const uint32_t f = (uint32_t)__builtin_ctz(lowered);
                lowered &= lowered - 1u;
                g->dist[f] = frustum_dist(g, f, true);
            }
            dist = vf_load(g->dist);
            epoch++;
        }
    }
    if (counters) counters->aabb_tests += aabb;
}

/* Frustum f's bounds from its packets (g->rays, g->live): true when its
 * live rays share one origin (a frustum), false when they need the packet
 * walk.  Per packet: the first live ray's origin against every live lane's,
 * and the live lanes' smallest and largest direction components and tnear. */
static bool frustum_bounds(const mft_group *g, uint32_t f, float org[3][MFT_FRUSTA], float dlo[3][MFT_FRUSTA],
                           float dhi[3][MFT_FRUSTA], float *tnear)
{
    bool common = true, any = false;
    const vf inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const uint32_t live = g->live[f][v];
        if (!live) continue;
        const bvh_packet *p = &g->rays[f][v];
        const vm m = vm_of_bits(live);
        if (!any) {
            float lane[BVH_W];
            const uint32_t l = (uint32_t)__builtin_ctz(live);
            for (int k = 0; k < 3; k++) {
                vf_store(lane, p->org[k]);
                org[k][f] = lane[l];
                vf_store(lane, p->dir[k]);
                dlo[k][f] = dhi[k][f] = lane[l];
            }
            vf_store(lane, p->tnear);
            *tnear = lane[l];
            any = true;
        }
        for (int k = 0; k < 3; k++) {
            common &= (vm_bits(vf_eq(p->org[k], vf_set1(org[k][f]))) & live) == live;
            const float lo = vf_hmin(vf_blend(m, inf, p->dir[k])), hi = vf_hmax(vf_blend(m, minus_inf, p->dir[k]));
            dlo[k][f] = lo < dlo[k][f] ? lo : dlo[k][f];
            dhi[k][f] = hi > dhi[k][f] ? hi : dhi[k][f];
        }
        const float t = vf_hmin(vf_blend(m, inf, p->tnear));
        *tnear = t < *tnear ? t : *tnear;
    }
    if (!any)
        for (int k = 0; k < 3; k++) org[k][f] = 0.0f, dlo[k][f] = dhi[k][f] = 1.0f;
    return common;
}

/* Loads frustum f of the group from rays[0 .. count-1]; frustum_bounds'
 * answer. */
static bool load_frustum(mft_group *g, uint32_t f, const rtt_ray *rays, size_t count, float org[3][MFT_FRUSTA],
                         float dlo[3][MFT_FRUSTA], float dhi[3][MFT_FRUSTA], float *tnear)
{
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const size_t first = (size_t)v * BVH_W, n = count > first ? (count - first < BVH_W ? count - first : BVH_W) : 0;
        g->live[f][v] = n ? bvh_packet_load_rays(&g->rays[f][v], rays + first, n) : 0; /* no reciprocals: frusta */
        g->occ[f][v] = 0;
        bvh_hits_clear(&g->hits[f][v]);
    }
    return frustum_bounds(g, f, org, dlo, dhi, tnear);
}

/* Frustum f as seen from `apex`, the point every one of its rays heads to
 * (a point light, bvh_query.toward): origin the apex, directions the
 * vectors d = ray origin - apex (not unit), t from 0 to 1, so each ray's
 * segment lies on apex + t d, t in [0, 1], up to rounding: the ray's
 * direction is the rounded unit vector towards the apex and d is rounded,
 * which moves its points off that line by a few ulps of the distances and
 * coordinates involved.  The frustum is tested with boxes grown by 2^-16 of
 * those magnitudes (bvh_frusta.h, `grow`), far more than the rounding. */
static void apex_frustum(mft_group *g, uint32_t f, const float apex[3], float org[3][MFT_FRUSTA],
                         float dlo[3][MFT_FRUSTA], float dhi[3][MFT_FRUSTA], float *tnear, float grow[MFT_FRUSTA])
{
    bool any = false;
    float size = 0.0f;
    for (int k = 0; k < 3; k++) {
        org[k][f] = apex[k];
        size = fabsf(apex[k]) > size ? fabsf(apex[k]) : size;
    }
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        float o[3][BVH_W];
        for (int k = 0; k < 3; k++) vf_store(o[k], g->rays[f][v].org[k]);
        for (uint32_t l = 0; l < BVH_W; l++) {
            if (!(g->live[f][v] >> l & 1u)) continue;
            for (int k = 0; k < 3; k++) {
                const float d = o[k][l] - apex[k];
                dlo[k][f] = !any || d < dlo[k][f] ? d : dlo[k][f];
                dhi[k][f] = !any || d > dhi[k][f] ? d : dhi[k][f];
                size = fabsf(o[k][l]) > size ? fabsf(o[k][l]) : size;
                size = fabsf(d) > size ? fabsf(d) : size;
            }
            any = true;
        }
    }
    *tnear = 0.0f;
    grow[f] = size * 0x1p-16f;
    g->apex |= 1u << f;
}

/* The group's frusta (their bounds org .. grow, a lane a frustum) through the tree. */
static void trace_group_bounds(const bvh_tree *tree, mft_group *g, uint32_t frusta, const vf org[3], const vf dlo[3],
                               const vf dhi[3], vf tnear, vf grow, bool closest, bvh_counters *counters)
{
    const vf one = vf_set1(1.0f);
    vf reach = vf_set1(0.0f);
    for (int k = 0; k < 3; k++) {
        g->b.org[k] = org[k];
        g->b.dlo[k] = dlo[k], g->b.dhi[k] = dhi[k];
        g->b.rlo[k] = vf_div(one, g->b.dlo[k]), g->b.rhi[k] = vf_div(one, g->b.dhi[k]);
        reach = vf_max(reach, vf_max(vf_abs(g->b.dlo[k]), vf_abs(g->b.dhi[k])));
    }
    g->b.tnear = tnear;
    g->b.grow = grow;
    mft_bounds_classify(&g->b);
    g->apex_reach = reach;
    for (uint32_t f = 0; f < MFT_FRUSTA; f++)
        g->dist[f] = !(frusta >> f & 1u) ? -INFINITY : g->apex >> f & 1u ? 1.0f : frustum_dist(g, f, false);
    if (frusta) trace_frusta(tree, g, frusta, closest, counters);
}

/* The same from per-frustum arrays. */
static void trace_group(const bvh_tree *tree, mft_group *g, uint32_t frusta, float org[3][MFT_FRUSTA],
                        float dlo[3][MFT_FRUSTA], float dhi[3][MFT_FRUSTA], const float *tnear, const float *grow,
                        bool closest, bvh_counters *counters)
{
    const vf o[3] = {vf_load(org[0]), vf_load(org[1]), vf_load(org[2])};
    const vf lo[3] = {vf_load(dlo[0]), vf_load(dlo[1]), vf_load(dlo[2])};
    const vf hi[3] = {vf_load(dhi[0]), vf_load(dhi[1]), vf_load(dhi[2])};
    trace_group_bounds(tree, g, frusta, o, lo, hi, vf_load(tnear), vf_load(grow), closest, counters);
}

void bvh_kernel_mft(const bvh_tree *tree, const bvh_query *q)
{
    const bool closest = q->hits != NULL;
    const size_t group_rays = (size_t)MFT_FRUSTA * MFT_RAYS;
    mft_group g;
    for (size_t first = 0; first < q->count; first += group_rays) {
        float org[3][MFT_FRUSTA], dlo[3][MFT_FRUSTA], dhi[3][MFT_FRUSTA];
        float tnear[MFT_FRUSTA], grow[MFT_FRUSTA] = {0};
        uint32_t frusta = 0;
        g.apex = g.pinhole = g.unset = 0;
        g.cull = false;
        for (uint32_t f = 0; f < MFT_FRUSTA; f++) {
            const size_t at = first + (size_t)f * MFT_RAYS;
            const size_t n = at < q->count ? (q->count - at < MFT_RAYS ? q->count - at : MFT_RAYS) : 0;
            tnear[f] = INFINITY;
            const bool common = load_frustum(&g, f, q->rays + at, n, org, dlo, dhi, &tnear[f]);
            uint32_t live = 0;
            for (uint32_t v = 0; v < MFT_VECS; v++) live |= g.live[f][v];
            if (q->counters) q->counters->packets++;
            if (!live || tree->triangle_count == 0) continue;
            if (common) {
                g.unset |= 1u << f;
                frusta |= 1u << f;
                continue;
            }
            if (!closest && q->toward) { /* rays to one point: a frustum from that point back to their origins */
                apex_frustum(&g, f, q->toward, org, dlo, dhi, &tnear[f], grow);
                g.unset |= 1u << f;
                frusta |= 1u << f;
                continue;
            }
            for (uint32_t v = 0; v < MFT_VECS; v++) /* no common origin: the packet walk, which wants the reciprocals */
                if (g.live[f][v]) {
                    bvh_packet_reciprocals(&g.rays[f][v]);
                    bvh_trace_packet(tree, &g.rays[f][v], g.live[f][v], closest ? &g.hits[f][v] : NULL,
                                     &g.occ[f][v], q->counters);
                }
        }
        trace_group(tree, &g, frusta, org, dlo, dhi, tnear, grow, closest, q->counters);
        for (uint32_t f = 0; f < MFT_FRUSTA; f++)
            for (uint32_t v = 0; v < MFT_VECS; v++) {
                const size_t at = first + (size_t)f * MFT_RAYS + (size_t)v * BVH_W;
                if (at >= q->count) continue;
                const size_t n = q->count - at < BVH_W ? q->count - at : BVH_W;
                if (closest)
                    bvh_hits_store(&g.hits[f][v], &q->hits[at], n);
                else
                    for (size_t l = 0; l < n; l++) q->occluded[at + l] = (g.occ[f][v] >> l) & 1u;
            }
    }
}

/* ---- primary rays made from the camera frame (bvh_camera_block) ----
 *
 * Frustum f of a group is 4x4 pixels, its packet v the rows v * BVH_W / 4
 * onwards; a group is GROUP_FX x GROUP_FY frusta (16 x 16 pixels on
 * AVX-512, 16 x 8 on AVX2, 8 x 8 on SSE4.1).  A lane's direction is
 * rtt_camera_ray's, computed in the same order with the same IEEE
 * operations (contraction is off), so the same bits: d = corner + (du (x +
 * 1/2) + dv (y + 1/2)), scaled by 1 / sqrt(d.d); a lane whose length falls
 * outside rtt_v3_normalize's fast range takes rtt_camera_ray itself. */
#define GROUP_FX (MFT_FRUSTA >= 8u ? 4u : 2u)
#define GROUP_FY (MFT_FRUSTA / GROUP_FX)
#define VEC_ROWS (BVH_W / 4u)

static bool camera_frustum(mft_group *g, uint32_t f, const bvh_camera_block *b, uint32_t fx, uint32_t fy)
{
    bool exact = true; /* every live lane's direction made the fast way (a positive multiple of d) */
    _Alignas(64) float col[BVH_W], row[BVH_W];
    for (uint32_t l = 0; l < BVH_W; l++) col[l] = (float)(l % 4u), row[l] = (float)(l / 4u);
    const vf lane_x = vf_load(col), lane_y = vf_load(row), zero = vf_set1(0.0f), one = vf_set1(1.0f);
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const uint32_t y = fy + v * VEC_ROWS;
        bvh_packet *p = &g->rays[f][v];
        /* pixel centres: small integers plus one half, exact in float; a
         * lane is on the block when its centre is below x1 and y1 */
        const vf px = vf_add(vf_set1((float)fx + 0.5f), lane_x), py = vf_add(vf_set1((float)y + 0.5f), lane_y);
        const uint32_t live = vm_bits(vm_and(vf_lt(px, vf_set1((float)b->x1)), vf_lt(py, vf_set1((float)b->y1))));
        vf d[3];
        for (int k = 0; k < 3; k++)
            d[k] = vf_add(vf_set1(b->corner[k]),
                          vf_add(vf_mul(vf_set1(b->du[k]), px), vf_mul(vf_set1(b->dv[k]), py)));
        const vf len = vf_sqrt(vf_add(vf_add(vf_mul(d[0], d[0]), vf_mul(d[1], d[1])), vf_mul(d[2], d[2])));
        const vf inv = vf_div(one, len);
        const uint32_t fast = vm_bits(vm_and(vf_gt(len, vf_set1(1e-18f)), vf_lt(len, vf_set1(1e18f))));
        _Alignas(64) float dir[3][BVH_W];
        for (int k = 0; k < 3; k++) vf_store(dir[k], vf_mul(d[k], inv));
        exact &= (live & ~fast) == 0;
        for (uint32_t slow = live & ~fast; slow; slow &= slow - 1u) {
            const uint32_t l = (uint32_t)__builtin_ctz(slow);
            const rtt_camera_frame frame = {{b->eye[0], b->eye[1], b->eye[2]},
                                            {b->corner[0], b->corner[1], b->corner[2]},
                                            {b->du[0], b->du[1], b->du[2]},
                                            {b->dv[0], b->dv[1], b->dv[2]}};
            const rtt_ray r = rtt_camera_ray(&frame, fx + l % 4u, y + l / 4u);
            for (int k = 0; k < 3; k++) dir[k][l] = r.dir[k];
        }
        /* bvh_packet_load's rule: a lane whose origin or direction is not finite is inactive */
        vm ok = vm_of_bits(live);
        for (int k = 0; k < 3; k++) {
            p->org[k] = vf_set1(b->eye[k]);
            p->dir[k] = vf_load(dir[k]);
            ok = vm_and(ok, vm_and(vf_eq(vf_sub(p->org[k], p->org[k]), zero), vf_eq(vf_sub(p->dir[k], p->dir[k]), zero)));
        }
        for (int k = 0; k < 3; k++) { /* no reciprocals: only the packet walk reads them */
            p->org[k] = vf_blend(ok, zero, p->org[k]);
            p->dir[k] = vf_blend(ok, one, p->dir[k]);
        }
        p->tnear = vf_blend(ok, vf_set1(INFINITY), zero);
        p->tfar = vf_blend(ok, vf_set1(-INFINITY), vf_set1(INFINITY));
        g->live[f][v] = vm_bits(ok);
        g->occ[f][v] = 0;
        bvh_hits_clear(&g->hits[f][v]);
    }
    return exact;
}

/* The direction box of a frustum camera_frustum made with some live ray
 * (its origin is the eye and its rays start at t = 0, as for a cornered
 * one): the live lanes' smallest and largest components, kept across its
 * packets lane by lane and reduced once per axis. */
static void camera_bounds(const mft_group *g, uint32_t f, float dlo[3][MFT_FRUSTA], float dhi[3][MFT_FRUSTA])
{
    const vf inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    vf lo[3] = {inf, inf, inf}, hi[3] = {minus_inf, minus_inf, minus_inf};
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const vm m = vm_of_bits(g->live[f][v]);
        for (int k = 0; k < 3; k++) {
            lo[k] = vf_min(lo[k], vf_blend(m, inf, g->rays[f][v].dir[k]));
            hi[k] = vf_max(hi[k], vf_blend(m, minus_inf, g->rays[f][v].dir[k]));
        }
    }
    for (int k = 0; k < 3; k++) dlo[k][f] = vf_hmin(lo[k]), dhi[k][f] = vf_hmax(hi[k]);
}

/* Every frustum's corner vectors (mft_cone), frustum f's block at
 * (fx[f], fy[f]): d at the centres of its corner pixels (the rays past the
 * image's edge are dead; their cone holds the live ones), and its scale:
 * the rounding of d, of its normalisation and of these corners is a few
 * ulps of the terms' size per axis, bounded by 2^-16 of it.  Returns the
 * frusta whose corners are finite. */
static uint32_t camera_cones(mft_cone *cone, const bvh_camera_block *b, vf fx, vf fy, vf *size_out)
{
    const vf zero = vf_set1(0.0f);
    vf cmax = zero, size = zero;
    cone->l1 = zero;
    for (int c = 0; c < 4; c++) {
        vf l1 = zero;
        const vf px = vf_add(fx, vf_set1(c & 1 ? 3.5f : 0.5f)), py = vf_add(fy, vf_set1(c & 2 ? 3.5f : 0.5f));
        for (int k = 0; k < 3; k++) {
            const vf su = vf_mul(vf_set1(b->du[k]), px), sv = vf_mul(vf_set1(b->dv[k]), py);
            const vf d = vf_add(vf_set1(b->corner[k]), vf_add(su, sv));
            cone->corner[c][k] = d;
            cmax = vf_max(cmax, vf_abs(d));
            l1 = vf_add(l1, vf_abs(d));
            size = vf_max(size, vf_add(vf_add(vf_set1(fabsf(b->corner[k])), vf_abs(su)), vf_abs(sv)));
        }
        cone->l1 = vf_max(cone->l1, l1);
    }
    const vf scale = vf_add(vf_mul(vf_set1(FRUSTA_EPS), cmax), vf_mul(size, vf_set1(0x1p-16f)));
    cone->pixel_scale = vf_add(scale, vf_mul(size, vf_set1(0x1p-19f)));
    cone->cx = vf_add(fx, vf_set1(2.0f)), cone->cy = vf_add(fy, vf_set1(2.0f));
    const vm quad_lane3 = vm_of_bits(BVH_LANES_ALL / 15u * 8u); /* lane 3 of every quad */
    for (int k = 0; k < 3; k++) {
        cone->eye_q[k] = vf_blend(quad_lane3, vf_set1(b->eye[k]), zero);
        cone->frame_q[0][k] = vf_set1(b->corner[k]), cone->frame_q[1][k] = vf_set1(b->du[k]);
        cone->frame_q[2][k] = vf_set1(b->dv[k]);
    }
    *size_out = size;
    return vm_bits(vf_eq(vf_sub(scale, scale), zero));
}

/* Every pinhole frustum's direction box at once (lanes = frusta), from its
 * four corner rays instead of its sixteen: a ray's direction is n = d / |d|
 * with d affine in the pixel, so over the block (corner pixels 3 apart)
 * each n_k is its corners' bilinear interpolant within
 * (9/8) (max |n_k''| along du + along dv), and along any direction u,
 * |n_k''| <= 6 |u|^2 / |d|^2 (differentiating d_k / |d| twice, each of
 * the three terms bounded with |d_k| <= |d|, |d.u| <= |d| |u|).  The least
 * |d| over the block: with c its centre and e = d - c (|e| <= h = 1.5 |du|
 * + 1.5 |dv|), |d|^2 = |c|^2 + 2 c.e + |e|^2 >= |c|^2 + 2 c.e, affine in
 * the pixel, so at least its least value at a corner, where it is that
 * corner's |d|^2 - |e|^2 >= |d|^2 - h^2.  Widened by the rounding the
 * cone's scale (camera_cones) covers (2^-16 of the terms' `size` per axis,
 * over the least length) and 2^-20 of each bound: no smaller than the rays' own box, a
 * little larger (the traversal only culls by it, so every ray still gets
 * its hit).  Returns the frusta it bounded (a positive least length,
 * finite bounds); camera_bounds takes the rest.  *in_range: those of them
 * whose every pixel's |d| lies ten times inside camera_frustum's fast range
 * (1e-18, 1e18): the least length above 1e-17 and the longest corner's
 * below 1e17 (|d| is convex over the block, so a corner is the longest),
 * so every ray would be made the fast way and the box bounds them. */
static uint32_t camera_boxes(const mft_cone *cone, const bvh_camera_block *b, vf size, vf dlo[3], vf dhi[3],
                             uint32_t *in_range)
{
    const vf zero = vf_set1(0.0f), one = vf_set1(1.0f);
    vf shortest_sq = vf_set1(INFINITY), longest_sq = zero, inv[4];
    for (int c = 0; c < 4; c++) {
        vf sq = zero;
        for (int k = 0; k < 3; k++) sq = vf_add(sq, vf_mul(cone->corner[c][k], cone->corner[c][k]));
        shortest_sq = vf_min(shortest_sq, sq);
        longest_sq = vf_max(longest_sq, sq);
        inv[c] = vf_div(one, vf_sqrt(sq));
    }
    float du = 0.0f, dv = 0.0f;
    for (int k = 0; k < 3; k++) du += b->du[k] * b->du[k], dv += b->dv[k] * b->dv[k];
    const float h = 1.5f * (sqrtf(du) + sqrtf(dv)) * (1.0f + 0x1p-20f);
    const vf widen = vf_set1(0x1p-20f), round = vf_mul(size, vf_set1(0x1p-16f));
    const vf shortest = vf_sub(vf_mul(vf_sqrt(vf_max(vf_sub(shortest_sq, vf_set1(h * h)), zero)), vf_sub(one, widen)),
                               vf_add(round, round));
    /* (9/8) 6 (|du|^2 + |dv|^2) / |d|^2, the interpolant's error, and the rounding */
    const vf bend = vf_div(vf_set1(6.75f * (du + dv) * (1.0f + 0x1p-20f)), vf_mul(shortest, shortest));
    const vf slack = vf_add(bend, vf_div(round, shortest));
    for (int k = 0; k < 3; k++) {
        vf lo = vf_mul(cone->corner[0][k], inv[0]), hi = lo;
        for (int c = 1; c < 4; c++) {
            const vf n = vf_mul(cone->corner[c][k], inv[c]);
            lo = vf_min(lo, n), hi = vf_max(hi, n);
        }
        dlo[k] = vf_sub(lo, vf_add(vf_mul(vf_abs(lo), widen), slack));
        dhi[k] = vf_add(hi, vf_add(vf_mul(vf_abs(hi), widen), slack));
    }
    vm ok = vf_gt(shortest, zero);
    for (int k = 0; k < 3; k++)
        ok = vm_and(ok, vm_and(vf_eq(vf_sub(dlo[k], dlo[k]), zero), vf_eq(vf_sub(dhi[k], dhi[k]), zero)));
    *in_range = vm_bits(vm_and(ok, vm_and(vf_gt(shortest, vf_set1(1e-17f)), vf_lt(longest_sq, vf_set1(1e34f)))));
    return vm_bits(ok);
}

/* The frusta of `candidates` (lanes) whose direction boxes (lo, hi, from
 * the eye, t from 0) enter the tree's root box: the traversal's own first
 * test, made before any ray, so a frustum that misses the scene's box (the
 * background around a mesh) never makes its rays. */
static uint32_t camera_reach_root(const bvh_tree *tree, const bvh_camera_block *b, const vf lo[3], const vf hi[3],
                                  uint32_t candidates)
{
    if (!candidates) return 0;
    mft_bounds bounds;
    const vf one = vf_set1(1.0f);
    for (int k = 0; k < 3; k++) {
        bounds.org[k] = vf_set1(b->eye[k]);
        bounds.dlo[k] = lo[k], bounds.dhi[k] = hi[k];
        bounds.rlo[k] = vf_div(one, lo[k]), bounds.rhi[k] = vf_div(one, hi[k]);
    }
    bounds.tnear = bounds.grow = vf_set1(0.0f);
    mft_bounds_classify(&bounds);
    vf entry;
    return vm_bits(frusta_box(&tree->root, &bounds, vf_set1(INFINITY), vm_of_bits(candidates), &entry));
}

/* The live lanes of frustum f's packets (pixels on the block), its hits
 * cleared, nothing occluded: a frustum that makes no rays. */
static uint32_t camera_live(mft_group *g, uint32_t f, const bvh_camera_block *b, uint32_t fx, uint32_t fy)
{
    uint32_t any = 0;
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const uint32_t y = fy + v * VEC_ROWS, cols = fx < b->x1 ? (b->x1 - fx < 4u ? b->x1 - fx : 4u) : 0;
        uint32_t live = 0;
        for (uint32_t r = 0; r < VEC_ROWS; r++)
            if (y + r < b->y1) live |= ((1u << cols) - 1u) << (4u * r);
        g->live[f][v] = live, g->occ[f][v] = 0;
        bvh_hits_clear(&g->hits[f][v]);
        any |= live;
    }
    return any;
}

void bvh_kernel_mft_camera(const bvh_tree *tree, const bvh_camera_block *b, rtt_hit *hits, bvh_counters *counters)
{
    const uint32_t width = b->x1 - b->x0;
    /* streamed only when every row starts on a 64-byte line */
    const bool stream = b->stream && !(((uintptr_t)hits | ((size_t)width * sizeof *hits)) & 63u);
    mft_group g;
    g.cull = tree->solid != NULL;
    for (int k = 0; k < 3; k++) g.eye[k] = b->eye[k];
    g.solid_seen = -1;
    g.solid_outside = false;
    /* frustum f's block relative to its group's, made once: written per
     * group as scalars and read back as a vector, the block's corners
     * stalled on the store buffer (a fifth of this function's time) */
    _Alignas(64) float block_dx[MFT_FRUSTA], block_dy[MFT_FRUSTA];
    for (uint32_t f = 0; f < MFT_FRUSTA; f++)
        block_dx[f] = (float)(4u * (f % GROUP_FX)), block_dy[f] = (float)(4u * (f / GROUP_FX));
    const vf lane_dx = vf_load(block_dx), lane_dy = vf_load(block_dy);
    for (uint32_t gy = b->y0; gy < b->y1; gy += 4u * GROUP_FY)
        for (uint32_t gx = b->x0; gx < b->x1; gx += 4u * GROUP_FX) {
            _Alignas(64) float dlo[3][MFT_FRUSTA], dhi[3][MFT_FRUSTA];
            /* images are at most 16384 pixels a side: the float sums are exact, as converting gx + dx was */
            const vf block_x = vf_add(vf_set1((float)gx), lane_dx), block_y = vf_add(vf_set1((float)gy), lane_dy);
            uint32_t frusta = 0, exact = 0, cornered = 0, bounded = 0;
            g.apex = g.unset = 0;
            vf size, box_lo[3], box_hi[3];
            uint32_t in_range;
            const uint32_t finite = camera_cones(&g.cone, b, block_x, block_y, &size);
            const uint32_t boxed = finite & camera_boxes(&g.cone, b, size, box_lo, box_hi, &in_range);
            const uint32_t outside = boxed & in_range & ~camera_reach_root(tree, b, box_lo, box_hi, boxed & in_range);
            for (uint32_t f = 0; f < MFT_FRUSTA; f++) {
                const uint32_t fx = gx + 4u * (f % GROUP_FX), fy = gy + 4u * (f / GROUP_FX);
                if (outside >> f & 1u) { /* misses the scene's box: no rays, every live lane a miss */
                    if (camera_live(&g, f, b, fx, fy) && counters) counters->packets++;
                    continue;
                }
                if (camera_frustum(&g, f, b, fx, fy)) exact |= 1u << f;
                uint32_t live = 0;
                for (uint32_t v = 0; v < MFT_VECS; v++) live |= g.live[f][v];
                if (!live) continue;
                if ((boxed & exact) >> f & 1u) /* every ray made the fast way: the corners bound them */
                    cornered |= 1u << f;
                else {
                    camera_bounds(&g, f, dlo, dhi);
                    bounded |= 1u << f;
                }
                if (counters) counters->packets++;
                if (tree->triangle_count == 0) continue;
                g.unset |= 1u << f;
                frusta |= 1u << f;
            }
            /* the bounds as vectors: a dead frustum's (outside or no live
             * ray) origin 0, directions 1, tnear infinite; a live one's
             * origin the eye from tnear 0, its directions the corners' box
             * when cornered, else (rare: rays made the wide-range way)
             * camera_bounds' scalars, read back only then (written a lane
             * at a time, loaded whole) */
            const vm live_lanes = vm_of_bits(cornered | bounded), corner_lanes = vm_of_bits(cornered),
                     bounded_lanes = vm_of_bits(bounded);
            const vf zero = vf_set1(0.0f), one = vf_set1(1.0f);
            vf bound_org[3], bound_lo[3], bound_hi[3];
            const vf bound_tnear = vf_blend(live_lanes, vf_set1(INFINITY), zero);
            for (int k = 0; k < 3; k++) {
                bound_org[k] = vf_blend(live_lanes, zero, vf_set1(b->eye[k]));
                bound_lo[k] = vf_blend(corner_lanes, one, box_lo[k]);
                bound_hi[k] = vf_blend(corner_lanes, one, box_hi[k]);
                if (bounded)
                    bound_lo[k] = vf_blend(bounded_lanes, bound_lo[k], vf_load(dlo[k])),
                    bound_hi[k] = vf_blend(bounded_lanes, bound_hi[k], vf_load(dhi[k]));
            }
            g.pinhole = finite & exact;
            trace_group_bounds(tree, &g, frusta, bound_org, bound_lo, bound_hi, bound_tnear, zero, true, counters);
            /* each packet's rows of four straight into the block's rows */
            for (uint32_t f = 0; f < MFT_FRUSTA; f++)
                for (uint32_t v = 0; v < MFT_VECS; v++) {
                    const uint32_t fx = gx + 4u * (f % GROUP_FX), fy = gy + 4u * (f / GROUP_FX) + v * VEC_ROWS;
                    if (fx >= b->x1 || fy >= b->y1) continue;
                    const uint32_t cols = b->x1 - fx < 4u ? b->x1 - fx : 4u;
                    const uint32_t rows = b->y1 - fy < VEC_ROWS ? b->y1 - fy : VEC_ROWS;
                    bvh_hits_store_rows(&g.hits[f][v], &hits[(size_t)(fy - b->y0) * width + (fx - b->x0)], width,
                                        cols, rows, stream);
                }
        }
    /* no fence: a caller handing the hits to another thread orders the
     * streamed rows (bvh_camera_block); one per 16x16 tile, each waiting
     * for its 4 KB to reach memory, cost 2-13% of a frame */
}

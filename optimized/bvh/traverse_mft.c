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
 *    survivors (bitscan), the 16-ray projected barycentric test
 *    (bvh_isect_wide.h) on that frustum's rays;
 *  - frusta are terminated one by one: an occlusion frustum leaves when all
 *    its rays are occluded; a closest-hit frustum's bound shrinks to its
 *    rays' farthest closest hit after every leaf that lowered one.
 *
 * What it departs from and why: the kernel takes any ray stream (engine,
 * conformance, bench), so the rays of a frustum are loaded from the stream
 * rather than generated from start and delta vectors, and the culling uses
 * the direction box (exact for any rays sharing an origin) rather than four
 * corner rays (exact only for pinhole grids).  A group of 16 whose rays do
 * not share one origin is traced by the packet walk instead (bvh_traverse.h).
 * No back-face CULLING (rtt's triangles are two-sided): the orientation only
 * picks the sign the edge tests need.  Bounds get a
 * relative slack of 2^-20 so that rounding never culls a ray's hit. */
#include <math.h>
#include <string.h>

#include "bvh_isect_wide.h"
#include "bvh_traverse.h"

#define MFT_RAYS 16u                 /* rays per frustum */
#define MFT_VECS (MFT_RAYS / BVH_W)  /* packets per frustum: 1, 2 or 4 */
#define MFT_FRUSTA BVH_W             /* frusta per group: one per lane */

typedef struct mft_group {
    vf org[3];                       /* per frustum: the common origin */
    vf dlo[3], dhi[3], rlo[3], rhi[3]; /* direction box and its reciprocals */
    vf tnear;                        /* smallest tnear of its rays */
    float dist[MFT_FRUSTA];          /* largest min(tfar, closest hit) of its rays */
    bvh_packet rays[MFT_FRUSTA][MFT_VECS];
    uint32_t live[MFT_FRUSTA][MFT_VECS];
    bvh_hits hits[MFT_FRUSTA][MFT_VECS];
    uint32_t occ[MFT_FRUSTA][MFT_VECS];
} mft_group;

static inline vf vf_abs(vf x) { return vf_max(x, vf_sub(vf_set1(0.0f), x)); }

/* The frusta of `active` whose interval bounds enter the box; their entries. */
static inline vm frusta_box(const bvh_child *c, const mft_group *g, vf dist, vm active, vf *entry)
{
    const vf zero = vf_set1(0.0f), inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    vf t0 = g->tnear, t1 = dist;
    for (int k = 0; k < 3; k++) {
        const vf p = vf_sub(vf_set1(c->lo[k]), g->org[k]), q = vf_sub(vf_set1(c->hi[k]), g->org[k]);
        const vf pa = vf_mul(p, g->rlo[k]), pb = vf_mul(p, g->rhi[k]);
        const vf qa = vf_mul(q, g->rlo[k]), qb = vf_mul(q, g->rhi[k]);
        const vm positive = vf_gt(g->dlo[k], zero), negative = vf_lt(g->dhi[k], zero);
        /* the interval contains zero: enter from below only along d > 0, from above only along d < 0 */
        const vf from_below = vf_blend(vf_gt(g->dhi[k], zero), inf, pb);
        const vf from_above = vf_blend(vf_lt(g->dlo[k], zero), inf, qa);
        vf in = vf_blend(vf_lt(q, zero), minus_inf, from_above);
        in = vf_blend(vf_gt(p, zero), in, from_below);
        vf out = inf;
        in = vf_blend(negative, in, vf_min(qa, qb));
        out = vf_blend(negative, out, vf_max(pa, pb));
        in = vf_blend(positive, in, vf_min(pa, pb));
        out = vf_blend(positive, out, vf_max(qa, qb));
        t0 = vf_max(in, t0);
        t1 = vf_min(out, t1);
    }
    const vf slack = vf_set1(0x1p-20f);
    t0 = vf_sub(t0, vf_mul(vf_abs(t0), slack));
    t1 = vf_add(t1, vf_mul(vf_abs(t1), slack));
    *entry = t0;
    return vm_and(active, vf_le(t0, t1));
}

/* The frusta of `active` some of whose directions may cross the triangle
 * ahead of the origin.  With A, B, C the corners relative to the origin and
 * D = A . (B x C), a direction d = aA + bB + cC hits ahead iff a, b, c >= 0,
 * that is iff (B x C).d, (C x A).d and (A x B).d all have the sign of D (the
 * triangle's orientation as the origin sees it: Benthin & Wald's back-face
 * test decides which sign the edge tests must have).  A frustum is culled
 * when over its whole direction box one edge's n.d has the wrong sign; an
 * origin (nearly) in the triangle's plane culls nothing. */
static inline uint32_t frusta_triangle(const bvh_corners *tri, const mft_group *g, vm active)
{
    vf rel[3][3];
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) rel[v][k] = vf_sub(vf_set1(tri->v[v][k]), g->org[k]);
    const vf eps = vf_set1(1e-4f), zero = vf_set1(0.0f);
    vm below = vm_of_bits(0), above = vm_of_bits(0); /* an edge with n.d < 0 (> 0) for every d */
    vf det = zero, det_mag = zero;
    for (int e = 0; e < 3; e++) {
        const vf *a = rel[(e + 1) % 3], *b = rel[(e + 2) % 3]; /* edge e: the corners other than e */
        const vf n[3] = {vf_sub(vf_mul(a[1], b[2]), vf_mul(a[2], b[1])), vf_sub(vf_mul(a[2], b[0]), vf_mul(a[0], b[2])),
                         vf_sub(vf_mul(a[0], b[1]), vf_mul(a[1], b[0]))};
        if (e == 0)
            for (int k = 0; k < 3; k++) {
                const vf x = vf_mul(rel[0][k], n[k]);
                det = vf_add(det, x);
                det_mag = vf_add(det_mag, vf_abs(x));
            }
        vf hi = zero, lo = zero, mag = zero;
        for (int k = 0; k < 3; k++) {
            const vf x = vf_mul(n[k], g->dlo[k]), y = vf_mul(n[k], g->dhi[k]);
            hi = vf_add(hi, vf_max(x, y));
            lo = vf_add(lo, vf_min(x, y));
            mag = vf_add(mag, vf_max(vf_abs(x), vf_abs(y)));
        }
        const vf margin = vf_mul(mag, eps);
        below = vm_or(below, vf_lt(hi, vf_sub(zero, margin)));
        above = vm_or(above, vf_gt(lo, margin));
    }
    const vf det_margin = vf_mul(det_mag, eps);
    const uint32_t facing = vm_bits(vf_gt(det, det_margin)), backing = vm_bits(vf_lt(det, vf_sub(zero, det_margin)));
    return vm_bits(active) & ~((facing & vm_bits(below)) | (backing & vm_bits(above)));
}

static float frustum_dist(const mft_group *g, uint32_t f, bool closest)
{
    float far = -INFINITY;
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        float tfar[BVH_W], t[BVH_W];
        vf_store(tfar, g->rays[f][v].tfar);
        vf_store(t, closest ? g->hits[f][v].t : vf_set1(INFINITY));
        for (uint32_t l = 0; l < BVH_W; l++)
            if (g->live[f][v] >> l & 1u) {
                const float d = t[l] < tfar[l] ? t[l] : tfar[l];
                far = d > far ? d : far;
            }
    }
    return far;
}

typedef struct mft_entry {
    const bvh_child *child;
    uint32_t frusta;
} mft_entry;

static void trace_frusta(const bvh_tree *tree, mft_group *g, uint32_t frusta, bool closest, bvh_counters *counters)
{
    mft_entry stack[BVH_TRAVERSAL_STACK];
    uint32_t top = 0, alive = frusta;
    vf dist = vf_load(g->dist);
    stack[top++] = (mft_entry){&tree->root, frusta};
    while (top > 0) {
        const mft_entry e = stack[--top];
        vf entry;
        uint32_t lanes = vm_bits(frusta_box(e.child, g, dist, vm_of_bits(e.frusta & alive), &entry));
        if (counters) counters->aabb_tests++;
        const bvh_child *c = e.child;
        while (lanes && c->count == 0) {
            const bvh_node *node = &tree->nodes[c->index];
            vf e0, e1;
            const vm active = vm_of_bits(lanes);
            const uint32_t l0 = vm_bits(frusta_box(&node->child[0], g, dist, active, &e0));
            const uint32_t l1 = vm_bits(frusta_box(&node->child[1], g, dist, active, &e1));
            if (counters) counters->aabb_tests += 2;
            if (l0 && l1) {
                const uint32_t both = l0 & l1;
                const uint32_t first0 = vm_bits(vm_and(vm_of_bits(both), vf_le(e0, e1)));
                const int near = __builtin_popcount(first0) * 2 < __builtin_popcount(both);
                if (top < BVH_TRAVERSAL_STACK) stack[top++] = (mft_entry){&node->child[!near], near ? l0 : l1};
                c = &node->child[near];
                lanes = near ? l1 : l0;
            } else {
                c = &node->child[l1 != 0];
                lanes = l0 | l1;
            }
        }
        if (!lanes) continue;
        uint32_t lowered = 0;
        for (uint32_t i = 0; i < c->count && lanes; i++) {
            const uint32_t rec = c->index + i;
            if (counters) counters->triangles += (uint64_t)__builtin_popcount(lanes);
            uint32_t survive = frusta_triangle(&tree->corners[rec], g, vm_of_bits(lanes));
            while (survive) {
                const uint32_t f = (uint32_t)__builtin_ctz(survive);
                survive &= survive - 1u;
                if (counters) counters->isect_tests++;
                for (uint32_t v = 0; v < MFT_VECS; v++) {
                    const uint32_t ray_lanes = g->live[f][v] & ~g->occ[f][v];
                    if (!ray_lanes) continue;
                    if (closest) {
                        if (bvh_isect_projected(&tree->triangles[rec], &g->rays[f][v], &g->hits[f][v],
                                                vm_of_bits(ray_lanes)))
                            lowered |= 1u << f;
                    } else {
                        g->occ[f][v] |= bvh_occluded_projected(&tree->triangles[rec], &g->rays[f][v],
                                                               vm_of_bits(ray_lanes));
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
        }
        if (!alive) break;
    }
}

/* Loads frustum f of the group from rays[0 .. count-1]; true when its live
 * rays share one origin (a frustum), false when they need the packet walk. */
static bool load_frustum(mft_group *g, uint32_t f, const rtt_ray *rays, size_t count, float org[3][MFT_FRUSTA],
                         float dlo[3][MFT_FRUSTA], float dhi[3][MFT_FRUSTA], float *tnear)
{
    bool common = true, any = false;
    for (uint32_t v = 0; v < MFT_VECS; v++) {
        const size_t first = (size_t)v * BVH_W, n = count > first ? (count - first < BVH_W ? count - first : BVH_W) : 0;
        g->live[f][v] = n ? bvh_packet_load(&g->rays[f][v], rays + first, n) : 0;
        g->occ[f][v] = 0;
        bvh_hits_clear(&g->hits[f][v]);
        for (uint32_t l = 0; l < BVH_W; l++) {
            if (!(g->live[f][v] >> l & 1u)) continue;
            const rtt_ray *r = &rays[first + l];
            if (!any) {
                for (int k = 0; k < 3; k++) org[k][f] = r->org[k], dlo[k][f] = dhi[k][f] = r->dir[k];
                *tnear = r->tnear;
                any = true;
            }
            for (int k = 0; k < 3; k++) {
                common &= r->org[k] == org[k][f];
                dlo[k][f] = r->dir[k] < dlo[k][f] ? r->dir[k] : dlo[k][f];
                dhi[k][f] = r->dir[k] > dhi[k][f] ? r->dir[k] : dhi[k][f];
            }
            *tnear = r->tnear < *tnear ? r->tnear : *tnear;
        }
    }
    if (!any)
        for (int k = 0; k < 3; k++) org[k][f] = 0.0f, dlo[k][f] = dhi[k][f] = 1.0f;
    return common;
}

void bvh_kernel_mft(const bvh_tree *tree, const bvh_query *q)
{
    const bool closest = q->hits != NULL;
    const size_t group_rays = (size_t)MFT_FRUSTA * MFT_RAYS;
    mft_group g;
    for (size_t first = 0; first < q->count; first += group_rays) {
        float org[3][MFT_FRUSTA], dlo[3][MFT_FRUSTA], dhi[3][MFT_FRUSTA], rlo[3][MFT_FRUSTA], rhi[3][MFT_FRUSTA];
        float tnear[MFT_FRUSTA];
        uint32_t frusta = 0;
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
                frusta |= 1u << f;
                continue;
            }
            for (uint32_t v = 0; v < MFT_VECS; v++) /* no common origin: the packet walk */
                if (g.live[f][v])
                    bvh_trace_packet(tree, &g.rays[f][v], g.live[f][v], closest ? &g.hits[f][v] : NULL,
                                     &g.occ[f][v], q->counters);
        }
        for (int k = 0; k < 3; k++)
            for (uint32_t f = 0; f < MFT_FRUSTA; f++) rlo[k][f] = 1.0f / dlo[k][f], rhi[k][f] = 1.0f / dhi[k][f];
        for (int k = 0; k < 3; k++) {
            g.org[k] = vf_load(org[k]);
            g.dlo[k] = vf_load(dlo[k]), g.dhi[k] = vf_load(dhi[k]);
            g.rlo[k] = vf_load(rlo[k]), g.rhi[k] = vf_load(rhi[k]);
        }
        g.tnear = vf_load(tnear);
        for (uint32_t f = 0; f < MFT_FRUSTA; f++) g.dist[f] = frusta >> f & 1u ? frustum_dist(&g, f, false) : -INFINITY;
        if (frusta) trace_frusta(tree, &g, frusta, closest, q->counters);
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

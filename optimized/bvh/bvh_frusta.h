/* What the multi-frusta kernels share (kernel side, one copy per
 * instruction set): a set of BVH_W frusta, one per SIMD lane, as a common
 * origin and the box of its rays' directions (Benthin & Wald 2009, 4.1),
 * the interval test of a box against every frustum at once and the
 * common-origin Pluecker test of a triangle against every frustum.  Used by
 * traverse_mft.c (primary rays, hard shadows) and shadow_frusta.c (soft
 * shadows, frusta:N).  Directions need not be unit: a frustum is the set of
 * points org + t d, d in [dlo, dhi], t in [tnear, dist]. */
#ifndef RTT_BVH_FRUSTA_H
#define RTT_BVH_FRUSTA_H

#include <math.h>

#include "bvh_simd.h"
#include "bvh_tree.h"

typedef struct mft_bounds {
    vf org[3];                         /* per frustum: the common origin */
    vf dlo[3], dhi[3], rlo[3], rhi[3]; /* direction box and its reciprocals */
    vf tnear;                          /* smallest t of its rays */
    vf grow;                           /* boxes are tested grown by this much: an origin known to a few ulps */
    /* per axis, from the direction box (mft_bounds_classify): the frusta
     * whose directions all point down the axis, those whose interval
     * contains zero, and of those the ones with some d > 0 and some d < 0 */
    vm negative[3], up[3], down[3];
    uint32_t straddle[3];
    /* per axis, the origin moved by grow to the side a box's near (far)
     * plane is taken from: org + grow against the low plane, org - grow
     * against the high one (a box grown by grow on every side) */
    vf org_near[3], org_far[3];
    vf dl1;                            /* sum over axes of max(|dlo|, |dhi|): a bound on |d|_1 */
    /* per axis, which plane is every frustum's near one: 1 the low (no
     * frustum's directions all negative), 2 the high (all of them), 0 it
     * varies (frusta_box blends per lane) */
    uint32_t near_side[3];
    /* When `ends_known`: a box holding a point of every live frustum at
     * some t in [tnear, dist] (soft shadows: the ends of their corner
     * vectors, on the light).  Every frustum enters a box that holds it,
     * so mft_descend takes such a child as entered by all without a test
     * (the test would say so: it is conservative).  mft_bounds_classify
     * clears it. */
    bool ends_known;
    float ends_lo[3], ends_hi[3];
} mft_bounds;

/* The per-axis classes of every frustum's direction box and its dl1, once
 * per group (the box test reads them at every node). */
static inline void mft_bounds_classify(mft_bounds *g)
{
    const vf zero = vf_set1(0.0f);
    g->ends_known = false;
    g->dl1 = zero;
    for (int k = 0; k < 3; k++) {
        g->dl1 = vf_add(g->dl1, vf_max(vf_abs(g->dlo[k]), vf_abs(g->dhi[k])));
        g->negative[k] = vf_lt(g->dhi[k], zero);
        g->up[k] = vf_gt(g->dhi[k], zero);
        g->down[k] = vf_lt(g->dlo[k], zero);
        g->straddle[k] = BVH_LANES_ALL & ~(vm_bits(vf_gt(g->dlo[k], zero)) | vm_bits(g->negative[k]));
        const uint32_t negative = vm_bits(g->negative[k]);
        g->near_side[k] = negative == 0 ? 1u : negative == BVH_LANES_ALL ? 2u : 0u;
        const vf org_lo = vf_add(g->org[k], g->grow), org_hi = vf_sub(g->org[k], g->grow);
        g->org_near[k] = vf_blend(g->negative[k], org_lo, org_hi);
        g->org_far[k] = vf_blend(g->negative[k], org_hi, org_lo);
    }
}

/* The frusta of `active` whose interval bounds enter the box; their entries.
 * Per axis, a frustum whose directions keep one sign enters the slab at
 * its near plane (the low one along d > 0, the high one along d < 0) no
 * earlier than the smaller of that plane's distances over dlo and dhi, and
 * leaves it at the far plane no later than the larger.  An interval that
 * contains zero (the paper's "zero fix", only on the axes where some
 * frustum of the group has one): entered from below only along d > 0, from
 * above only along d < 0, at the steepest direction's entry, never left.
 * When every frustum of the group takes the same plane as its near one on
 * an axis (mft_bounds.near_side: 99.6-100% of the bench's soft-shadow
 * groups per axis, whose 16 frusta are coherent), the planes are read as
 * they are instead of blended per lane: the same values, two vector
 * operations fewer per axis and box. */
static inline vm frusta_box(const bvh_child *c, const mft_bounds *g, vf dist, vm active, vf *entry)
{
    const vf inf = vf_set1(INFINITY), minus_inf = vf_set1(-INFINITY);
    vf t0 = g->tnear, t1 = dist;
    const uint32_t lanes = vm_bits(active);
    for (int k = 0; k < 3; k++) {
        vf near, far;
        if (g->near_side[k]) { /* one plane for every frustum: no blends */
            const bool low = g->near_side[k] == 1u;
            near = vf_sub(vf_set1(low ? c->lo[k] : c->hi[k]), g->org_near[k]);
            far = vf_sub(vf_set1(low ? c->hi[k] : c->lo[k]), g->org_far[k]);
        } else {
            const vf lo = vf_set1(c->lo[k]), hi = vf_set1(c->hi[k]);
            near = vf_sub(vf_blend(g->negative[k], lo, hi), g->org_near[k]);
            far = vf_sub(vf_blend(g->negative[k], hi, lo), g->org_far[k]);
        }
        vf in = vf_min(vf_mul(near, g->rlo[k]), vf_mul(near, g->rhi[k]));
        vf out = vf_max(vf_mul(far, g->rlo[k]), vf_mul(far, g->rhi[k]));
        if (g->straddle[k] & lanes) {
            /* a straddling direction box is not all negative: its near
             * plane is the low one, its far plane the high one */
            const vf p = near, q = far;
            const vf zero = vf_set1(0.0f);
            const vf from_below = vf_blend(g->up[k], inf, vf_mul(p, g->rhi[k]));
            const vf from_above = vf_blend(g->down[k], inf, vf_mul(q, g->rlo[k]));
            vf zero_in = vf_blend(vf_lt(q, zero), minus_inf, from_above);
            zero_in = vf_blend(vf_gt(p, zero), zero_in, from_below);
            const vm straddle = vm_of_bits(g->straddle[k]);
            in = vf_blend(straddle, in, zero_in);
            out = vf_blend(straddle, out, inf);
        }
        t0 = vf_max(in, t0);
        t1 = vf_min(out, t1);
    }
    *entry = t0;
    return vm_and(active, bvh_interval_holds(t0, t1));
}

/* Per frustum: the triangle's corners relative to its origin, the normal
 * of each edge plane through the origin (edge e: rel[e+1] x rel[e+2],
 * computed as rel[e+1] x E[e] with E[e] = v[e+2] - v[e+1], the triangle's
 * own edge) and D = rel[0] . n[0] with det_mag the magnitudes of its terms.
 * Rounding: each of rel, E and their products is rounded by 2^-24 of
 * itself, so n is known to 2^-22 (|rel_j E_k| + |rel_k E_j|) per
 * component, at most cross_error = 2^-20 reach edge (twice that): reach
 * the largest |rel| component, edge the largest |E| component.  Crossing
 * the corners' differences instead, rel[e+1] x rel[e+2], would err by
 * 2^-21 reach^2, which for a triangle small and far from the origin (a
 * fuzzed 4e-5 triangle 20 units away; armadillo's far triangles under
 * camera frusta) is many times |n| itself and turns edge planes round.
 * Every margin below carries cross_error. */
typedef struct frusta_tri {
    vf rel[3][3], n[3][3];
    vf det, det_mag, reach, cross_error;
    float edge[3][3];  /* E[e] = v[e+2] - v[e+1] */
    float edge_max;    /* the largest |E| component */
    float normal[3];   /* (v1 - v0) x (v2 - v0) = E[2] x -E[1], as computed */
    float area;        /* |normal|_1 */
} frusta_tri;

/* The margins' constants, one place for the frusta of every kind (the
 * vector forms below and frusta_triangle_pinhole's four-lane one): the
 * planes' relative tolerance, sqrt 3 rounded up (|rel|_2 <= sqrt(3)
 * reach), n's rounding per component over reach x edge (above), and
 * |rel[0]|_1 <= 3 reach for D's. */
#define FRUSTA_EPS 1e-4f
#define FRUSTA_SQRT3 1.7321f
#define FRUSTA_CROSS_ERROR 0x1p-20f
#define FRUSTA_DET_TERMS 3.0f

/* The triangle's terms that no origin changes: its edges E[e] = v[e+2] -
 * v[e+1] and their largest |component|, the normal (v1 - v0) x (v2 - v0)
 * = E[2] x -E[1] as computed; returns its |.|_1 (the area term). */
static inline float frusta_edge_terms(const bvh_corners *tri, float edge[3][3], float *edge_max, float normal[3])
{
    float largest = 0.0f;
    for (int e = 0; e < 3; e++)
        for (int k = 0; k < 3; k++) {
            edge[e][k] = tri->v[(e + 2) % 3][k] - tri->v[(e + 1) % 3][k];
            const float size = fabsf(edge[e][k]); /* not fmaxf: a call into libm here */
            largest = size > largest ? size : largest;
        }
    *edge_max = largest;
    normal[0] = edge[1][1] * edge[2][2] - edge[1][2] * edge[2][1];
    normal[1] = edge[1][2] * edge[2][0] - edge[1][0] * edge[2][2];
    normal[2] = edge[1][0] * edge[2][1] - edge[1][1] * edge[2][0];
    return fabsf(normal[0]) + fabsf(normal[1]) + fabsf(normal[2]);
}

static inline void frusta_edges(const bvh_corners *tri, const mft_bounds *g, frusta_tri *t)
{
    t->area = frusta_edge_terms(tri, t->edge, &t->edge_max, t->normal);
    t->reach = vf_set1(0.0f);
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) {
            t->rel[v][k] = vf_sub(vf_set1(tri->v[v][k]), g->org[k]);
            t->reach = vf_max(t->reach, vf_abs(t->rel[v][k]));
        }
    t->cross_error = vf_mul(t->reach, vf_set1(t->edge_max * FRUSTA_CROSS_ERROR));
    for (int e = 0; e < 3; e++) {
        const vf *a = t->rel[(e + 1) % 3];
        const vf b[3] = {vf_set1(t->edge[e][0]), vf_set1(t->edge[e][1]), vf_set1(t->edge[e][2])};
        t->n[e][0] = vf_sub(vf_mul(a[1], b[2]), vf_mul(a[2], b[1]));
        t->n[e][1] = vf_sub(vf_mul(a[2], b[0]), vf_mul(a[0], b[2]));
        t->n[e][2] = vf_sub(vf_mul(a[0], b[1]), vf_mul(a[1], b[0]));
    }
    t->det = t->det_mag = vf_set1(0.0f);
    for (int k = 0; k < 3; k++) {
        const vf x = vf_mul(t->rel[0][k], t->n[0][k]);
        t->det = vf_add(t->det, x);
        t->det_mag = vf_add(t->det_mag, vf_abs(x));
    }
}

/* Which lanes see the triangle facing them (D > margin) and which backing
 * (D < -margin), from D, the magnitudes of its terms, the corners' largest
 * |component| relative to the origin (reach), area_eps = |normal|_1
 * sqrt(3) eps and the normals' rounding bound cross_error; frusta_orientation
 * from frusta_edges' terms, frusta_pinhole_setup from its quads'. */
static inline void frusta_facing(vf det, vf det_mag, vf reach, vf area_eps, vf cross_error, vm *facing, vm *backing)
{
    /* D decides the orientation only when the origin lies clear of the
     * triangle's plane on the scale of its corners: D = 2 area x distance,
     * so the distance must pass eps times the farthest corner, |rel|_2 <=
     * sqrt(3) reach (the reference's watertight test rounds on that scale;
     * an origin on an edge of a long sliver has |D| = det_mag yet sits on
     * the triangle), and D must pass its own rounding: n[0]'s error
     * (cross_error per component) times |rel[0]|_1 <= 3 reach */
    const vf det_margin = vf_add(vf_max(vf_mul(det_mag, vf_set1(FRUSTA_EPS)), vf_mul(reach, area_eps)),
                                 vf_mul(cross_error, vf_mul(reach, vf_set1(FRUSTA_DET_TERMS))));
    *facing = vf_gt(det, det_margin), *backing = vf_lt(det, vf_sub(vf_set1(0.0f), det_margin));
}

static inline void frusta_orientation(const frusta_tri *t, uint32_t *facing, uint32_t *backing)
{
    vm face, back;
    frusta_facing(t->det, t->det_mag, t->reach, vf_set1(t->area * FRUSTA_SQRT3 * FRUSTA_EPS), t->cross_error, &face,
                  &back);
    *facing = vm_bits(face), *backing = vm_bits(back);
}

/* The frusta of `active` some of whose directions may cross the triangle
 * ahead of the origin.  With A, B, C the corners relative to the origin and
 * D = A . (B x C), a direction d = aA + bB + cC hits ahead iff a, b, c >= 0,
 * that is iff (B x C).d, (C x A).d and (A x B).d all have the sign of D (the
 * triangle's orientation as the origin sees it: Benthin & Wald's back-face
 * test decides which sign the edge tests must have).  A frustum is culled
 * when over all its directions (its direction box) one edge's n.d has the
 * wrong sign; an origin (nearly) in the triangle's plane -- within 1e-4 of
 * its farthest corner's distance -- culls nothing.  The margin is 1e-4 of
 * n.d's terms plus |n|_1 slack (a direction known only to within slack per
 * axis) plus n's rounding over |d|_1 <= dl1. */
static inline uint32_t frusta_cull(const frusta_tri *t, const mft_bounds *g, vf dl1, vf slack, vm active)
{
    const vf eps = vf_set1(FRUSTA_EPS), zero = vf_set1(0.0f);
    const vf normal_error = vf_mul(t->cross_error, dl1); /* n's rounding, |dn.d| <= cross_error |d|_1 */
    vm below = vm_of_bits(0), above = vm_of_bits(0); /* an edge with n.d < 0 (> 0) for every d */
    for (int e = 0; e < 3; e++) {
        const vf *n = t->n[e];
        vf hi = zero, lo = zero, mag = zero;
        const vf spread = vf_add(vf_add(vf_abs(n[0]), vf_abs(n[1])), vf_abs(n[2]));
        for (int k = 0; k < 3; k++) {
            const vf x = vf_mul(n[k], g->dlo[k]), y = vf_mul(n[k], g->dhi[k]);
            hi = vf_add(hi, vf_max(x, y));
            lo = vf_add(lo, vf_min(x, y));
            mag = vf_add(mag, vf_max(vf_abs(x), vf_abs(y)));
        }
        /* directions known to slack per axis, normals to cross_error */
        const vf margin = vf_add(vf_add(vf_mul(mag, eps), vf_mul(spread, slack)), normal_error);
        below = vm_or(below, vf_lt(hi, vf_sub(zero, margin)));
        above = vm_or(above, vf_gt(lo, margin));
    }
    uint32_t facing, backing;
    frusta_orientation(t, &facing, &backing);
    return vm_bits(active) & ~((facing & vm_bits(below)) | (backing & vm_bits(above)));
}

/* frusta_cull over each frustum's direction box (|d|_1 <= dl1), the
 * directions known to slack per axis. */
static inline uint32_t frusta_triangle_bounded(const bvh_corners *tri, const mft_bounds *g, vf slack, vm active)
{
    frusta_tri t;
    frusta_edges(tri, g, &t);
    return frusta_cull(&t, g, g->dl1, slack, active);
}

static inline uint32_t frusta_triangle(const bvh_corners *tri, const mft_bounds *g, vm active)
{
    return frusta_triangle_bounded(tri, g, vf_set1(0.0f), active);
}

/* Pinhole frusta (primary rays made from the camera frame): every ray
 * direction of a frustum is, up to rounding, a positive multiple of a
 * convex combination of its four corner vectors (d = corner + du x + dv y
 * is affine in the pixel; normalising is a positive scale).  A frustum's
 * scale is eps * cmax + grow: cmax the largest |component| of its corner
 * vectors, grow a bound per axis on the rounding of the corners and of the
 * rays' directions (scaled back to the corners' length); camera_cones
 * (traverse_mft.c) makes it and keeps it in pixel_scale.  The frusta of a
 * camera group share one origin, the eye, and one frame (corner, du, dv),
 * so an edge plane's n.d(x, y) = n.corner + (n.du) x + (n.dv) y is an edge
 * function of the pixel, made once per triangle (frusta_triangle_pinhole). */
typedef struct mft_cone {
    vf corner[4][3];
    vf l1;             /* the largest |corner|_1: the normals' rounding scales with it */
    vf cx, cy;         /* the centre of the block's corner pixel centres (x + 2, y + 2) */
    vf pixel_scale;    /* scale plus the edge functions' rounding (2^-19 of the corners' terms) */
    /* the common origin and the frame (corner, du, dv) in quads (bvh_simd.h)
     * for the triangles' set-up: each component in every lane, but eye_q's
     * lane 3 of every quad zero */
    vf eye_q[3], frame_q[3][3];
} mft_cone;

/* The cull of frusta_cull for pinhole frusta (every one's origin the eye),
 * in the pixel plane: per edge plane n (frusta_edges' formula) the edge
 * function's largest and least value over a frustum's corner pixel centres
 * are its value at their centre plus and minus 1.5 (|n.du| + |n.dv|) --
 * the four corner vectors' dot products, exactly, in three operations per
 * frustum instead of twelve.  One margin per edge and frustum: |n.c| <=
 * |n|_1 cmax for every corner c, so |n|_1 (eps cmax + grow) covers
 * frusta_cull's eps * mag and the corners' and the rays' rounding; the edge
 * function's own rounding (its three dot products with the frame, the
 * products with the centre, the spread, the sums: about ten ulps, under
 * 2^-20.5, of sum_k |n_k| (|corner_k| + |du_k| x + |dv_k| y) <= |n|_1
 * size, size camera_cones' largest sum over an axis of the corners' terms)
 * is covered three times over by pixel_scale's 2^-19 size over scale, and
 * n's by cross_error over |d|_1 <= l1.  The orientation (frusta_facing's
 * D and margin) is one for every frustum: a triangle facing them is culled
 * from those whose directions all fall below an edge, a backing one from
 * those above, one whose plane passes near the eye from none.
 *
 * In two steps: frusta_pinhole_setup makes the per-triangle terms of
 * FRUSTA_QUADS triangles of a leaf at once (the eye is common, so they do
 * not depend on the frustum), frusta_pinhole_cull tests one of them
 * against every frustum.  The set-up is a chain of dependent shuffles and
 * products; made for one triangle at a time in four lanes it was a third of
 * the camera path's traversal (bench/results/bvh-mft.md, eleventh
 * session). */
#define FRUSTA_QUADS (BVH_W / 4u)

/* Per triangle t of a set-up, its lanes 4t .. 4t + 2 (one per edge e):
 * the edge function's frame terms sign n.du (fx), sign n.dv (fy) and sign
 * n.corner plus its spread 1.5 (|fx| + |fy|) (f0), |n|_1 (l1); the normals'
 * rounding bound (cross_error, in every lane of the quad); bit 4t of
 * facing (backing): the triangle faces (backs) the eye beyond the margin. */
typedef struct frusta_pinhole_tris {
    _Alignas(64) float fx[BVH_W];
    _Alignas(64) float fy[BVH_W];
    _Alignas(64) float f0[BVH_W];
    _Alignas(64) float l1[BVH_W];
    _Alignas(64) float cross_error[BVH_W];
    uint32_t facing, backing;
} frusta_pinhole_tris;

/* The set-up of the `count` (>= 1) triangles from tri on, up to
 * FRUSTA_QUADS of them (the quads past count repeat the last), a quad per
 * triangle with one lane per edge e (lane 3 zero): the same operations in
 * the same order as frusta_edges and frusta_edge_terms, so the same bits.
 * x[k] holds (v0, v1, v2)[k], rel[k] those minus the eye, a[k] the corner
 * rel[e + 1], edge[k] E[e] = v[e + 2] - v[e + 1], next and after E[e + 1]
 * and E[e + 2] (lane 0: the normal E[1] x E[2]). */
static inline void frusta_pinhole_setup(const bvh_corners *tri, uint32_t count, const mft_cone *cone,
                                        frusta_pinhole_tris *s)
{
    const float *corner[3][FRUSTA_QUADS];
    for (uint32_t q = 0; q < FRUSTA_QUADS; q++)
        for (int v = 0; v < 3; v++) corner[v][q] = tri[q < count ? q : count - 1u].v[v];
    const vf zero = vf_set1(0.0f);
    vf x[3];
    { /* each quad's 4x4 transpose, row 3 (the loads' fourth words and zeros) dropped */
        const vf r0 = vf_load_quads(corner[0]), r1 = vf_load_quads(corner[1]), r2 = vf_load_quads(corner[2]);
        const vf t0 = vf_unpacklo(r0, r1), t1 = vf_unpackhi(r0, r1), t2 = vf_unpacklo(r2, zero),
                 t3 = vf_unpackhi(r2, zero);
        x[0] = vf_shuffle(t0, t2, 0x44), x[1] = vf_shuffle(t0, t2, 0xEE), x[2] = vf_shuffle(t1, t3, 0x44);
    }
    vf rel[3], a[3], edge[3], next[3], after[3], reach4 = zero, edge4 = zero;
    for (int k = 0; k < 3; k++) {
        rel[k] = vf_sub(x[k], cone->eye_q[k]);
        a[k] = vf_shuffle(rel[k], rel[k], _MM_SHUFFLE(3, 0, 2, 1));
        edge[k] = vf_sub(vf_shuffle(x[k], x[k], _MM_SHUFFLE(3, 1, 0, 2)), vf_shuffle(x[k], x[k], _MM_SHUFFLE(3, 0, 2, 1)));
        next[k] = vf_shuffle(edge[k], edge[k], _MM_SHUFFLE(3, 0, 2, 1));
        after[k] = vf_shuffle(edge[k], edge[k], _MM_SHUFFLE(3, 1, 0, 2));
        reach4 = vf_max(reach4, vf_abs(rel[k]));
        edge4 = vf_max(edge4, vf_abs(edge[k]));
    }
    vf n[3], normal[3];
    n[0] = vf_sub(vf_mul(a[1], edge[2]), vf_mul(a[2], edge[1]));
    n[1] = vf_sub(vf_mul(a[2], edge[0]), vf_mul(a[0], edge[2]));
    n[2] = vf_sub(vf_mul(a[0], edge[1]), vf_mul(a[1], edge[0]));
    normal[0] = vf_sub(vf_mul(next[1], after[2]), vf_mul(next[2], after[1]));
    normal[1] = vf_sub(vf_mul(next[2], after[0]), vf_mul(next[0], after[2]));
    normal[2] = vf_sub(vf_mul(next[0], after[1]), vf_mul(next[1], after[0]));
    /* lane 0 of each quad: D = rel[0] . n[0], its terms' magnitudes and the area term */
    const vf d0 = vf_mul(rel[0], n[0]), d1 = vf_mul(rel[1], n[1]), d2 = vf_mul(rel[2], n[2]);
    const vf det4 = vf_add(vf_add(d0, d1), d2);
    const vf mag4 = vf_add(vf_add(vf_abs(d0), vf_abs(d1)), vf_abs(d2));
    const vf area4 = vf_add(vf_add(vf_abs(normal[0]), vf_abs(normal[1])), vf_abs(normal[2]));
    /* the largest |rel| (lane 0) and |E| (lane 1) over each quad's lanes (maxima are exact) */
    vf most = vf_max(vf_unpacklo(reach4, edge4), vf_unpackhi(reach4, edge4));
    most = vf_max(most, vf_shuffle(most, most, 0xEE));
    /* per triangle, in every lane of its quad */
    const vf reach = vf_shuffle(most, most, 0x00), edge_max = vf_shuffle(most, most, 0x55);
    const vf det = vf_shuffle(det4, det4, 0x00), det_mag = vf_shuffle(mag4, mag4, 0x00);
    const vf area = vf_shuffle(area4, area4, 0x00);
    /* the orientation, with frusta_edges' cross_error and area term */
    const vf cross_error = vf_mul(reach, vf_mul(edge_max, vf_set1(FRUSTA_CROSS_ERROR)));
    const vf area_eps = vf_mul(vf_mul(area, vf_set1(FRUSTA_SQRT3)), vf_set1(FRUSTA_EPS));
    vm facing, backing;
    frusta_facing(det, det_mag, reach, area_eps, cross_error, &facing, &backing);
    s->facing = vm_bits(facing), s->backing = vm_bits(backing);
    /* facing: culled where an edge function stays below -margin over the
     * block; backing: where one stays above margin (its negation below).
     * Per edge (lane) its edge function's frame terms f[j] = sign n.frame[j]. */
    const vf sign = vf_blend(facing, vf_set1(-1.0f), vf_set1(1.0f));
    vf f[3];
    for (int j = 0; j < 3; j++)
        f[j] = vf_mul(sign, vf_add(vf_add(vf_mul(n[0], cone->frame_q[j][0]), vf_mul(n[1], cone->frame_q[j][1])),
                                   vf_mul(n[2], cone->frame_q[j][2])));
    const vf spread = vf_mul(vf_set1(1.5f), vf_add(vf_abs(f[1]), vf_abs(f[2])));
    vf_store(s->fx, f[1]), vf_store(s->fy, f[2]), vf_store(s->f0, vf_add(f[0], spread));
    vf_store(s->l1, vf_add(vf_add(vf_abs(n[0]), vf_abs(n[1])), vf_abs(n[2])));
    vf_store(s->cross_error, cross_error);
}

/* The frusta of `active` (pinhole frusta of cone) that triangle t of s may
 * reach.  `cull` (the back-face culling of a solid's triangle,
 * traverse_mft.c): +1 drops a triangle that faces the eye (D > margin:
 * behind its winding's normal), -1 one that backs it, 0 none. */
static inline uint32_t frusta_pinhole_cull(const frusta_pinhole_tris *s, uint32_t t, const mft_cone *cone, int cull,
                                           uint32_t active)
{
    const uint32_t at = 4u * t;
    const bool facing = s->facing >> at & 1u, backing = s->backing >> at & 1u;
    if (!facing && !backing) return active; /* the eye (nearly) in its plane */
    if ((cull > 0 && facing) || (cull < 0 && backing)) return 0;
    const vf normal_error = vf_mul(vf_set1(s->cross_error[at]), cone->l1);
    vm culled = vm_of_bits(0);
    for (uint32_t e = at; e < at + 3u; e++) {
        const vf top =
            vf_add(vf_add(vf_mul(vf_set1(s->fx[e]), cone->cx), vf_mul(vf_set1(s->fy[e]), cone->cy)), vf_set1(s->f0[e]));
        const vf margin = vf_add(vf_mul(vf_set1(s->l1[e]), cone->pixel_scale), normal_error);
        culled = vm_or(culled, vf_lt(vf_add(top, margin), vf_set1(0.0f)));
    }
    return active & ~vm_bits(culled);
}

/* frusta_cull over the cone of four corner directions per frustum
 * (corner[c][axis], each known to within corner_grow per axis, as are the
 * rays' directions on the corners' scale; corner_max the largest
 * |component| and corner_l1 the largest |corner|_1 of a frustum's
 * corners): every direction of the frustum is a positive combination of
 * them (the paper's corner rays), a tighter bound than their box.  One
 * margin per edge and frustum, as frusta_triangle_pinhole's: |n.c| <=
 * |n|_1 corner_max for every corner c, so |n|_1 (eps corner_max +
 * corner_grow) covers frusta_cull's eps times n.d's terms and the corners'
 * rounding, and cross_error corner_l1 n's; three products an edge and
 * corner, no magnitudes.  The caller makes t (frusta_edges), and
 * facing and backing by frusta_orientation, and may read its normal after. */
static inline uint32_t frusta_triangle_cone(const frusta_tri *t, const vf corner[4][3], vf corner_max, vf corner_l1,
                                            vf corner_grow, vm active, uint32_t facing, uint32_t backing)
{
    const vf zero = vf_set1(0.0f), normal_error = vf_mul(t->cross_error, corner_l1);
    const vf scale = vf_add(vf_mul(vf_set1(FRUSTA_EPS), corner_max), corner_grow);
    vm below = vm_of_bits(0), above = vm_of_bits(0);
    for (int e = 0; e < 3; e++) {
        const vf *n = t->n[e];
        vf hi = vf_set1(-INFINITY), lo = vf_set1(INFINITY);
        for (int c = 0; c < 4; c++) {
            const vf dot = vf_add(vf_add(vf_mul(n[0], corner[c][0]), vf_mul(n[1], corner[c][1])),
                                  vf_mul(n[2], corner[c][2]));
            hi = vf_max(dot, hi), lo = vf_min(dot, lo);
        }
        const vf margin =
            vf_add(vf_mul(vf_add(vf_add(vf_abs(n[0]), vf_abs(n[1])), vf_abs(n[2])), scale), normal_error);
        below = vm_or(below, vf_lt(hi, vf_sub(zero, margin)));
        above = vm_or(above, vf_gt(lo, margin));
    }
    return vm_bits(active) & ~((facing & vm_bits(below)) | (backing & vm_bits(above)));
}

/* A subtree left for later: its child record, the frusta that entered it
 * and the epoch of the frusta's bounds they entered under (the caller's
 * count of changes to `dist`; MFT_UNTESTED for a box never tested). */
typedef struct mft_entry {
    const bvh_child *child;
    uint32_t frusta, epoch;
} mft_entry;

#define MFT_UNTESTED UINT32_MAX

/* What child c refers to, asked for while its box is tested: its node, or
 * its leaf's corners (the frusta's first read there). */
static inline void mft_prefetch(const bvh_tree *tree, const bvh_child *c)
{
    if (c->count == 0) {
        __builtin_prefetch(&tree->nodes[c->index]);
    } else {
        __builtin_prefetch(&tree->corners[c->index]);
        __builtin_prefetch(&tree->corners[c->index + c->count - 1u]);
    }
}

/* Does child c's box hold the frusta's ends box (mft_bounds.ends_lo, hi)? */
static inline bool mft_holds_ends(const bvh_child *c, const mft_bounds *b)
{
    return b->ends_known && c->lo[0] <= b->ends_lo[0] && c->lo[1] <= b->ends_lo[1] && c->lo[2] <= b->ends_lo[2] &&
           c->hi[0] >= b->ends_hi[0] && c->hi[1] >= b->ends_hi[1] && c->hi[2] >= b->ends_hi[2];
}

/* Set in an entry's frusta (and mft_descend's lanes) when its child holds
 * the ends box: only then may its children hold it too. */
#define MFT_HOLDS_ENDS (1u << 31)
_Static_assert(BVH_W < 32, "MFT_HOLDS_ENDS is above every lane's bit");

/* From child c with the frusta *lanes that enter it, down to a leaf: per
 * node both children against every frustum in one pass, the child more
 * frusta enter first first, the other pushed with its frusta (and
 * `epoch`).  While the node holds the frusta's ends box (MFT_HOLDS_ENDS in
 * *lanes and on the stack: a child can hold it only if its parent does), a
 * child that holds it too is entered by every frustum without a test, at
 * tnear; taking a box as entered can only add work, never lose a hit.
 * Soft shadows on the maps: 17% of the box tests (their frusta all end at
 * one small light, inside many big boxes).  The loop in this form (the
 * lanes' masks kept to their bits) ran frusta:16 on the maps 16-28%
 * quicker than the form before it even without that (GCC 12's code for
 * it; bench/results/bvh-mft.md, fifteenth session).  Returns
 * the leaf reached, *lanes its frusta (0: none left, nothing to test). */
static inline const bvh_child *mft_descend(const bvh_tree *tree, const bvh_child *c, uint32_t *lanes,
                                           const mft_bounds *b, vf dist, uint32_t epoch, mft_entry *stack,
                                           uint32_t *top, uint64_t *aabb_tests)
{
    uint32_t live = *lanes;
    while ((live & BVH_LANES_ALL) && c->count == 0) {
        const bvh_node *node = &tree->nodes[c->index];
        for (int k = 0; k < 2; k++) mft_prefetch(tree, &node->child[k]);
        vf e0, e1;
        const vm active = vm_of_bits(live & BVH_LANES_ALL);
        uint32_t l0, l1;
        if (live & MFT_HOLDS_ENDS) {
            const bool h0 = mft_holds_ends(&node->child[0], b), h1 = mft_holds_ends(&node->child[1], b);
            if (h0) l0 = (live & BVH_LANES_ALL) | MFT_HOLDS_ENDS, e0 = b->tnear;
            else l0 = vm_bits(frusta_box(&node->child[0], b, dist, active, &e0)), ++*aabb_tests;
            if (h1) l1 = (live & BVH_LANES_ALL) | MFT_HOLDS_ENDS, e1 = b->tnear;
            else l1 = vm_bits(frusta_box(&node->child[1], b, dist, active, &e1)), ++*aabb_tests;
        } else {
            l0 = vm_bits(frusta_box(&node->child[0], b, dist, active, &e0));
            l1 = vm_bits(frusta_box(&node->child[1], b, dist, active, &e1));
            *aabb_tests += 2;
        }
        if ((l0 & BVH_LANES_ALL) && (l1 & BVH_LANES_ALL)) {
            const uint32_t both = l0 & l1 & BVH_LANES_ALL;
            const uint32_t first0 = vm_bits(vm_and(vm_of_bits(both), vf_le(e0, e1)));
            const int near = __builtin_popcount(first0) * 2 < __builtin_popcount(both);
            if (*top < BVH_TRAVERSAL_STACK)
                stack[(*top)++] = (mft_entry){&node->child[!near], near ? l0 : l1, epoch};
            c = &node->child[near];
            live = near ? l1 : l0;
        } else {
            c = &node->child[(l1 & BVH_LANES_ALL) != 0];
            live = (l1 & BVH_LANES_ALL) ? l1 : l0;
        }
    }
    *lanes = live & BVH_LANES_ALL;
    return c;
}

/* The next leaf some frusta of `alive` reach: entries popped off the stack
 * and descended from; NULL when the stack is empty.  *lanes: the leaf's
 * frusta.  A popped box is tested again against the frusta still alive
 * when their bounds changed since it was pushed (`epoch`, the caller's
 * count of changes to dist, moved on); under the same bounds the test
 * would repeat its answer, so the frusta that entered it and are alive
 * still are taken as they are. */
static inline const bvh_child *mft_next_leaf(const bvh_tree *tree, const mft_bounds *b, vf dist, uint32_t epoch,
                                             uint32_t alive, mft_entry *stack, uint32_t *top, uint64_t *aabb_tests,
                                             uint32_t *lanes)
{
    while (*top > 0) {
        const mft_entry e = stack[--*top];
        uint32_t live = e.frusta & (alive | MFT_HOLDS_ENDS);
        if (e.epoch != epoch && (live & BVH_LANES_ALL)) {
            vf entry;
            live = vm_bits(frusta_box(e.child, b, dist, vm_of_bits(live & BVH_LANES_ALL), &entry)) |
                   (live & MFT_HOLDS_ENDS);
            ++*aabb_tests;
        }
        const bvh_child *c = mft_descend(tree, e.child, &live, b, dist, epoch, stack, top, aabb_tests);
        if (live) {
            *lanes = live;
            return c;
        }
    }
    return NULL;
}

#endif

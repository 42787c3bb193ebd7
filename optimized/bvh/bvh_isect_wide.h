/* The BVH leaves' triangle tests, BVH_W rays against one record, the one
 * place the BVH kernels test triangles (bvh-mono uses optimized/isect/'s
 * scalar forms through bvh_isect1_record):
 *
 *  - Wald's projected barycentric test on the kd_triangle record
 *    (isect_projected_bary.h), the same arithmetic in the same order as its
 *    four-lane SSE form;
 *  - Woop, Benthin & Wald's watertight test on the record's corners
 *    (isect_woop_watertight.h), the same arithmetic in the same order as
 *    its four-lane SSE form: lanes grouped by the ray's dominant axis kz
 *    (bvh_wt_prepare, once per packet: the shear depends on the ray only),
 *    edge functions per triangle, a lane whose edge function, determinant or
 *    scaled t is zero, subnormal, infinite or NaN decided again in double by
 *    the same scalar function the kd kernels use (wt_decide1).
 *
 * So under either test a lane's t, u, v are bit-identical to the kd
 * kernels' and to every other width's.  bvh_isect_record and
 * bvh_occluded_record run the test the tree names (bvh_tree.watertight):
 * the kernels never branch on it themselves.
 *
 * Ties: a lane takes a hit when t is strictly closer, or equally close with a
 * smaller prim.  NaN never hits (every comparison with NaN is false). */
#ifndef RTT_BVH_ISECT_WIDE_H
#define RTT_BVH_ISECT_WIDE_H

#include <float.h>

#include "bvh_packet.h"
#include "bvh_tree.h"
#include "bvh_wt_lanes.h"
#include "isect_projected_bary.h"
#include "isect_woop_watertight.h"

/* The lanes under `active` whose ray hits `tri` with tnear < t < tfar and
 * t <= tbest; t, beta, gamma of every lane in the outputs. */
static inline vm bvh_isect_projected_mask(const kd_triangle *tri, const bvh_packet *r, vm active, vf tbest, vf *t_out,
                                          vf *beta_out, vf *gamma_out)
{
    const uint32_t k = tri->k, ku = kd_axis_u[k], kv = kd_axis_v[k];
    const vf nu = vf_set1(tri->n_u), nv = vf_set1(tri->n_v);
    /* relative to vertex 0: the error follows the triangle's size, not its place */
    const vf rk = vf_sub(vf_set1(tri->a_k), r->org[k]);
    const vf ru = vf_sub(vf_set1(tri->a_u), r->org[ku]);
    const vf rv = vf_sub(vf_set1(tri->a_v), r->org[kv]);
    const vf den = vf_add(r->dir[k], vf_add(vf_mul(nu, r->dir[ku]), vf_mul(nv, r->dir[kv])));
    const vf num = vf_add(rk, vf_add(vf_mul(nu, ru), vf_mul(nv, rv)));
    const vf t = vf_div(num, den);
    vm valid = vm_and(active, vm_and(vf_gt(t, r->tnear), vf_lt(t, r->tfar)));
    valid = vm_and(valid, vf_le(t, tbest));
    *t_out = t;
    if (vm_bits(valid) == 0) {
        *beta_out = *gamma_out = vf_set1(0.0f);
        return valid;
    }
    const vf hu = vf_sub(vf_mul(t, r->dir[ku]), ru);
    const vf hv = vf_sub(vf_mul(t, r->dir[kv]), rv);
    const vf beta = vf_add(vf_mul(vf_set1(tri->b_nu), hu), vf_mul(vf_set1(tri->b_nv), hv));
    const vf gamma = vf_add(vf_mul(vf_set1(tri->c_nu), hu), vf_mul(vf_set1(tri->c_nv), hv));
    const vf zero = vf_set1(0.0f);
    valid = vm_and(valid, vm_and(vf_ge(beta, zero), vf_ge(gamma, zero)));
    valid = vm_and(valid, vf_le(vf_add(beta, gamma), vf_set1(1.0f)));
    *beta_out = beta, *gamma_out = gamma;
    return valid;
}

/* Closest hit: lowers the lanes of `hits` under `active` that hit `tri`
 * closer (or as close with a smaller prim); returns the lanes it lowered. */
static inline uint32_t bvh_isect_projected(const kd_triangle *tri, const bvh_packet *r, bvh_hits *hits, vm active)
{
    vf t, beta, gamma;
    vm valid = bvh_isect_projected_mask(tri, r, active, hits->t, &t, &beta, &gamma);
    if (vm_bits(valid) == 0) return 0;
    const vi prim = vi_set1(tri->prim);
    const vm closer = vm_or(vf_lt(t, hits->t), vm_and(vf_eq(t, hits->t), vi_lt_u(prim, hits->prim)));
    valid = vm_and(valid, closer);
    hits->t = vf_blend(valid, hits->t, t);
    hits->u = vf_blend(valid, hits->u, beta);
    hits->v = vf_blend(valid, hits->v, gamma);
    hits->prim = vi_blend(valid, hits->prim, prim);
    return vm_bits(valid);
}

/* Occlusion: the lanes under `active` whose ray hits `tri` in (tnear, tfar). */
static inline uint32_t bvh_occluded_projected(const kd_triangle *tri, const bvh_packet *r, vm active)
{
    vf t, beta, gamma;
    return vm_bits(bvh_isect_projected_mask(tri, r, active, vf_set1(INFINITY), &t, &beta, &gamma));
}

/* ---- the watertight test ---- */

/* A packet's lanes grouped by dominant direction axis (ties to the smaller
 * axis: |x| >= |y|, |x| >= |z| -> 0), each group's axes and shear
 * sx = d_kx / d_kz, sy = d_ky / d_kz, sz = 1 / d_kz. */
typedef struct bvh_wt_shears {
    uint32_t count;                     /* groups holding a lane: 0 to 3, 1 for coherent rays */
    uint32_t lanes[3], kx[3], ky[3], kz[3];
    vf sx[3], sy[3], sz[3];
} bvh_wt_shears;

static inline void bvh_wt_prepare(const bvh_packet *r, uint32_t live, bvh_wt_shears *s)
{
    const vf ax = vf_abs(r->dir[0]), ay = vf_abs(r->dir[1]), az = vf_abs(r->dir[2]);
    const uint32_t x = vm_bits(vm_and(vf_ge(ax, ay), vf_ge(ax, az)));
    const uint32_t y = vm_bits(vf_ge(ay, az)) & ~x;
    const uint32_t masks[3] = {x, y, BVH_LANES_ALL & ~(x | y)};
    s->count = 0;
    for (uint32_t kz = 0; kz < 3; kz++) {
        const uint32_t lanes = masks[kz] & live;
        if (!lanes) continue;
        const uint32_t g = s->count++, kx = kz == 2 ? 0 : kz + 1, ky = kz == 0 ? 2 : kz - 1;
        s->lanes[g] = lanes, s->kx[g] = kx, s->ky[g] = ky, s->kz[g] = kz;
        s->sx[g] = vf_div(r->dir[kx], r->dir[kz]);
        s->sy[g] = vf_div(r->dir[ky], r->dir[kz]);
        s->sz[g] = vf_div(vf_set1(1.0f), r->dir[kz]);
    }
}

/* The lanes `slow` of a watertight test decided as the scalar form
 * decides them (wt_decide1, in double), from the sheared corners `parts`
 * (ax, ay, az, bx, .. cz); `valid` with those lanes' answers, their t, u, v
 * in *t, *u, *v.  Out of line: rare, and it keeps the float path small
 * enough to inline into the kernels' leaf loops. */
static __attribute__((noinline)) uint32_t bvh_wt_decide_lanes(const vf parts[9], const bvh_packet *r, vf tbest,
                                                             uint32_t slow, uint32_t valid, vf *t, vf *u, vf *v)
{
    _Alignas(64) float lane[9][BVH_W], tl[BVH_W], ul[BVH_W], vl[BVH_W], tn[BVH_W], tf[BVH_W], tb[BVH_W];
    for (int i = 0; i < 9; i++) vf_store(lane[i], parts[i]);
    vf_store(tl, *t), vf_store(ul, *u), vf_store(vl, *v);
    vf_store(tn, r->tnear), vf_store(tf, r->tfar), vf_store(tb, tbest);
    for (uint32_t bits = slow; bits; bits &= bits - 1u) {
        const uint32_t l = (uint32_t)__builtin_ctz(bits);
        const wt_lane one = {lane[0][l], lane[1][l], lane[2][l], lane[3][l], lane[4][l],
                             lane[5][l], lane[6][l], lane[7][l], lane[8][l]};
        const bool hit = wt_decide1(&one, tn[l], tf[l], &tl[l], &ul[l], &vl[l]) && tl[l] <= tb[l];
        valid = hit ? valid | 1u << l : valid & ~(1u << l);
    }
    *t = vf_load(tl), *u = vf_load(ul), *v = vf_load(vl);
    return valid;
}

/* The lanes `active` (inside group g of s) whose ray hits `tri` with
 * tnear < t < tfar and t <= tbest; t, u, v of those lanes in the outputs
 * (u, v only when `want_uv`).  isect4_watertight_mask at packet width.
 * Always inlined into the closest-hit test (bvh_isect_watertight): GCC 12
 * left it a call in the multi-frusta and packet kernels, whose outputs
 * then went through memory (bvh-mft-camera +1 to +4%, the medians of
 * pinned A/B pairs, bench/results/bvh-mft.md, seventeenth session); the occlusion test takes
 * it through bvh_isect_watertight_mask, inlined or not as GCC weighs it
 * (forced there too it cost the maps' frusta:16 about 4%). */
static inline __attribute__((always_inline)) uint32_t
bvh_wt_mask_inlined(const bvh_corners *tri, const bvh_packet *r, const bvh_wt_shears *s, uint32_t g, uint32_t active,
                    vf tbest, bool want_uv, vf *t_out, vf *u_out, vf *v_out)
{
    const uint32_t kx = s->kx[g], ky = s->ky[g], kz = s->kz[g];
    const float *pa = tri->v[0], *pb = tri->v[1], *pc = tri->v[2];
    const vf akx = vf_sub(vf_set1(pa[kx]), r->org[kx]), aky = vf_sub(vf_set1(pa[ky]), r->org[ky]);
    const vf akz = vf_sub(vf_set1(pa[kz]), r->org[kz]);
    const vf bkx = vf_sub(vf_set1(pb[kx]), r->org[kx]), bky = vf_sub(vf_set1(pb[ky]), r->org[ky]);
    const vf bkz = vf_sub(vf_set1(pb[kz]), r->org[kz]);
    const vf ckx = vf_sub(vf_set1(pc[kx]), r->org[kx]), cky = vf_sub(vf_set1(pc[ky]), r->org[ky]);
    const vf ckz = vf_sub(vf_set1(pc[kz]), r->org[kz]);
    const vf sx = s->sx[g], sy = s->sy[g];
    const vf ax = vf_sub(akx, vf_mul(sx, akz)), ay = vf_sub(aky, vf_mul(sy, akz));
    const vf bx = vf_sub(bkx, vf_mul(sx, bkz)), by = vf_sub(bky, vf_mul(sy, bkz));
    const vf cx = vf_sub(ckx, vf_mul(sx, ckz)), cy = vf_sub(cky, vf_mul(sy, ckz));
    const vf u = vf_sub(vf_mul(cx, by), vf_mul(cy, bx));
    const vf v = vf_sub(vf_mul(ax, cy), vf_mul(ay, cx));
    const vf w = vf_sub(vf_mul(bx, ay), vf_mul(by, ax));
    const vf zero = vf_set1(0.0f);
    /* the common case first: a miss decided by the signs alone, all three
     * positive or all negative by their least and greatest (exact for the
     * lanes without a NaN; a NaN lane is not normal, so decided below by
     * the double path whatever this says) */
    const uint32_t positive = vm_bits(vf_gt(vf_min(vf_min(u, v), w), zero));
    const uint32_t negative = vm_bits(vf_lt(vf_max(vf_max(u, v), w), zero));
    const uint32_t inside = active & (positive | negative);
    /* a lane with a zero, subnormal, infinite or NaN edge function is the
     * double path's, whatever its signs say */
    const uint32_t edges_normal = vm_bits(bvh_wt_normal3(u, v, w));
    if ((inside | (active & ~edges_normal)) == 0) return 0;
    const vf sz = s->sz[g];
    const vf az = vf_mul(sz, akz), bz = vf_mul(sz, bkz), cz = vf_mul(sz, ckz);
    const vf det = vf_add(vf_add(u, v), w);
    const vf t_scaled = vf_add(vf_add(vf_mul(u, az), vf_mul(v, bz)), vf_mul(w, cz));
    const uint32_t normal = edges_normal & vm_bits(vm_and(bvh_wt_normal(det), bvh_wt_normal(t_scaled)));
    vf t = vf_div(t_scaled, det);
    uint32_t valid = inside & normal & vm_bits(vm_and(vm_and(vf_gt(t, r->tnear), vf_lt(t, r->tfar)), vf_le(t, tbest)));
    vf bu = zero, bv = zero;
    if (want_uv && valid) bu = vf_div(v, det), bv = vf_div(w, det);
    /* the flat and short lanes' answer is no, without asking the scalar form */
    const uint32_t slow =
        bvh_wt_undecided(active & ~normal, ax, ay, az, bx, by, bz, cx, cy, cz, det, t_scaled, r->tnear);
    if (slow) { /* rare: those lanes decided as the scalar form decides them */
        const vf parts[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
        valid = bvh_wt_decide_lanes(parts, r, tbest, slow, valid, &t, &bu, &bv);
    }
    *t_out = t, *u_out = bu, *v_out = bv;
    return valid;
}

static inline uint32_t bvh_isect_watertight_mask(const bvh_corners *tri, const bvh_packet *r, const bvh_wt_shears *s,
                                                 uint32_t g, uint32_t active, vf tbest, bool want_uv, vf *t_out,
                                                 vf *u_out, vf *v_out)
{
    return bvh_wt_mask_inlined(tri, r, s, g, active, tbest, want_uv, t_out, u_out, v_out);
}

/* Closest hit of every group: lowers the lanes of `hits` under `active`
 * that hit `tri` closer (or as close with a smaller prim, tri->prim);
 * returns the lanes it lowered. */
static inline uint32_t bvh_isect_watertight(const bvh_corners *tri, const bvh_packet *r,
                                            const bvh_wt_shears *s, bvh_hits *hits, uint32_t active)
{
    uint32_t lowered = 0;
    for (uint32_t g = 0; g < s->count; g++) {
        const uint32_t lanes = active & s->lanes[g];
        if (!lanes) continue;
        vf t, u, v;
        uint32_t bits = bvh_wt_mask_inlined(tri, r, s, g, lanes, hits->t, true, &t, &u, &v);
        if (!bits) continue;
        const vi prim = vi_set1(tri->prim);
        const vm closer = vm_or(vf_lt(t, hits->t), vm_and(vf_eq(t, hits->t), vi_lt_u(prim, hits->prim)));
        const vm valid = vm_and(vm_of_bits(bits), closer);
        hits->t = vf_blend(valid, hits->t, t);
        hits->u = vf_blend(valid, hits->u, u);
        hits->v = vf_blend(valid, hits->v, v);
        hits->prim = vi_blend(valid, hits->prim, prim);
        lowered |= vm_bits(valid);
    }
    return lowered;
}

/* Occlusion: the lanes under `active` whose ray crosses `tri` in (tnear, tfar). */
static inline uint32_t bvh_occluded_watertight(const bvh_corners *tri, const bvh_packet *r, const bvh_wt_shears *s,
                                               uint32_t active)
{
    uint32_t hit = 0;
    for (uint32_t g = 0; g < s->count; g++) {
        const uint32_t lanes = active & s->lanes[g];
        if (!lanes) continue;
        vf t, u, v;
        hit |= bvh_isect_watertight_mask(tri, r, s, g, lanes, vf_set1(INFINITY), false, &t, &u, &v);
    }
    return hit;
}

/* ---- the test the tree names ---- */

/* The shears of packet r's lanes `live` when the tree runs the watertight
 * test (then `s`), NULL for the projected test: once per packet. */
static inline const bvh_wt_shears *bvh_record_setup(const bvh_tree *tree, const bvh_packet *r, uint32_t live,
                                                    bvh_wt_shears *s)
{
    if (!tree->watertight) return NULL;
    bvh_wt_prepare(r, live, s);
    return s;
}

/* Closest hit against record `rec` under the tree's test (`s` from
 * bvh_record_setup); returns the lanes it lowered. */
static inline uint32_t bvh_isect_record(const bvh_tree *tree, uint32_t rec, const bvh_packet *r,
                                        const bvh_wt_shears *s, bvh_hits *hits, uint32_t active)
{
    if (s) return bvh_isect_watertight(&tree->corners[rec], r, s, hits, active);
    return bvh_isect_projected(&tree->triangles[rec], r, hits, vm_of_bits(active));
}

/* Occlusion against record `rec` under the tree's test. */
static inline uint32_t bvh_occluded_record(const bvh_tree *tree, uint32_t rec, const bvh_packet *r,
                                           const bvh_wt_shears *s, uint32_t active)
{
    if (s) return bvh_occluded_watertight(&tree->corners[rec], r, s, active);
    return bvh_occluded_projected(&tree->triangles[rec], r, vm_of_bits(active));
}

/* One ray (bvh-mono) against record `rec` under the tree's test (`s` from
 * wt_ray1_setup when watertight): the closest hit lowered into *hit, or
 * with hit NULL true when the ray crosses the record. */
static inline bool bvh_isect1_record(const bvh_tree *tree, uint32_t rec, const kd_ray1 *ray, const wt_ray1 *s,
                                     kd_hit1 *hit)
{
    if (!tree->watertight) {
        if (!hit) return occluded1_projected_bary(&tree->triangles[rec], ray);
        isect1_projected_bary(&tree->triangles[rec], ray, hit);
        return false;
    }
    const bvh_corners *c = &tree->corners[rec];
    float t, u, v;
    if (!isect1_watertight_corners(c->v[0], c->v[1], c->v[2], ray, s, &t, &u, &v)) return false;
    if (!hit) return true;
    const uint32_t prim = c->prim;
    if (t < hit->t || (t == hit->t && prim < hit->prim)) *hit = (kd_hit1){t, u, v, prim};
    return false;
}

#endif

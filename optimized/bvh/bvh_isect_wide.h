/* The BVH leaves' triangle test, BVH_W rays against one record: Wald's
 * projected barycentric test on the kd_triangle record (optimized/isect/,
 * isect_projected_bary.h), the same arithmetic in the same order as its
 * four-lane SSE form, so a lane's t, u, v are bit-identical to the kd
 * kernels' and to every other width's.  The one place the BVH kernels test
 * triangles at packet width (the single-ray kernel uses the header's scalar
 * twin): a second triangle test for the BVH goes beside this one.
 *
 * Ties: a lane takes a hit when t is strictly closer, or equally close with a
 * smaller prim.  NaN never hits (every comparison with NaN is false). */
#ifndef RTT_BVH_ISECT_WIDE_H
#define RTT_BVH_ISECT_WIDE_H

#include "bvh_packet.h"
#include "isect_projected_bary.h"

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

#endif

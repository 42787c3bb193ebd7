/* The watertight test's per-lane predicates in the width-generic
 * vocabulary (bvh_simd.h), one copy per instruction set: the BVH leaves'
 * test (bvh_isect_wide.h) and the perspective grids' shadow kernel
 * (../pgrid/pgrid_shadow.c) take the float path only on lanes whose values
 * are all normal, and both spare the double path the lanes it would answer
 * "no" anyway (flat lanes, and lanes whose t is provably below tnear). */
#ifndef RTT_BVH_WT_LANES_H
#define RTT_BVH_WT_LANES_H

#include <float.h>
#include <math.h>

#include "bvh_simd.h"

/* Normal floats: neither zero, subnormal, infinite nor NaN. */
static inline vm bvh_wt_normal(vf x)
{
    const vf a = vf_abs(x);
    return vm_and(vf_ge(a, vf_set1(FLT_MIN)), vf_lt(a, vf_set1(INFINITY)));
}

/* bvh_wt_normal(u) & bvh_wt_normal(v) & bvh_wt_normal(w), by the bits of
 * |u|, |v|, |w| (ordered as the magnitudes, NaN above infinity): the
 * smallest at least FLT_MIN's, the largest below infinity's. */
static inline vm bvh_wt_normal3(vf u, vf v, vf w)
{
    const vi au = vf_abs_bits(u), av = vf_abs_bits(v), aw = vf_abs_bits(w);
    const vi lo = vi_min_s(vi_min_s(au, av), aw), hi = vi_max_s(vi_max_s(au, av), aw);
    return vm_and(vi_gt_s(lo, vi_set1(0x007fffffu)), vi_gt_s(vi_set1(0x7f800000u), hi));
}

/* The lanes whose three sheared corners lie in the origin's kz plane (az =
 * bz = cz = 0: a map's axis-aligned floor under a shadow ray's own origin,
 * the common case of the double path) and whose tnear >= 0: T = 0 in
 * double too, so t = +-0, never above tnear, and the scalar form
 * (wt_decide1) would answer no. */
static inline uint32_t bvh_wt_flat_lanes(vf az, vf bz, vf cz, vf tnear)
{
    const vf zero = vf_set1(0.0f);
    return vm_bits(vm_and(vm_and(vf_eq(az, zero), vf_eq(bz, zero)), vm_and(vf_eq(cz, zero), vf_ge(tnear, zero))));
}

/* The lanes whose t the double path would find below tnear > 0 although
 * T (t_scaled) came out zero or subnormal in float: an origin in or near
 * the triangle's plane, as a map's shadow ray from a point on a floor meets
 * the walls that stand on it (the flat lanes' neighbours).  With
 * E = |az| (|cx by| + |cy bx|) + |bz| (|ax cy| + |ay cx|) + |cz| (|bx ay| +
 * |by ax|) and D the sum of those six products, float u, v, w are within
 * 2^-23 of their terms, so float T is within 2^-21 E of the exact T and
 * float det within 2^-21 D of the exact det; the double path's T and det
 * are within 2^-50 of them.  Every float operation adds at most 2^-150
 * absolutely besides (subnormal results): FLT_MIN covers the sum of them.
 * So when (|T| + 2^-20 E + FLT_MIN) < tnear (|det| - 2^-20 D - FLT_MIN)
 * (1 - 2^-20), the double path's |t| is below tnear even after its
 * rounding to float, and wt_decide1 answers no (as it does for mixed signs
 * or det = 0).  Inf or NaN anywhere fails the comparison: those lanes stay
 * the double path's. */
static inline uint32_t bvh_wt_short_lanes(vf ax, vf ay, vf az, vf bx, vf by, vf bz, vf cx, vf cy, vf cz, vf det,
                                          vf t_scaled, vf tnear)
{
    const vf eu = vf_add(vf_abs(vf_mul(cx, by)), vf_abs(vf_mul(cy, bx)));
    const vf ev = vf_add(vf_abs(vf_mul(ax, cy)), vf_abs(vf_mul(ay, cx)));
    const vf ew = vf_add(vf_abs(vf_mul(bx, ay)), vf_abs(vf_mul(by, ax)));
    const vf e = vf_add(vf_add(vf_mul(eu, vf_abs(az)), vf_mul(ev, vf_abs(bz))), vf_mul(ew, vf_abs(cz)));
    const vf d = vf_add(vf_add(eu, ev), ew);
    const vf k = vf_set1(0x1p-20f), tiny = vf_set1(FLT_MIN), zero = vf_set1(0.0f);
    const vf t_bound = vf_add(vf_add(vf_abs(t_scaled), vf_mul(e, k)), tiny);
    const vf det_bound = vf_sub(vf_sub(vf_abs(det), vf_mul(d, k)), tiny);
    const vf reach = vf_mul(vf_mul(tnear, det_bound), vf_set1(1.0f - 0x1p-20f));
    return vm_bits(vm_and(vf_gt(tnear, zero), vm_and(vf_gt(det_bound, zero), vf_lt(t_bound, reach))));
}

/* Of the lanes `slow` the float path could not decide, those still owed
 * to the double path: less the flat and the short lanes, which it would
 * answer no (the short lanes' bound only when flat ones leave some). */
static inline uint32_t bvh_wt_undecided(uint32_t slow, vf ax, vf ay, vf az, vf bx, vf by, vf bz, vf cx, vf cy, vf cz,
                                        vf det, vf t_scaled, vf tnear)
{
    if (slow) slow &= ~bvh_wt_flat_lanes(az, bz, cz, tnear);
    if (slow) slow &= ~bvh_wt_short_lanes(ax, ay, az, bx, by, bz, cx, cy, cz, det, t_scaled, tnear);
    return slow;
}

#endif

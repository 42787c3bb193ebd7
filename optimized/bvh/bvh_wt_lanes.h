/* The watertight test's per-lane predicates in the width-generic
 * vocabulary (bvh_simd.h), one copy per instruction set: the BVH leaves'
 * test (bvh_isect_wide.h) and the perspective grids' shadow kernel
 * (../pgrid/pgrid_shadow.c) take the float path only on lanes whose values
 * are all normal, and both spare the double path the lanes it would answer
 * "no" anyway. */
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

#endif

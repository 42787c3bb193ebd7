/* Cone proxies (Thesis 4.1.7, Listings 4.4 and 4.5): the cone bounding a
 * group of rays (cone.c) and where it crosses a split plane, for the cone
 * and MFT-cone kernels (traverse_cone.c) and the cone shadow groups
 * (shadows/shadow_cone.c). */
#ifndef RTT_OPTIMIZED_CONE_H
#define RTT_OPTIMIZED_CONE_H

#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "block.h"
#include "simd4.h"

/* A cone (4.1.7): apex, unit axis, tan of the half angle and the per-axis
 * reciprocal denominators of Equation 4.8 (Listing 4.4).  near/far are in
 * tau units, the axis parameter (x - apex) . axis.  60 bytes, scalar: the
 * single-cone traversal reads it per node. */
typedef struct kd_cone {
    float apex[3], axis[3];
    float tan_angle;
    float pre[2][3];
    float near, far;
} kd_cone;
_Static_assert(sizeof(kd_cone) == 15 * sizeof(float), "kd_cone is 15 floats");

/* Four cones in SSE lanes (MFT-cone, 4.1.9): only what a split reads.  176
 * bytes: 11 SSE registers. */
typedef struct kd_cone4 {
    __m128 apex[3];
    __m128 pre0[3], pre1[3];
    __m128 near, far;
} kd_cone4;
_Static_assert(sizeof(kd_cone4) == 11 * sizeof(__m128), "kd_cone4 is the split's part of four kd_cones");

/* Cone of group g (apex behind all origins, half angle covering every
 * direction).  Returns 1 when built (and records the tau conversion in the
 * block), 0 when the group has no live ray, -1 when no cone narrower than
 * ~80 degrees bounds it or a ray starts before t = 0 (then the block is
 * traced packet by packet). */
int kd_cone_build(kd_block *block, uint32_t g, kd_cone *out);
/* Four cones into the lanes; absent lanes get an empty interval. */
void kd_cone4_pack(const kd_cone c[4], const int present[4], kd_cone4 *out);

/* Listing 4.5 at plane `split` on `axis`: the cone's disk starts to cross
 * into the back child at t1 and has left the front child at t2 (Equation
 * 4.8: the distance to the plane times the two precomputed reciprocals,
 * negative distances compensated to +inf); front is the side of the apex.
 * Beyond the listing: an apex exactly on the plane (dist == 0) would give
 * 0 * pre = 0 for both and send the whole cone to the back, so such a cone
 * visits both children with its full interval.  Widened relatively. */
static inline void kd_cone_split(const void *proxy, uint32_t axis, float split, float near, int *front_left,
                                 float *dmin, float *dmax)
{
    (void)near;
    const kd_cone *c = proxy;
    float dist = split - c->apex[axis];
    if (dist == 0.0f) {
        *front_left = 1, *dmin = -INFINITY, *dmax = INFINITY;
        return;
    }
    float t_a = dist * c->pre[0][axis], t_b = dist * c->pre[1][axis];
    t_a = t_a < 0.0f ? INFINITY : t_a;
    t_b = t_b < 0.0f ? INFINITY : t_b;
    *front_left = dist > 0.0f;
    /* neither is NaN: pre is finite or infinite, dist nonzero and finite */
    *dmin = kd_fmin1(t_a, t_b) * (1.0f - KD_WIDEN);
    *dmax = kd_fmax1(t_a, t_b) * (1.0f + KD_WIDEN);
}

/* The same for four cones in the lanes. */
static inline void kd_cone4_split(const void *proxy, uint32_t axis, float split, __m128 near, __m128 *front_left,
                                  __m128 *dmin, __m128 *dmax)
{
    (void)near;
    const kd_cone4 *c = proxy;
    const __m128 zero = _mm_setzero_ps(), pinf = _mm_set1_ps(INFINITY);
    __m128 dist = _mm_sub_ps(_mm_set1_ps(split), c->apex[axis]);
    __m128 t_a = _mm_mul_ps(dist, c->pre0[axis]), t_b = _mm_mul_ps(dist, c->pre1[axis]);
    t_a = _mm_blendv_ps(t_a, pinf, _mm_cmplt_ps(t_a, zero));
    t_b = _mm_blendv_ps(t_b, pinf, _mm_cmplt_ps(t_b, zero));
    __m128 on_plane = _mm_cmpeq_ps(dist, zero);
    __m128 lo = _mm_blendv_ps(_mm_min_ps(t_a, t_b), _mm_set1_ps(-INFINITY), on_plane);
    __m128 hi = _mm_blendv_ps(_mm_max_ps(t_a, t_b), pinf, on_plane);
    *dmin = _mm_mul_ps(lo, _mm_set1_ps(1.0f - KD_WIDEN));
    *dmax = _mm_mul_ps(hi, _mm_set1_ps(1.0f + KD_WIDEN));
    *front_left = _mm_cmpge_ps(dist, zero);
}

#endif

/* Interval frusta: the proxies of the frustum and MFT kernels (Thesis
 * 2.3.2, 4.1.3, 4.1.5), generalised from the thesis' corner rays to
 * arbitrary rays by interval arithmetic (frustum.c), and the four-lane
 * interval traversal over four of them (MFT, and the per-lane fallback of
 * every proxy kernel: block.c). */
#ifndef RTT_OPTIMIZED_FRUSTUM_H
#define RTT_OPTIMIZED_FRUSTUM_H

#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "block.h"
#include "traverse_interval.h"

/* Conservative interval-arithmetic frustum of a group of rays: origin box,
 * and per axis the range of positive and of |negative| reciprocal
 * directions.  A ray whose direction component has its sign bit clear
 * counts as positive (+0 gives +inf), set as negative.  Sentinels: pos_lo =
 * +inf when no positive ray (then has_pos = 0).  104 bytes, scalar: the
 * single-frustum traversal reads it per node. */
typedef struct kd_frustum {
    float org_lo[3], org_hi[3];
    float pos_lo[3], pos_hi[3];      /* 1/dir over rays with dir >= +0 */
    float neg_lo[3], neg_hi[3];      /* |1/dir| over rays with dir <= -0 */
    uint32_t has_pos[3], has_neg[3];
    float near, far;                 /* root interval, near > far when empty */
} kd_frustum;
_Static_assert(sizeof(kd_frustum) == 104, "kd_frustum is 26 floats");

/* Four frusta in SSE lanes (MFT, 4.1.5); masks are all-ones lanes.  416
 * bytes: 26 SSE registers, read lane-parallel per node. */
typedef struct kd_frustum4 {
    __m128 org_lo[3], org_hi[3];
    __m128 pos_lo[3], pos_hi[3];
    __m128 neg_lo[3], neg_hi[3];
    __m128 has_pos[3], has_neg[3];
    __m128 near, far;
} kd_frustum4;
_Static_assert(sizeof(kd_frustum4) == 26 * sizeof(__m128), "kd_frustum4 is kd_frustum in four lanes");

/* Frustum of group g of the block; false when the group has no live ray. */
int kd_frustum_build(const kd_block *block, uint32_t g, kd_frustum *out);
/* True when a frustum would bound its rays too loosely to pay: origins
 * spread over more than a hundredth of the scene, or mixed direction signs
 * on all three axes (random rays). */
int kd_frustum_is_incoherent(const kd_block *block, const kd_frustum *f);
/* Four frusta into the lanes; absent lanes get an empty interval. */
void kd_frustum4_pack(const kd_frustum f[4], const int present[4], kd_frustum4 *out);
/* One exact frustum per live lane of packet p (the per-lane fallback):
 * each lane's origin, its reciprocal direction and its root interval. */
void kd_frustum4_of_lanes(const kd_block *block, uint32_t p, kd_frustum4 *out);

/* dmin/dmax of each lane's frustum at plane `split` on `axis`, in
 * front-to-back terms (the SSE form of traverse_frustum.c's split): origins
 * all on the left of the plane (split - origin > 0) put the left child in
 * front, a ray with a positive direction crossing at (split - o) / dir and
 * one with a negative direction never (+inf); origins on the right the
 * mirror image; origins on both sides, or a lane whose interval starts
 * behind its origins, both children with the full interval. */
static inline void kd_frustum4_split(const void *proxy, uint32_t axis, float split, __m128 near, __m128 *front_left,
                                     __m128 *dmin, __m128 *dmax)
{
    const kd_frustum4 *f = proxy;
    const __m128 zero = _mm_setzero_ps(), pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
    __m128 s = _mm_set1_ps(split);
    __m128 a_lo = _mm_sub_ps(s, f->org_hi[axis]), a_hi = _mm_sub_ps(s, f->org_lo[axis]);
    __m128 ahead = _mm_cmpge_ps(near, zero);
    __m128 left = _mm_and_ps(_mm_cmpgt_ps(a_lo, zero), ahead);
    __m128 right = _mm_and_ps(_mm_cmplt_ps(a_hi, zero), ahead);
    __m128 dmin_left = _mm_mul_ps(a_lo, f->pos_lo[axis]);
    __m128 dmax_left = _mm_blendv_ps(_mm_mul_ps(a_hi, f->pos_hi[axis]), pinf, f->has_neg[axis]);
    __m128 dmin_right = _mm_mul_ps(_mm_sub_ps(zero, a_hi), f->neg_lo[axis]);
    __m128 dmax_right = _mm_blendv_ps(_mm_mul_ps(_mm_sub_ps(zero, a_lo), f->neg_hi[axis]), pinf, f->has_pos[axis]);
    __m128 lo = _mm_blendv_ps(_mm_blendv_ps(ninf, dmin_right, right), dmin_left, left);
    __m128 hi = _mm_blendv_ps(_mm_blendv_ps(pinf, dmax_right, right), dmax_left, left);
    *dmin = _mm_mul_ps(lo, _mm_set1_ps(1.0f - KD_WIDEN));
    *dmax = _mm_mul_ps(hi, _mm_set1_ps(1.0f + KD_WIDEN));
    *front_left = _mm_andnot_ps(right, _mm_castsi128_ps(_mm_set1_epi32(-1)));
}

/* The four-lane interval traversal (4.1.5) of the block's groups under four
 * frusta.  Inline here, not a function of traverse_mft.c, so that the MFT
 * kernel and the per-lane fallback (block.c) each expand it without calling
 * each other. */
static inline __attribute__((always_inline)) void kd_traverse4_frusta(kd_block *block, const kd_frustum4 *frusta)
{
    kd_traverse4(block, frusta, kd_frustum4_split, frusta->near, frusta->far);
}

#endif

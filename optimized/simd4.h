/* The small helpers every kernel shares: min/max without libm, horizontal
 * reductions of four SSE lanes, finiteness masks and the relative widening
 * of distances.  Header-only (static inline), so each kernel object
 * compiles its own copy for the instruction set it is built for. */
#ifndef RTT_OPTIMIZED_SIMD4_H
#define RTT_OPTIMIZED_SIMD4_H

#include <immintrin.h>

/* min/max that return the second operand when either is NaN, like minss /
 * maxss and _mm_min_ps / _mm_max_ps: one instruction each, where fminf /
 * fmaxf are libm calls without -ffast-math.  Callers that may see a NaN
 * put the operand to keep second. */
static inline float kd_min1(float a, float b) { return a < b ? a : b; }
static inline float kd_max1(float a, float b) { return a > b ? a : b; }
static inline double kd_min1d(double a, double b) { return a < b ? a : b; }
static inline double kd_max1d(double a, double b) { return a > b ? a : b; }

/* fmin / fmax exactly as libm computes them on x86-64 (minss/maxss on
 * ordered operands; a NaN operand is ignored), without the call: for code
 * whose operands may be NaN and which must keep libm's answer, such as the
 * cone build over rays some of whose lanes are degenerate.  One compare
 * more than kd_min1. */
static inline float kd_fmin1(float a, float b) { return a < b || b != b ? a : b; }
static inline float kd_fmax1(float a, float b) { return a > b || b != b ? a : b; }
static inline double kd_fmin1d(double a, double b) { return a < b || b != b ? a : b; }
static inline double kd_fmax1d(double a, double b) { return a > b || b != b ? a : b; }

/* Horizontal minimum, maximum and sum of the four lanes. */
static inline float kd_hmin4(__m128 v)
{
    v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(v);
}

static inline float kd_hmax4(__m128 v)
{
    v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(v);
}

static inline float kd_hsum4(__m128 v)
{
    v = _mm_add_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    v = _mm_add_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtss_f32(v);
}

/* All-ones lanes where x is finite: x - x is 0 only there (NaN otherwise). */
static inline __m128 kd_finite4(__m128 x) { return _mm_cmpeq_ps(_mm_sub_ps(x, x), _mm_setzero_ps()); }

/* x widened by the relative amount w, down (lo) or up (hi), whatever its
 * sign, keeping infinities: x - |x| w would turn +inf into NaN.  A NaN x
 * stays NaN (the min/max keep their second operand). */
static inline float kd_widen_lo(float x, float w) { return kd_min1(x * (1.0f - w), x * (1.0f + w)); }
static inline float kd_widen_hi(float x, float w) { return kd_max1(x * (1.0f - w), x * (1.0f + w)); }
static inline __m128 kd_widen_lo4(__m128 x, float w)
{
    return _mm_min_ps(_mm_mul_ps(x, _mm_set1_ps(1.0f - w)), _mm_mul_ps(x, _mm_set1_ps(1.0f + w)));
}
static inline __m128 kd_widen_hi4(__m128 x, float w)
{
    return _mm_max_ps(_mm_mul_ps(x, _mm_set1_ps(1.0f - w)), _mm_mul_ps(x, _mm_set1_ps(1.0f + w)));
}

#endif

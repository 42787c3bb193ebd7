/* The BVH kernels' SIMD vocabulary at the width of the instruction set
 * they are compiled for: 16 float lanes on AVX-512 (masks in k registers),
 * 8 on AVX2, 4 on SSE4.1 (masks as all-ones lanes).  Every operation is one
 * IEEE operation per lane in the same order on every width, and contraction
 * is off, so a lane computes the same bits whatever the width.
 *
 * min/max follow the x86 rule: when either operand is NaN the SECOND is
 * returned, so an accumulator passed second is never replaced by a NaN.
 * vf_abs_bits: a lane's bits with the sign cleared, as a signed integer
 * (0 .. 0x7fffffff: ordered as |x|, infinities above the finite, NaNs above
 * those), for vi_min_s/vi_max_s/vi_gt_s (signed 32-bit).
 * vf_load_records8: BVH_W records of eight floats, one word per field.
 * vf_hmin/vf_hmax: the smallest/largest lane (for NaN-free words; the
 * callers put +-inf in the lanes that must not count).
 * vi_mul: the low 32 bits of each lane's product; vf_trunc: each lane
 * truncated to a signed integer (for lanes within int32's range).
 * vf_gather: lane l from base[index lane l] (hardware gathers on AVX2 and
 * AVX-512, four loads on SSE4.1).
 * Quads: a vector as BVH_W / 4 independent groups of four lanes (SSE's
 * 128-bit lanes), each holding its own small vector (a triangle's corner
 * per lane, say).  vf_shuffle(a, b, imm) is _mm_shuffle_ps in every quad
 * (imm a compile-time constant), vf_unpacklo/hi _mm_unpacklo/hi_ps in
 * every quad, vf_load_quads quad q from the four floats at p[q]. */
#ifndef RTT_BVH_SIMD_H
#define RTT_BVH_SIMD_H

#include <immintrin.h>
#include <stdint.h>

#if defined(__AVX512F__) && defined(__AVX512DQ__)
#define BVH_W 16u
typedef __m512 vf;
typedef __m512i vi;
typedef __mmask16 vm;
static inline vf vf_set1(float x) { return _mm512_set1_ps(x); }
static inline vf vf_load(const float *p) { return _mm512_loadu_ps(p); }
static inline void vf_store(float *p, vf a) { _mm512_storeu_ps(p, a); }
static inline void vf_stream(float *p, vf a) { _mm512_stream_ps(p, a); } /* p on a 64-byte line */
static inline vf vf_add(vf a, vf b) { return _mm512_add_ps(a, b); }
static inline vf vf_sub(vf a, vf b) { return _mm512_sub_ps(a, b); }
static inline vf vf_mul(vf a, vf b) { return _mm512_mul_ps(a, b); }
static inline vf vf_div(vf a, vf b) { return _mm512_div_ps(a, b); }
static inline vf vf_sqrt(vf a) { return _mm512_sqrt_ps(a); }
static inline vf vf_min(vf a, vf b) { return _mm512_min_ps(a, b); }
static inline vf vf_max(vf a, vf b) { return _mm512_max_ps(a, b); }
static inline vm vf_lt(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
static inline vm vf_le(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
static inline vm vf_gt(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
static inline vm vf_ge(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
static inline vm vf_eq(vf a, vf b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
static inline vm vm_and(vm a, vm b) { return (vm)(a & b); }
static inline vm vm_or(vm a, vm b) { return (vm)(a | b); }
/* the 16 bits through kmovw into a general register (which zero-extends),
 * not the implicit conversion: GCC 12 at -O3 with -fsanitize=thread was seen
 * to spill a mask with a 16-bit kmovw and reload it as 32 bits, leaving
 * stack garbage in bits 16..31 (optimized/pgrid/pgrid_cell.c's vm_bits) */
static inline uint32_t vm_bits(vm a)
{
    uint32_t bits;
    __asm__("kmovw %1, %0" : "=r"(bits) : "k"(a));
    return bits;
}
static inline vm vm_of_bits(uint32_t bits) { return (vm)bits; }
/* lanes of m take b, the others a */
static inline vf vf_blend(vm m, vf a, vf b) { return _mm512_mask_blend_ps(m, a, b); }
static inline vi vi_set1(uint32_t x) { return _mm512_set1_epi32((int)x); }
static inline vi vi_load(const uint32_t *p) { return _mm512_loadu_si512(p); }
static inline void vi_store(uint32_t *p, vi a) { _mm512_storeu_si512(p, a); }
static inline vi vi_blend(vm m, vi a, vi b) { return _mm512_mask_blend_epi32(m, a, b); }
static inline vm vi_lt_u(vi a, vi b) { return _mm512_cmplt_epu32_mask(a, b); }
static inline vf vi_as_vf(vi a) { return _mm512_castsi512_ps(a); }
static inline vi vf_as_vi(vf a) { return _mm512_castps_si512(a); }
static inline vi vf_abs_bits(vf a) { return _mm512_and_si512(_mm512_castps_si512(a), _mm512_set1_epi32(0x7fffffff)); }
static inline vi vi_min_s(vi a, vi b) { return _mm512_min_epi32(a, b); }
static inline vi vi_add(vi a, vi b) { return _mm512_add_epi32(a, b); }
/* lane l = base[index lane l] (indices of valid floats) */
static inline vf vf_gather(const float *base, vi index) { return _mm512_i32gather_ps(index, base, 4); }
static inline vi vi_max_s(vi a, vi b) { return _mm512_max_epi32(a, b); }
static inline vm vi_gt_s(vi a, vi b) { return _mm512_cmpgt_epi32_mask(a, b); }
static inline vm vi_eq(vi a, vi b) { return _mm512_cmpeq_epi32_mask(a, b); }
static inline vi vi_mul(vi a, vi b) { return _mm512_mullo_epi32(a, b); }
static inline vi vf_trunc(vf a) { return _mm512_cvttps_epi32(a); }
static inline float vf_hmin(vf a) { return _mm512_reduce_min_ps(a); }
/* out[a] lane l = p[8 l + a]: BVH_W consecutive records of eight floats, a
 * field per word.  Rays l and l + 8 share a zmm, an 8x8 transpose per half. */
static inline void vf_load_records8(const float *p, vf out[8])
{
    __m512 r[8], t[8], u[8];
    for (int i = 0; i < 8; i++)
        r[i] = _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(p + 8 * i)), _mm256_loadu_ps(p + 64 + 8 * i), 1);
    for (int i = 0; i < 8; i += 2) t[i] = _mm512_unpacklo_ps(r[i], r[i + 1]), t[i + 1] = _mm512_unpackhi_ps(r[i], r[i + 1]);
    for (int i = 0; i < 8; i += 4) {
        u[i] = _mm512_shuffle_ps(t[i], t[i + 2], 0x44), u[i + 1] = _mm512_shuffle_ps(t[i], t[i + 2], 0xEE);
        u[i + 2] = _mm512_shuffle_ps(t[i + 1], t[i + 3], 0x44), u[i + 3] = _mm512_shuffle_ps(t[i + 1], t[i + 3], 0xEE);
    }
    const __m512i lo = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
    const __m512i hi = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
    for (int i = 0; i < 4; i++) {
        out[i] = _mm512_permutex2var_ps(u[i], lo, u[i + 4]);
        out[i + 4] = _mm512_permutex2var_ps(u[i], hi, u[i + 4]);
    }
}
static inline float vf_hmax(vf a) { return _mm512_reduce_max_ps(a); }
#define vf_shuffle(a, b, imm) _mm512_shuffle_ps((a), (b), (imm))
static inline vf vf_unpacklo(vf a, vf b) { return _mm512_unpacklo_ps(a, b); }
static inline vf vf_unpackhi(vf a, vf b) { return _mm512_unpackhi_ps(a, b); }
static inline vf vf_load_quads(const float *const p[4])
{
    const __m512 lo = _mm512_insertf32x4(_mm512_castps128_ps512(_mm_loadu_ps(p[0])), _mm_loadu_ps(p[1]), 1);
    return _mm512_insertf32x4(_mm512_insertf32x4(lo, _mm_loadu_ps(p[2]), 2), _mm_loadu_ps(p[3]), 3);
}
#elif defined(__AVX2__)
#define BVH_W 8u
typedef __m256 vf;
typedef __m256i vi;
typedef __m256 vm;
static inline vf vf_set1(float x) { return _mm256_set1_ps(x); }
static inline vf vf_load(const float *p) { return _mm256_loadu_ps(p); }
static inline void vf_store(float *p, vf a) { _mm256_storeu_ps(p, a); }
static inline void vf_stream(float *p, vf a) { _mm256_stream_ps(p, a); } /* p on 32 bytes */
static inline vf vf_add(vf a, vf b) { return _mm256_add_ps(a, b); }
static inline vf vf_sub(vf a, vf b) { return _mm256_sub_ps(a, b); }
static inline vf vf_mul(vf a, vf b) { return _mm256_mul_ps(a, b); }
static inline vf vf_div(vf a, vf b) { return _mm256_div_ps(a, b); }
static inline vf vf_sqrt(vf a) { return _mm256_sqrt_ps(a); }
static inline vf vf_min(vf a, vf b) { return _mm256_min_ps(a, b); }
static inline vf vf_max(vf a, vf b) { return _mm256_max_ps(a, b); }
static inline vm vf_lt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
static inline vm vf_le(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
static inline vm vf_gt(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
static inline vm vf_ge(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
static inline vm vf_eq(vf a, vf b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
static inline vm vm_and(vm a, vm b) { return _mm256_and_ps(a, b); }
static inline vm vm_or(vm a, vm b) { return _mm256_or_ps(a, b); }
static inline uint32_t vm_bits(vm a) { return (uint32_t)_mm256_movemask_ps(a); }
static inline vm vm_of_bits(uint32_t bits)
{
    const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i b = _mm256_and_si256(_mm256_set1_epi32((int)bits), lane);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(b, lane));
}
static inline vf vf_blend(vm m, vf a, vf b) { return _mm256_blendv_ps(a, b, m); }
static inline vi vi_set1(uint32_t x) { return _mm256_set1_epi32((int)x); }
static inline vi vi_load(const uint32_t *p) { return _mm256_loadu_si256((const __m256i *)p); }
static inline void vi_store(uint32_t *p, vi a) { _mm256_storeu_si256((__m256i *)p, a); }
static inline vf vi_as_vf(vi a) { return _mm256_castsi256_ps(a); }
static inline vi vf_as_vi(vf a) { return _mm256_castps_si256(a); }
static inline vi vf_abs_bits(vf a) { return _mm256_and_si256(_mm256_castps_si256(a), _mm256_set1_epi32(0x7fffffff)); }
static inline vi vi_min_s(vi a, vi b) { return _mm256_min_epi32(a, b); }
static inline vi vi_add(vi a, vi b) { return _mm256_add_epi32(a, b); }
static inline vf vf_gather(const float *base, vi index) { return _mm256_i32gather_ps(base, index, 4); }
static inline vi vi_max_s(vi a, vi b) { return _mm256_max_epi32(a, b); }
static inline vm vi_gt_s(vi a, vi b) { return _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b)); }
static inline vm vi_eq(vi a, vi b) { return _mm256_castsi256_ps(_mm256_cmpeq_epi32(a, b)); }
static inline vi vi_mul(vi a, vi b) { return _mm256_mullo_epi32(a, b); }
static inline vi vf_trunc(vf a) { return _mm256_cvttps_epi32(a); }
static inline vi vi_blend(vm m, vi a, vi b)
{
    return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(a), _mm256_castsi256_ps(b), m));
}
static inline vm vi_lt_u(vi a, vi b)
{
    const __m256i lt = _mm256_andnot_si256(_mm256_cmpeq_epi32(a, b), _mm256_cmpeq_epi32(_mm256_min_epu32(a, b), a));
    return _mm256_castsi256_ps(lt);
}
static inline void vf_load_records8(const float *p, vf out[8])
{
    __m256 r[8], t[8], u[8];
    for (int i = 0; i < 8; i++) r[i] = _mm256_loadu_ps(p + 8 * i);
    for (int i = 0; i < 8; i += 2) t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]), t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    for (int i = 0; i < 8; i += 4) {
        u[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44), u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xEE);
        u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44), u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xEE);
    }
    for (int i = 0; i < 4; i++) {
        out[i] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x20);
        out[i + 4] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x31);
    }
}
static inline float vf_hmin(vf a)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
static inline float vf_hmax(vf a)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
#define vf_shuffle(a, b, imm) _mm256_shuffle_ps((a), (b), (imm))
static inline vf vf_unpacklo(vf a, vf b) { return _mm256_unpacklo_ps(a, b); }
static inline vf vf_unpackhi(vf a, vf b) { return _mm256_unpackhi_ps(a, b); }
static inline vf vf_load_quads(const float *const p[2]) { return _mm256_set_m128(_mm_loadu_ps(p[1]), _mm_loadu_ps(p[0])); }
#else
#define BVH_W 4u
typedef __m128 vf;
typedef __m128i vi;
typedef __m128 vm;
static inline vf vf_set1(float x) { return _mm_set1_ps(x); }
static inline vf vf_load(const float *p) { return _mm_loadu_ps(p); }
static inline void vf_store(float *p, vf a) { _mm_storeu_ps(p, a); }
static inline void vf_stream(float *p, vf a) { _mm_stream_ps(p, a); } /* p on 16 bytes */
static inline vf vf_add(vf a, vf b) { return _mm_add_ps(a, b); }
static inline vf vf_sub(vf a, vf b) { return _mm_sub_ps(a, b); }
static inline vf vf_mul(vf a, vf b) { return _mm_mul_ps(a, b); }
static inline vf vf_div(vf a, vf b) { return _mm_div_ps(a, b); }
static inline vf vf_sqrt(vf a) { return _mm_sqrt_ps(a); }
static inline vf vf_min(vf a, vf b) { return _mm_min_ps(a, b); }
static inline vf vf_max(vf a, vf b) { return _mm_max_ps(a, b); }
static inline vm vf_lt(vf a, vf b) { return _mm_cmplt_ps(a, b); }
static inline vm vf_le(vf a, vf b) { return _mm_cmple_ps(a, b); }
static inline vm vf_gt(vf a, vf b) { return _mm_cmpgt_ps(a, b); }
static inline vm vf_ge(vf a, vf b) { return _mm_cmpge_ps(a, b); }
static inline vm vf_eq(vf a, vf b) { return _mm_cmpeq_ps(a, b); }
static inline vm vm_and(vm a, vm b) { return _mm_and_ps(a, b); }
static inline vm vm_or(vm a, vm b) { return _mm_or_ps(a, b); }
static inline uint32_t vm_bits(vm a) { return (uint32_t)_mm_movemask_ps(a); }
static inline vm vm_of_bits(uint32_t bits)
{
    const __m128i lane = _mm_setr_epi32(1, 2, 4, 8);
    const __m128i b = _mm_and_si128(_mm_set1_epi32((int)bits), lane);
    return _mm_castsi128_ps(_mm_cmpeq_epi32(b, lane));
}
static inline vf vf_blend(vm m, vf a, vf b) { return _mm_blendv_ps(a, b, m); }
static inline vi vi_set1(uint32_t x) { return _mm_set1_epi32((int)x); }
static inline vi vi_load(const uint32_t *p) { return _mm_loadu_si128((const __m128i *)p); }
static inline void vi_store(uint32_t *p, vi a) { _mm_storeu_si128((__m128i *)p, a); }
static inline vf vi_as_vf(vi a) { return _mm_castsi128_ps(a); }
static inline vi vf_as_vi(vf a) { return _mm_castps_si128(a); }
static inline vi vf_abs_bits(vf a) { return _mm_and_si128(_mm_castps_si128(a), _mm_set1_epi32(0x7fffffff)); }
static inline vi vi_min_s(vi a, vi b) { return _mm_min_epi32(a, b); }
static inline vi vi_add(vi a, vi b) { return _mm_add_epi32(a, b); }
static inline vf vf_gather(const float *base, vi index)
{
    return _mm_setr_ps(base[_mm_extract_epi32(index, 0)], base[_mm_extract_epi32(index, 1)],
                       base[_mm_extract_epi32(index, 2)], base[_mm_extract_epi32(index, 3)]);
}
static inline vi vi_max_s(vi a, vi b) { return _mm_max_epi32(a, b); }
static inline vm vi_gt_s(vi a, vi b) { return _mm_castsi128_ps(_mm_cmpgt_epi32(a, b)); }
static inline vm vi_eq(vi a, vi b) { return _mm_castsi128_ps(_mm_cmpeq_epi32(a, b)); }
static inline vi vi_mul(vi a, vi b) { return _mm_mullo_epi32(a, b); }
static inline vi vf_trunc(vf a) { return _mm_cvttps_epi32(a); }
static inline vi vi_blend(vm m, vi a, vi b)
{
    return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b), m));
}
static inline vm vi_lt_u(vi a, vi b)
{
    return _mm_castsi128_ps(_mm_andnot_si128(_mm_cmpeq_epi32(a, b), _mm_cmpeq_epi32(_mm_min_epu32(a, b), a)));
}
static inline void vf_load_records8(const float *p, vf out[8])
{
    for (int h = 0; h < 2; h++) {
        __m128 r0 = _mm_loadu_ps(p + 4 * h), r1 = _mm_loadu_ps(p + 8 + 4 * h);
        __m128 r2 = _mm_loadu_ps(p + 16 + 4 * h), r3 = _mm_loadu_ps(p + 24 + 4 * h);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        out[4 * h] = r0, out[4 * h + 1] = r1, out[4 * h + 2] = r2, out[4 * h + 3] = r3;
    }
}
static inline float vf_hmin(vf a)
{
    const __m128 m = _mm_min_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
static inline float vf_hmax(vf a)
{
    const __m128 m = _mm_max_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
#define vf_shuffle(a, b, imm) _mm_shuffle_ps((a), (b), (imm))
static inline vf vf_unpacklo(vf a, vf b) { return _mm_unpacklo_ps(a, b); }
static inline vf vf_unpackhi(vf a, vf b) { return _mm_unpackhi_ps(a, b); }
static inline vf vf_load_quads(const float *const p[1]) { return _mm_loadu_ps(p[0]); }
#endif

/* |x|; NaN stays NaN (the second operand of the max) */
static inline vf vf_abs(vf x) { return vf_max(x, vf_sub(vf_set1(0.0f), x)); }

/* BVH_SLAB_SLACK: the relative slack of every kernel's box test.  A slab
 * distance (box plane - origin) / d is rounded three times, so it is off by
 * up to 3 ulps of itself: of the origin's distance, which the builder's
 * widening of the boxes (by their own size and coordinates) does not
 * cover, so a tiny box far from the origin would lose a ray that grazes
 * it.  bvh_interval_holds tests the interval [t0, t1] with t1 moved out by
 * 2^-19 of itself, which covers both ends' rounding (t0 <= t1 exactly
 * implies computed t0 <= t1 + 6 ulps of |t1| when both have one sign, and
 * t0 < 0 <= t1 otherwise): one multiply-max more per box, not four. */
#define BVH_SLAB_SLACK 0x1p-19f

static inline vm bvh_interval_holds(vf t0, vf t1)
{
    const vf grown = vf_max(vf_mul(t1, vf_set1(1.0f + BVH_SLAB_SLACK)), vf_mul(t1, vf_set1(1.0f - BVH_SLAB_SLACK)));
    return vf_le(t0, grown);
}

#define BVH_LANES_ALL ((uint32_t)((1ull << BVH_W) - 1u))

#endif

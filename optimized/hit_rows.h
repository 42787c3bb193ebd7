/* A packet's hit records row after row: the one transpose the kernels
 * that write hits as records use (bvh/traverse_mft.c's camera path,
 * pgrid/pgrid_cell.c's resolve, bvh/bvh_packet.h's bvh_hits_store for a
 * stream's packets, whose records are its rows one after another).  A packet of W lanes (16 on AVX-512, 8 on
 * AVX2, 4 on SSE4.1: the width the translation unit is compiled for) holds
 * rows of four pixels, lane 4 r + i at row r, column i; its four word
 * vectors (t, u, v and the prim's bits) become four vectors of records
 * (rtt_hit, 16 bytes) in lane order, four to a 128-bit part: row r's 64
 * bytes are vectors r * 16 / W to (r + 1) * 16 / W - 1.  Inline, so each
 * kernel copy has its own. */
#ifndef RTT_HIT_ROWS_H
#define RTT_HIT_ROWS_H

#include <immintrin.h>

#if defined(__AVX512F__)
#define HIT_ROWS_W 16u
typedef __m512 hit_rows_vec;
static inline void hit_rows_of_lanes(__m512 t, __m512 u, __m512 v, __m512 prim, __m512 out[4])
{
    /* per 128-bit part (a row): the records of pixels 0, 1 and 2, 3, then
     * each row gathered from the four records' parts */
    const __m512 tu_lo = _mm512_unpacklo_ps(t, u), tu_hi = _mm512_unpackhi_ps(t, u);
    const __m512 vp_lo = _mm512_unpacklo_ps(v, prim), vp_hi = _mm512_unpackhi_ps(v, prim);
    const __m512 p0 = _mm512_shuffle_ps(tu_lo, vp_lo, 0x44), p1 = _mm512_shuffle_ps(tu_lo, vp_lo, 0xEE);
    const __m512 p2 = _mm512_shuffle_ps(tu_hi, vp_hi, 0x44), p3 = _mm512_shuffle_ps(tu_hi, vp_hi, 0xEE);
    const __m512 a = _mm512_shuffle_f32x4(p0, p1, 0x44), b = _mm512_shuffle_f32x4(p0, p1, 0xEE);
    const __m512 c = _mm512_shuffle_f32x4(p2, p3, 0x44), d = _mm512_shuffle_f32x4(p2, p3, 0xEE);
    out[0] = _mm512_shuffle_f32x4(a, c, 0x88), out[1] = _mm512_shuffle_f32x4(a, c, 0xDD);
    out[2] = _mm512_shuffle_f32x4(b, d, 0x88), out[3] = _mm512_shuffle_f32x4(b, d, 0xDD);
}
#elif defined(__AVX2__)
#define HIT_ROWS_W 8u
typedef __m256 hit_rows_vec;
static inline void hit_rows_of_lanes(__m256 t, __m256 u, __m256 v, __m256 prim, __m256 out[4])
{
    /* record i of row 0 in the low half, of row 1 in the high half */
    const __m256 tu_lo = _mm256_unpacklo_ps(t, u), tu_hi = _mm256_unpackhi_ps(t, u);
    const __m256 vp_lo = _mm256_unpacklo_ps(v, prim), vp_hi = _mm256_unpackhi_ps(v, prim);
    const __m256 p0 = _mm256_shuffle_ps(tu_lo, vp_lo, 0x44), p1 = _mm256_shuffle_ps(tu_lo, vp_lo, 0xEE);
    const __m256 p2 = _mm256_shuffle_ps(tu_hi, vp_hi, 0x44), p3 = _mm256_shuffle_ps(tu_hi, vp_hi, 0xEE);
    out[0] = _mm256_permute2f128_ps(p0, p1, 0x20), out[1] = _mm256_permute2f128_ps(p2, p3, 0x20);
    out[2] = _mm256_permute2f128_ps(p0, p1, 0x31), out[3] = _mm256_permute2f128_ps(p2, p3, 0x31);
}
#else
#define HIT_ROWS_W 4u
typedef __m128 hit_rows_vec;
static inline void hit_rows_of_lanes(__m128 t, __m128 u, __m128 v, __m128 prim, __m128 out[4])
{
    _MM_TRANSPOSE4_PS(t, u, v, prim);
    out[0] = t, out[1] = u, out[2] = v, out[3] = prim;
}
#endif

/* vectors of records a row of four pixels spans */
#define HIT_ROWS_PER_ROW (16u / HIT_ROWS_W)

#endif

/* Hunt & Mark 2008, section 5.1: one cell of the eye rays' perspective
 * grid processed like a tiled Z-buffer.  In object order (the cell's list,
 * global triangle order), for each triangle the pixels of its rectangle
 * inside the cell are tested in packets of one vector: 4x4 pixels with
 * AVX-512, 4x2 with AVX2, 4x1 with SSE4.1 (the paper's 4-wide packets),
 * against the cell's depth buffer, which keeps the closest t along the
 * unnormalised pixel direction and the triangle that gave it.  The rays
 * are the pixel formula (pgrid_eye.h), never loaded.
 *
 * Exactness: the test is pgrid_eye.h's edge functions, the same
 * operations in the same order in every lane and in pgrid_eye_resolve, so
 * every copy gives the same bits and a pixel's hit is recomputed exactly
 * from the triangle kept.  A strictly closer t replaces the kept one: the
 * list is in prim order, so equal depths keep the smaller prim.
 *
 * Hierarchical depth test: each block keeps the largest depth it holds
 * (an upper bound: refreshed when a triangle that runs it wins there,
 * never lower than the truth since depths only decrease), and a triangle
 * whose rectangle spans DEPTH_TEST_MIN_BLOCKS blocks or more skips every
 * block whose maximum is at or below its exact lower bound on t_D
 * (t_lower_bound): the block test could not have replaced a lane there.
 * Smaller triangles run the plain loop, which neither tests nor refreshes.
 * Measured (bench/results/pgrid.md): the maps' overdraw -7..-10% a frame,
 * the meshes within the noise.
 *
 * Trades: every pixel block of the rectangle is tested even where the
 * triangle covers a corner of it (no coverage mask by edge stepping); a
 * division per block with a lane inside. */
#include <immintrin.h>
#include <math.h>

#include "rtt/vec3.h"

#include "hit_rows.h"

#include "pgrid_eye.h"
#include "pgrid_isa.h"

#if defined(__AVX512F__)
#define LANES 16
typedef __m512 vfloat;
typedef __mmask16 vmask;
static inline vfloat vf_set1(float x) { return _mm512_set1_ps(x); }
static inline vfloat vf_add(vfloat a, vfloat b) { return _mm512_add_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm512_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm512_div_ps(a, b); }
static inline vfloat vf_load(const float *p) { return _mm512_load_ps(p); }
static inline vfloat vf_lane_x(void)
{
    return _mm512_setr_ps(0.5f, 1.5f, 2.5f, 3.5f, 0.5f, 1.5f, 2.5f, 3.5f, 0.5f, 1.5f, 2.5f, 3.5f, 0.5f, 1.5f, 2.5f, 3.5f);
}
static inline vfloat vf_lane_y(void)
{
    return _mm512_setr_ps(0.5f, 0.5f, 0.5f, 0.5f, 1.5f, 1.5f, 1.5f, 1.5f, 2.5f, 2.5f, 2.5f, 2.5f, 3.5f, 3.5f, 3.5f, 3.5f);
}
/* all three >= 0 or all three <= 0 */
static inline vmask vm_inside(vfloat a, vfloat b, vfloat c)
{
    const __m512 z = _mm512_setzero_ps();
    vmask pos = _mm512_cmp_ps_mask(a, z, _CMP_GE_OQ) & _mm512_cmp_ps_mask(b, z, _CMP_GE_OQ) &
                _mm512_cmp_ps_mask(c, z, _CMP_GE_OQ);
    vmask neg = _mm512_cmp_ps_mask(a, z, _CMP_LE_OQ) & _mm512_cmp_ps_mask(b, z, _CMP_LE_OQ) &
                _mm512_cmp_ps_mask(c, z, _CMP_LE_OQ);
    return pos | neg;
}
static inline bool vm_any(vmask m) { return m != 0; }
/* lanes of m with 0 < t < depth */
static inline vmask vm_closer(vmask m, vfloat t, vfloat depth)
{
    return m & _mm512_cmp_ps_mask(t, _mm512_setzero_ps(), _CMP_GT_OQ) & _mm512_cmp_ps_mask(t, depth, _CMP_LT_OQ);
}
static inline void store_closer(vmask m, float *depth, uint32_t *triangle, vfloat t, uint32_t index)
{
    _mm512_mask_store_ps(depth, m, t);
    _mm512_mask_store_epi32(triangle, m, _mm512_set1_epi32((int)index));
}
static inline void clear_block(float *depth, uint32_t *triangle)
{
    _mm512_store_ps(depth, _mm512_set1_ps(INFINITY));
    _mm512_store_si512((void *)triangle, _mm512_set1_epi32(-1));
}
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm512_sub_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm512_sqrt_ps(a); }
static inline void vf_store(float *p, vfloat a) { _mm512_store_ps(p, a); }
static inline float vf_hmax(vfloat a) { return _mm512_reduce_max_ps(a); }
static inline vfloat vf_blend(vmask m, vfloat a, vfloat b) { return _mm512_mask_blend_ps(m, a, b); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm512_max_ps(a, b); }
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm512_min_ps(a, b); }
static inline vmask vm_lt(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
static inline vmask vm_or(vmask a, vmask b) { return a | b; }
static inline vfloat vf_lane_index(void)
{
    return _mm512_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f, 9.0f, 10.0f, 11.0f, 12.0f, 13.0f, 14.0f, 15.0f);
}
static inline void vf_store_i32(int32_t *p, vfloat a) { _mm512_storeu_si512((void *)p, _mm512_cvttps_epi32(a)); }
/* A mask's 16 bits as an integer, through kmovw into a general register
 * (which zero-extends).  Not the implicit conversion: GCC 12 at -O3 with
 * -fsanitize=thread spilled the mask with a 16-bit kmovw and reloaded the
 * integer with a 32-bit mov, so bits 16..31 held stack garbage, and a loop
 * over a block's lane bits (pgrid_resolve_cell's wide-range lanes) ran past
 * the vector's 16 lanes and wrote into other lanes' results. */
static inline uint32_t vm_bits(vmask m)
{
    uint32_t bits;
    __asm__("kmovw %1, %0" : "=r"(bits) : "k"(m));
    return bits;
}
/* The lanes of a block holding a triangle, and (in those lanes) the
 * fields [0, count) of its surface (pgrid_surface as floats); others 0. */
static inline vmask gather_surfaces(const pgrid_surface *surfaces, const uint32_t *triangle, int count, vfloat *field)
{
    const __m512i index = _mm512_load_si512((const void *)triangle);
    const vmask hit = _mm512_cmpneq_epi32_mask(index, _mm512_set1_epi32(-1));
    if (!hit) {
        for (int k = 0; k < count; k++) field[k] = _mm512_setzero_ps();
        return hit;
    }
    /* one triangle behind every hit (most blocks): its record broadcast,
     * not ten gathers; the lanes' values are the same */
    const uint32_t first = triangle[__builtin_ctz(vm_bits(hit))];
    if (!_mm512_mask_cmpneq_epi32_mask(hit, index, _mm512_set1_epi32((int)first))) {
        const float *f = (const float *)&surfaces[first];
        for (int k = 0; k < count; k++) field[k] = _mm512_set1_ps(f[k]);
        return hit;
    }
    /* two triangles (a block across a big triangle's edge): both records
     * broadcast into their lanes; more (a mesh's small triangles): gathered */
    const vmask lanes = _mm512_mask_cmpeq_epi32_mask(hit, index, _mm512_set1_epi32((int)first)), rest = hit & (vmask)~lanes;
    const uint32_t second = triangle[__builtin_ctz(vm_bits(rest))];
    if (!_mm512_mask_cmpneq_epi32_mask(rest, index, _mm512_set1_epi32((int)second))) {
        const float *f = (const float *)&surfaces[first], *f2 = (const float *)&surfaces[second];
        for (int k = 0; k < count; k++) field[k] = _mm512_mask_blend_ps(rest, _mm512_set1_ps(f[k]), _mm512_set1_ps(f2[k]));
        return hit;
    }
    const __m512i at = _mm512_mullo_epi32(index, _mm512_set1_epi32((int)(sizeof(pgrid_surface) / sizeof(float))));
    for (int k = 0; k < count; k++)
        field[k] = _mm512_mask_i32gather_ps(_mm512_setzero_ps(), hit, at, (const float *)surfaces + k, 4);
    return hit;
}
/* A block's hit records (t, u, v, prim of lane i = x + 4 y; the misses'
 * record where `hit` is clear) into the first `pixels` records of its
 * first `rows` rows: hit_rows.h's transpose, one (masked) store per row, or
 * with `stream` (every row starts on a 64-byte line) a non-temporal one
 * per whole row. */
static inline void store_block(rtt_hit *row, size_t stride, uint32_t pixels, uint32_t rows, vmask hit, vfloat t,
                               vfloat u, vfloat v, vfloat prim, bool stream)
{
    t = _mm512_mask_blend_ps(hit, _mm512_set1_ps(INFINITY), t);
    u = _mm512_maskz_mov_ps(hit, u);
    v = _mm512_maskz_mov_ps(hit, v);
    prim = _mm512_mask_blend_ps(hit, _mm512_castsi512_ps(_mm512_set1_epi32((int)RTT_MISS)), prim);
    __m512 out[4];
    hit_rows_of_lanes(t, u, v, prim, out);
    if (stream && pixels >= 4u) {
        for (uint32_t r = 0; r < rows; r++) _mm512_stream_ps((float *)(row + r * stride), out[r]);
        return;
    }
    const __mmask16 words = (__mmask16)(pixels >= 4u ? 0xFFFFu : (1u << (4u * pixels)) - 1u);
    for (uint32_t r = 0; r < rows; r++) _mm512_mask_storeu_ps((float *)(row + r * stride), words, out[r]);
}
/* lanes of m where a is in (lo, hi) */
static inline uint32_t vm_bits_inside(vmask m, vfloat a, float lo, float hi)
{
    return vm_bits(m & _mm512_cmp_ps_mask(a, _mm512_set1_ps(lo), _CMP_GT_OQ) & _mm512_cmp_ps_mask(a, _mm512_set1_ps(hi), _CMP_LT_OQ));
}
#elif defined(__AVX2__)
#define LANES 8
typedef __m256 vfloat;
typedef __m256 vmask;
static inline vfloat vf_set1(float x) { return _mm256_set1_ps(x); }
static inline vfloat vf_add(vfloat a, vfloat b) { return _mm256_add_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm256_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm256_div_ps(a, b); }
static inline vfloat vf_load(const float *p) { return _mm256_load_ps(p); }
static inline vfloat vf_lane_x(void) { return _mm256_setr_ps(0.5f, 1.5f, 2.5f, 3.5f, 0.5f, 1.5f, 2.5f, 3.5f); }
static inline vfloat vf_lane_y(void) { return _mm256_setr_ps(0.5f, 0.5f, 0.5f, 0.5f, 1.5f, 1.5f, 1.5f, 1.5f); }
static inline vmask vm_inside(vfloat a, vfloat b, vfloat c)
{
    const __m256 z = _mm256_setzero_ps();
    __m256 pos = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(a, z, _CMP_GE_OQ), _mm256_cmp_ps(b, z, _CMP_GE_OQ)),
                               _mm256_cmp_ps(c, z, _CMP_GE_OQ));
    __m256 neg = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(a, z, _CMP_LE_OQ), _mm256_cmp_ps(b, z, _CMP_LE_OQ)),
                               _mm256_cmp_ps(c, z, _CMP_LE_OQ));
    return _mm256_or_ps(pos, neg);
}
static inline bool vm_any(vmask m) { return _mm256_movemask_ps(m) != 0; }
static inline vmask vm_closer(vmask m, vfloat t, vfloat depth)
{
    return _mm256_and_ps(m, _mm256_and_ps(_mm256_cmp_ps(t, _mm256_setzero_ps(), _CMP_GT_OQ),
                                          _mm256_cmp_ps(t, depth, _CMP_LT_OQ)));
}
static inline void store_closer(vmask m, float *depth, uint32_t *triangle, vfloat t, uint32_t index)
{
    _mm256_store_ps(depth, _mm256_blendv_ps(_mm256_load_ps(depth), t, m));
    __m256 old = _mm256_load_ps((const float *)triangle);
    __m256 now = _mm256_castsi256_ps(_mm256_set1_epi32((int)index));
    _mm256_store_ps((float *)triangle, _mm256_blendv_ps(old, now, m));
}
static inline void clear_block(float *depth, uint32_t *triangle)
{
    _mm256_store_ps(depth, _mm256_set1_ps(INFINITY));
    _mm256_store_si256((__m256i *)triangle, _mm256_set1_epi32(-1));
}
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm256_sub_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm256_sqrt_ps(a); }
static inline void vf_store(float *p, vfloat a) { _mm256_store_ps(p, a); }
static inline float vf_hmax(vfloat a)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
static inline vfloat vf_blend(vmask m, vfloat a, vfloat b) { return _mm256_blendv_ps(a, b, m); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm256_max_ps(a, b); }
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm256_min_ps(a, b); }
static inline vmask vm_lt(vfloat a, vfloat b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
static inline vmask vm_or(vmask a, vmask b) { return _mm256_or_ps(a, b); }
static inline vfloat vf_lane_index(void) { return _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f); }
static inline void vf_store_i32(int32_t *p, vfloat a) { _mm256_storeu_si256((__m256i *)p, _mm256_cvttps_epi32(a)); }
static inline vmask gather_surfaces(const pgrid_surface *surfaces, const uint32_t *triangle, int count, vfloat *field)
{
    const __m256i index = _mm256_load_si256((const __m256i *)triangle);
    const __m256 hit = _mm256_castsi256_ps(_mm256_xor_si256(_mm256_cmpeq_epi32(index, _mm256_set1_epi32(-1)),
                                                            _mm256_set1_epi32(-1)));
    const __m256i at = _mm256_mullo_epi32(index, _mm256_set1_epi32((int)(sizeof(pgrid_surface) / sizeof(float))));
    for (int k = 0; k < count; k++)
        field[k] = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), (const float *)surfaces + k, at, hit, 4);
    return hit;
}
static inline uint32_t vm_bits_inside(vmask m, vfloat a, float lo, float hi)
{
    return (uint32_t)_mm256_movemask_ps(_mm256_and_ps(m, _mm256_and_ps(_mm256_cmp_ps(a, _mm256_set1_ps(lo), _CMP_GT_OQ),
                                                                       _mm256_cmp_ps(a, _mm256_set1_ps(hi), _CMP_LT_OQ))));
}
static inline uint32_t vm_bits(vmask m) { return (uint32_t)_mm256_movemask_ps(m); }
/* the AVX-512 store for a 4x2 block: a row in two vectors */
static inline void store_block(rtt_hit *row, size_t stride, uint32_t pixels, uint32_t rows, vmask hit, vfloat t,
                               vfloat u, vfloat v, vfloat prim, bool stream)
{
    t = _mm256_blendv_ps(_mm256_set1_ps(INFINITY), t, hit);
    u = _mm256_and_ps(u, hit);
    v = _mm256_and_ps(v, hit);
    prim = _mm256_blendv_ps(_mm256_castsi256_ps(_mm256_set1_epi32((int)RTT_MISS)), prim, hit);
    __m256 rec[4];
    hit_rows_of_lanes(t, u, v, prim, rec);
    const __m256 out[2][2] = {{rec[0], rec[1]}, {rec[2], rec[3]}};
    if (stream && pixels >= 4u) {
        for (uint32_t r = 0; r < rows; r++) {
            float *p = (float *)(row + r * stride);
            _mm256_stream_ps(p, out[r][0]);
            _mm256_stream_ps(p + 8, out[r][1]);
        }
        return;
    }
    const __m256i lane = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
    const __m256i first = _mm256_cmpgt_epi32(_mm256_set1_epi32((int)pixels), lane);
    const __m256i second = _mm256_cmpgt_epi32(_mm256_set1_epi32((int)pixels - 2), lane);
    for (uint32_t r = 0; r < rows; r++) {
        float *p = (float *)(row + r * stride);
        _mm256_maskstore_ps(p, first, out[r][0]);
        _mm256_maskstore_ps(p + 8, second, out[r][1]);
    }
}
#else
#define LANES 4
typedef __m128 vfloat;
typedef __m128 vmask;
static inline vfloat vf_set1(float x) { return _mm_set1_ps(x); }
static inline vfloat vf_add(vfloat a, vfloat b) { return _mm_add_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm_div_ps(a, b); }
static inline vfloat vf_load(const float *p) { return _mm_load_ps(p); }
static inline vfloat vf_lane_x(void) { return _mm_setr_ps(0.5f, 1.5f, 2.5f, 3.5f); }
static inline vfloat vf_lane_y(void) { return _mm_set1_ps(0.5f); }
static inline vmask vm_inside(vfloat a, vfloat b, vfloat c)
{
    const __m128 z = _mm_setzero_ps();
    __m128 pos = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(a, z), _mm_cmpge_ps(b, z)), _mm_cmpge_ps(c, z));
    __m128 neg = _mm_and_ps(_mm_and_ps(_mm_cmple_ps(a, z), _mm_cmple_ps(b, z)), _mm_cmple_ps(c, z));
    return _mm_or_ps(pos, neg);
}
static inline bool vm_any(vmask m) { return _mm_movemask_ps(m) != 0; }
static inline vmask vm_closer(vmask m, vfloat t, vfloat depth)
{
    return _mm_and_ps(m, _mm_and_ps(_mm_cmpgt_ps(t, _mm_setzero_ps()), _mm_cmplt_ps(t, depth)));
}
static inline void store_closer(vmask m, float *depth, uint32_t *triangle, vfloat t, uint32_t index)
{
    _mm_store_ps(depth, _mm_blendv_ps(_mm_load_ps(depth), t, m));
    __m128 old = _mm_load_ps((const float *)triangle);
    _mm_store_ps((float *)triangle, _mm_blendv_ps(old, _mm_castsi128_ps(_mm_set1_epi32((int)index)), m));
}
static inline void clear_block(float *depth, uint32_t *triangle)
{
    _mm_store_ps(depth, _mm_set1_ps(INFINITY));
    _mm_store_si128((__m128i *)triangle, _mm_set1_epi32(-1));
}
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm_sub_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm_sqrt_ps(a); }
static inline void vf_store(float *p, vfloat a) { _mm_store_ps(p, a); }
static inline float vf_hmax(vfloat a)
{
    const __m128 m = _mm_max_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
static inline vfloat vf_blend(vmask m, vfloat a, vfloat b) { return _mm_blendv_ps(a, b, m); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm_max_ps(a, b); }
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm_min_ps(a, b); }
static inline vmask vm_lt(vfloat a, vfloat b) { return _mm_cmplt_ps(a, b); }
static inline vmask vm_or(vmask a, vmask b) { return _mm_or_ps(a, b); }
static inline vfloat vf_lane_index(void) { return _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f); }
static inline void vf_store_i32(int32_t *p, vfloat a) { _mm_storeu_si128((__m128i *)p, _mm_cvttps_epi32(a)); }
static inline vmask gather_surfaces(const pgrid_surface *surfaces, const uint32_t *triangle, int count, vfloat *field)
{
    _Alignas(16) float lane[PGRID_SURFACE_FLOATS][4] = {{0}};
    for (int i = 0; i < 4; i++)
        if (triangle[i] != PGRID_NO_TRIANGLE) {
            const float *f = (const float *)&surfaces[triangle[i]];
            for (int k = 0; k < count; k++) lane[k][i] = f[k];
        }
    for (int k = 0; k < count; k++) field[k] = _mm_load_ps(lane[k]);
    const __m128i index = _mm_load_si128((const __m128i *)triangle);
    return _mm_castsi128_ps(_mm_xor_si128(_mm_cmpeq_epi32(index, _mm_set1_epi32(-1)), _mm_set1_epi32(-1)));
}
static inline uint32_t vm_bits_inside(vmask m, vfloat a, float lo, float hi)
{
    return (uint32_t)_mm_movemask_ps(_mm_and_ps(m, _mm_and_ps(_mm_cmpgt_ps(a, _mm_set1_ps(lo)), _mm_cmplt_ps(a, _mm_set1_ps(hi)))));
}
static inline uint32_t vm_bits(vmask m) { return (uint32_t)_mm_movemask_ps(m); }
/* a 4x1 block: a record per vector */
static inline void store_block(rtt_hit *row, size_t stride, uint32_t pixels, uint32_t rows, vmask hit, vfloat t,
                               vfloat u, vfloat v, vfloat prim, bool stream)
{
    (void)stride, (void)rows;
    t = _mm_blendv_ps(_mm_set1_ps(INFINITY), t, hit);
    u = _mm_and_ps(u, hit);
    v = _mm_and_ps(v, hit);
    prim = _mm_blendv_ps(_mm_castsi128_ps(_mm_set1_epi32((int)RTT_MISS)), prim, hit);
    __m128 out[4];
    hit_rows_of_lanes(t, u, v, prim, out);
    if (stream && pixels >= 4u) {
        for (uint32_t p = 0; p < 4u; p++) _mm_stream_ps((float *)(row + p), out[p]);
        return;
    }
    for (uint32_t p = 0; p < pixels && p < 4u; p++) _mm_storeu_ps((float *)(row + p), out[p]);
}
#endif

#define BLOCK_H (LANES / 4)
/* the smallest rectangle (in blocks) that runs the hierarchical depth
 * test: 4, 8 and 16 swept on the bench scenes, 8 the best compromise
 * (smaller costs the meshes' many small triangles their bound and refresh,
 * larger leaves the maps' mid-sized wall pieces out) */
#define DEPTH_TEST_MIN_BLOCKS 8u
/* how many references ahead the cell loop prefetches a triangle */
#define PREFETCH_AHEAD 6u

/* A triangle's three edges (sign * a, b, c; a fourth lane of zeros) for
 * row_span, set up once per triangle, with each edge's bound as a line in
 * the row's y: -r / a = p + q y, r = c + b y + max(b / 2, b (BLOCK_H - 1/2))
 * the largest sign * w_e over the row's pixel centres at fx = 0.  The line
 * rounds differently from the division, by less than a pixel while
 * |p| + |q| 2^16 < 2^21 (three roundings of 2^-24 relative each), well
 * inside the block of slack each way; a triangle outside that range keeps
 * the division per row (`linear` false). */
typedef struct row_edges {
    __m128 a, b, c, p, q;
    bool linear, sloped; /* sloped: no edge has a = 0 */
} row_edges;

static inline row_edges row_edges_make(const pgrid_triangle *t, float sign)
{
    const __m128 s = _mm_set1_ps(sign);
    row_edges e = {.a = _mm_mul_ps(s, _mm_setr_ps(t->a[0], t->a[1], t->a[2], 0.0f)),
                   .b = _mm_mul_ps(s, _mm_setr_ps(t->b[0], t->b[1], t->b[2], 0.0f)),
                   .c = _mm_mul_ps(s, _mm_setr_ps(t->c[0], t->c[1], t->c[2], 0.0f))};
    const __m128 k = _mm_max_ps(_mm_mul_ps(e.b, _mm_set1_ps(0.5f)), _mm_mul_ps(e.b, _mm_set1_ps((float)BLOCK_H - 0.5f)));
    const __m128 neg = _mm_set1_ps(-0.0f), zero = _mm_setzero_ps();
    const __m128 sloped = _mm_cmpneq_ps(e.a, zero);
    const __m128 one_a = _mm_blendv_ps(_mm_set1_ps(1.0f), e.a, sloped);
    e.p = _mm_and_ps(sloped, _mm_div_ps(_mm_xor_ps(_mm_add_ps(e.c, k), neg), one_a));
    e.q = _mm_and_ps(sloped, _mm_div_ps(_mm_xor_ps(e.b, neg), one_a));
    const __m128 size = _mm_add_ps(_mm_andnot_ps(neg, e.p), _mm_mul_ps(_mm_andnot_ps(neg, e.q), _mm_set1_ps(65536.0f)));
    /* NaN sizes fail the comparison too */
    e.linear = (_mm_movemask_ps(_mm_cmplt_ps(size, _mm_set1_ps(2097152.0f))) & 7) == 7;
    e.sloped = (_mm_movemask_ps(sloped) & 7) == 7;
    return e;
}

/* Edge stepping for wide rectangles: the blocks of one block row that can
 * hold a pixel inside the triangle.  A hit at t > 0 has every w_e of the
 * sign of det (their sum is N . D), so on the row's pixel centres fy in
 * [y + 0.5, y + BLOCK_H - 0.5] each edge bounds fx on one side; the span
 * is widened by a block each way for the rounding of this bound (the
 * test itself stays the per-lane one), so no block with a pixel inside is
 * skipped.  False when no block of the row can be.  The three edges go
 * through one SSE vector, each bound a line in y set up per triangle
 * (row_edges): the division per edge and row it replaces was a third of
 * oa_dm4's frame.  When every edge slopes and every bound is a line,
 * row_spans gives all the rectangle's rows at once instead, LANES rows a
 * vector, the same spans. */
static inline __attribute__((always_inline)) bool row_span(const row_edges *e, float y, uint32_t X0, uint32_t *bx0,
                                                           uint32_t *bx1)
{
    float lo = (float)X0 + 4.0f * (float)*bx0, hi = (float)X0 + 4.0f * (float)*bx1 + 4.0f;
    /* per edge, the largest sign * w_e over the row's fy, at fx = 0 */
    const __m128 top = _mm_add_ps(e->c, _mm_mul_ps(e->b, _mm_set1_ps(y + 0.5f)));
    const __m128 bottom = _mm_add_ps(e->c, _mm_mul_ps(e->b, _mm_set1_ps(y + (float)BLOCK_H - 0.5f)));
    const __m128 r = _mm_max_ps(top, bottom); /* top > bottom ? top : bottom */
    const __m128 zero = _mm_setzero_ps();
    /* an edge with a = 0 that is negative all along the row: no pixel */
    if (_mm_movemask_ps(_mm_and_ps(_mm_cmpeq_ps(e->a, zero), _mm_cmplt_ps(r, zero))) & 7) return false;
    /* a > 0 bounds fx from below at -r / a, a < 0 from above (NaN bounds nothing) */
    const __m128 bound = e->linear ? _mm_add_ps(e->p, _mm_mul_ps(e->q, _mm_set1_ps(y)))
                                   : _mm_div_ps(_mm_xor_ps(r, _mm_set1_ps(-0.0f)), e->a);
    const __m128 ordered = _mm_cmpord_ps(bound, bound);
    const __m128 from = _mm_blendv_ps(_mm_set1_ps(-INFINITY), bound, _mm_and_ps(ordered, _mm_cmpgt_ps(e->a, zero)));
    const __m128 to = _mm_blendv_ps(_mm_set1_ps(INFINITY), bound, _mm_and_ps(ordered, _mm_cmplt_ps(e->a, zero)));
    __m128 f = _mm_max_ps(from, _mm_movehl_ps(from, from)), g = _mm_min_ps(to, _mm_movehl_ps(to, to));
    f = _mm_max_ss(f, _mm_shuffle_ps(f, f, 1)), g = _mm_min_ss(g, _mm_shuffle_ps(g, g, 1));
    const float from_max = _mm_cvtss_f32(f), to_min = _mm_cvtss_f32(g);
    if (from_max > lo) lo = from_max;
    if (to_min < hi) hi = to_min;
    const float first = (lo - (float)X0) * 0.25f - 1.0f, last = (hi - (float)X0) * 0.25f + 1.0f;
    const float b0 = (float)*bx0, b1 = (float)*bx1;
    if (first > last || first > b1 || last < b0) return false;
    /* first clamped to [bx0, bx1], then last to [that, bx1] (a NaN keeps
     * the old end), without branches */
    const float start = first > b0 ? first : b0, lo_block = start < b1 ? start : b1;
    const float end = last < b1 ? last : b1, hi_block = end > lo_block ? end : lo_block;
    *bx0 = (uint32_t)lo_block, *bx1 = (uint32_t)hi_block;
    return true;
}

/* A lower bound on the t_D the block test computes for any pixel of the
 * rectangle [fx0, fx1] x [fy0, fy1] (pixel centres) where the triangle
 * is hit (t_D > 0); 0 when none is known.  The test's t_D is det / den with
 * den = (c3 + b3 fy) + a3 fx, each operation rounded: rounding is
 * monotone, so den over the rectangle is largest and smallest at its
 * corners, and a hit (t_D > 0) has den of the sign of det, so t_D is
 * smallest where |den| is largest, which the same operations give at a
 * corner.  A block whose kept depths are all at or below the bound holds
 * no lane the triangle could replace (the test is strictly closer). */
static float t_lower_bound(const pgrid_triangle *t, float fx0, float fx1, float fy0, float fy1)
{
    const float r0 = t->c[3] + t->b[3] * fy0, r1 = t->c[3] + t->b[3] * fy1;
    const float d00 = r0 + t->a[3] * fx0, d01 = r0 + t->a[3] * fx1, d10 = r1 + t->a[3] * fx0, d11 = r1 + t->a[3] * fx1;
    /* a NaN lane (inf - inf) has one at a corner too: no bound then */
    if (isnan(d00) || isnan(d01) || isnan(d10) || isnan(d11)) return 0.0f;
    if (t->det > 0.0f) {
        float m = d00 > d01 ? d00 : d01;
        m = m > d10 ? m : d10;
        m = m > d11 ? m : d11;
        return m > 0.0f ? t->det / m : 0.0f;
    }
    if (t->det < 0.0f) {
        float m = d00 < d01 ? d00 : d01;
        m = m < d10 ? m : d10;
        m = m < d11 ? m : d11;
        return m < 0.0f ? t->det / m : 0.0f;
    }
    return 0.0f;
}

/* Block rows at a time: the spans of rows [by0, by0 + rows) of a rectangle
 * of blocks [bx0, bx1], LANES rows a vector, for edges that all slope and
 * whose bounds are lines (row_edges): row_span's arithmetic on the line,
 * each row's ends clamped the same way, first[i] > last[i] for a row with
 * no block.  `first` and `last` hold rows rounded up to LANES. */
static inline __attribute__((always_inline)) void row_spans(const row_edges *e, uint32_t Y0, uint32_t by0,
                                                            uint32_t rows, uint32_t X0, uint32_t bx0, uint32_t bx1,
                                                            int32_t *first, int32_t *last)
{
    const vfloat lane = vf_lane_index(), row_h = vf_set1((float)BLOCK_H), x0 = vf_set1((float)X0);
    const vfloat b0 = vf_set1((float)bx0), b1 = vf_set1((float)bx1), quarter = vf_set1(0.25f), one = vf_set1(1.0f);
    float a[4], p[4], q[4];
    _mm_storeu_ps(a, e->a), _mm_storeu_ps(p, e->p), _mm_storeu_ps(q, e->q);
    for (uint32_t i = 0; i < rows; i += LANES) {
        /* each row's y, as row_span's: (float)(Y0 + by * BLOCK_H), exact */
        const vfloat y = vf_add(vf_set1((float)(Y0 + (by0 + i) * BLOCK_H)), vf_mul(lane, row_h));
        vfloat lo = vf_set1((float)X0 + 4.0f * (float)bx0), hi = vf_set1((float)X0 + 4.0f * (float)bx1 + 4.0f);
        for (int k = 0; k < 3; k++) {
            const vfloat bound = vf_add(vf_set1(p[k]), vf_mul(vf_set1(q[k]), y));
            if (a[k] > 0.0f) lo = vf_max(bound, lo); /* bound > lo ? bound : lo */
            else hi = vf_min(bound, hi);                     /* bound < hi ? bound : hi */
        }
        const vfloat f = vf_sub(vf_mul(vf_sub(lo, x0), quarter), one), l = vf_add(vf_mul(vf_sub(hi, x0), quarter), one);
        const vmask none = vm_or(vm_or(vm_lt(l, f), vm_lt(b1, f)), vm_lt(l, b0));
        const vfloat lo_block = vf_min(vf_max(f, b0), b1), hi_block = vf_max(vf_min(l, b1), lo_block);
        vf_store_i32(first + i, vf_blend(none, lo_block, vf_add(b1, one)));
        vf_store_i32(last + i, vf_blend(none, hi_block, b1));
    }
}

/* One triangle's rectangle of blocks [bx0, bx1] x [by0, by1] (inside the
 * cell with corner (X0, Y0)) against the cell's buffers; true when it won
 * a pixel.  With `hiz` (a constant: two copies) a block is skipped when its
 * kept depths are all at or below tri_min, and a block it wins has its
 * maximum refreshed; without, the maxima are left as they are, which keeps
 * them upper bounds (depths only decrease).  Always inlined, so each copy
 * is the loop alone (a per-block flag test cost the meshes 5%). */
static inline __attribute__((always_inline)) bool trace_triangle(const pgrid_triangle *t, uint32_t index, uint32_t X0,
                                                                 uint32_t Y0, uint32_t bx0, uint32_t bx1, uint32_t by0,
                                                                 uint32_t by1, uint32_t blocks_x, float *restrict depth,
                                                                 uint32_t *restrict triangle,
                                                                 float *restrict block_max, const bool hiz,
                                                                 float tri_min)
{
    const vfloat lane_x = vf_lane_x(), lane_y = vf_lane_y();
    const vfloat a0 = vf_set1(t->a[0]), a1 = vf_set1(t->a[1]), a2 = vf_set1(t->a[2]);
    const vfloat b0 = vf_set1(t->b[0]), b1 = vf_set1(t->b[1]), b2 = vf_set1(t->b[2]);
    const vfloat c0 = vf_set1(t->c[0]), c1 = vf_set1(t->c[1]), c2 = vf_set1(t->c[2]);
    const vfloat a3 = vf_set1(t->a[3]), b3 = vf_set1(t->b[3]), c3 = vf_set1(t->c[3]);
    const vfloat det = vf_set1(t->det);
    /* rows of 5 blocks or more are cut to their span (row_span) */
    const bool wide = bx1 - bx0 >= 4u;
    const row_edges edges = wide ? row_edges_make(t, t->det < 0.0f ? -1.0f : 1.0f) : (row_edges){.linear = false};
    /* all rows' spans at once when the bounds are lines of sloped edges */
    const bool spans_at_once = wide && edges.linear && edges.sloped;
    _Alignas(64) int32_t span_first[PGRID_EYE_CELL_MAX / BLOCK_H + LANES], span_last[PGRID_EYE_CELL_MAX / BLOCK_H + LANES];
    if (spans_at_once) row_spans(&edges, Y0, by0, by1 - by0 + 1u, X0, bx0, bx1, span_first, span_last);
    bool won = false;
    for (uint32_t by = by0; by <= by1; by++) {
        uint32_t first = bx0, last = bx1;
        if (spans_at_once) {
            if (span_first[by - by0] > span_last[by - by0]) continue;
            first = (uint32_t)span_first[by - by0], last = (uint32_t)span_last[by - by0];
        } else if (wide && !row_span(&edges, (float)(Y0 + by * BLOCK_H), X0, &first, &last)) {
            continue;
        }
        const vfloat fy = vf_add(vf_set1((float)(Y0 + by * BLOCK_H)), lane_y);
        const vfloat r0 = vf_add(c0, vf_mul(b0, fy)), r1 = vf_add(c1, vf_mul(b1, fy)),
                     r2 = vf_add(c2, vf_mul(b2, fy)), r3 = vf_add(c3, vf_mul(b3, fy));
        for (uint32_t bx = first; bx <= last; bx++) {
            const uint32_t block = by * blocks_x + bx;
            if (hiz && block_max[block] <= tri_min) continue;
            const vfloat fx = vf_add(vf_set1((float)(X0 + bx * 4u)), lane_x);
            const vfloat w0 = vf_add(r0, vf_mul(a0, fx)), w1 = vf_add(r1, vf_mul(a1, fx)),
                         w2 = vf_add(r2, vf_mul(a2, fx));
            const vmask inside = vm_inside(w0, w1, w2);
            /* small triangles' blocks go on without the branch: inside or
             * not is data there (bunny00 -7%, the elephant -10%) */
            if (hiz && !vm_any(inside)) continue;
            const size_t at = (size_t)block * LANES;
            const vfloat tv = vf_div(det, vf_add(r3, vf_mul(a3, fx)));
            const vfloat kept = vf_load(depth + at);
            const vmask closer = vm_closer(inside, tv, kept);
            if (vm_any(closer)) {
                store_closer(closer, depth + at, triangle + at, tv, index);
                if (hiz) block_max[block] = vf_hmax(vf_blend(closer, kept, tv));
                won = true;
            }
        }
    }
    return won;
}

void pgrid_trace_cell(const pgrid_eye *g, uint32_t cell, pgrid_cell_buffers *buffers);

void pgrid_trace_cell(const pgrid_eye *g, uint32_t cell, pgrid_cell_buffers *buffers)
{
    float *restrict depth = buffers->depth, *restrict block_max = buffers->block_max;
    uint32_t *restrict triangle = buffers->triangle;
    const uint32_t side = g->cell, blocks_x = side / 4u;
    const uint32_t X0 = (cell % g->cells_x) * side, Y0 = (cell / g->cells_x) * side;
    const uint32_t X1 = (X0 + side < g->width ? X0 + side : g->width) - 1u;
    const uint32_t Y1 = (Y0 + side < g->height ? Y0 + side : g->height) - 1u;
    for (uint32_t b = 0; b < side * side / LANES; b++) block_max[b] = INFINITY;
    const uint32_t end = g->cell_first[cell + 1];
    for (uint32_t r = g->cell_first[cell]; r < end; r++) {
        /* a cell's triangles lie all over the array (mesh order), which
         * outgrows the cache: ask for one a few references ahead */
        if (r + PREFETCH_AHEAD < end) __builtin_prefetch(&g->triangles[g->refs[r + PREFETCH_AHEAD]]);
        const uint32_t index = g->refs[r];
        const pgrid_triangle *t = &g->triangles[index];
        const uint32_t x0 = t->x0 > X0 ? t->x0 : X0, x1 = t->x1 < X1 ? t->x1 : X1;
        const uint32_t y0 = t->y0 > Y0 ? t->y0 : Y0, y1 = t->y1 < Y1 ? t->y1 : Y1;
        const uint32_t bx0 = (x0 - X0) / 4u, bx1 = (x1 - X0) / 4u, by0 = (y0 - Y0) / BLOCK_H,
                       by1 = (y1 - Y0) / BLOCK_H;
        bool won;
        if ((bx1 - bx0 + 1u) * (by1 - by0 + 1u) >= DEPTH_TEST_MIN_BLOCKS) {
            const float tri_min = t_lower_bound(t, (float)(X0 + 4u * bx0) + 0.5f, (float)(X0 + 4u * bx1) + 3.5f,
                                                (float)(Y0 + by0 * BLOCK_H) + 0.5f,
                                                (float)(Y0 + by1 * BLOCK_H) + ((float)BLOCK_H - 0.5f));
            won = trace_triangle(t, index, X0, Y0, bx0, bx1, by0, by1, blocks_x, depth, triangle, block_max, true,
                                 tri_min);
        } else {
            won = trace_triangle(t, index, X0, Y0, bx0, bx1, by0, by1, blocks_x, depth, triangle, block_max, false,
                                 0.0f);
        }
        /* the resolve reads the surface of every triangle left in the
         * buffers: a winner's is brought in now, while the cell is traced */
        if (won) __builtin_prefetch(&g->surfaces[index]);
    }
}

void pgrid_resolve_cell(const pgrid_eye *g, uint32_t cell, pgrid_cell_buffers *buffers, rtt_hit *hits,
                        size_t stride, bool stream);

/* The hits of the cell's pixels from its buffers, a block (one vector)
 * at a time: t along the normalised direction is t_D |D| (|D| in
 * rtt_camera_ray's order: rtt_v3_length, whose wide-range fallback a lane
 * outside (1e-18, 1e18) takes), u, v the barycentric map of the hit point
 * t_D D (pgrid_eye.h); each lane's operations are the scalar formula's, in
 * its order, so every width gives the same bits. */
void pgrid_resolve_cell(const pgrid_eye *g, uint32_t cell, pgrid_cell_buffers *buffers, rtt_hit *hits,
                        size_t stride, bool stream)
{
    float *depth = buffers->depth;
    uint32_t *triangle = buffers->triangle;
    /* a block's rows of four start on a line when the cell's first does and the stride is whole lines */
    stream = stream && !(((uintptr_t)hits | (stride * sizeof *hits)) & 63u);
    const uint32_t side = g->cell;
    const uint32_t X0 = (cell % g->cells_x) * side, Y0 = (cell / g->cells_x) * side;
    const uint32_t w = (X0 + side < g->width ? X0 + side : g->width) - X0;
    const uint32_t h = (Y0 + side < g->height ? Y0 + side : g->height) - Y0;
    const rtt_camera_frame *f = &g->frame;
    const vfloat lane_x = vf_lane_x(), lane_y = vf_lane_y(), inv_scale = vf_set1(g->inv_scale);
    const vfloat corner_x = vf_set1(f->corner.x), corner_y = vf_set1(f->corner.y), corner_z = vf_set1(f->corner.z);
    const vfloat du_x = vf_set1(f->du.x), du_y = vf_set1(f->du.y), du_z = vf_set1(f->du.z);
    const vfloat dv_x = vf_set1(f->dv.x), dv_y = vf_set1(f->dv.y), dv_z = vf_set1(f->dv.z);
    for (uint32_t by = 0; by * BLOCK_H < h; by++) {
        const vfloat fy = vf_add(vf_set1((float)(Y0 + by * BLOCK_H)), lane_y);
        const vfloat row_x = vf_mul(dv_x, fy), row_y = vf_mul(dv_y, fy), row_z = vf_mul(dv_z, fy);
        for (uint32_t bx = 0; bx * 4u < w; bx++) {
            const size_t at = ((size_t)by * (side / 4u) + bx) * LANES;
            vfloat sf[PGRID_SURFACE_FLOATS];
            const vmask hit = gather_surfaces(g->surfaces, triangle + at, PGRID_SURFACE_FLOATS, sf);
            const uint32_t hit_bits = vm_bits(hit);
            vfloat t = sf[0], u = sf[0], v = sf[0]; /* any value: store_block keeps only the hit lanes */
            if (hit_bits) {
                const vfloat fx = vf_add(vf_set1((float)(X0 + bx * 4u)), lane_x), t_d = vf_load(depth + at);
                const vfloat d_x = vf_add(corner_x, vf_add(vf_mul(du_x, fx), row_x));
                const vfloat d_y = vf_add(corner_y, vf_add(vf_mul(du_y, fx), row_y));
                const vfloat d_z = vf_add(corner_z, vf_add(vf_mul(du_z, fx), row_z));
                const vfloat q_x = vf_sub(vf_mul(t_d, d_x), sf[0]), q_y = vf_sub(vf_mul(t_d, d_y), sf[1]),
                             q_z = vf_sub(vf_mul(t_d, d_z), sf[2]);
                u = vf_add(vf_add(vf_mul(q_x, sf[3]), vf_mul(q_y, sf[4])), vf_mul(q_z, sf[5]));
                v = vf_add(vf_add(vf_mul(q_x, sf[6]), vf_mul(q_y, sf[7])), vf_mul(q_z, sf[8]));
                const vfloat length = vf_sqrt(vf_add(vf_add(vf_mul(d_x, d_x), vf_mul(d_y, d_y)), vf_mul(d_z, d_z)));
                t = vf_mul(vf_mul(t_d, inv_scale), length);
                /* lanes whose |D| needs rtt_v3_length's wide-range path */
                const uint32_t wide_bits = hit_bits & ~vm_bits_inside(hit, length, 1e-18f, 1e18f);
                if (wide_bits) {
                    _Alignas(64) float out_t[LANES];
                    vf_store(out_t, t);
                    for (uint32_t wide = wide_bits; wide; wide &= wide - 1) {
                        const uint32_t i = (uint32_t)__builtin_ctz(wide);
                        const float px = (float)(X0 + bx * 4u + i % 4u) + 0.5f, py = (float)(Y0 + by * BLOCK_H + i / 4u) + 0.5f;
                        const rtt_vec3 d = rtt_v3_add(f->corner, rtt_v3_add(rtt_v3_scale(f->du, px), rtt_v3_scale(f->dv, py)));
                        out_t[i] = depth[at + i] * g->inv_scale * rtt_v3_length(d);
                    }
                    t = vf_load(out_t);
                }
            }
            clear_block(depth + at, triangle + at); /* as the next cell's trace wants them, while the lines are here */
            const uint32_t x = bx * 4u, y = by * BLOCK_H;
            store_block(hits + (size_t)y * stride + x, stride, w - x, h - y < BLOCK_H ? h - y : BLOCK_H, hit, t, u, v,
                        sf[9], stream);
        }
    }
    if (stream) _mm_sfence(); /* the streamed rows ordered before whatever tells a reader they are there */
}

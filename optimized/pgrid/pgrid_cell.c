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
 * list is in prim order, so equal depths keep the smaller prim.  Trades:
 * every pixel block of the rectangle is tested even where the triangle
 * covers a corner of it (no coverage mask by edge stepping); a division
 * per block with a lane inside. */
#include <immintrin.h>
#include <math.h>

#include "rtt/vec3.h"

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
#endif

#define BLOCK_H (LANES / 4)

/* Edge stepping for wide rectangles: the blocks of one block row that can
 * hold a pixel inside the triangle.  A hit at t > 0 has every w_e of the
 * sign of det (their sum is N . D), so on the row's pixel centres fy in
 * [y + 0.5, y + BLOCK_H - 0.5] each edge bounds fx on one side; the span
 * is widened by a block each way for the rounding of this bound (the
 * test itself stays the per-lane one), so no block with a pixel inside is
 * skipped.  False when no block of the row can be. */
static bool row_span(const pgrid_triangle *t, float sign, float y, uint32_t X0, uint32_t *bx0, uint32_t *bx1)
{
    float lo = (float)X0 + 4.0f * (float)*bx0, hi = (float)X0 + 4.0f * (float)*bx1 + 4.0f;
    for (int e = 0; e < 3; e++) {
        const float a = sign * t->a[e], b = sign * t->b[e], c = sign * t->c[e];
        /* the largest sign * w_e over the row's fy, at fx = 0 */
        const float top = c + b * (y + 0.5f), bottom = c + b * (y + (float)BLOCK_H - 0.5f);
        const float r = top > bottom ? top : bottom;
        if (a > 0.0f) {
            const float from = -r / a;
            if (from > lo) lo = from;
        } else if (a < 0.0f) {
            const float to = -r / a;
            if (to < hi) hi = to;
        } else if (r < 0.0f) {
            return false;
        }
    }
    const float first = (lo - (float)X0) * 0.25f - 1.0f, last = (hi - (float)X0) * 0.25f + 1.0f;
    if (first > last || first > (float)*bx1 || last < (float)*bx0) return false;
    if (first > (float)*bx0) *bx0 = first < (float)*bx1 ? (uint32_t)first : *bx1;
    if (last < (float)*bx1) *bx1 = last > (float)*bx0 ? (uint32_t)last : *bx0;
    return true;
}

void pgrid_trace_cell(const pgrid_eye *g, uint32_t cell, float *depth, uint32_t *triangle);

void pgrid_trace_cell(const pgrid_eye *g, uint32_t cell, float *depth, uint32_t *triangle)
{
    const uint32_t side = g->cell, blocks_x = side / 4u;
    const uint32_t X0 = (cell % g->cells_x) * side, Y0 = (cell / g->cells_x) * side;
    const uint32_t X1 = (X0 + side < g->width ? X0 + side : g->width) - 1u;
    const uint32_t Y1 = (Y0 + side < g->height ? Y0 + side : g->height) - 1u;
    for (uint32_t b = 0; b < side * side / LANES; b++) clear_block(depth + b * LANES, triangle + b * LANES);
    const vfloat lane_x = vf_lane_x(), lane_y = vf_lane_y();
    const uint32_t end = g->cell_first[cell + 1];
    for (uint32_t r = g->cell_first[cell]; r < end; r++) {
        const uint32_t index = g->refs[r];
        const pgrid_triangle *t = &g->triangles[index];
        const uint32_t x0 = t->x0 > X0 ? t->x0 : X0, x1 = t->x1 < X1 ? t->x1 : X1;
        const uint32_t y0 = t->y0 > Y0 ? t->y0 : Y0, y1 = t->y1 < Y1 ? t->y1 : Y1;
        const vfloat a0 = vf_set1(t->a[0]), a1 = vf_set1(t->a[1]), a2 = vf_set1(t->a[2]);
        const vfloat b0 = vf_set1(t->b[0]), b1 = vf_set1(t->b[1]), b2 = vf_set1(t->b[2]);
        const vfloat c0 = vf_set1(t->c[0]), c1 = vf_set1(t->c[1]), c2 = vf_set1(t->c[2]);
        const vfloat a3 = vf_set1(t->a[3]), b3 = vf_set1(t->b[3]), c3 = vf_set1(t->c[3]);
        const vfloat det = vf_set1(t->det);
        const float sign = t->det < 0.0f ? -1.0f : 1.0f;
        for (uint32_t by = (y0 - Y0) / BLOCK_H; by <= (y1 - Y0) / BLOCK_H; by++) {
            const vfloat fy = vf_add(vf_set1((float)(Y0 + by * BLOCK_H)), lane_y);
            const vfloat r0 = vf_add(c0, vf_mul(b0, fy)), r1 = vf_add(c1, vf_mul(b1, fy)),
                         r2 = vf_add(c2, vf_mul(b2, fy)), r3 = vf_add(c3, vf_mul(b3, fy));
            uint32_t bx0 = (x0 - X0) / 4u, bx1 = (x1 - X0) / 4u;
            if (bx1 - bx0 >= 4u && !row_span(t, sign, (float)(Y0 + by * BLOCK_H), X0, &bx0, &bx1)) continue;
            for (uint32_t bx = bx0; bx <= bx1; bx++) {
                const vfloat fx = vf_add(vf_set1((float)(X0 + bx * 4u)), lane_x);
                const vfloat w0 = vf_add(r0, vf_mul(a0, fx)), w1 = vf_add(r1, vf_mul(a1, fx)),
                             w2 = vf_add(r2, vf_mul(a2, fx));
                const vmask inside = vm_inside(w0, w1, w2);
                if (!vm_any(inside)) continue;
                const size_t at = ((size_t)by * blocks_x + bx) * LANES;
                const vfloat tv = vf_div(det, vf_add(r3, vf_mul(a3, fx)));
                const vmask closer = vm_closer(inside, tv, vf_load(depth + at));
                if (vm_any(closer)) store_closer(closer, depth + at, triangle + at, tv, index);
            }
        }
    }
}

void pgrid_resolve_cell(const pgrid_eye *g, uint32_t cell, const float *depth, const uint32_t *triangle,
                        rtt_hit *hits, size_t stride);

/* The hits of the cell's pixels from its buffers: t along the normalised
 * direction is t_D |D| (|D| in rtt_camera_ray's order), u, v the
 * barycentric map of the hit point t_D D (pgrid_eye.h). */
void pgrid_resolve_cell(const pgrid_eye *g, uint32_t cell, const float *depth, const uint32_t *triangle,
                        rtt_hit *hits, size_t stride)
{
    const uint32_t side = g->cell;
    const uint32_t X0 = (cell % g->cells_x) * side, Y0 = (cell / g->cells_x) * side;
    const uint32_t w = (X0 + side < g->width ? X0 + side : g->width) - X0;
    const uint32_t h = (Y0 + side < g->height ? Y0 + side : g->height) - Y0;
    const rtt_camera_frame *f = &g->frame;
    for (uint32_t y = 0; y < h; y++) {
        const float fy = (float)(Y0 + y) + 0.5f;
        const rtt_vec3 row = rtt_v3_scale(f->dv, fy);
        const size_t block_row = (size_t)(y / BLOCK_H) * (side / 4u) * LANES + (y % BLOCK_H) * 4u;
        rtt_hit *out = hits + (size_t)y * stride;
        for (uint32_t x = 0; x < w; x++) {
            const size_t at = block_row + (x / 4u) * LANES + x % 4u;
            const uint32_t index = triangle[at];
            if (index == PGRID_NO_TRIANGLE) {
                out[x] = (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS};
                continue;
            }
            const pgrid_surface *sf = &g->surfaces[index];
            const float fx = (float)(X0 + x) + 0.5f, t_d = depth[at];
            const rtt_vec3 d = rtt_v3_add(f->corner, rtt_v3_add(rtt_v3_scale(f->du, fx), row));
            const rtt_vec3 q = rtt_v3(t_d * d.x - sf->origin[0], t_d * d.y - sf->origin[1], t_d * d.z - sf->origin[2]);
            const float u = (q.x * sf->m_u[0] + q.y * sf->m_u[1]) + q.z * sf->m_u[2];
            const float v = (q.x * sf->m_v[0] + q.y * sf->m_v[1]) + q.z * sf->m_v[2];
            out[x] = (rtt_hit){t_d * g->inv_scale * rtt_v3_length(d), u, v, g->triangles[index].prim};
        }
    }
}

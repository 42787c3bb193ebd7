/* The footprint stage of the light grids' build (pgrid_light.h,
 * pgrid_print_job) on the kernel side: the records in vectors of doubles,
 * 8 on AVX-512, 4 on AVX2, 2 on SSE4.1, for the common case -- a triangle
 * farther than 256 E from the light whose corners all lie inside one
 * face's pyramid narrowed by mu_T (most triangles meet one face), so that
 * face's four planes clip nothing.  Every lane computes
 * pgrid_light_print_record's double operations in their order (IEEE and
 * correctly rounded, contraction off), so it writes the same bits; a lane
 * outside that case (near the light, on two faces or more, clipped by a
 * plane, an odd value anywhere) is left to pgrid_light_print_record.
 *
 * Measured (bench/results/pgrid.md, "fifth session: the light grid's
 * build"): the scalar stage was 60% of a mesh's light-grid build, two
 * square roots and three divisions per triangle in one dependency chain;
 * in vectors the build went from 6.0 to 4.0 ms on the bunny. */
#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "pgrid_isa.h"
#include "pgrid_light.h"

#define pgrid_light_prints PGRID_ISA(pgrid_light_prints)
void pgrid_light_prints(const pgrid_print_job *job, uint32_t first, uint32_t end);

/* doubles at this copy's width; comparisons give lane bits */
#if defined(__AVX512F__)
#define VD_W 8u
typedef __m512d vd;
static inline vd vd_set1(double x) { return _mm512_set1_pd(x); }
static inline vd vd_load(const double *p) { return _mm512_loadu_pd(p); }
static inline vd vd_load_floats(const float *p) { return _mm512_cvtps_pd(_mm256_loadu_ps(p)); }
static inline void vd_store(double *p, vd a) { _mm512_storeu_pd(p, a); }
static inline vd vd_add(vd a, vd b) { return _mm512_add_pd(a, b); }
static inline vd vd_sub(vd a, vd b) { return _mm512_sub_pd(a, b); }
static inline vd vd_mul(vd a, vd b) { return _mm512_mul_pd(a, b); }
static inline vd vd_div(vd a, vd b) { return _mm512_div_pd(a, b); }
static inline vd vd_sqrt(vd a) { return _mm512_sqrt_pd(a); }
static inline uint32_t vd_lt(vd a, vd b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
static inline uint32_t vd_ge(vd a, vd b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
static inline uint32_t vd_gt(vd a, vd b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
static inline uint32_t vd_le(vd a, vd b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
/* lanes of m take b, the others a */
static inline vd vd_blend(uint32_t m, vd a, vd b) { return _mm512_mask_blend_pd((__mmask8)m, a, b); }
/* fabs: the sign bit cleared */
static inline vd vd_abs(vd a) { return _mm512_abs_pd(a); }
static inline vd vd_min(vd a, vd b) { return _mm512_min_pd(a, b); }
static inline vd vd_max(vd a, vd b) { return _mm512_max_pd(a, b); }
/* truncated towards zero, as (int32_t) does */
static inline void vd_store_trunc(int32_t *p, vd a) { _mm256_storeu_si256((__m256i *)p, _mm512_cvttpd_epi32(a)); }
#elif defined(__AVX2__)
#define VD_W 4u
typedef __m256d vd;
static inline vd vd_set1(double x) { return _mm256_set1_pd(x); }
static inline vd vd_load(const double *p) { return _mm256_loadu_pd(p); }
static inline vd vd_load_floats(const float *p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
static inline void vd_store(double *p, vd a) { _mm256_storeu_pd(p, a); }
static inline vd vd_add(vd a, vd b) { return _mm256_add_pd(a, b); }
static inline vd vd_sub(vd a, vd b) { return _mm256_sub_pd(a, b); }
static inline vd vd_mul(vd a, vd b) { return _mm256_mul_pd(a, b); }
static inline vd vd_div(vd a, vd b) { return _mm256_div_pd(a, b); }
static inline vd vd_sqrt(vd a) { return _mm256_sqrt_pd(a); }
static inline uint32_t vd_lt(vd a, vd b) { return (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_LT_OQ)); }
static inline uint32_t vd_ge(vd a, vd b) { return (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_GE_OQ)); }
static inline uint32_t vd_gt(vd a, vd b) { return (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_GT_OQ)); }
static inline uint32_t vd_le(vd a, vd b) { return (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_LE_OQ)); }
static inline vd vd_abs(vd a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
static inline vd vd_min(vd a, vd b) { return _mm256_min_pd(a, b); }
static inline vd vd_max(vd a, vd b) { return _mm256_max_pd(a, b); }
static inline void vd_store_trunc(int32_t *p, vd a) { _mm_storeu_si128((__m128i *)p, _mm256_cvttpd_epi32(a)); }
static inline vd vd_blend(uint32_t m, vd a, vd b)
{
    const __m256i lane = _mm256_setr_epi64x(1, 2, 4, 8);
    const __m256i bits = _mm256_and_si256(_mm256_set1_epi64x((long long)m), lane);
    return _mm256_blendv_pd(a, b, _mm256_castsi256_pd(_mm256_cmpeq_epi64(bits, lane)));
}
#else
#define VD_W 2u
typedef __m128d vd;
static inline vd vd_set1(double x) { return _mm_set1_pd(x); }
static inline vd vd_load(const double *p) { return _mm_loadu_pd(p); }
static inline vd vd_load_floats(const float *p) { return _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd((const double *)p))); }
static inline void vd_store(double *p, vd a) { _mm_storeu_pd(p, a); }
static inline vd vd_add(vd a, vd b) { return _mm_add_pd(a, b); }
static inline vd vd_sub(vd a, vd b) { return _mm_sub_pd(a, b); }
static inline vd vd_mul(vd a, vd b) { return _mm_mul_pd(a, b); }
static inline vd vd_div(vd a, vd b) { return _mm_div_pd(a, b); }
static inline vd vd_sqrt(vd a) { return _mm_sqrt_pd(a); }
static inline uint32_t vd_lt(vd a, vd b) { return (uint32_t)_mm_movemask_pd(_mm_cmplt_pd(a, b)); }
static inline uint32_t vd_ge(vd a, vd b) { return (uint32_t)_mm_movemask_pd(_mm_cmpge_pd(a, b)); }
static inline uint32_t vd_gt(vd a, vd b) { return (uint32_t)_mm_movemask_pd(_mm_cmpgt_pd(a, b)); }
static inline uint32_t vd_le(vd a, vd b) { return (uint32_t)_mm_movemask_pd(_mm_cmple_pd(a, b)); }
static inline vd vd_abs(vd a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a); }
static inline vd vd_min(vd a, vd b) { return _mm_min_pd(a, b); }
static inline vd vd_max(vd a, vd b) { return _mm_max_pd(a, b); }
static inline void vd_store_trunc(int32_t *p, vd a) { _mm_storel_epi64((__m128i *)p, _mm_cvttpd_epi32(a)); }
static inline vd vd_blend(uint32_t m, vd a, vd b)
{
    const __m128i lane = _mm_setr_epi32(1, 0, 2, 0);
    const __m128i bits = _mm_and_si128(_mm_set1_epi64x((long long)m), lane);
    return _mm_blendv_pd(a, b, _mm_castsi128_pd(_mm_cmpeq_epi64(bits, lane)));
}
#endif

#define VD_ALL ((1u << VD_W) - 1u)

/* x < acc ? x : acc, and x > acc ? x : acc: the scalar code's selections */
static inline vd vd_less(vd x, vd acc) { return vd_blend(vd_lt(x, acc), acc, x); }
static inline vd vd_more(vd x, vd acc) { return vd_blend(vd_gt(x, acc), acc, x); }

/* What a vector of records leaves for the output loop. */
typedef struct prints_lanes {
    double d[VD_W];
    int32_t a[2][VD_W], b[2][VD_W]; /* the footprint's first and last cells (x, y) */
    uint32_t fast, front, steep, face[VD_W];
} prints_lanes;

/* The lanes of one vector: corners c[corner][axis] relative to the light,
 * `outward` the side of a culled mesh's triangle (0: not culled). */
static void prints_vector(const vd c[3][3], vd outward, double E, uint32_t res, prints_lanes *out)
{
    const vd zero = vd_set1(0.0);
    for (uint32_t l = 0; l < VD_W; l++) out->face[l] = 0; /* read for the fast lanes only */
    /* distance_bound: the box's and the plane's distances */
    vd box = zero;
    for (int k = 0; k < 3; k++) {
        vd lo = c[0][k], hi = c[0][k];
        for (int i = 1; i < 3; i++) lo = vd_less(c[i][k], lo), hi = vd_more(c[i][k], hi);
        /* gap = lo > 0 ? lo : hi < 0 ? -hi : 0 */
        vd gap = vd_blend(vd_lt(hi, zero), zero, vd_sub(zero, hi));
        gap = vd_blend(vd_gt(lo, zero), gap, lo);
        box = vd_add(box, vd_mul(gap, gap));
    }
    vd e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = vd_sub(c[1][k], c[0][k]), e2[k] = vd_sub(c[2][k], c[0][k]);
    const vd n[3] = {vd_sub(vd_mul(e1[1], e2[2]), vd_mul(e1[2], e2[1])),
                     vd_sub(vd_mul(e1[2], e2[0]), vd_mul(e1[0], e2[2])),
                     vd_sub(vd_mul(e1[0], e2[1]), vd_mul(e1[1], e2[0]))};
    const vd len = vd_sqrt(vd_add(vd_add(vd_mul(n[0], n[0]), vd_mul(n[1], n[1])), vd_mul(n[2], n[2])));
    const vd dot = vd_add(vd_add(vd_mul(n[0], c[0][0]), vd_mul(n[1], c[0][1])), vd_mul(n[2], c[0][2]));
    const vd plane = vd_blend(vd_gt(len, zero), zero, vd_div(vd_abs(dot), len));
    const vd b = vd_sqrt(box);
    const vd d = vd_blend(vd_gt(b, plane), plane, b);
    vd_store(out->d, d);
    /* front: -(n . c0) * outward > 4 E |n| (a culled mesh's triangle) */
    const vd side = vd_mul(vd_sub(zero, dot), outward);
    out->front = vd_gt(side, vd_mul(vd_set1(4.0 * E), len)) & (vd_lt(outward, zero) | vd_gt(outward, zero));
    /* steep: side > 0.11 len |farthest corner| */
    vd far = zero;
    for (int v = 0; v < 3; v++)
        far = vd_more(vd_add(vd_add(vd_mul(c[v][0], c[v][0]), vd_mul(c[v][1], c[v][1])), vd_mul(c[v][2], c[v][2])), far);
    out->steep = out->front & vd_gt(side, vd_mul(vd_mul(vd_set1(PGRID_STEEP_COSINE), len), vd_sqrt(far)));
    /* mu, and the near ones (left to the scalar record) */
    const vd mu = vd_add(vd_set1(1e-5), vd_mul(vd_set1(4.0), vd_div(vd_set1(2.0 * E), vd_sub(d, vd_set1(2.0 * E)))));
    uint32_t fast = vd_gt(d, vd_set1(256.0 * E)) & vd_le(mu, vd_set1(4e-2));
    /* single_face: every corner's major axis and sign the same, its other
     * two coordinates inside the pyramid narrowed by 2 mu */
    const vd narrow_by = vd_sub(vd_set1(1.0), vd_mul(vd_set1(2.0), mu));
    uint32_t axis_bits[3] = {0, 0, 0}, negative = 0;
    for (int i = 0; i < 3 && fast; i++) {
        const vd ax = vd_abs(c[i][0]), ay = vd_abs(c[i][1]), az = vd_abs(c[i][2]);
        const uint32_t x_major = vd_ge(ax, ay) & vd_ge(ax, az), y_major = ~x_major & vd_ge(ay, az) & VD_ALL,
                       z_major = ~x_major & ~y_major & VD_ALL;
        const vd major = vd_blend(x_major, vd_blend(y_major, az, ay), ax);
        const vd u = vd_blend(x_major, vd_blend(y_major, ax, az), ay);
        const vd v = vd_blend(x_major, vd_blend(y_major, ay, ax), az);
        const vd narrow = vd_mul(major, narrow_by);
        fast &= vd_lt(u, narrow) & vd_lt(v, narrow);
        const uint32_t neg = (x_major & vd_lt(c[i][0], zero)) | (y_major & vd_lt(c[i][1], zero)) |
                             (z_major & vd_lt(c[i][2], zero));
        if (i == 0) {
            axis_bits[0] = x_major, axis_bits[1] = y_major, axis_bits[2] = z_major, negative = neg;
        } else {
            fast &= ~((axis_bits[0] ^ x_major) | (axis_bits[1] ^ y_major) | (negative ^ neg));
        }
    }
    out->fast = fast;
    if (!fast) return;
    /* face_footprint on that face: the corners' (axis, u, v) coordinates */
    vd q[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            /* coordinate (axis + k) % 3 of corner i */
            const vd x = c[i][k % 3], y = c[i][(k + 1) % 3], z = c[i][(k + 2) % 3];
            q[i][k] = vd_blend(axis_bits[0], vd_blend(axis_bits[1], z, y), x);
        }
    const vd wide = vd_add(vd_set1(1.0), mu);
    const vd signed_wide = vd_blend(negative, wide, vd_sub(zero, wide)); /* sign * wide, exact */
    /* the four planes: inside all of them, or the scalar record clips */
    for (int k = 0; k < 4 && fast; k++) {
        const int across = k < 2 ? 1 : 2;
        for (int i = 0; i < 3; i++) {
            const vd m = vd_mul(signed_wide, q[i][0]);
            const vd value = k % 2 ? vd_add(m, q[i][across]) : vd_sub(m, q[i][across]);
            fast &= ~vd_lt(value, zero);
        }
    }
    /* the corners' face coordinates */
    vd lo[2] = {vd_set1(INFINITY), vd_set1(INFINITY)}, hi[2] = {vd_set1(-INFINITY), vd_set1(-INFINITY)};
    for (int i = 0; i < 3 && fast; i++) {
        const vd major = vd_blend(negative, q[i][0], vd_sub(zero, q[i][0])); /* sign * q[axis], exact */
        fast &= vd_gt(major, zero);
        const vd s = vd_div(q[i][1], major), t = vd_div(q[i][2], major);
        lo[0] = vd_less(s, lo[0]), hi[0] = vd_more(s, hi[0]);
        lo[1] = vd_less(t, lo[1]), hi[1] = vd_more(t, hi[1]);
    }
    out->fast = fast;
    /* face_footprint's cells: x < 0 → 0, x >= res → res - 1, else (int32_t)x; the same as truncating
     * x clamped to [0, res - 1] for the fast lanes' values (finite) */
    const vd one = vd_set1(1.0), half = vd_set1(0.5), r = vd_set1((double)res), zero_cell = zero,
             last_cell = vd_set1((double)res - 1.0);
    for (int k = 0; k < 2; k++) {
        const vd a = vd_mul(vd_mul(vd_add(vd_sub(lo[k], mu), one), half), r);
        const vd b = vd_mul(vd_mul(vd_add(vd_add(hi[k], mu), one), half), r);
        vd_store_trunc(out->a[k], vd_min(vd_max(a, zero_cell), last_cell));
        vd_store_trunc(out->b[k], vd_min(vd_max(b, zero_cell), last_cell));
    }
    for (uint32_t l = 0; l < VD_W; l++)
        out->face[l] = 2u * (axis_bits[1] >> l & 1u ? 1u : axis_bits[2] >> l & 1u ? 2u : 0u) + (negative >> l & 1u);
}

void pgrid_light_prints(const pgrid_print_job *job, uint32_t first, uint32_t end)
{
    pgrid_light *light = job->light;
    const pgrid_shadows *grids = job->grids;
    const float *position = light->position;
    const uint32_t n = job->n, res = job->res;
    uint32_t i = first;
    const float *lanes = grids->corner_lanes;
    const size_t stride = grids->corner_stride;
    for (; i + VD_W <= end; i += VD_W) {
        /* (double)corner - position[a], as the scalar record (float to double exact) */
        vd c[3][3];
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++)
                c[v][a] = vd_sub(vd_load_floats(lanes + (size_t)(3 * v + a) * stride + i), vd_set1((double)position[a]));
        prints_lanes out;
        prints_vector((const vd(*)[3])c, vd_load_floats(lanes + 9 * stride + i), job->E, res, &out);
        for (uint32_t l = 0; l < VD_W; l++) {
            const uint32_t r = i + l;
            if (!(out.fast >> l & 1u)) {
                pgrid_light_print_record(job, r);
                continue;
            }
            const bool front = out.front >> l & 1u;
            light->bound[r] = (float)(out.d[l] * (1.0 - 1e-6));
            light->record_front[r] = front ? (out.steep >> l & 1u ? PGRID_PRIM_STEEP : PGRID_PRIM_FACING) : 0;
            const pgrid_footprint f = {(uint16_t)out.a[0][l], (uint16_t)out.a[1][l], (uint16_t)out.b[0][l],
                                       (uint16_t)out.b[1][l]};
            light->prints[(size_t)out.face[l] * n + r] = f; /* its one face's entry (pgrid_light.prints) */
            light->face_mask[r] = (uint8_t)(1u << out.face[l]);
        }
    }
    for (; i < end; i++) pgrid_light_print_record(job, i);
}

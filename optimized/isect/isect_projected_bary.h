/* Wald's projected barycentric ray/triangle test (Wald 2004, "Realtime Ray
 * Tracing and Interactive Global Illumination" 7.1; Thesis 4.2 uses it for
 * its packet intersection), four rays at once in SSE4.1 and one ray in
 * scalar code, on the 48-byte records of kd_tree.h.
 *
 * The record is projected onto the plane of the dominant normal axis k, and
 * everything is computed relative to vertex 0, r = a - o:
 *   t     = (r_k + n_u r_u + n_v r_v) / (d_k + n_u d_u + n_v d_v)
 *   h     = t d_{u,v} - r_{u,v}        (the hit point minus vertex 0)
 *   beta  = b_nu h_u + b_nv h_v      (weight of vertex 1)
 *   gamma = c_nu h_u + c_nv h_v      (weight of vertex 2)
 *   hit   iff tnear < t < tfar, beta >= 0, gamma >= 0, beta + gamma <= 1.
 * Working relative to the vertex makes the rounding of t and of h follow
 * the distance between the ray's origin and the triangle, not the size of
 * the coordinates: a ray leaving a surface 1000 units from the scene's
 * origin is decided as finely as one leaving it at 1 (the absolute form,
 * n_d - o_k - ..., lost 3e-5 of barycentric there).
 *
 * What it trades: one division and a dozen multiply-adds per ray, no cross
 * products; but it is NOT watertight: t is computed first and the edge tests
 * are made on a rounded hit point, so a ray through a shared edge or vertex
 * can miss both neighbours.  The conformance suite measures the escape rate
 * against the watertight reference; it is not hidden here.
 *
 * Ties: a lane takes a hit when t is strictly closer, or equally close with a
 * smaller prim, so the result does not depend on the order records are met.
 * NaN rays never hit (every comparison with NaN is false). */
#ifndef RTT_ISECT_PROJECTED_BARY_H
#define RTT_ISECT_PROJECTED_BARY_H

#include <immintrin.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "isect_hit.h"
#include "kd_tree.h"
#include "packet.h"

/* Fills the record of triangle `prim` with corners p; false (no record) when
 * the triangle is degenerate or its record would not be finite.  Computed in
 * double so that scenes at 1e-20 or 1e20 neither underflow nor overflow. */
bool kd_triangle_record(kd_triangle *rec, const rtt_vec3 p[3], uint32_t prim);

/* The lanes of `rays` that hit `tri` with tnear < t < tfar and t <= tbest;
 * on return `*t_out`, `*beta_out`, `*gamma_out` hold the lane values. */
/* The projection's other two axes, u = (k+1)%3 and v = (k+2)%3. */
static const uint8_t kd_axis_u[3] = {1, 2, 0}, kd_axis_v[3] = {2, 0, 1};

/* Broadcast of float `i` of a record row loaded whole: one shuffle instead
 * of a scalar load and a shuffle per field (records are 3 x 16 bytes). */
#define KD_SPLAT(row, i) _mm_shuffle_ps((row), (row), _MM_SHUFFLE(i, i, i, i))

static inline __m128 isect4_projected_bary_mask(const kd_triangle *tri, const ray_packet4 *rays, __m128 tbest,
                                                __m128 *t_out, __m128 *beta_out, __m128 *gamma_out)
{
    const uint32_t k = tri->k, ku = kd_axis_u[k], kv = kd_axis_v[k];
    const __m128 row0 = _mm_loadu_ps((const float *)tri); /* n_u n_v a_k a_u */
    const __m128 nu = KD_SPLAT(row0, 0), nv = KD_SPLAT(row0, 1);
    const __m128 row1 = _mm_loadu_ps((const float *)tri + 4); /* a_v b_nu b_nv c_nu */
    const __m128 rk = _mm_sub_ps(KD_SPLAT(row0, 2), rays->org[k]);
    const __m128 ru = _mm_sub_ps(KD_SPLAT(row0, 3), rays->org[ku]);
    const __m128 rv = _mm_sub_ps(KD_SPLAT(row1, 0), rays->org[kv]);
    __m128 den = _mm_add_ps(rays->dir[k], _mm_add_ps(_mm_mul_ps(nu, rays->dir[ku]), _mm_mul_ps(nv, rays->dir[kv])));
    __m128 num = _mm_add_ps(rk, _mm_add_ps(_mm_mul_ps(nu, ru), _mm_mul_ps(nv, rv)));
    __m128 t = _mm_div_ps(num, den);
    __m128 valid = _mm_and_ps(_mm_cmpgt_ps(t, rays->tnear), _mm_cmplt_ps(t, rays->tfar));
    valid = _mm_and_ps(valid, _mm_cmple_ps(t, tbest));
    if (_mm_movemask_ps(valid) == 0) {
        *t_out = t, *beta_out = *gamma_out = _mm_setzero_ps(); /* written on every path: no lane is valid */
        return valid;
    }
    const __m128 c_nv = _mm_set1_ps(tri->c_nv);
    __m128 hu = _mm_sub_ps(_mm_mul_ps(t, rays->dir[ku]), ru);
    __m128 hv = _mm_sub_ps(_mm_mul_ps(t, rays->dir[kv]), rv);
    __m128 beta = _mm_add_ps(_mm_mul_ps(KD_SPLAT(row1, 1), hu), _mm_mul_ps(KD_SPLAT(row1, 2), hv));
    __m128 gamma = _mm_add_ps(_mm_mul_ps(KD_SPLAT(row1, 3), hu), _mm_mul_ps(c_nv, hv));
    const __m128 zero = _mm_setzero_ps();
    valid = _mm_and_ps(valid, _mm_cmpge_ps(beta, zero));
    valid = _mm_and_ps(valid, _mm_cmpge_ps(gamma, zero));
    valid = _mm_and_ps(valid, _mm_cmple_ps(_mm_add_ps(beta, gamma), _mm_set1_ps(1.0f)));
    *t_out = t, *beta_out = beta, *gamma_out = gamma;
    return valid;
}

/* Closest hit: updates the lanes of `hits` under `active` whose ray hits
 * `tri` in (tnear, tfar) closer than (or as close with a smaller prim than)
 * the hit they hold. */
static inline void isect4_projected_bary(const kd_triangle *tri, const ray_packet4 *rays, hit_packet4 *hits,
                                         __m128 active)
{
    __m128 t, beta, gamma;
    /* t <= hits->t admits the tie; the prim comparison below settles it. */
    __m128 valid = _mm_and_ps(active, isect4_projected_bary_mask(tri, rays, hits->t, &t, &beta, &gamma));
    if (_mm_movemask_ps(valid)) hit_packet4_take_closer(hits, valid, t, beta, gamma, tri->prim);
}

/* Occlusion: the lanes under `active` whose ray hits `tri` in (tnear, tfar). */
static inline __m128 occluded4_projected_bary(const kd_triangle *tri, const ray_packet4 *rays, __m128 active)
{
    __m128 t, beta, gamma;
    const __m128 inf = _mm_set1_ps(INFINITY);
    return _mm_and_ps(active, isect4_projected_bary_mask(tri, rays, inf, &t, &beta, &gamma));
}

/* One ray: a scalar twin of the above, same arithmetic in the same order. */

static inline bool isect1_projected_bary_test(const kd_triangle *tri, const kd_ray1 *ray, float tbest, float *t_out,
                                              float *beta_out, float *gamma_out)
{
    const uint32_t k = tri->k, ku = k == 2 ? 0 : k + 1, kv = k == 0 ? 2 : k - 1;
    const float rk = tri->a_k - ray->org[k], ru = tri->a_u - ray->org[ku], rv = tri->a_v - ray->org[kv];
    float den = ray->dir[k] + (tri->n_u * ray->dir[ku] + tri->n_v * ray->dir[kv]);
    float num = rk + (tri->n_u * ru + tri->n_v * rv);
    float t = num / den;
    if (!(t > ray->tnear && t < ray->tfar && t <= tbest)) return false;
    float hu = t * ray->dir[ku] - ru;
    float hv = t * ray->dir[kv] - rv;
    float beta = tri->b_nu * hu + tri->b_nv * hv;
    float gamma = tri->c_nu * hu + tri->c_nv * hv;
    if (!(beta >= 0.0f && gamma >= 0.0f && beta + gamma <= 1.0f)) return false;
    *t_out = t, *beta_out = beta, *gamma_out = gamma;
    return true;
}

static inline void isect1_projected_bary(const kd_triangle *tri, const kd_ray1 *ray, kd_hit1 *hit)
{
    float t, beta, gamma;
    if (!isect1_projected_bary_test(tri, ray, hit->t, &t, &beta, &gamma)) return;
    if (t < hit->t || (t == hit->t && tri->prim < hit->prim)) {
        hit->t = t, hit->u = beta, hit->v = gamma;
        hit->prim = tri->prim;
    }
}

static inline bool occluded1_projected_bary(const kd_triangle *tri, const kd_ray1 *ray)
{
    float t, beta, gamma;
    return isect1_projected_bary_test(tri, ray, INFINITY, &t, &beta, &gamma);
}

#endif

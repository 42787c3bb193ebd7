/* Thesis 4.1.7 and Listing 4.4: a cone bounding a group of rays, and the
 * per-axis values Equation 4.8 precomputes.
 *
 * The thesis builds cones for primary tiles, all rays from the eye.  For
 * arbitrary rays: the axis v is the normalised mean direction, the half
 * angle b covers every direction (sin from |w x v| / |w|, accurate at the
 * small angles of primary tiles, then widened), and the apex is pulled back
 * along -v from the centre c of the origins' box by r / sin(b), r the radius
 * of that box's sphere.  Every origin then lies in the cone, and since the
 * set of vectors within b of v is a convex cone, so does every point
 * o + t w, t >= 0.  The interval is in units of the axis parameter
 * tau = (x - apex) . v; for a ray, tau = offset + t * speed with
 * offset = (o - apex) . v and speed = w . v > 0 (kd_block.cone_*).
 * Trades: a cone bounds a square tile more loosely than a pyramid (Table
 * 4.5) but needs no horizontal min/max per node. */
#include <float.h>
#include <math.h>

#include "cone.h"
#include "simd4.h"

#define KD_CONE_MIN_COS 0.17f /* ~80 degrees: wider cones do not pay */

int kd_cone_build(kd_block *b, uint32_t g, kd_cone *c)
{
    double sum[3] = {0, 0, 0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double tnear_min = INFINITY;
    uint32_t rays = 0;
    /* pass 1: mean direction, origin box */
    for (uint32_t i = b->group_first[g]; i < b->group_first[g + 1]; i++) {
        uint32_t p = b->order[i];
        int live = _mm_movemask_ps(b->live[p]);
        if (!live) continue;
        const ray_packet4 *r = &b->packets[p];
        float o[3][4], d[3][4], tn[4];
        for (int a = 0; a < 3; a++) _mm_storeu_ps(o[a], r->org[a]), _mm_storeu_ps(d[a], r->dir[a]);
        _mm_storeu_ps(tn, r->tnear);
        for (int l = 0; l < 4; l++) {
            if (!(live >> l & 1)) continue;
            double len = sqrt((double)d[0][l] * d[0][l] + (double)d[1][l] * d[1][l] + (double)d[2][l] * d[2][l]);
            for (int a = 0; a < 3; a++) {
                sum[a] += d[a][l] / len;
                lo[a] = kd_fmin1d(lo[a], o[a][l]);
                hi[a] = kd_fmax1d(hi[a], o[a][l]);
            }
            tnear_min = kd_fmin1d(tnear_min, tn[l]);
            rays++;
        }
    }
    if (!rays) return 0;
    if (tnear_min < 0.0) return -1;
    double slen = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (!(slen > 0.0)) return -1;
    double v[3] = {sum[0] / slen, sum[1] / slen, sum[2] / slen}, centre[3], radius2 = 0.0;
    for (int a = 0; a < 3; a++) {
        centre[a] = 0.5 * (lo[a] + hi[a]);
        radius2 += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
    }
    /* pass 2: widest direction */
    double sin2_max = 0.0, cos_min = 1.0;
    for (uint32_t i = b->group_first[g]; i < b->group_first[g + 1]; i++) {
        uint32_t p = b->order[i];
        int live = _mm_movemask_ps(b->live[p]);
        if (!live) continue;
        float d[3][4];
        for (int a = 0; a < 3; a++) _mm_storeu_ps(d[a], b->packets[p].dir[a]);
        for (int l = 0; l < 4; l++) {
            if (!(live >> l & 1)) continue;
            double w[3] = {d[0][l], d[1][l], d[2][l]};
            double len2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
            double cx = w[1] * v[2] - w[2] * v[1], cy = w[2] * v[0] - w[0] * v[2], cz = w[0] * v[1] - w[1] * v[0];
            sin2_max = kd_fmax1d(sin2_max, (cx * cx + cy * cy + cz * cz) / len2);
            cos_min = kd_fmin1d(cos_min, (w[0] * v[0] + w[1] * v[1] + w[2] * v[2]) / sqrt(len2));
        }
    }
    if (cos_min < KD_CONE_MIN_COS) return -1;
    double radius = sqrt(radius2) * (1.0 + 1e-4) + 1e-30;
    double sin_b = sqrt(sin2_max) * (1.0 + 1e-3) + 1e-6;
    if (radius > 1e-30 && sin_b < 1e-3) sin_b = 1e-3;
    if (sin_b >= 0.99) return -1;
    double cos_b = sqrt(1.0 - sin_b * sin_b), tan_b = sin_b / cos_b;
    double back = radius > 1e-30 ? radius / sin_b : 0.0;
    for (int a = 0; a < 3; a++) {
        c->apex[a] = (float)(centre[a] - v[a] * back);
        c->axis[a] = (float)v[a];
        b->cone_apex[g][a] = c->apex[a];
        b->cone_axis[g][a] = c->axis[a];
        /* Listing 4.4 */
        double beta = tan_b * sqrt(kd_fmax1d(0.0, 1.0 - v[a] * v[a]));
        c->pre[0][a] = (float)(1.0 / (v[a] + beta));
        c->pre[1][a] = (float)(1.0 / (v[a] - beta));
    }
    c->tan_angle = (float)tan_b;
    b->units = KD_UNITS_CONE_AXIS;
    /* root interval in tau units, per ray from its clipped [entry, exit] */
    __m128 near = _mm_set1_ps(INFINITY), far = _mm_set1_ps(-INFINITY);
    for (uint32_t i = b->group_first[g]; i < b->group_first[g + 1]; i++) {
        uint32_t p = b->order[i];
        __m128 live = b->live[p];
        if (!_mm_movemask_ps(live)) continue;
        const ray_packet4 *r = &b->packets[p];
        __m128 entry, exit, offset = _mm_setzero_ps(), speed = _mm_setzero_ps();
        kd_block_root_interval(b, p, &entry, &exit);
        for (int a = 0; a < 3; a++) {
            offset = _mm_add_ps(offset,
                                _mm_mul_ps(_mm_sub_ps(r->org[a], _mm_set1_ps(c->apex[a])), _mm_set1_ps(c->axis[a])));
            speed = _mm_add_ps(speed, _mm_mul_ps(r->dir[a], _mm_set1_ps(c->axis[a])));
        }
        entry = _mm_max_ps(entry, _mm_setzero_ps());
        near = _mm_min_ps(near, _mm_blendv_ps(near, _mm_add_ps(offset, _mm_mul_ps(entry, speed)), live));
        far = _mm_max_ps(far, _mm_blendv_ps(far, _mm_add_ps(offset, _mm_mul_ps(exit, speed)), live));
    }
    /* lanes of rays that meet nothing may hold NaN: ignored, as fminf / fmaxf ignore them */
    _Alignas(16) float lane[4];
    _mm_store_ps(lane, near);
    float n = kd_fmin1(kd_fmin1(lane[0], lane[1]), kd_fmin1(lane[2], lane[3]));
    _mm_store_ps(lane, far);
    float f = kd_fmax1(kd_fmax1(lane[0], lane[1]), kd_fmax1(lane[2], lane[3]));
    /* tau is computed with rounding relative to |offset| too */
    float slack = 1e-5f * (fabsf(n) + fabsf(f)) + FLT_MIN;
    c->near = kd_widen_lo(n, KD_WIDEN) - slack;
    c->far = kd_widen_hi(f, KD_WIDEN) + slack;
    return c->near <= c->far ? 1 : 0;
}

void kd_cone4_pack(const kd_cone c[4], const int present[4], kd_cone4 *out)
{
    float v[4];
    for (int a = 0; a < 3; a++) {
        for (int l = 0; l < 4; l++) v[l] = present[l] ? c[l].apex[a] : 0.0f;
        out->apex[a] = _mm_loadu_ps(v);
        for (int l = 0; l < 4; l++) v[l] = present[l] ? c[l].pre[0][a] : 1.0f;
        out->pre0[a] = _mm_loadu_ps(v);
        for (int l = 0; l < 4; l++) v[l] = present[l] ? c[l].pre[1][a] : 1.0f;
        out->pre1[a] = _mm_loadu_ps(v);
    }
    for (int l = 0; l < 4; l++) v[l] = present[l] ? c[l].near : INFINITY;
    out->near = _mm_loadu_ps(v);
    for (int l = 0; l < 4; l++) v[l] = present[l] ? c[l].far : -INFINITY;
    out->far = _mm_loadu_ps(v);
}

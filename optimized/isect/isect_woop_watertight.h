/* Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT
 * 2(1)), section 3 and the appendix listing, without back-face culling:
 * four rays at once in SSE4.1 and one ray in scalar code, on the corners of
 * kd_tree.h (kd_corners, parallel to the projected records).
 *
 * Per ray, once per leaf: the dominant direction axis kz, kx = (kz+1)%3,
 * ky = (kz+2)%3, and the shear sx = d_kx/d_kz, sy = d_ky/d_kz, sz = 1/d_kz.
 * Per triangle the corners relative to the origin are sheared onto the ray's
 * +z axis and the three edge functions U, V, W are evaluated in 2D at the
 * origin; the ray hits iff they share a sign, at t = T / det with
 * det = U + V + W, T = U az + V bz + W cz.  Two triangles that share an edge
 * compute its edge function from the same two transformed corners with the
 * opposite sign, so a ray cannot slip between them: the test is watertight.
 *
 * The paper swaps kx and ky when d_kz < 0 to keep the winding; a two-sided
 * test does not need it, and without the swap U, V, W, T and det are the
 * exact negations of the swapped ones, so t, u, v are the same bits.  This
 * is the reference's arithmetic (reference/isect_watertight.c) in the same
 * order: the two engines answer every ray alike, triangle by triangle.
 *
 * Packets: the lanes are grouped by kz (at most three groups, almost always
 * one for coherent rays), so inside a group the axes are scalars and the
 * corners are read by index, as the projected test reads its records.
 *
 * When any of U, V, W, det, T is zero, subnormal, infinite or NaN in a lane,
 * that lane is decided again in double (the products of two floats are
 * exact there): a ray through an edge or a vertex is not decided by float
 * cancellation, and edge functions, which grow as scale^2 (T as scale^3),
 * may leave float's range in scenes far from 1.  Rare, so scalar.
 *
 * What it trades against the projected test: 48 more bytes per record read
 * (the corners), the shear per ray per leaf, three more subtractions and a
 * few more multiplies per triangle; in return no ray escapes through a
 * shared edge or vertex (bench/results/accuracy.md measures both).
 *
 * Ties: a lane takes a hit when t is strictly closer, or equally close with a
 * smaller prim.  NaN rays never hit. */
#ifndef RTT_ISECT_WOOP_WATERTIGHT_H
#define RTT_ISECT_WOOP_WATERTIGHT_H

#include <float.h>
#include <immintrin.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "isect_hit.h"
#include "kd_tree.h"
#include "packet.h"

/* The shear of the lanes of one kz group. */
typedef struct wt_shear4 {
    uint32_t kx, ky, kz;
    __m128 sx, sy, sz;
} wt_shear4;

/* The lanes whose dominant direction axis is 0, 1 and 2 (ties to the
 * smaller axis, as the reference: |x| >= |y|, |x| >= |z| → 0). */
static inline void wt_axis_masks4(const ray_packet4 *rays, __m128 masks[3])
{
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 ax = _mm_andnot_ps(sign, rays->dir[0]), ay = _mm_andnot_ps(sign, rays->dir[1]),
                 az = _mm_andnot_ps(sign, rays->dir[2]);
    masks[0] = _mm_and_ps(_mm_cmpge_ps(ax, ay), _mm_cmpge_ps(ax, az));
    masks[1] = _mm_andnot_ps(masks[0], _mm_cmpge_ps(ay, az));
    masks[2] = _mm_andnot_ps(_mm_or_ps(masks[0], masks[1]), _mm_castsi128_ps(_mm_set1_epi32(-1)));
}

static inline void wt_shear4_setup(wt_shear4 *s, const ray_packet4 *rays, uint32_t kz)
{
    s->kz = kz, s->kx = kz == 2 ? 0 : kz + 1, s->ky = kz == 0 ? 2 : kz - 1;
    s->sx = _mm_div_ps(rays->dir[s->kx], rays->dir[kz]);
    s->sy = _mm_div_ps(rays->dir[s->ky], rays->dir[kz]);
    s->sz = _mm_div_ps(_mm_set1_ps(1.0f), rays->dir[kz]);
}

/* The kz groups of the lanes under `active` that hold a lane: their lanes
 * and shears, and how many there are (0 to 3; 1 for coherent rays). */
static inline uint32_t wt_groups4(const ray_packet4 *rays, __m128 active, __m128 lanes[3], wt_shear4 shears[3])
{
    __m128 masks[3];
    wt_axis_masks4(rays, masks);
    uint32_t count = 0;
    for (uint32_t kz = 0; kz < 3; kz++) {
        lanes[count] = _mm_and_ps(active, masks[kz]);
        if (_mm_movemask_ps(lanes[count]) == 0) continue;
        wt_shear4_setup(&shears[count++], rays, kz);
    }
    return count;
}

/* One lane's transformed corners (x, y, z of a, b, c). */
typedef struct wt_lane {
    float ax, ay, az, bx, by, bz, cx, cy, cz;
} wt_lane;

/* The reference's decision on transformed corners: float when every value
 * is normal, else double.  True with t, u, v when the ray crosses the
 * triangle with tnear < t < tfar. */
static inline bool wt_decide1(const wt_lane *l, float tnear, float tfar, float *t_out, float *u_out, float *v_out)
{
    const float u = l->cx * l->by - l->cy * l->bx;
    const float v = l->ax * l->cy - l->ay * l->cx;
    const float w = l->bx * l->ay - l->by * l->ax;
    const float det = u + v + w;
    const float t_scaled = u * l->az + v * l->bz + w * l->cz;
    float t, bu, bv;
    if (isnormal(u) && isnormal(v) && isnormal(w) && isnormal(det) && isnormal(t_scaled)) {
        if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
        t = t_scaled / det, bu = v / det, bv = w / det;
    } else {
        const double ud = (double)l->cx * l->by - (double)l->cy * l->bx;
        const double vd = (double)l->ax * l->cy - (double)l->ay * l->cx;
        const double wd = (double)l->bx * l->ay - (double)l->by * l->ax;
        if ((ud < 0.0 || vd < 0.0 || wd < 0.0) && (ud > 0.0 || vd > 0.0 || wd > 0.0)) return false;
        const double detd = ud + vd + wd;
        if (detd == 0.0) return false; /* the ray lies in the triangle's plane */
        /* + 0.0f: a zero as +0 whichever way the edges are wound (as the reference does) */
        t = (float)((ud * l->az + vd * l->bz + wd * l->cz) / detd) + 0.0f;
        bu = (float)(vd / detd) + 0.0f, bv = (float)(wd / detd) + 0.0f;
    }
    if (!(t > tnear && t < tfar)) return false; /* also rejects NaN */
    *t_out = t, *u_out = bu, *v_out = bv;
    return true;
}

/* Normal floats: neither zero, subnormal, infinite nor NaN. */
static inline __m128 wt_normal4(__m128 x)
{
    const __m128 a = _mm_andnot_ps(_mm_set1_ps(-0.0f), x);
    return _mm_and_ps(_mm_cmpge_ps(a, _mm_set1_ps(FLT_MIN)), _mm_cmplt_ps(a, _mm_set1_ps(INFINITY)));
}

/* The lanes under `active` (one kz group) that hit `tri` with
 * tnear < t < tfar and t <= tbest; t, u, v of those lanes in the outputs
 * (u, v only when `want_uv`). */
static inline __m128 isect4_watertight_mask(const kd_corners *tri, const ray_packet4 *rays, const wt_shear4 *s,
                                            __m128 active, __m128 tbest, bool want_uv, __m128 *t_out,
                                            __m128 *u_out, __m128 *v_out)
{
    const uint32_t kx = s->kx, ky = s->ky, kz = s->kz;
    const __m128 akx = _mm_sub_ps(_mm_set1_ps(tri->a[kx]), rays->org[kx]);
    const __m128 aky = _mm_sub_ps(_mm_set1_ps(tri->a[ky]), rays->org[ky]);
    const __m128 akz = _mm_sub_ps(_mm_set1_ps(tri->a[kz]), rays->org[kz]);
    const __m128 bkx = _mm_sub_ps(_mm_set1_ps(tri->b[kx]), rays->org[kx]);
    const __m128 bky = _mm_sub_ps(_mm_set1_ps(tri->b[ky]), rays->org[ky]);
    const __m128 bkz = _mm_sub_ps(_mm_set1_ps(tri->b[kz]), rays->org[kz]);
    const __m128 ckx = _mm_sub_ps(_mm_set1_ps(tri->c[kx]), rays->org[kx]);
    const __m128 cky = _mm_sub_ps(_mm_set1_ps(tri->c[ky]), rays->org[ky]);
    const __m128 ckz = _mm_sub_ps(_mm_set1_ps(tri->c[kz]), rays->org[kz]);
    const __m128 ax = _mm_sub_ps(akx, _mm_mul_ps(s->sx, akz)), ay = _mm_sub_ps(aky, _mm_mul_ps(s->sy, akz));
    const __m128 bx = _mm_sub_ps(bkx, _mm_mul_ps(s->sx, bkz)), by = _mm_sub_ps(bky, _mm_mul_ps(s->sy, bkz));
    const __m128 cx = _mm_sub_ps(ckx, _mm_mul_ps(s->sx, ckz)), cy = _mm_sub_ps(cky, _mm_mul_ps(s->sy, ckz));
    const __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
    const __m128 v = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
    const __m128 w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
    const __m128 zero = _mm_setzero_ps();
    /* the common case first: a miss decided by the signs alone */
    const __m128 positive = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)), _mm_cmpgt_ps(w, zero));
    const __m128 negative = _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)), _mm_cmplt_ps(w, zero));
    const __m128 inside = _mm_and_ps(active, _mm_or_ps(positive, negative));
    /* a lane with a zero, subnormal, infinite or NaN edge function is the
     * double path's, whatever its signs say */
    const __m128 edges_normal = _mm_and_ps(_mm_and_ps(wt_normal4(u), wt_normal4(v)), wt_normal4(w));
    const __m128 odd_edges = _mm_andnot_ps(edges_normal, active);
    if (_mm_movemask_ps(_mm_or_ps(inside, odd_edges)) == 0) return zero;
    const __m128 az = _mm_mul_ps(s->sz, akz), bz = _mm_mul_ps(s->sz, bkz), cz = _mm_mul_ps(s->sz, ckz);
    const __m128 det = _mm_add_ps(_mm_add_ps(u, v), w);
    const __m128 t_scaled = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, az), _mm_mul_ps(v, bz)), _mm_mul_ps(w, cz));
    const __m128 normal = _mm_and_ps(edges_normal, _mm_and_ps(wt_normal4(det), wt_normal4(t_scaled)));
    __m128 t = _mm_div_ps(t_scaled, det);
    __m128 valid = _mm_and_ps(_mm_and_ps(inside, normal), _mm_and_ps(_mm_cmpgt_ps(t, rays->tnear),
                                                                        _mm_cmplt_ps(t, rays->tfar)));
    valid = _mm_and_ps(valid, _mm_cmple_ps(t, tbest));
    __m128 bu = zero, bv = zero;
    if (want_uv && _mm_movemask_ps(valid)) bu = _mm_div_ps(v, det), bv = _mm_div_ps(w, det);
    const int slow = _mm_movemask_ps(_mm_andnot_ps(normal, active));
    if (slow) {
        _Alignas(16) float lane[12][4], tl[4], ul[4], vl[4], tn[4], tf[4], tb[4];
        const __m128 parts[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
        for (int i = 0; i < 9; i++) _mm_store_ps(lane[i], parts[i]);
        _mm_store_ps(tl, t), _mm_store_ps(ul, bu), _mm_store_ps(vl, bv);
        _mm_store_ps(tn, rays->tnear), _mm_store_ps(tf, rays->tfar), _mm_store_ps(tb, tbest);
        _Alignas(16) int32_t hit[4];
        _mm_store_si128((__m128i *)hit, _mm_castps_si128(valid));
        for (int l = 0; l < 4; l++) {
            if (!(slow >> l & 1)) continue;
            const wt_lane one = {lane[0][l], lane[1][l], lane[2][l], lane[3][l], lane[4][l],
                                 lane[5][l], lane[6][l], lane[7][l], lane[8][l]};
            hit[l] = wt_decide1(&one, tn[l], tf[l], &tl[l], &ul[l], &vl[l]) && tl[l] <= tb[l] ? -1 : 0;
        }
        valid = _mm_castsi128_ps(_mm_load_si128((const __m128i *)hit));
        t = _mm_load_ps(tl), bu = _mm_load_ps(ul), bv = _mm_load_ps(vl);
    }
    *t_out = t, *u_out = bu, *v_out = bv;
    return valid;
}

/* Closest hit of one kz group: lowers the lanes of `hits` under `active`
 * where `tri` is closer (or as close with a smaller prim). */
static inline void isect4_watertight(const kd_corners *tri, const ray_packet4 *rays, const wt_shear4 *s,
                                     hit_packet4 *hits, __m128 active)
{
    __m128 t, u, v;
    __m128 valid = isect4_watertight_mask(tri, rays, s, active, hits->t, true, &t, &u, &v);
    if (_mm_movemask_ps(valid)) hit_packet4_take_closer(hits, valid, t, u, v, tri->prim);
}

/* One ray: the same arithmetic, the ray's shear computed by the caller. */
typedef struct wt_ray1 {
    uint32_t kx, ky, kz;
    float sx, sy, sz;
} wt_ray1;

static inline void wt_ray1_setup(wt_ray1 *s, const kd_ray1 *ray)
{
    const float ax = fabsf(ray->dir[0]), ay = fabsf(ray->dir[1]), az = fabsf(ray->dir[2]);
    s->kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    s->kx = s->kz == 2 ? 0 : s->kz + 1, s->ky = s->kz == 0 ? 2 : s->kz - 1;
    s->sx = ray->dir[s->kx] / ray->dir[s->kz];
    s->sy = ray->dir[s->ky] / ray->dir[s->kz];
    s->sz = 1.0f / ray->dir[s->kz];
}

/* One ray against the corners a, b, c (any record layout that holds them:
 * kd_corners, the BVH's bvh_corners). */
static inline bool isect1_watertight_corners(const float a[3], const float b[3], const float c[3], const kd_ray1 *ray,
                                             const wt_ray1 *s, float *t, float *u, float *v)
{
    const uint32_t kx = s->kx, ky = s->ky, kz = s->kz;
    const float akz = a[kz] - ray->org[kz], bkz = b[kz] - ray->org[kz], ckz = c[kz] - ray->org[kz];
    const wt_lane l = {
        (a[kx] - ray->org[kx]) - s->sx * akz, (a[ky] - ray->org[ky]) - s->sy * akz, s->sz * akz,
        (b[kx] - ray->org[kx]) - s->sx * bkz, (b[ky] - ray->org[ky]) - s->sy * bkz, s->sz * bkz,
        (c[kx] - ray->org[kx]) - s->sx * ckz, (c[ky] - ray->org[ky]) - s->sy * ckz, s->sz * ckz,
    };
    return wt_decide1(&l, ray->tnear, ray->tfar, t, u, v);
}

static inline bool isect1_watertight_test(const kd_corners *tri, const kd_ray1 *ray, const wt_ray1 *s, float *t,
                                          float *u, float *v)
{
    return isect1_watertight_corners(tri->a, tri->b, tri->c, ray, s, t, u, v);
}

#endif

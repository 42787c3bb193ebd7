/* Interval frusta of groups of rays (Thesis 2.3.2 frustums, 4.1.3, 4.1.5;
 * frustum.h).
 *
 * Frustum construction, generalised from the thesis' corner rays: the
 * thesis builds the interval frustum from the four corner rays of a primary
 * tile, which assumes one origin.  Here a group of arbitrary rays is bounded
 * by interval arithmetic instead: the origin box and, per axis, the ranges
 * of positive and of negative reciprocal directions.  For a common origin
 * and equal signs this gives exactly the corner-ray distances; for mixed
 * signs it gives the omni-directional rule of Listing 4.2 (a ray going away
 * from the plane never crosses it: distance +inf).  Trades: a frustum per
 * group costs one pass over its packets per axis, and a group whose origins
 * spread or whose signs mix on every axis bounds nothing useful (it is then
 * traced lane by lane, kd_frustum4_of_lanes). */
#include <math.h>

#include "frustum.h"

/* One pass per axis (eight accumulators stay in registers; all of them at
 * once spilled to the stack on every packet), then the root interval. */
int kd_frustum_build(const kd_block *b, uint32_t g, kd_frustum *f)
{
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY), sign = _mm_set1_ps(-0.0f);
    const uint16_t *first = &b->order[b->group_first[g]], *last = &b->order[b->group_first[g + 1]];
    for (int a = 0; a < 3; a++) {
        __m128 olo = pinf, ohi = ninf, plo = pinf, phi = ninf, nlo = pinf, nhi = ninf;
        __m128 hpos = _mm_setzero_ps(), hneg = _mm_setzero_ps();
        for (const uint16_t *i = first; i < last; i++) {
            __m128 live = b->live[*i];
            const ray_packet4 *r = &b->packets[*i];
            olo = _mm_min_ps(olo, _mm_blendv_ps(pinf, r->org[a], live));
            ohi = _mm_max_ps(ohi, _mm_blendv_ps(ninf, r->org[a], live));
            __m128 neg = _mm_and_ps(_mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(r->dir[a]), 31)), live);
            __m128 pos = _mm_andnot_ps(neg, live);
            /* the packet's reciprocal (1/dir, packet.h); the split distances
             * are widened by KD_WIDEN, far more than a refined rcp's error */
            __m128 mag = _mm_andnot_ps(sign, r->inv_dir[a]);
            plo = _mm_min_ps(plo, _mm_blendv_ps(pinf, mag, pos));
            phi = _mm_max_ps(phi, _mm_blendv_ps(ninf, mag, pos));
            nlo = _mm_min_ps(nlo, _mm_blendv_ps(pinf, mag, neg));
            nhi = _mm_max_ps(nhi, _mm_blendv_ps(ninf, mag, neg));
            hpos = _mm_or_ps(hpos, pos);
            hneg = _mm_or_ps(hneg, neg);
        }
        f->org_lo[a] = kd_hmin4(olo);
        f->org_hi[a] = kd_hmax4(ohi);
        f->pos_lo[a] = kd_hmin4(plo);
        f->pos_hi[a] = kd_hmax4(phi);
        f->neg_lo[a] = kd_hmin4(nlo);
        f->neg_hi[a] = kd_hmax4(nhi);
        f->has_pos[a] = _mm_movemask_ps(hpos) != 0;
        f->has_neg[a] = _mm_movemask_ps(hneg) != 0;
    }
    __m128 near = pinf, far = ninf;
    for (const uint16_t *i = first; i < last; i++) {
        __m128 live = b->live[*i];
        near = _mm_min_ps(near, _mm_blendv_ps(pinf, b->root_entry[*i], live));
        far = _mm_max_ps(far, _mm_blendv_ps(ninf, b->root_exit[*i], live));
    }
    f->near = kd_hmin4(near);
    f->far = kd_hmax4(far);
    return f->near <= f->far;
}

int kd_frustum_is_incoherent(const kd_block *b, const kd_frustum *f)
{
    rtt_vec3 e = rtt_v3_sub(b->tree->bounds.hi, b->tree->bounds.lo);
    float scene = kd_max1(e.x, kd_max1(e.y, e.z));
    int mixed = 0;
    for (int a = 0; a < 3; a++) {
        if (f->org_hi[a] - f->org_lo[a] > 0.01f * scene) return 1;
        mixed += f->has_pos[a] && f->has_neg[a];
    }
    return mixed == 3;
}

/* Lane l of the result: `value[l]` where present[l], else `idle`. */
static __m128 lanes_or(const int present[4], const float value[4], float idle)
{
    return _mm_setr_ps(present[0] ? value[0] : idle, present[1] ? value[1] : idle, present[2] ? value[2] : idle,
                       present[3] ? value[3] : idle);
}

/* All-ones lanes where present[l] and flag[l]. */
static __m128 mask_lanes(const int present[4], const uint32_t flag[4])
{
    return _mm_castsi128_ps(_mm_setr_epi32(present[0] && flag[0] ? -1 : 0, present[1] && flag[1] ? -1 : 0,
                                           present[2] && flag[2] ? -1 : 0, present[3] && flag[3] ? -1 : 0));
}

void kd_frustum4_pack(const kd_frustum f[4], const int present[4], kd_frustum4 *out)
{
    for (int a = 0; a < 3; a++) {
        const float org_lo[4] = {f[0].org_lo[a], f[1].org_lo[a], f[2].org_lo[a], f[3].org_lo[a]};
        const float org_hi[4] = {f[0].org_hi[a], f[1].org_hi[a], f[2].org_hi[a], f[3].org_hi[a]};
        const float pos_lo[4] = {f[0].pos_lo[a], f[1].pos_lo[a], f[2].pos_lo[a], f[3].pos_lo[a]};
        const float pos_hi[4] = {f[0].pos_hi[a], f[1].pos_hi[a], f[2].pos_hi[a], f[3].pos_hi[a]};
        const float neg_lo[4] = {f[0].neg_lo[a], f[1].neg_lo[a], f[2].neg_lo[a], f[3].neg_lo[a]};
        const float neg_hi[4] = {f[0].neg_hi[a], f[1].neg_hi[a], f[2].neg_hi[a], f[3].neg_hi[a]};
        const uint32_t has_pos[4] = {f[0].has_pos[a], f[1].has_pos[a], f[2].has_pos[a], f[3].has_pos[a]};
        const uint32_t has_neg[4] = {f[0].has_neg[a], f[1].has_neg[a], f[2].has_neg[a], f[3].has_neg[a]};
        out->org_lo[a] = lanes_or(present, org_lo, 0.0f);
        out->org_hi[a] = lanes_or(present, org_hi, 0.0f);
        out->pos_lo[a] = lanes_or(present, pos_lo, 1.0f);
        out->pos_hi[a] = lanes_or(present, pos_hi, 1.0f);
        out->neg_lo[a] = lanes_or(present, neg_lo, 1.0f);
        out->neg_hi[a] = lanes_or(present, neg_hi, 1.0f);
        out->has_pos[a] = mask_lanes(present, has_pos);
        out->has_neg[a] = mask_lanes(present, has_neg);
    }
    const float near[4] = {f[0].near, f[1].near, f[2].near, f[3].near};
    const float far[4] = {f[0].far, f[1].far, f[2].far, f[3].far};
    out->near = lanes_or(present, near, INFINITY);
    out->far = lanes_or(present, far, -INFINITY);
}

void kd_frustum4_of_lanes(const kd_block *b, uint32_t p, kd_frustum4 *f)
{
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
    const __m128 sign = _mm_set1_ps(-0.0f), one = _mm_set1_ps(1.0f);
    const __m128 live = b->live[p];
    const ray_packet4 *r = &b->packets[p];
    for (int a = 0; a < 3; a++) {
        __m128 org = _mm_and_ps(r->org[a], live);
        __m128 inv = _mm_div_ps(one, r->dir[a]);
        __m128 mag = _mm_blendv_ps(one, _mm_andnot_ps(sign, inv), live);
        __m128 neg = _mm_and_ps(_mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(r->dir[a]), 31)), live);
        __m128 pos = _mm_andnot_ps(neg, live);
        f->org_lo[a] = f->org_hi[a] = org;
        f->pos_lo[a] = _mm_blendv_ps(pinf, mag, pos);
        f->pos_hi[a] = _mm_blendv_ps(ninf, mag, pos);
        f->neg_lo[a] = _mm_blendv_ps(pinf, mag, neg);
        f->neg_hi[a] = _mm_blendv_ps(ninf, mag, neg);
        f->has_pos[a] = pos;
        f->has_neg[a] = neg;
    }
    __m128 entry, exit;
    kd_block_root_interval(b, p, &entry, &exit);
    f->near = _mm_blendv_ps(pinf, entry, live);
    f->far = _mm_blendv_ps(ninf, exit, live);
}

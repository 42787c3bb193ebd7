/* Ray packets of the BVH kernels: BVH_W rays (bvh_simd.h: 16, 8 or 4) in
 * structure-of-arrays form, and their closest hits.  A lane without a ray,
 * or with a ray that is not finite, is inactive (tnear = +inf > tfar = -inf)
 * and answers a miss.  Kernel side: compiled once per instruction set. */
#ifndef RTT_BVH_PACKET_H
#define RTT_BVH_PACKET_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "bvh_simd.h"
#include "packet.h" /* ray_is_traceable: the kd kernels' rule for rays they refuse */
#include "rtt/engine.h"

typedef struct bvh_packet {
    vf org[3], dir[3], inv_dir[3];
    vf tnear, tfar;
} bvh_packet;

typedef struct bvh_hits {
    vf t, u, v;
    vi prim;
} bvh_hits;

/* Loads rays[0 .. count-1] (count <= BVH_W); returns the live lanes.  The
 * rays are copied into lanes as they are, then checked and completed a
 * packet at a time: a lane whose origin or direction is not finite or whose
 * interval is NaN (ray_is_traceable's rule) is inactive, as is a lane past
 * count; the reciprocals are one IEEE division per lane, as 1.0f / d. */
static inline uint32_t bvh_packet_load(bvh_packet *p, const rtt_ray *rays, size_t count)
{
    _Static_assert(sizeof(rtt_ray) == 8 * sizeof(float), "a ray is eight floats: org, dir, tnear, tfar");
    vf field[8];
    if (count >= BVH_W) {
        vf_load_records8(&rays[0].org[0], field);
    } else {
        float v[8][BVH_W];
        for (uint32_t l = 0; l < BVH_W; l++) {
            const float *r = l < count ? &rays[l].org[0] : NULL;
            for (int a = 0; a < 8; a++) v[a][l] = r ? r[a] : 0.0f;
        }
        for (int a = 0; a < 8; a++) field[a] = vf_load(v[a]);
    }
    const vf zero = vf_set1(0.0f);
    vm ok = vm_of_bits(count >= BVH_W ? BVH_LANES_ALL : (uint32_t)((1u << count) - 1u));
    for (int a = 0; a < 3; a++) {
        p->org[a] = field[a];
        p->dir[a] = field[3 + a];
        /* finite: x - x is 0 (inf - inf and NaN are NaN) */
        ok = vm_and(ok, vm_and(vf_eq(vf_sub(p->org[a], p->org[a]), zero), vf_eq(vf_sub(p->dir[a], p->dir[a]), zero)));
    }
    const vf tnear = field[6], tfar = field[7];
    ok = vm_and(ok, vm_and(vf_eq(tnear, tnear), vf_eq(tfar, tfar)));
    const vf one = vf_set1(1.0f);
    for (int a = 0; a < 3; a++) {
        p->org[a] = vf_blend(ok, zero, p->org[a]);
        p->dir[a] = vf_blend(ok, one, p->dir[a]);
        p->inv_dir[a] = vf_div(one, p->dir[a]);
    }
    p->tnear = vf_blend(ok, vf_set1(INFINITY), tnear);
    p->tfar = vf_blend(ok, vf_set1(-INFINITY), tfar);
    return vm_bits(vm_and(ok, vf_le(tnear, tfar)));
}

static inline void bvh_hits_clear(bvh_hits *h)
{
    h->t = vf_set1(INFINITY);
    h->u = h->v = vf_set1(0.0f);
    h->prim = vi_set1(RTT_MISS);
}

static inline void bvh_hits_store(const bvh_hits *h, rtt_hit *out, size_t count)
{
    float t[BVH_W], u[BVH_W], v[BVH_W];
    uint32_t prim[BVH_W];
    vf_store(t, h->t), vf_store(u, h->u), vf_store(v, h->v), vi_store(prim, h->prim);
    for (uint32_t l = 0; l < BVH_W && l < count; l++)
        out[l] = prim[l] == RTT_MISS ? (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS} : (rtt_hit){t[l], u[l], v[l], prim[l]};
}

/* A packet of rows of four rays (lane 4 r + i: row r, column i; BVH_W / 4
 * rows) stores its hits into `rows` rows of `cols` records from `out`,
 * `stride` records apart, bvh_hits_store's records (a miss: t = +inf, u = v
 * = 0).  A whole row's four records are transposed in registers and stored
 * at once (64 bytes); a row cut by the image's edge (cols < 4) goes a
 * record at a time. */
static inline void bvh_hits_store_rows(const bvh_hits *h, rtt_hit *out, size_t stride, uint32_t cols, uint32_t rows)
{
    _Static_assert(sizeof(rtt_hit) == 4 * sizeof(float), "a hit is four words: t, u, v, prim");
    const vm hit = vi_lt_u(h->prim, vi_set1(RTT_MISS));
    const vf t = vf_blend(hit, vf_set1(INFINITY), h->t);
    const vf u = vf_blend(hit, vf_set1(0.0f), h->u), v = vf_blend(hit, vf_set1(0.0f), h->v);
    if (cols < 4u) {
        _Alignas(64) float tl[BVH_W], ul[BVH_W], vl[BVH_W];
        _Alignas(64) uint32_t pl[BVH_W];
        vf_store(tl, t), vf_store(ul, u), vf_store(vl, v), vi_store(pl, h->prim);
        for (uint32_t r = 0; r < rows; r++)
            for (uint32_t i = 0; i < cols; i++) {
                const uint32_t l = 4u * r + i;
                out[r * stride + i] = (rtt_hit){tl[l], ul[l], vl[l], pl[l]};
            }
        return;
    }
#if BVH_W == 16
    const __m512 p = _mm512_castsi512_ps(h->prim);
    /* per 128-bit lane (a row): records 0, 1 and 2, 3 of its pixels, then
     * the rows gathered from the four records' lanes */
    const __m512 tu_lo = _mm512_unpacklo_ps(t, u), tu_hi = _mm512_unpackhi_ps(t, u);
    const __m512 vp_lo = _mm512_unpacklo_ps(v, p), vp_hi = _mm512_unpackhi_ps(v, p);
    const __m512 r0 = _mm512_shuffle_ps(tu_lo, vp_lo, 0x44), r1 = _mm512_shuffle_ps(tu_lo, vp_lo, 0xEE);
    const __m512 r2 = _mm512_shuffle_ps(tu_hi, vp_hi, 0x44), r3 = _mm512_shuffle_ps(tu_hi, vp_hi, 0xEE);
    const __m512 a = _mm512_shuffle_f32x4(r0, r1, 0x44), b = _mm512_shuffle_f32x4(r0, r1, 0xEE);
    const __m512 c = _mm512_shuffle_f32x4(r2, r3, 0x44), d = _mm512_shuffle_f32x4(r2, r3, 0xEE);
    const __m512 row[4] = {_mm512_shuffle_f32x4(a, c, 0x88), _mm512_shuffle_f32x4(a, c, 0xDD),
                           _mm512_shuffle_f32x4(b, d, 0x88), _mm512_shuffle_f32x4(b, d, 0xDD)};
    for (uint32_t r = 0; r < rows; r++) _mm512_storeu_ps((float *)(out + r * stride), row[r]);
#elif BVH_W == 8
    const __m256 p = _mm256_castsi256_ps(h->prim);
    const __m256 tu_lo = _mm256_unpacklo_ps(t, u), tu_hi = _mm256_unpackhi_ps(t, u);
    const __m256 vp_lo = _mm256_unpacklo_ps(v, p), vp_hi = _mm256_unpackhi_ps(v, p);
    /* record i of row 0 in the low half, of row 1 in the high half */
    const __m256 r0 = _mm256_shuffle_ps(tu_lo, vp_lo, 0x44), r1 = _mm256_shuffle_ps(tu_lo, vp_lo, 0xEE);
    const __m256 r2 = _mm256_shuffle_ps(tu_hi, vp_hi, 0x44), r3 = _mm256_shuffle_ps(tu_hi, vp_hi, 0xEE);
    for (uint32_t r = 0; r < rows; r++) {
        const int half = r ? 0x31 : 0x20;
        float *row = (float *)(out + r * stride);
        _mm256_storeu_ps(row, _mm256_permute2f128_ps(r0, r1, half));
        _mm256_storeu_ps(row + 8, _mm256_permute2f128_ps(r2, r3, half));
    }
#else
    __m128 r0 = t, r1 = u, r2 = v, r3 = _mm_castsi128_ps(h->prim);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    float *row = (float *)out;
    (void)rows; /* one row of four */
    _mm_storeu_ps(row, r0), _mm_storeu_ps(row + 4, r1), _mm_storeu_ps(row + 8, r2), _mm_storeu_ps(row + 12, r3);
#endif
}

#endif

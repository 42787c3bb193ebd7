/* Ray packets of the BVH kernels: BVH_W rays (bvh_simd.h: 16, 8 or 4) in
 * structure-of-arrays form, and their closest hits.  A lane without a ray,
 * or with a ray that is not finite, is inactive (tnear = +inf > tfar = -inf)
 * and answers a miss.  Kernel side: compiled once per instruction set. */
#ifndef RTT_BVH_PACKET_H
#define RTT_BVH_PACKET_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bvh_simd.h"
#include "hit_rows.h"
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

/* The reciprocals of p's directions: one IEEE division per lane, as 1.0f / d
 * (the packet walk's box test reads them; the frusta kernels do not). */
static inline void bvh_packet_reciprocals(bvh_packet *p)
{
    for (int a = 0; a < 3; a++) p->inv_dir[a] = vf_div(vf_set1(1.0f), p->dir[a]);
}

/* Loads rays[0 .. count-1] (count <= BVH_W) without the reciprocals;
 * returns the live lanes.  The rays are copied into lanes as they are, then
 * checked and completed a packet at a time: a lane whose origin or
 * direction is not finite or whose interval is NaN (ray_is_traceable's
 * rule) is inactive, as is a lane past count. */
static inline uint32_t bvh_packet_load_rays(bvh_packet *p, const rtt_ray *rays, size_t count)
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
    }
    p->tnear = vf_blend(ok, vf_set1(INFINITY), tnear);
    p->tfar = vf_blend(ok, vf_set1(-INFINITY), tfar);
    return vm_bits(vm_and(ok, vf_le(tnear, tfar)));
}

/* bvh_packet_load_rays and the reciprocals. */
static inline uint32_t bvh_packet_load(bvh_packet *p, const rtt_ray *rays, size_t count)
{
    const uint32_t live = bvh_packet_load_rays(p, rays, count);
    bvh_packet_reciprocals(p);
    return live;
}

static inline void bvh_hits_clear(bvh_hits *h)
{
    h->t = vf_set1(INFINITY);
    h->u = h->v = vf_set1(0.0f);
    h->prim = vi_set1(RTT_MISS);
}

/* The words of the packet's hit records, a miss as t = +inf, u = v = 0
 * (prim is the packet's own): w[0] t, w[1] u, w[2] v. */
static inline void bvh_hits_words(const bvh_hits *h, vf w[3])
{
    const vm hit = vi_lt_u(h->prim, vi_set1(RTT_MISS));
    w[0] = vf_blend(hit, vf_set1(INFINITY), h->t);
    w[1] = vf_blend(hit, vf_set1(0.0f), h->u), w[2] = vf_blend(hit, vf_set1(0.0f), h->v);
}

/* The same words lane by lane, for the stores of a record at a time. */
static inline void bvh_hits_lanes(const bvh_hits *h, float t[BVH_W], float u[BVH_W], float v[BVH_W],
                                  uint32_t prim[BVH_W])
{
    vf w[3];
    bvh_hits_words(h, w);
    vf_store(t, w[0]), vf_store(u, w[1]), vf_store(v, w[2]), vi_store(prim, h->prim);
}

/* A packet of rows of four rays (lane 4 r + i: row r, column i; BVH_W / 4
 * rows) stores its hits into `rows` rows of `cols` records from `out`,
 * `stride` records apart (bvh_hits_words' records).  A whole row's four
 * records are transposed in registers and stored at once (64 bytes; with
 * `stream`, rows on 64-byte lines, non-temporal); a row cut by the image's
 * edge (cols < 4) goes a record at a time (hit_rows.h's transpose). */
static inline void bvh_hits_store_rows(const bvh_hits *h, rtt_hit *out, size_t stride, uint32_t cols, uint32_t rows,
                                       bool stream)
{
    _Static_assert(sizeof(rtt_hit) == 4 * sizeof(float), "a hit is four words: t, u, v, prim");
    if (cols < 4u) {
        _Alignas(64) float tl[BVH_W], ul[BVH_W], vl[BVH_W];
        _Alignas(64) uint32_t pl[BVH_W];
        bvh_hits_lanes(h, tl, ul, vl, pl);
        for (uint32_t r = 0; r < rows; r++)
            for (uint32_t i = 0; i < cols; i++) {
                const uint32_t l = 4u * r + i;
                out[r * stride + i] = (rtt_hit){tl[l], ul[l], vl[l], pl[l]};
            }
        return;
    }
    _Static_assert(HIT_ROWS_W == BVH_W, "hit_rows.h is compiled for the packet's width");
    vf w[3], rec[4];
    bvh_hits_words(h, w);
    hit_rows_of_lanes(w[0], w[1], w[2], vi_as_vf(h->prim), rec);
    for (uint32_t r = 0; r < rows; r++)
        for (uint32_t j = 0; j < HIT_ROWS_PER_ROW; j++) {
            float *at = (float *)(out + r * stride) + j * BVH_W;
            if (stream) vf_stream(at, rec[r * HIT_ROWS_PER_ROW + j]);
            else vf_store(at, rec[r * HIT_ROWS_PER_ROW + j]);
        }
}

/* The packet's hits into out[0 .. count-1] (count <= BVH_W): a whole packet
 * is its BVH_W / 4 rows of four records one after another
 * (bvh_hits_store_rows with a stride of four), a part a record at a time. */
static inline void bvh_hits_store(const bvh_hits *h, rtt_hit *out, size_t count)
{
    if (count >= BVH_W) {
        bvh_hits_store_rows(h, out, 4u, 4u, BVH_W / 4u, false);
        return;
    }
    float tl[BVH_W], ul[BVH_W], vl[BVH_W];
    uint32_t pl[BVH_W];
    bvh_hits_lanes(h, tl, ul, vl, pl);
    for (uint32_t l = 0; l < count; l++) out[l] = (rtt_hit){tl[l], ul[l], vl[l], pl[l]};
}

#endif

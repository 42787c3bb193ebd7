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

/* Loads rays[0 .. count-1] (count <= BVH_W); returns the live lanes. */
static inline uint32_t bvh_packet_load(bvh_packet *p, const rtt_ray *rays, size_t count)
{
    float org[3][BVH_W], dir[3][BVH_W], inv[3][BVH_W], tnear[BVH_W], tfar[BVH_W];
    uint32_t live = 0;
    for (uint32_t l = 0; l < BVH_W; l++) {
        const rtt_ray *r = l < count ? &rays[l] : NULL;
        const int ok = r && ray_is_traceable(r);
        for (int a = 0; a < 3; a++) {
            org[a][l] = ok ? r->org[a] : 0.0f;
            dir[a][l] = ok ? r->dir[a] : 1.0f;
            inv[a][l] = 1.0f / dir[a][l];
        }
        tnear[l] = ok ? r->tnear : INFINITY;
        tfar[l] = ok ? r->tfar : -INFINITY;
        if (ok && r->tnear <= r->tfar) live |= 1u << l;
    }
    for (int a = 0; a < 3; a++) {
        p->org[a] = vf_load(org[a]);
        p->dir[a] = vf_load(dir[a]);
        p->inv_dir[a] = vf_load(inv[a]);
    }
    p->tnear = vf_load(tnear);
    p->tfar = vf_load(tfar);
    return live;
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

#endif

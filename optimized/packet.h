/* SSE ray packets: the unit every optimized kernel works on.
 *
 * A packet is four rays in the four SSE lanes (structure of arrays, 16-byte
 * aligned).  Lanes that carry no ray have tnear > tfar (inactive).  Kernels
 * take blocks of packets: a 2x2 packet is one block of 1; a frustum tile of
 * side T is one block of T*T/4 packets (2x2 pixel quads in row-major order of
 * quads).  Arbitrary ray streams are cut into such blocks by the engine.
 *
 * Loading and storing are header-only (static inline) so that the kernels
 * that load packets themselves (the shadow groups) compile them for their
 * own instruction set; the arithmetic is the same in every copy. */
#ifndef RTT_OPTIMIZED_PACKET_H
#define RTT_OPTIMIZED_PACKET_H

#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "simd4.h"

/* 176 bytes: origin, direction, reciprocal direction and the interval. */
typedef struct ray_packet4 {
    __m128 org[3], dir[3], inv_dir[3];
    __m128 tnear, tfar;
} ray_packet4;
_Static_assert(sizeof(ray_packet4) == 176, "ray_packet4 is 11 SSE registers");

/* 64 bytes; prim lanes RTT_MISS and t = +inf on a miss. */
typedef struct hit_packet4 {
    __m128 t, u, v;
    __m128i prim;
} hit_packet4;
_Static_assert(sizeof(hit_packet4) == 64, "hit_packet4 is one cache line");

/* The thesis' counters (Tables 4.1-4.5): N = steps / packets, I = isects /
 * packets, counted per 2x2 packet.  Kernels add to them only when the
 * pointer is non-NULL, so counting never changes results and costs nothing
 * when off. */
typedef struct kd_counters {
    uint64_t packets, steps, isects;
} kd_counters;

/* A ray whose origin or direction is not finite, or whose interval is NaN,
 * is loaded as an inactive lane (tnear = +inf > tfar = -inf): it reports a
 * miss and can never steer a traversal into a loop. */
static inline int ray_is_traceable(const rtt_ray *r)
{
    for (int a = 0; a < 3; a++)
        if (!isfinite(r->org[a]) || !isfinite(r->dir[a])) return 0;
    return !isnan(r->tnear) && !isnan(r->tfar);
}

/* Loads up to four rays (count 1..4) into a packet; missing lanes inactive.
 * A zero direction component gives inv_dir = +-inf with the sign of the
 * zero, which is what the kernels' near/far child order relies on. */
static inline void ray_packet4_load(ray_packet4 *packet, const rtt_ray *rays, uint32_t count)
{
    _Alignas(16) float org[3][4], dir[3][4], inv[3][4], tnear[4], tfar[4];
    for (uint32_t l = 0; l < 4; l++) {
        const rtt_ray *r = l < count ? &rays[l] : NULL;
        int live = r && ray_is_traceable(r);
        for (int a = 0; a < 3; a++) {
            org[a][l] = live ? r->org[a] : 0.0f;
            dir[a][l] = live ? r->dir[a] : 1.0f;
            inv[a][l] = 1.0f / dir[a][l];
        }
        tnear[l] = live ? r->tnear : INFINITY;
        tfar[l] = live ? r->tfar : -INFINITY;
    }
    for (int a = 0; a < 3; a++) {
        packet->org[a] = _mm_load_ps(org[a]);
        packet->dir[a] = _mm_load_ps(dir[a]);
        packet->inv_dir[a] = _mm_load_ps(inv[a]);
    }
    packet->tnear = _mm_load_ps(tnear);
    packet->tfar = _mm_load_ps(tfar);
}

static inline void hit_packet4_clear(hit_packet4 *hits)
{
    hits->t = _mm_set1_ps(INFINITY);
    hits->u = _mm_setzero_ps();
    hits->v = _mm_setzero_ps();
    hits->prim = _mm_set1_epi32(-1);
}

/* The first `count` lanes (at most 4) as rtt_hits: a miss is t = +inf,
 * u = v = 0, prim RTT_MISS (rtt_hit's contract, whatever the lanes hold). */
static inline void hit_packet4_store(const hit_packet4 *hits, rtt_hit *out, uint32_t count)
{
    _Alignas(16) float t[4], u[4], v[4];
    _Alignas(16) uint32_t prim[4];
    _mm_store_ps(t, hits->t);
    _mm_store_ps(u, hits->u);
    _mm_store_ps(v, hits->v);
    _mm_store_si128((__m128i *)prim, hits->prim);
    for (uint32_t l = 0; l < count && l < 4; l++) {
        out[l].prim = prim[l];
        out[l].t = prim[l] == RTT_MISS ? INFINITY : t[l];
        out[l].u = prim[l] == RTT_MISS ? 0.0f : u[l];
        out[l].v = prim[l] == RTT_MISS ? 0.0f : v[l];
    }
}

/* Lanes carrying a ray that can hit anything: finite origin and direction,
 * a nonzero direction, tnear < tfar (both not NaN).  The others are dead
 * lanes for every kernel. */
static inline __m128 ray_packet4_valid(const ray_packet4 *r)
{
    __m128 valid = _mm_cmplt_ps(r->tnear, r->tfar), nonzero = _mm_setzero_ps();
    for (int a = 0; a < 3; a++) {
        valid = _mm_and_ps(valid, _mm_and_ps(kd_finite4(r->org[a]), kd_finite4(r->dir[a])));
        nonzero = _mm_or_ps(nonzero, _mm_cmpneq_ps(r->dir[a], _mm_setzero_ps()));
    }
    return _mm_and_ps(valid, nonzero);
}

/* Slab test of the packet against the box [lo, hi]: per lane the entry and
 * exit parameters, clipped to [tnear, tfar], not widened (callers widen by
 * their own amount).  A NaN slab (a ray parallel to a face, its origin
 * exactly on it) drops that axis: min/max keep their second operand. */
static inline void ray_packet4_slab(const ray_packet4 *r, const float lo[3], const float hi[3], __m128 tnear,
                                    __m128 tfar, __m128 *entry, __m128 *exit)
{
    __m128 t0 = tnear, t1 = tfar;
    for (int a = 0; a < 3; a++) {
        __m128 ta = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(lo[a]), r->org[a]), r->inv_dir[a]);
        __m128 tb = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(hi[a]), r->org[a]), r->inv_dir[a]);
        t0 = _mm_max_ps(_mm_min_ps(ta, tb), t0);
        t1 = _mm_min_ps(_mm_max_ps(ta, tb), t1);
    }
    *entry = t0;
    *exit = t1;
}

#endif

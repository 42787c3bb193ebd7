/* Loading rays into SSE packets and storing hits back (packet.h).
 *
 * A ray whose origin or direction is not finite, or whose interval is NaN,
 * is loaded as an inactive lane (tnear = +inf > tfar = -inf): it reports a
 * miss and can never steer a traversal into a loop.  A zero direction
 * component gives inv_dir = +-inf with the sign of the zero, which is what
 * the kernels' near/far child order relies on. */
#include <math.h>
#include <string.h>

#include "packet.h"

static int ray_is_traceable(const rtt_ray *r)
{
    for (int a = 0; a < 3; a++)
        if (!isfinite(r->org[a]) || !isfinite(r->dir[a])) return 0;
    return !isnan(r->tnear) && !isnan(r->tfar);
}

void ray_packet4_load(ray_packet4 *packet, const rtt_ray *rays, uint32_t count)
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

void hit_packet4_clear(hit_packet4 *hits)
{
    hits->t = _mm_set1_ps(INFINITY);
    hits->u = _mm_setzero_ps();
    hits->v = _mm_setzero_ps();
    hits->prim = _mm_set1_epi32(-1);
}

void hit_packet4_store(const hit_packet4 *hits, rtt_hit *out, uint32_t count)
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

/* What the triangle tests write their answers into: one ray and its closest
 * hit for the scalar (mono) forms (the fields of rtt_ray and rtt_hit,
 * without the file contract), and the closest-hit rule of the 4-wide forms. */
#ifndef RTT_ISECT_HIT_H
#define RTT_ISECT_HIT_H

#include <immintrin.h>
#include <stdint.h>

#include "packet.h"

typedef struct kd_ray1 {
    float org[3], dir[3], tnear, tfar;
} kd_ray1;

typedef struct kd_hit1 {
    float t, u, v;
    uint32_t prim;
} kd_hit1;

/* Lowers the lanes of `hits` under `valid` where (t, prim) is closer: t
 * strictly smaller, or equal with a smaller prim, so the result does not
 * depend on the order triangles are met. */
static inline void hit_packet4_take_closer(hit_packet4 *hits, __m128 valid, __m128 t, __m128 u, __m128 v,
                                           uint32_t prim_index)
{
    const __m128i prim = _mm_set1_epi32((int32_t)prim_index);
    /* prims compare unsigned: RTT_MISS (all ones) is the largest. */
    __m128i smaller = _mm_cmpeq_epi32(_mm_min_epu32(prim, hits->prim), prim);
    __m128 closer = _mm_or_ps(_mm_cmplt_ps(t, hits->t), _mm_and_ps(_mm_cmpeq_ps(t, hits->t),
                                                                     _mm_castsi128_ps(smaller)));
    valid = _mm_and_ps(valid, closer);
    hits->t = _mm_blendv_ps(hits->t, t, valid);
    hits->u = _mm_blendv_ps(hits->u, u, valid);
    hits->v = _mm_blendv_ps(hits->v, v, valid);
    hits->prim = _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(hits->prim), _mm_castsi128_ps(prim), valid));
}

#endif

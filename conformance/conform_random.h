/* The fixed pseudo-random sequence of the conformance ray sets (splitmix64:
 * small, the same on every platform, so a seed names one ray set forever).
 * Private to conformance/. */
#ifndef RTT_CONFORM_RANDOM_H
#define RTT_CONFORM_RANDOM_H

#include <math.h>
#include <stdint.h>

#include "rtt/vec3.h"

static inline uint64_t next_u64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* [0, 1) with 24 bits */
static inline float next_unit(uint64_t *state) { return (float)(next_u64(state) >> 40) * (1.0f / 16777216.0f); }
/* [0, n); 0 when n is 0 */
static inline uint32_t next_below(uint64_t *state, uint32_t n) { return n ? (uint32_t)(next_u64(state) % n) : 0; }

/* Uniform on the unit sphere. */
static inline rtt_vec3 random_direction(uint64_t *state)
{
    float z = 2.0f * next_unit(state) - 1.0f, phi = 6.2831853f * next_unit(state);
    float s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return rtt_v3(s * cosf(phi), s * sinf(phi), z);
}

#endif

/* The small fixed random generator of the tests (xorshift64): the same
 * sequence on every machine, so a seed names one scene or ray set. */
#ifndef RTT_TEST_RANDOM_H
#define RTT_TEST_RANDOM_H

#include <stdint.h>

typedef struct rng {
    uint64_t s;
} rng;

static inline float rng_float(rng *r) /* [0, 1) */
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return (float)(r->s >> 40) / (float)(1u << 24);
}

static inline float rng_range(rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }

#endif

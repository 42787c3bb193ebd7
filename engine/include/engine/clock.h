/* A monotonic clock in nanoseconds: the one every timer of rtt reads. */
#ifndef RTT_ENGINE_CLOCK_H
#define RTT_ENGINE_CLOCK_H

#include <stdint.h>
#include <time.h>

static inline uint64_t rtt_clock_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static inline double rtt_clock_seconds(void)
{
    return 1e-9 * (double)rtt_clock_ns();
}

#endif

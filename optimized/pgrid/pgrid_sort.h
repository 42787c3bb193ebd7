/* The perspective grids' sort: 64-bit keys by their high word, stably (a
 * key's low word, typically its index, keeps equal high words in their
 * order).  Least-significant-digit radix on the high word less `lo`, the
 * keys' smallest, in as few passes of at most 11 bits as the range
 * (hi - lo) needs, the digits as even as they go; the histogram on the
 * stack, nothing allocated.  The sorted keys are in keys or in spare (count
 * each): the pointer returned.  Used by the shadow kernel (a batch's runs
 * by light cell), the light grids' scene half (the records' Morton order)
 * and the eye grid's drawing order. */
#ifndef RTT_OPTIMIZED_PGRID_SORT_H
#define RTT_OPTIMIZED_PGRID_SORT_H

#include <stdint.h>
#include <string.h>

static inline uint64_t *pgrid_sort_keys(uint64_t *keys, uint64_t *spare, uint32_t count, uint32_t lo, uint32_t hi)
{
    enum { MOST_BITS = 11 };
    const uint32_t range = hi - lo, bits = range ? 32u - (uint32_t)__builtin_clz(range) : 0u;
    const uint32_t passes = (bits + MOST_BITS - 1) / MOST_BITS, digit = passes ? (bits + passes - 1) / passes : 0u;
    const uint32_t mask = (1u << digit) - 1u;
    uint32_t histogram[1u << MOST_BITS];
    for (uint32_t pass = 0, shift = 0; pass < passes; pass++, shift += digit) {
        memset(histogram, 0, (mask + 1u) * sizeof *histogram);
        for (uint32_t i = 0; i < count; i++) histogram[((uint32_t)(keys[i] >> 32) - lo) >> shift & mask]++;
        for (uint32_t b = 0, sum = 0; b <= mask; b++) {
            const uint32_t n = histogram[b];
            histogram[b] = sum, sum += n;
        }
        for (uint32_t i = 0; i < count; i++) spare[histogram[((uint32_t)(keys[i] >> 32) - lo) >> shift & mask]++] = keys[i];
        uint64_t *sorted = spare;
        spare = keys, keys = sorted;
    }
    return keys;
}

#endif

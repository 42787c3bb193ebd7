/* Large arrays on huge pages.  A build's arrays are fresh memory: every 4 KiB
 * page costs a fault on first touch, and on a virtual machine whose faults
 * go through the hypervisor (this project's benchmark hosts) the faults were
 * half of a cold BVH build (11 us a 4 KiB fault there; bench/results/
 * bvh-build.md).  Arrays of 1 MiB or more are aligned to 2 MiB, rounded up
 * to whole 2 MiB pages and advised as huge-page candidates (Linux
 * transparent huge pages, madvise mode), so one fault maps 512 small pages'
 * worth; what rounding wastes is less than the array itself.  Smaller arrays
 * are plain aligned_alloc.  Either way the memory is released with free(). */
#ifndef RTT_ENGINE_PAGES_H
#define RTT_ENGINE_PAGES_H

#include <stddef.h>

/* `bytes` (0 allowed) aligned to `align` (a power of two, at most 4096), or
 * NULL when out of memory or when the size overflows. */
void *rtt_alloc_pages(size_t bytes, size_t align);

#endif

/* Large arrays on huge pages (pages.h). */
#define _GNU_SOURCE
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

#include "engine/pages.h"

#define RTT_HUGE_PAGE ((size_t)2 << 20)
/* Below this an array keeps small pages: the waste of a whole 2 MiB page
 * would be more than twice its size. */
#define RTT_HUGE_PAGE_FROM ((size_t)1 << 20)

void *rtt_alloc_pages(size_t bytes, size_t align)
{
    if (align < sizeof(void *)) align = sizeof(void *);
    if (bytes < RTT_HUGE_PAGE_FROM) {
        /* below 1 MiB, rounding up to `align` cannot wrap */
        return aligned_alloc(align, bytes ? (bytes + align - 1) & ~(align - 1) : align);
    }
    if (bytes > SIZE_MAX - RTT_HUGE_PAGE) return NULL;
    const size_t rounded = (bytes + RTT_HUGE_PAGE - 1) & ~(RTT_HUGE_PAGE - 1);
    void *data = aligned_alloc(RTT_HUGE_PAGE, rounded);
#ifdef MADV_HUGEPAGE
    if (data) (void)madvise(data, rounded, MADV_HUGEPAGE); /* advice only: without it the pages are small */
#endif
    return data;
}

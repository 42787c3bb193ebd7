/* Large arrays on huge pages (engine/pages.h): aligned as asked, the whole
 * size usable, released with free(), sizes that overflow refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "engine/pages.h"

#define HUGE_PAGE ((size_t)2 << 20)
#define HUGE_FROM ((size_t)1 << 20)

static void test_small_arrays_take_the_alignment_asked_for(void **state)
{
    (void)state;
    const size_t aligns[] = {1, 8, 16, 64, 4096};
    const size_t sizes[] = {0, 1, 48, 1000, HUGE_FROM - 1};
    for (size_t a = 0; a < sizeof aligns / sizeof *aligns; a++)
        for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
            unsigned char *p = rtt_alloc_pages(sizes[s], aligns[a]);
            assert_non_null(p); /* 0 bytes still gives a pointer free() takes */
            assert_int_equal((uintptr_t)p % aligns[a], 0);
            memset(p, 0xab, sizes[s]);
            if (sizes[s]) assert_int_equal(p[sizes[s] - 1], 0xab);
            free(p);
        }
}

static void test_large_arrays_start_on_a_huge_page_and_are_whole(void **state)
{
    (void)state;
    const size_t sizes[] = {HUGE_FROM, HUGE_PAGE, HUGE_PAGE + 1, 5 * HUGE_PAGE + 12345};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        unsigned char *p = rtt_alloc_pages(sizes[s], 64);
        assert_non_null(p);
        assert_int_equal((uintptr_t)p % HUGE_PAGE, 0);
        for (size_t i = 0; i < sizes[s]; i += 4096) p[i] = (unsigned char)i;
        p[sizes[s] - 1] = 7;
        assert_int_equal(p[sizes[s] - 1], 7);
        assert_int_equal(p[4096], (unsigned char)4096);
        free(p);
    }
}

static void test_sizes_that_overflow_are_refused(void **state)
{
    (void)state;
    assert_null(rtt_alloc_pages(SIZE_MAX, 64));
    assert_null(rtt_alloc_pages(SIZE_MAX - HUGE_PAGE / 2, 64));
    assert_null(rtt_alloc_pages(SIZE_MAX - 10, 16));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_arrays_take_the_alignment_asked_for),
        cmocka_unit_test(test_large_arrays_start_on_a_huge_page_and_are_whole),
        cmocka_unit_test(test_sizes_that_overflow_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

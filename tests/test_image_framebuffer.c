/* The framebuffer: which planes rtt_image_create allocates, and what sizes it refuses. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include <string.h>

#include "rtt/image.h"
#include "rtt/render.h"

static void test_image_create_allocates_only_requested_aovs(void **state)
{
    (void)state;
    rtt_error err = { "" };
    rtt_image *plain = rtt_image_create(3, 2, 0, &err);
    assert_non_null(plain);
    assert_int_equal(plain->width, 3);
    assert_int_equal(plain->height, 2);
    assert_non_null(plain->rgb);
    assert_null(plain->depth);
    assert_null(plain->prim);
    assert_null(plain->normal);
    for (int i = 0; i < 18; i++)
        assert_true(plain->rgb[i] == 0.0f);
    rtt_image_free(plain);

    rtt_image *depth_only = rtt_image_create(3, 2, RTT_AOV_DEPTH, &err);
    assert_non_null(depth_only->depth);
    assert_null(depth_only->prim);
    assert_null(depth_only->normal);
    rtt_image_free(depth_only);

    rtt_image *all = rtt_image_create(3, 2, RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL, &err);
    assert_non_null(all);
    for (int i = 0; i < 6; i++) {
        assert_true(isinf(all->depth[i]) && all->depth[i] > 0);   /* a miss until rendered */
        assert_int_equal(all->prim[i], RTT_MISS);
    }
    assert_non_null(all->normal);
    rtt_image_free(all);
}

static void test_image_create_refuses_empty_and_absurd_sizes(void **state)
{
    (void)state;
    rtt_error err = { "" };
    assert_null(rtt_image_create(0, 5, 0, &err));
    assert_non_null(strstr(err.message, "0x5"));
    assert_null(rtt_image_create(UINT32_MAX, UINT32_MAX, 0, &err));
    assert_non_null(strstr(err.message, "too large"));
    assert_null(rtt_image_create(4, 4, 1u << 7, &err));
    rtt_image_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_image_create_allocates_only_requested_aovs),
        cmocka_unit_test(test_image_create_refuses_empty_and_absurd_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Tests of the image metrics (image/compare.c) on hand-built images whose
 * answers are worked out by hand. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "rtt/image.h"

static rtt_image *filled(uint32_t w, uint32_t h, float value)
{
    rtt_error err;
    rtt_image *image = rtt_image_create(w, h, 0, &err);
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        image->rgb[i] = value;
    return image;
}

static void test_identical_images_have_zero_error(void **state)
{
    (void)state;
    rtt_image *a = filled(5, 3, 0.3f), *b = filled(5, 3, 0.3f);
    rtt_image_metrics m;
    rtt_error err;
    assert_true(rtt_image_compare(a, b, &m, &err));
    assert_float_equal(m.rmse, 0.0, 0.0);
    assert_float_equal(m.max_error, 0.0, 0.0);
    assert_float_equal(m.share_over_1_255, 0.0, 0.0);
    assert_int_equal(m.pixels_over_1_255, 0);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void test_one_channel_off_gives_known_rmse_max_and_share(void **state)
{
    (void)state;
    /* 2x2 image, 12 samples; pixel 1 green off by 0.6, pixel 3 blue off by 0.001 */
    rtt_image *a = filled(2, 2, 0.2f), *b = filled(2, 2, 0.2f);
    b->rgb[1 * 3 + 1] = 0.8f;
    b->rgb[3 * 3 + 2] = 0.201f;
    rtt_image_metrics m;
    rtt_error err;
    assert_true(rtt_image_compare(a, b, &m, &err));
    double expected_rmse = sqrt((0.6 * 0.6 + 0.001 * 0.001) / 12.0);
    assert_float_equal(m.rmse, expected_rmse, 1e-6);
    assert_float_equal(m.max_error, 0.6, 1e-6);
    assert_int_equal(m.pixels_over_1_255, 1);   /* 0.001 < 1/255 */
    assert_float_equal(m.share_over_1_255, 0.25, 0.0);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void test_pixel_counts_once_when_several_channels_are_off(void **state)
{
    (void)state;
    rtt_image *a = filled(3, 1, 0.0f), *b = filled(3, 1, 0.0f);
    b->rgb[0] = b->rgb[1] = b->rgb[2] = 0.5f;   /* pixel 0, all three channels */
    b->rgb[8] = 2.0f / 255.0f;                  /* pixel 2, just over one step */
    rtt_image_metrics m;
    rtt_error err;
    assert_true(rtt_image_compare(a, b, &m, &err));
    assert_int_equal(m.pixels_over_1_255, 2);
    assert_float_equal(m.share_over_1_255, 2.0 / 3.0, 1e-12);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void test_colours_are_clamped_before_comparing(void **state)
{
    (void)state;
    /* 2 vs 50 are both white, -1 vs 0 both black, inf vs 1 white, NaN vs 0 black */
    rtt_image *a = filled(4, 1, 0.0f), *b = filled(4, 1, 0.0f);
    const float av[4] = { 2.0f, -1.0f, INFINITY, NAN };
    const float bv[4] = { 50.0f, 0.0f, 1.0f, 0.0f };
    for (size_t p = 0; p < 4; p++)
        for (size_t k = 0; k < 3; k++) {
            a->rgb[p * 3 + k] = av[p];
            b->rgb[p * 3 + k] = bv[p];
        }
    rtt_image_metrics m;
    rtt_error err;
    assert_true(rtt_image_compare(a, b, &m, &err));
    assert_float_equal(m.rmse, 0.0, 0.0);
    assert_float_equal(m.max_error, 0.0, 0.0);
    /* white against an over-bright black: error is exactly 1 */
    a->rgb[0] = 1e9f;
    b->rgb[0] = -1e9f;
    assert_true(rtt_image_compare(a, b, &m, &err));
    assert_float_equal(m.max_error, 1.0, 0.0);
    assert_float_equal(m.rmse, sqrt(1.0 / 12.0), 1e-12);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void test_size_mismatch_is_an_error_naming_both_sizes(void **state)
{
    (void)state;
    rtt_image *a = filled(4, 3, 0.0f), *b = filled(3, 4, 0.0f);
    rtt_image_metrics m;
    rtt_error err = { "" };
    assert_false(rtt_image_compare(a, b, &m, &err));
    assert_string_equal(err.message, "images differ in size (4x3 vs 3x4)");
    rtt_image_free(a);
    rtt_image_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identical_images_have_zero_error),
        cmocka_unit_test(test_one_channel_off_gives_known_rmse_max_and_share),
        cmocka_unit_test(test_pixel_counts_once_when_several_channels_are_off),
        cmocka_unit_test(test_colours_are_clamped_before_comparing),
        cmocka_unit_test(test_size_mismatch_is_an_error_naming_both_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

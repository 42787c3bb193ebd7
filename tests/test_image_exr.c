/* Tests of the EXR writer and reader (image/exr_write.c, image/exr_read.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <OpenEXR/openexr.h> /* tests/ gets no OpenEXR include path */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/render.h"
#include "test_tempdir.h"

/* cmocka setup: each test writes into its own /tmp/rtt_test_exr_XXXXXX. */
static int make_scratch(void **state)
{
    return scratch_create(state, "exr");
}

static bool same_float_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Colours with the values a renderer produces, and some it should not. */
static float sample_value(size_t i)
{
    const float specials[] = { 0.0f, -0.0f, 1.0f, 0.5f, 1e-30f, FLT_MIN / 4, 65504.0f, 1e30f, -2.5f, INFINITY };
    return i % 3 == 0 ? specials[(i / 3) % 10] : (float)i * 0.37f;
}

static void test_exr_round_trip_keeps_rgb_bits(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(37, 21, 0, &err);   /* > one 16-line ZIP chunk, odd width */
    for (size_t i = 0; i < 37 * 21 * 3; i++)
        image->rgb[i] = sample_value(i);
    const char *path = scratch_path(state, "rgb.exr");
    assert_true(rtt_image_write_exr(image, path, &err));
    rtt_image *back = rtt_image_read_exr(path, &err);
    assert_non_null(back);
    assert_int_equal(back->width, 37);
    assert_int_equal(back->height, 21);
    assert_null(back->depth);
    assert_null(back->prim);
    assert_null(back->normal);
    for (size_t i = 0; i < 37 * 21 * 3; i++)
        assert_true(same_float_bits(back->rgb[i], image->rgb[i]));
    rtt_image_free(back);
    rtt_image_free(image);
}

static void test_exr_round_trip_keeps_every_aov(void **state)
{
    rtt_error err = { "" };
    const uint32_t w = 9, h = 40;
    rtt_image *image = rtt_image_create(w, h, RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL, &err);
    for (size_t p = 0; p < w * h; p++) {
        for (size_t k = 0; k < 3; k++) {
            image->rgb[p * 3 + k] = (float)(p + k) / 100.0f;
            image->normal[p * 3 + k] = k == 0 ? -1.0f : (float)p / (float)(w * h);
        }
        /* every fourth pixel is a miss: depth +inf, prim RTT_MISS */
        image->depth[p] = p % 4 == 0 ? INFINITY : (float)p * 1e10f;
        image->prim[p] = p % 4 == 0 ? RTT_MISS : (uint32_t)(p * 2654435761u);
    }
    const char *path = scratch_path(state, "aov.exr");
    assert_true(rtt_image_write_exr(image, path, &err));
    rtt_image *back = rtt_image_read_exr(path, &err);
    assert_non_null(back);
    assert_non_null(back->depth);
    assert_non_null(back->prim);
    assert_non_null(back->normal);
    for (size_t p = 0; p < w * h; p++) {
        assert_true(same_float_bits(back->depth[p], image->depth[p]));
        assert_int_equal(back->prim[p], image->prim[p]);
        for (size_t k = 0; k < 3; k++) {
            assert_true(same_float_bits(back->rgb[p * 3 + k], image->rgb[p * 3 + k]));
            assert_true(same_float_bits(back->normal[p * 3 + k], image->normal[p * 3 + k]));
        }
    }
    assert_true(isinf(back->depth[0]));
    rtt_image_free(back);
    rtt_image_free(image);
}

static void test_exr_round_trip_keeps_only_the_aovs_written(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(4, 4, RTT_AOV_PRIM, &err);
    for (size_t p = 0; p < 16; p++)
        image->prim[p] = (uint32_t)p;
    const char *path = scratch_path(state, "prim.exr");
    assert_true(rtt_image_write_exr(image, path, &err));
    rtt_image *back = rtt_image_read_exr(path, &err);
    assert_non_null(back);
    assert_null(back->depth);
    assert_null(back->normal);
    assert_non_null(back->prim);
    assert_int_equal(back->prim[15], 15);
    rtt_image_free(back);
    rtt_image_free(image);
}

static uint16_t half_bits(float value)
{
    /* exact for the test's values: small integers and simple fractions */
    if (value == 0.0f)
        return 0;
    int exponent;
    float mantissa = frexpf(value, &exponent);          /* value = m * 2^e, m in [0.5,1) */
    uint16_t sign = value < 0 ? 0x8000 : 0;
    uint16_t bits = (uint16_t)((exponent + 14) << 10);
    bits |= (uint16_t)lrintf((fabsf(mantissa) * 2.0f - 1.0f) * 1024.0f);
    return sign | bits;
}

/* Writes a half-float RGB scanline EXR (no compression, 2 chunks not
 * starting at y = 0) with OpenEXR directly, as another program would. */
static void write_half_exr(const char *path, uint32_t w, uint32_t h, const uint16_t *rgb_half)
{
    exr_context_t ctxt;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), EXR_ERR_SUCCESS);
    int part;
    assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    exr_attr_box2i_t window = { .min = { .x = 10, .y = -3 }, .max = { .x = 10 + (int)w - 1, .y = -3 + (int)h - 1 } };
    exr_attr_v2f_t center = { .x = 0, .y = 0 };
    assert_int_equal(exr_initialize_required_attr(ctxt, part, &window, &window, 1.0f, &center, 1.0f,
                                                  EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_NONE),
                     EXR_ERR_SUCCESS);
    const char *names[3] = { "R", "G", "B" };
    for (int k = 0; k < 3; k++)
        assert_int_equal(exr_add_channel(ctxt, part, names[k], EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    for (int y = -3; y < -3 + (int)h; y++) {   /* NONE compression: one line per chunk */
        exr_chunk_info_t cinfo;
        assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, y, &cinfo), EXR_ERR_SUCCESS);
        if (y == -3)
            assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &encoder), EXR_ERR_SUCCESS);
        else
            assert_int_equal(exr_encoding_update(ctxt, part, &cinfo, &encoder), EXR_ERR_SUCCESS);
        for (int c = 0; c < encoder.channel_count; c++) {
            int k = encoder.channels[c].channel_name[0] == 'R' ? 0 : encoder.channels[c].channel_name[0] == 'G' ? 1 : 2;
            encoder.channels[c].user_bytes_per_element = 2;
            encoder.channels[c].user_data_type = EXR_PIXEL_HALF;
            encoder.channels[c].user_pixel_stride = 6;
            encoder.channels[c].user_line_stride = (int32_t)(w * 6);
            encoder.channels[c].encode_from_ptr = (const uint8_t *)(rgb_half + (size_t)(y + 3) * w * 3 + k);
        }
        if (y == -3)
            assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &encoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_encoding_run(ctxt, part, &encoder), EXR_ERR_SUCCESS);
    }
    exr_encoding_destroy(ctxt, &encoder);
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
}

static void test_exr_reads_half_float_file_with_offset_data_window(void **state)
{
    const uint32_t w = 5, h = 3;
    uint16_t rgb_half[5 * 3 * 3];
    float expected[5 * 3 * 3];
    for (size_t i = 0; i < w * h * 3; i++) {
        expected[i] = (float)i * 0.25f - 2.0f;   /* exact in half */
        rgb_half[i] = half_bits(expected[i]);
    }
    const char *path = scratch_path(state, "half.exr");
    write_half_exr(path, w, h, rgb_half);
    rtt_error err = { "" };
    rtt_image *image = rtt_image_read_exr(path, &err);
    assert_non_null(image);
    assert_int_equal(image->width, w);
    assert_int_equal(image->height, h);
    for (size_t i = 0; i < w * h * 3; i++)
        assert_float_equal(image->rgb[i], expected[i], 0.0);
    rtt_image_free(image);
}

static void test_exr_reader_refuses_a_file_that_is_not_exr(void **state)
{
    const char *path = scratch_path(state, "not.exr");
    FILE *f = fopen(path, "wb");
    fputs("this is not an OpenEXR file at all\n", f);
    fclose(f);
    rtt_error err = { "" };
    assert_null(rtt_image_read_exr(path, &err));
    assert_int_equal(strncmp(err.message, path, strlen(path)), 0);
    assert_null(strchr(err.message, '\n'));
}

static void test_exr_reader_refuses_a_missing_file(void **state)
{
    const char *path = scratch_path(state, "missing.exr");
    rtt_error err = { "" };
    assert_null(rtt_image_read_exr(path, &err));
    assert_non_null(strstr(err.message, "missing.exr: cannot open"));
}

static void test_exr_reader_refuses_a_truncated_file(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(64, 64, RTT_AOV_DEPTH, &err);
    for (size_t i = 0; i < 64 * 64 * 3; i++)
        image->rgb[i] = (float)((i * 7919) % 1000) / 7.0f;   /* poorly compressible */
    const char *path = scratch_path(state, "cut.exr");
    assert_true(rtt_image_write_exr(image, path, &err));
    rtt_image_free(image);
    FILE *f = fopen(path, "rb");
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    assert_int_equal(truncate(path, size / 2), 0);
    assert_null(rtt_image_read_exr(path, &err));
    assert_int_equal(strncmp(err.message, path, strlen(path)), 0);
}

static void test_exr_reader_refuses_a_file_without_rgb(void **state)
{
    const char *path = scratch_path(state, "alpha.exr");
    exr_context_t ctxt;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), EXR_ERR_SUCCESS);
    int part;
    assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, 1, 1, EXR_COMPRESSION_NONE), EXR_ERR_SUCCESS);
    assert_int_equal(exr_add_channel(ctxt, part, "A", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1), EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);
    exr_chunk_info_t cinfo;
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    float alpha = 1.0f;
    assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, 0, &cinfo), EXR_ERR_SUCCESS);
    assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &encoder), EXR_ERR_SUCCESS);
    encoder.channels[0].user_bytes_per_element = 4;
    encoder.channels[0].user_data_type = EXR_PIXEL_FLOAT;
    encoder.channels[0].user_pixel_stride = 4;
    encoder.channels[0].user_line_stride = 4;
    encoder.channels[0].encode_from_ptr = (const uint8_t *)&alpha;
    assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &encoder), EXR_ERR_SUCCESS);
    assert_int_equal(exr_encoding_run(ctxt, part, &encoder), EXR_ERR_SUCCESS);
    exr_encoding_destroy(ctxt, &encoder);
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);

    rtt_error err = { "" };
    assert_null(rtt_image_read_exr(path, &err));
    assert_non_null(strstr(err.message, "no half or float channel \"R\""));
}

static void test_exr_reader_refuses_a_tiled_file(void **state)
{
    const char *path = scratch_path(state, "tiled.exr");
    exr_context_t ctxt;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), EXR_ERR_SUCCESS);
    int part;
    assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_TILED, &part), EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, 4, 4, EXR_COMPRESSION_NONE), EXR_ERR_SUCCESS);
    assert_int_equal(exr_set_tile_descriptor(ctxt, part, 4, 4, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN),
                     EXR_ERR_SUCCESS);
    const char *names[3] = { "R", "G", "B" };
    for (int k = 0; k < 3; k++)
        assert_int_equal(exr_add_channel(ctxt, part, names[k], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);
    exr_finish(&ctxt);   /* no tiles written: the header alone says what the file is */

    rtt_error err = { "" };
    assert_null(rtt_image_read_exr(path, &err));
    assert_int_equal(strncmp(err.message, path, strlen(path)), 0);
    assert_null(strchr(err.message, '\n'));
}

/* Rewrites the data window's max corner in an EXR header in place. */
static void patch_data_window(const char *path, int32_t max_x, int32_t max_y)
{
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    char header[4096];
    size_t n = fread(header, 1, sizeof header, f);
    const char key[] = "dataWindow\0box2i\0";
    size_t at = 0;
    while (at + sizeof key < n && memcmp(header + at, key, sizeof key - 1) != 0)
        at++;
    assert_true(at + sizeof key < n);
    long max_offset = (long)(at + sizeof key - 1 + 4 + 8);   /* after the size and min corner */
    int32_t corner[2] = { max_x, max_y };
    fseek(f, max_offset, SEEK_SET);
    assert_int_equal(fwrite(corner, sizeof corner, 1, f), 1);
    fclose(f);
}

static void test_exr_reader_refuses_a_header_promising_more_pixels_than_the_file_holds(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(3000, 16, 0, &err);   /* zeros: one tiny ZIP chunk */
    const char *path = scratch_path(state, "bomb.exr");
    assert_true(rtt_image_write_exr(image, path, &err));
    rtt_image_free(image);
    patch_data_window(path, 2999999, 15);   /* claims 3 million pixels per line */
    assert_null(rtt_image_read_exr(path, &err));
    assert_int_equal(strncmp(err.message, path, strlen(path)), 0);
    assert_non_null(strstr(err.message, "more than"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_exr_round_trip_keeps_rgb_bits, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_round_trip_keeps_every_aov, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_round_trip_keeps_only_the_aovs_written, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reads_half_float_file_with_offset_data_window, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_file_that_is_not_exr, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_missing_file, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_truncated_file, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_file_without_rgb, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_tiled_file, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_exr_reader_refuses_a_header_promising_more_pixels_than_the_file_holds,
                                        make_scratch, remove_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Tests of the PNG writer (image/png_write.c), the format dispatch
 * (image/image_write.c) and atomic replacement (image/atomic_file.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rtt/image.h"
#include "rtt/render.h"
#include "test_tempdir.h"

/* cmocka setup: each test writes into its own /tmp/rtt_test_png_XXXXXX. */
static int make_scratch(void **state)
{
    return scratch_create(state, "png");
}

static size_t files_in(void **state)
{
    scratch *s = *state;
    DIR *dir = opendir(s->dir);
    size_t n = 0;
    for (struct dirent *e; (e = readdir(dir));)
        n += e->d_name[0] != '.';
    closedir(dir);
    return n;
}

/* Reads an 8-bit RGB PNG with libpng's simplified API. */
static uint8_t *read_png_rgb(const char *path, uint32_t *w, uint32_t *h)
{
    png_image png;
    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path))
        return NULL;
    png.format = PNG_FORMAT_RGB;
    uint8_t *pixels = malloc(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, NULL, pixels, 0, NULL)) {
        free(pixels);
        return NULL;
    }
    *w = png.width;
    *h = png.height;
    return pixels;
}

static void test_png_is_srgb_encoded_clamped_8_bit(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(4, 2, 0, &err);
    /* linear inputs and their sRGB 8-bit codes (IEC 61966-2-1) */
    const float linear[8] = { 0.0f, 1.0f, 0.5f, 0.2158605f, 0.0031308f, -1.0f, 7.5f, NAN };
    const uint8_t code[8] = { 0, 255, 188, 128, 10, 0, 255, 0 };
    for (size_t p = 0; p < 8; p++)
        for (size_t k = 0; k < 3; k++)
            image->rgb[p * 3 + k] = k == 1 ? linear[p] : linear[7 - p];
    const char *path = scratch_path(state, "srgb.png");
    assert_true(rtt_image_write_png(image, path, &err));
    uint32_t w = 0, h = 0;
    uint8_t *pixels = read_png_rgb(path, &w, &h);
    assert_non_null(pixels);
    assert_int_equal(w, 4);
    assert_int_equal(h, 2);
    for (size_t p = 0; p < 8; p++) {
        assert_int_equal(pixels[p * 3 + 1], code[p]);
        assert_int_equal(pixels[p * 3 + 0], code[7 - p]);
        assert_int_equal(pixels[p * 3 + 2], code[7 - p]);
    }
    free(pixels);
    rtt_image_free(image);
}

static void test_png_keeps_row_order_top_first(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(1, 3, 0, &err);
    image->rgb[0] = 1.0f;    /* top row red */
    image->rgb[8] = 1.0f;    /* bottom row blue */
    const char *path = scratch_path(state, "rows.png");
    assert_true(rtt_image_write(image, path, &err));
    uint32_t w, h;
    uint8_t *pixels = read_png_rgb(path, &w, &h);
    assert_non_null(pixels);
    assert_int_equal(pixels[0], 255);
    assert_int_equal(pixels[5], 0);
    assert_int_equal(pixels[8], 255);
    free(pixels);
    rtt_image_free(image);
}

static void test_write_picks_format_by_extension_ignoring_case(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(2, 2, 0, &err);
    image->rgb[3] = 0.25f;
    const char *exr = scratch_path(state, "a.EXR");
    assert_true(rtt_image_write(image, exr, &err));
    rtt_image *back = rtt_image_read_exr(exr, &err);
    assert_non_null(back);
    assert_float_equal(back->rgb[3], 0.25f, 0.0);
    rtt_image_free(back);
    const char *png = scratch_path(state, "b.Png");
    assert_true(rtt_image_write(image, png, &err));
    uint32_t w, h;
    uint8_t *pixels = read_png_rgb(png, &w, &h);
    assert_non_null(pixels);
    free(pixels);
    rtt_image_free(image);
}

static void test_write_refuses_unknown_extension_and_creates_nothing(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(2, 2, 0, &err);
    assert_false(rtt_image_write(image, "out.jpg", &err));
    assert_string_equal(err.message, "out.jpg: unknown image format (use .exr or .png)");
    assert_false(rtt_image_write(image, scratch_path(state, "exr"), &err));
    assert_int_equal(files_in(state), 0);
    rtt_image_free(image);
}

static void write_marker(const char *path)
{
    FILE *f = fopen(path, "wb");
    fputs("old contents", f);
    fclose(f);
}

static bool still_marker(const char *path)
{
    char text[32] = "";
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    return strcmp(text, "old contents") == 0;
}

static void test_failed_write_leaves_existing_file_and_no_temporary(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(3, 3, 0, &err);
    const char *existing = scratch_path(state, "keep.png");
    write_marker(existing);
    /* a directory where the temporary's name should go: creation fails */
    char blocker[160];
    snprintf(blocker, sizeof blocker, "%s.tmp.%ld", existing, (long)getpid());
    assert_int_equal(mkdir(blocker, 0700), 0);
    assert_false(rtt_image_write_png(image, existing, &err));
    assert_non_null(strstr(err.message, "keep.png: cannot create"));
    assert_false(rtt_image_write_exr(image, existing, &err));
    assert_true(still_marker(existing));
    rmdir(blocker);
    assert_int_equal(files_in(state), 1);

    /* an empty image is refused before anything is touched */
    rtt_image empty = { 0 };
    assert_false(rtt_image_write_exr(&empty, existing, &err));
    assert_true(still_marker(existing));
    rtt_image_free(image);
}

static void test_write_into_missing_directory_fails_with_one_line(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(3, 3, 0, &err);
    const char *path = scratch_path(state, "no/such/dir/out.exr");
    assert_false(rtt_image_write(image, path, &err));
    assert_int_equal(strncmp(err.message, path, strlen(path)), 0);
    assert_null(strchr(err.message, '\n'));
    assert_false(rtt_image_write_png(image, path, &err));
    assert_int_equal(files_in(state), 0);
    rtt_image_free(image);
}

static void test_successful_write_replaces_existing_file(void **state)
{
    rtt_error err = { "" };
    rtt_image *image = rtt_image_create(3, 3, 0, &err);
    const char *path = scratch_path(state, "replace.exr");
    write_marker(path);
    assert_true(rtt_image_write(image, path, &err));
    assert_false(still_marker(path));
    rtt_image *back = rtt_image_read_exr(path, &err);
    assert_non_null(back);
    rtt_image_free(back);
    assert_int_equal(files_in(state), 1);
    rtt_image_free(image);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_png_is_srgb_encoded_clamped_8_bit, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_png_keeps_row_order_top_first, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_write_picks_format_by_extension_ignoring_case, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_write_refuses_unknown_extension_and_creates_nothing, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_failed_write_leaves_existing_file_and_no_temporary, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_write_into_missing_directory_fails_with_one_line, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_successful_write_replaces_existing_file, make_scratch, remove_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

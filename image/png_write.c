/* PNG writer: what a person looks at.  Linear colours are clamped to [0,1],
 * encoded with the sRGB transfer function (IEC 61966-2-1) and rounded to
 * 8 bits; the file carries an sRGB chunk so viewers do not convert again.
 *
 * libpng reports errors by longjmp; the handler records the message and the
 * setjmp in write_png turns it into an rtt_error.  NaN is written as black. */
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/atomic_file.h"
#include "rtt/image.h"

typedef struct png_failure {
    jmp_buf jump;
    char message[256];
} png_failure;

static void on_png_error(png_structp png, png_const_charp message)
{
    png_failure *failure = png_get_error_ptr(png);
    snprintf(failure->message, sizeof failure->message, "%s", message ? message : "libpng error");
    longjmp(failure->jump, 1);
}

static void on_png_warning(png_structp png, png_const_charp message)
{
    (void)png;
    (void)message;   /* warnings are not errors; the library never prints */
}

uint8_t rtt_linear_to_srgb8(float linear)
{
    if (!(linear > 0.0f))
        return 0;   /* also NaN */
    if (linear >= 1.0f)
        return 255;
    float encoded = linear <= 0.0031308f ? 12.92f * linear : 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(encoded * 255.0f);
}

/* Everything that may longjmp lives here, with no locals that change after
 * setjmp, so nothing is clobbered. */
static bool write_png(FILE *stream, const rtt_image *image, uint8_t *row, png_failure *failure)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, failure, on_png_error, on_png_warning);
    if (!png) {
        snprintf(failure->message, sizeof failure->message, "out of memory");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(failure->jump)) {
        if (!info)
            snprintf(failure->message, sizeof failure->message, "out of memory");
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, stream);
    png_set_IHDR(png, info, image->width, image->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (uint32_t y = 0; y < image->height; y++) {
        const float *src = image->rgb + (size_t)y * image->width * 3;
        for (size_t i = 0; i < (size_t)image->width * 3; i++)
            row[i] = rtt_linear_to_srgb8(src[i]);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return true;
}

bool rtt_image_write_png(const rtt_image *image, const char *path, rtt_error *err)
{
    if (!image || !image->rgb || image->width == 0 || image->height == 0 || image->width > PNG_UINT_31_MAX ||
        image->height > PNG_UINT_31_MAX)
        return rtt_error_set(err, "%s: no image to write", path);
    uint8_t *row = malloc((size_t)image->width * 3);
    if (!row)
        return rtt_error_set(err, "%s: out of memory", path);
    rtt_atomic_file file;
    if (!rtt_atomic_file_open(&file, path, err)) {
        free(row);
        return false;
    }
    png_failure failure = { .message = "" };
    bool written = write_png(file.stream, image, row, &failure);
    free(row);
    if (!written) {
        rtt_atomic_file_abort(&file);
        return rtt_error_set(err, "%s: cannot write PNG: %s", path, failure.message);
    }
    return rtt_atomic_file_commit(&file, err);
}

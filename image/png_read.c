/* PNG reader, for `rtt compare`: any PNG libpng reads (palette, grey, 16-bit,
 * alpha), converted by libpng's simplified API to 8-bit sRGB RGB (alpha
 * composited on black), then decoded to linear colours with the sRGB
 * transfer function, the inverse of png_write.c's, so a PNG compares with
 * the EXR it came from within its 8-bit rounding. */
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "rtt/image.h"

#define MAX_SIDE 16384u

static float srgb_to_linear(uint8_t v)
{
    float c = (float)v / 255.0f;
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

rtt_image *rtt_image_read_png(const char *path, rtt_error *err)
{
    png_image png;
    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path)) {
        rtt_error_set(err, "%s: cannot read as PNG: %s", path, png.message);
        return NULL;
    }
    if (png.width == 0 || png.height == 0 || png.width > MAX_SIDE || png.height > MAX_SIDE) {
        rtt_error_set(err, "%s: a %ux%u PNG is outside 1..%u pixels a side", path, png.width, png.height, MAX_SIDE);
        png_image_free(&png);
        return NULL;
    }
    png.format = PNG_FORMAT_RGB;
    size_t bytes = PNG_IMAGE_SIZE(png);
    uint8_t *pixels = malloc(bytes);
    rtt_image *image = pixels ? rtt_image_create(png.width, png.height, 0, err) : NULL;
    if (!pixels || !image) {
        if (!pixels) rtt_error_set(err, "%s: out of memory for a %ux%u PNG", path, png.width, png.height);
        png_image_free(&png);
        free(pixels);
        rtt_image_free(image);
        return NULL;
    }
    const png_color black = {0, 0, 0};
    if (!png_image_finish_read(&png, &black, pixels, 0, NULL)) {
        rtt_error_set(err, "%s: cannot read as PNG: %s", path, png.message);
        png_image_free(&png);
        free(pixels);
        rtt_image_free(image);
        return NULL;
    }
    float table[256];
    for (int v = 0; v < 256; v++) table[v] = srgb_to_linear((uint8_t)v);
    for (size_t i = 0; i < (size_t)png.width * png.height * 3; i++) image->rgb[i] = table[pixels[i]];
    free(pixels);
    return image;
}

rtt_image *rtt_image_read(const char *path, rtt_error *err)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (dot && (!slash || dot > slash)) {
        if (strcasecmp(dot, ".png") == 0) return rtt_image_read_png(path, err);
        if (strcasecmp(dot, ".exr") == 0) return rtt_image_read_exr(path, err);
    }
    rtt_error_set(err, "%s: unknown image format (use .exr or .png)", path);
    return NULL;
}

/* Framebuffer, image files and image metrics (image/). */
#ifndef RTT_IMAGE_H
#define RTT_IMAGE_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/error.h"

/* Linear RGB float framebuffer with optional AOV planes (NULL when absent). */
typedef struct rtt_image {
    uint32_t width, height;
    float *rgb;        /* width*height*3, row 0 at the top */
    float *depth;      /* hit distance t, +inf on a miss */
    uint32_t *prim;    /* global triangle index, RTT_MISS on a miss */
    float *normal;     /* width*height*3, shading normal */
} rtt_image;

/* aovs: rtt_aov bits (render.h). */
rtt_image *rtt_image_create(uint32_t width, uint32_t height, uint32_t aovs, rtt_error *err);
void rtt_image_free(rtt_image *image);

/* Writes to a temporary beside path, then renames, so an existing file is
 * never left half-written.  EXR keeps R,G,B (+ depth, prim, normal.X/Y/Z)
 * as 32-bit float (prim as uint); PNG is sRGB, clamped, 8 bit. */
bool rtt_image_write_exr(const rtt_image *image, const char *path, rtt_error *err);
bool rtt_image_write_png(const rtt_image *image, const char *path, rtt_error *err);
/* A linear value as the 8-bit sRGB code PNG output stores (clamped to
 * [0, 1]; NaN → 0). */
uint8_t rtt_linear_to_srgb8(float linear);
/* Picks the format from the extension (.exr or .png). */
bool rtt_image_write(const rtt_image *image, const char *path, rtt_error *err);
rtt_image *rtt_image_read_exr(const char *path, rtt_error *err);

typedef struct rtt_image_metrics {
    double rmse;             /* over all RGB samples */
    double max_error;        /* largest absolute channel difference */
    double share_over_1_255; /* fraction of pixels with any channel off by > 1/255 */
    uint64_t pixels_over_1_255;
} rtt_image_metrics;

/* Fails (with a message) when sizes differ. Compares on colours clamped to
 * [0,1] like the PNG a user sees. */
bool rtt_image_compare(const rtt_image *a, const rtt_image *b, rtt_image_metrics *out, rtt_error *err);


#endif

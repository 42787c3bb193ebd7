/* The framebuffer: a linear RGB float image with optional AOV planes.
 *
 * A plane exists only when the caller asks for it (rtt_aov bits), so a render
 * without AOVs pays for nothing but its colours. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/render.h"

/* Largest pixel count we allocate: keeps width*height*3*sizeof(float) far
 * from size_t overflow and refuses absurd sizes with a message, not a crash. */
#define MAX_PIXELS (UINT64_C(1) << 28)

static void *alloc_plane(size_t count, size_t size, bool *ok)
{
    void *plane = calloc(count, size);
    if (!plane)
        *ok = false;
    return plane;
}

rtt_image *rtt_image_create(uint32_t width, uint32_t height, uint32_t aovs, rtt_error *err)
{
    if (width == 0 || height == 0) {
        rtt_error_set(err, "image:create: size %ux%u is empty", width, height);
        return NULL;
    }
    uint64_t pixels = (uint64_t)width * height;
    if (pixels > MAX_PIXELS) {
        rtt_error_set(err, "image:create: size %ux%u is too large", width, height);
        return NULL;
    }
    if (aovs & ~(uint32_t)(RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL)) {
        rtt_error_set(err, "image:create: unknown AOV bits 0x%x", aovs);
        return NULL;
    }
    rtt_image *image = calloc(1, sizeof *image);
    if (!image) {
        rtt_error_set(err, "image:create: out of memory");
        return NULL;
    }
    size_t n = (size_t)pixels;
    bool ok = true;
    image->width = width;
    image->height = height;
    image->rgb = alloc_plane(n * 3, sizeof(float), &ok);
    if (aovs & RTT_AOV_DEPTH) {
        image->depth = alloc_plane(n, sizeof(float), &ok);
        for (size_t i = 0; ok && i < n; i++)
            image->depth[i] = INFINITY;
    }
    if (aovs & RTT_AOV_PRIM) {
        image->prim = alloc_plane(n, sizeof(uint32_t), &ok);
        for (size_t i = 0; ok && i < n; i++)
            image->prim[i] = RTT_MISS;
    }
    if (aovs & RTT_AOV_NORMAL)
        image->normal = alloc_plane(n * 3, sizeof(float), &ok);
    if (!ok) {
        rtt_image_free(image);
        rtt_error_set(err, "image:create: out of memory for %ux%u", width, height);
        return NULL;
    }
    return image;
}

void rtt_image_free(rtt_image *image)
{
    if (!image)
        return;
    free(image->rgb);
    free(image->depth);
    free(image->prim);
    free(image->normal);
    free(image);
}

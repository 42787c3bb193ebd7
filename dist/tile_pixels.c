/* A run of tiles' pixels as bytes: what a rank sends rank 0.  Tile by tile,
 * row by row, each plane the image has in turn (rgb, depth, prim, normal):
 * floats travel as their bytes, so rank 0's image is bit for bit what the
 * rank rendered. */
#include <string.h>

#include "dist_internal.h"

enum { PLANE_RGB = 1, PLANE_DEPTH = 2, PLANE_PRIM = 4, PLANE_NORMAL = 8 };

uint32_t dist_image_planes(const rtt_image *image)
{
    return PLANE_RGB | (image->depth ? PLANE_DEPTH : 0u) | (image->prim ? PLANE_PRIM : 0u) |
           (image->normal ? PLANE_NORMAL : 0u);
}

static size_t pixel_bytes(uint32_t planes)
{
    return 3 * sizeof(float) + (planes & PLANE_DEPTH ? sizeof(float) : 0) +
           (planes & PLANE_PRIM ? sizeof(uint32_t) : 0) + (planes & PLANE_NORMAL ? 3 * sizeof(float) : 0);
}

size_t dist_run_bytes(const rtt_tile_grid *grid, uint32_t planes, uint32_t first, uint32_t count)
{
    if (count == 0 || first >= grid->total || count > grid->total - first) return 0;
    size_t pixels = 0;
    for (uint32_t t = first; t < first + count; t++) {
        uint32_t x0, y0, x1, y1;
        rtt_tile_rect(grid, t, &x0, &y0, &x1, &y1);
        pixels += (size_t)(x1 - x0) * (y1 - y0);
    }
    return pixels * pixel_bytes(planes);
}

/* One row of a plane with `channels` 4-byte values per pixel. */
static unsigned char *copy_row(void *plane, uint32_t channels, size_t offset, uint32_t pixels,
                               unsigned char *bytes, bool to_image)
{
    if (!plane) return bytes;
    unsigned char *row = (unsigned char *)plane + offset * channels * 4u;
    size_t size = (size_t)pixels * channels * 4u;
    if (to_image)
        memcpy(row, bytes, size);
    else
        memcpy(bytes, row, size);
    return bytes + size;
}

void dist_run_copy(rtt_image *image, const rtt_tile_grid *grid, uint32_t first, uint32_t count,
                   unsigned char *bytes, bool to_image)
{
    for (uint32_t t = first; t < first + count; t++) {
        uint32_t x0, y0, x1, y1;
        rtt_tile_rect(grid, t, &x0, &y0, &x1, &y1);
        for (uint32_t y = y0; y < y1; y++) {
            size_t offset = (size_t)y * image->width + x0;
            bytes = copy_row(image->rgb, 3, offset, x1 - x0, bytes, to_image);
            bytes = copy_row(image->depth, 1, offset, x1 - x0, bytes, to_image);
            bytes = copy_row(image->prim, 1, offset, x1 - x0, bytes, to_image);
            bytes = copy_row(image->normal, 3, offset, x1 - x0, bytes, to_image);
        }
    }
}

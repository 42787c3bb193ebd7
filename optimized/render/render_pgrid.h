/* The optimized renderer's eye rays through the perspective grid
 * (--accel pgrid, Hunt & Mark 2008 section 5.1): the grid is built at the
 * start of every frame, each of its cells is one tile of the renderer, and
 * a cell's hits go to the shader proxy as the tile's primary rays, so
 * shadows, reflections and refractions are traced as with the kd-tree
 * (through it: secondary rays use the kd kernels). */
#ifndef RTT_OPTIMIZED_RENDER_PGRID_H
#define RTT_OPTIMIZED_RENDER_PGRID_H

#include "pgrid_eye.h"
#include "shader_proxy.h"

typedef struct pgrid_render {
    pgrid_eye grid;
    const pgrid_kernel *kernel;
    uint32_t threads;
    pgrid_cell_buffers *buffers; /* per thread: a cell's depth, triangle and block buffers */
    rtt_hit **hits;         /* per thread: the cell's hits, row-major */
    double build_seconds;
} pgrid_render;

/* Builds the frame's grid (cells of `cell` pixels, 0 → the default) and the
 * per-thread buffers; false (err filled) when out of memory. */
bool pgrid_render_begin(pgrid_render *r, const pgrid_kernel *kernel, const rtt_scene *scene,
                        const uint8_t *degenerate, const rtt_camera_frame *frame, uint32_t width, uint32_t height,
                        uint32_t cell, uint32_t threads, rtt_error *err);
/* The cell with corner (x0, y0): traced, its pixels' rays (rtt_camera_ray)
 * and hits pushed to the proxy in row-major order. */
void pgrid_render_cell(const pgrid_render *r, uint32_t thread, sp_scratch *s, uint32_t x0, uint32_t y0,
                       uint32_t x1, uint32_t y1);
void pgrid_render_end(pgrid_render *r);

#endif

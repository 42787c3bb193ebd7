/* render_pgrid.h: a frame's perspective grid for the tiled renderer. */
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "render_pgrid.h"

bool pgrid_render_begin(pgrid_render *r, const pgrid_kernel *kernel, const rtt_scene *scene,
                        const uint8_t *degenerate, const rtt_camera_frame *frame, uint32_t width, uint32_t height,
                        uint32_t cell, uint32_t threads, rtt_error *err)
{
    memset(r, 0, sizeof *r);
    const uint64_t t0 = rtt_clock_ns();
    r->kernel = kernel;
    r->threads = threads;
    r->grid.threads = threads;
    if (!pgrid_eye_build(&r->grid, scene, degenerate, frame, width, height, cell, err)) return false;
    r->build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    const size_t entries = (size_t)r->grid.cell * r->grid.cell;
    r->buffers = calloc(threads, sizeof *r->buffers);
    r->hits = calloc(threads, sizeof *r->hits);
    bool ok = r->buffers && r->hits;
    for (uint32_t t = 0; ok && t < threads; t++) {
        r->hits[t] = malloc(entries * sizeof(rtt_hit));
        ok = r->hits[t] && pgrid_cell_buffers_alloc(&r->buffers[t], r->grid.cell);
    }
    return ok || rtt_error_set(err, "%s: out of memory for the perspective grid's cells", scene->path);
}

void pgrid_render_cell(const pgrid_render *r, uint32_t thread, sp_scratch *s, uint32_t x0, uint32_t y0,
                       uint32_t x1, uint32_t y1)
{
    const pgrid_eye *g = &r->grid;
    const uint64_t t0 = rtt_clock_ns();
    const uint32_t cell = (y0 / g->cell) * g->cells_x + x0 / g->cell;
    rtt_hit *hits = r->hits[thread];
    r->kernel->trace_cell(g, cell, &r->buffers[thread]);
    r->kernel->resolve_cell(g, cell, &r->buffers[thread], hits, g->cell, false); /* shaded next: kept in cache */
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) {
            const rtt_ray ray = rtt_camera_ray(&g->frame, x, y);
            sp_primary_push_hit(s, &ray, &hits[(y - y0) * g->cell + (x - x0)], y * g->width + x);
        }
    sp_primary_hits_done(s, rtt_clock_ns() - t0);
}

void pgrid_render_end(pgrid_render *r)
{
    for (uint32_t t = 0; t < r->threads; t++) {
        if (r->buffers) pgrid_cell_buffers_free(&r->buffers[t]);
        if (r->hits) free(r->hits[t]);
    }
    free(r->hits);
    free(r->buffers);
    pgrid_eye_free(&r->grid);
}

/* One frame of eye rays through the perspective grid alone, without
 * shading (pgrid_eye_trace_frame): what the bench races against Embree and
 * llvmpipe and what the tests compare with the reference.  The build runs
 * on the calling thread and is part of the frame; the cells go to the
 * thread pool, each worker with its own depth and triangle buffers (kept
 * in the grid from frame to frame, left cleared by every cell's resolve). */
#include <math.h>
#include <stdlib.h>

#include "engine/clock.h"
#include "engine/threads.h"
#include "pgrid_eye.h"

typedef struct frame_job {
    const pgrid_eye *grid;
    const pgrid_kernel *kernel;
    rtt_hit *hits;
    pgrid_cell_buffers *buffers; /* per thread */
} frame_job;

bool pgrid_cell_buffers_alloc(pgrid_cell_buffers *b, uint32_t cell)
{
    const size_t entries = (size_t)cell * cell;
    b->depth = aligned_alloc(64, entries * sizeof(float));
    b->triangle = aligned_alloc(64, entries * sizeof(uint32_t));
    b->block_max = malloc((entries / 4u ? entries / 4u : 1u) * sizeof(float));
    if (b->depth && b->triangle && b->block_max) {
        for (size_t i = 0; i < entries; i++) b->depth[i] = INFINITY, b->triangle[i] = PGRID_NO_TRIANGLE;
        return true;
    }
    pgrid_cell_buffers_free(b);
    return false;
}

void pgrid_cell_buffers_free(pgrid_cell_buffers *b)
{
    free(b->depth);
    free(b->triangle);
    free(b->block_max);
    b->depth = NULL, b->triangle = NULL, b->block_max = NULL;
}

static void trace_cell(void *context, uint32_t thread, uint32_t cell)
{
    const frame_job *job = context;
    const pgrid_eye *g = job->grid;
    const uint32_t X0 = (cell % g->cells_x) * g->cell, Y0 = (cell / g->cells_x) * g->cell;
    job->kernel->trace_cell(g, cell, &job->buffers[thread]);
    job->kernel->resolve_cell(g, cell, &job->buffers[thread], job->hits + (size_t)Y0 * g->width + X0, g->width, true);
}

uint32_t pgrid_eye_cell_rule(uint32_t width, uint32_t height, uint32_t threads, uint32_t bytes_per_pixel,
                             uint64_t refs_default, uint64_t refs_big)
{
    const uint32_t big = 2u * PGRID_EYE_CELL_DEFAULT;
    const uint64_t cells = (uint64_t)((width + big - 1u) / big) * ((height + big - 1u) / big);
    const uint64_t bytes = (uint64_t)big * big * bytes_per_pixel, l2 = rtt_cpu_l2_bytes();
    if (cells < 4u * (uint64_t)(threads ? threads : 1u)) return PGRID_EYE_CELL_DEFAULT;
    if (bytes <= l2 / 4u || (bytes <= l2 / 2u && 5u * refs_big <= 4u * refs_default)) return big;
    return PGRID_EYE_CELL_DEFAULT;
}

void pgrid_eye_frame_buffers_free(pgrid_eye *grid)
{
    for (uint32_t t = 0; t < grid->frame_buffer_count; t++) pgrid_cell_buffers_free(&grid->frame_buffers[t]);
    free(grid->frame_buffers);
    grid->frame_buffers = NULL, grid->frame_buffer_count = 0, grid->frame_buffer_cell = 0;
}

/* The grid's cell buffers for `threads` threads at its cell: the frame
 * before's when they fit, else new ones; false (none held) when out of memory. */
static bool frame_buffers_ready(pgrid_eye *grid, uint32_t threads)
{
    if (grid->frame_buffer_cell == grid->cell && grid->frame_buffer_count >= threads) return true;
    pgrid_eye_frame_buffers_free(grid);
    if (!(grid->frame_buffers = calloc(threads, sizeof *grid->frame_buffers))) return false;
    for (; grid->frame_buffer_count < threads; grid->frame_buffer_count++)
        if (!pgrid_cell_buffers_alloc(&grid->frame_buffers[grid->frame_buffer_count], grid->cell)) {
            pgrid_eye_frame_buffers_free(grid);
            return false;
        }
    grid->frame_buffer_cell = grid->cell;
    return true;
}

bool pgrid_eye_trace_frame(pgrid_eye *grid, const pgrid_kernel *kernel, const rtt_scene *scene,
                           const uint8_t *degenerate, const rtt_camera_frame *frame, uint32_t width,
                           uint32_t height, uint32_t cell, uint32_t threads, rtt_hit *hits, double *build_seconds,
                           rtt_error *err)
{
    const uint64_t t0 = rtt_clock_ns();
    grid->threads = threads;
    threads = rtt_thread_count(threads);
    grid->cell_rule_bytes = 8u; /* cell 0: the build's rule for streamed hits (depth and triangle) */
    if (!pgrid_eye_build(grid, scene, degenerate, frame, width, height, cell, err)) return false;
    if (build_seconds) *build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    const bool ok = frame_buffers_ready(grid, threads);
    frame_job job = {grid, kernel, hits, grid->frame_buffers};
    if (ok) rtt_parallel_run(pgrid_eye_cell_count(grid), threads, trace_cell, &job);
    return ok || rtt_error_set(err, "%s: out of memory tracing the perspective grid", scene->path);
}

/* The tile scheduler (threads.h; the thesis' tiled threading): an image's
 * tiles as tasks of the thread pool, in row-major order, or the tiles a
 * source hands out (rtt_tiles_run_from). */
#include <stdatomic.h>

#include "engine/threads.h"

#define DEFAULT_TILE 16u

typedef struct tile_job {
    rtt_tile_grid grid;
    rtt_tile_fn fn;
    void *context;
    rtt_progress_fn progress;
    void *progress_context;
    const rtt_tile_source *source;   /* NULL: task t is tile t */
    atomic_uint done;   /* tiles finished (counted only for `progress`) */
} tile_job;

void rtt_tile_rect(const rtt_tile_grid *grid, uint32_t t, uint32_t *x0, uint32_t *y0, uint32_t *x1, uint32_t *y1)
{
    *x0 = (t % grid->tiles_x) * grid->tile;
    *y0 = (t / grid->tiles_x) * grid->tile;
    *x1 = grid->width - *x0 < grid->tile ? grid->width : *x0 + grid->tile;
    *y1 = grid->height - *y0 < grid->tile ? grid->height : *y0 + grid->tile;
}

static void run_tile(tile_job *job, uint32_t thread, uint32_t t)
{
    uint32_t x0, y0, x1, y1;
    rtt_tile_rect(&job->grid, t, &x0, &y0, &x1, &y1);
    job->fn(job->context, thread, x0, y0, x1, y1);
    if (!job->progress) return; /* the count is the progress callback's: without one, no shared line to bounce */
    uint32_t done = atomic_fetch_add_explicit(&job->done, 1, memory_order_acq_rel) + 1;
    job->progress(job->progress_context, done, job->grid.total);
}

static void run_task_tile(void *context, uint32_t thread, uint32_t t)
{
    run_tile(context, thread, t);
}

/* One task per worker: the runs its source hands it, until there are none. */
static void run_source_worker(void *context, uint32_t thread, uint32_t task)
{
    (void)task;
    tile_job *job = context;
    const rtt_tile_source *source = job->source;
    uint32_t first, count;
    while (source->take(source->context, &job->grid, thread, &first, &count)) {
        for (uint32_t t = first; t < first + count && t < job->grid.total; t++) run_tile(job, thread, t);
        if (source->rendered) source->rendered(source->context, &job->grid, thread, first, count);
    }
}

void rtt_tiles_run_from(const rtt_tile_source *source, uint32_t width, uint32_t height, uint32_t tile,
                        uint32_t threads, rtt_tile_fn fn, void *context, rtt_progress_fn progress,
                        void *progress_context)
{
    if (width == 0 || height == 0 || !fn) return;
    if (tile == 0) tile = DEFAULT_TILE;
    uint32_t tiles_x = (uint32_t)(((uint64_t)width + tile - 1) / tile);
    uint32_t tiles_y = (uint32_t)(((uint64_t)height + tile - 1) / tile);
    tile_job job = {
        .grid = {.width = width, .height = height, .tile = tile, .tiles_x = tiles_x,
                 .total = tiles_x * tiles_y}, /* at most width*height, fits */
        .fn = fn, .context = context, .progress = progress, .progress_context = progress_context,
        .source = source,
    };
    atomic_init(&job.done, 0);
    if (source) {
        threads = rtt_thread_count(threads);
        rtt_parallel_run(threads, threads, run_source_worker, &job);
    } else {
        rtt_parallel_run(job.grid.total, threads, run_task_tile, &job);
    }
}

void rtt_tiles_run(uint32_t width, uint32_t height, uint32_t tile, uint32_t threads, rtt_tile_fn fn,
                   void *context, rtt_progress_fn progress, void *progress_context)
{
    rtt_tiles_run_from(NULL, width, height, tile, threads, fn, context, progress, progress_context);
}

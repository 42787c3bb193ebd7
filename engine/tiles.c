/* The tile scheduler (threads.h; the thesis' tiled threading): an image's
 * tiles as tasks of the thread pool, in row-major order. */
#include <stdatomic.h>

#include "engine/threads.h"

#define DEFAULT_TILE 16u

typedef struct tile_job {
    uint32_t width, height, tile, tiles_x, total;
    rtt_tile_fn fn;
    void *context;
    rtt_progress_fn progress;
    void *progress_context;
    atomic_uint done;   /* tiles finished */
} tile_job;

static void run_tile(void *context, uint32_t thread, uint32_t t)
{
    tile_job *job = context;
    uint32_t x0 = (t % job->tiles_x) * job->tile, y0 = (t / job->tiles_x) * job->tile;
    uint32_t x1 = job->width - x0 < job->tile ? job->width : x0 + job->tile;
    uint32_t y1 = job->height - y0 < job->tile ? job->height : y0 + job->tile;
    job->fn(job->context, thread, x0, y0, x1, y1);
    uint32_t done = atomic_fetch_add_explicit(&job->done, 1, memory_order_acq_rel) + 1;
    if (job->progress) job->progress(job->progress_context, done, job->total);
}

void rtt_tiles_run(uint32_t width, uint32_t height, uint32_t tile, uint32_t threads, rtt_tile_fn fn,
                   void *context, rtt_progress_fn progress, void *progress_context)
{
    if (width == 0 || height == 0 || !fn) return;
    if (tile == 0) tile = DEFAULT_TILE;
    tile_job job = {
        .width = width, .height = height, .tile = tile,
        .tiles_x = (uint32_t)(((uint64_t)width + tile - 1) / tile),
        .fn = fn, .context = context, .progress = progress, .progress_context = progress_context,
    };
    uint32_t tiles_y = (uint32_t)(((uint64_t)height + tile - 1) / tile);
    job.total = job.tiles_x * tiles_y; /* at most width*height, fits */
    atomic_init(&job.done, 0);
    rtt_parallel_run(job.total, threads, run_tile, &job);
}

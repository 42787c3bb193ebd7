/* The tile scheduler: the one place threads live (thesis 3.x "tiled
 * threading"; c-ray's thread pool).
 *
 * The image is cut into tile x tile squares (clipped at the right and bottom
 * edges).  An atomic counter hands them out in row-major order, so workers
 * take the next free tile as soon as they finish one and load balances
 * itself.  Tiles are independent, so the result does not depend on the
 * thread count or on which worker renders which tile.
 *
 * The progress callback is called after every finished tile from the thread
 * that finished it, possibly from several threads at once: it must be
 * thread-safe.  `done` counts tiles finished so far (1..total); calls from
 * different threads may arrive out of order. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#include "rtt/image.h"

#define DEFAULT_TILE 16u
#define MAX_THREADS 1024u

typedef struct tile_job {
    uint32_t width, height, tile;
    uint32_t tiles_x, total;
    rtt_tile_fn fn;
    void *context;
    rtt_progress_fn progress;
    void *progress_context;
    atomic_uint next;   /* next tile to hand out */
    atomic_uint done;   /* tiles finished */
} tile_job;

typedef struct tile_worker {
    tile_job *job;
    uint32_t index;
} tile_worker;

static void run_tiles(tile_job *job, uint32_t thread)
{
    for (;;) {
        uint32_t t = atomic_fetch_add_explicit(&job->next, 1, memory_order_relaxed);
        if (t >= job->total)
            return;
        uint32_t x0 = (t % job->tiles_x) * job->tile;
        uint32_t y0 = (t / job->tiles_x) * job->tile;
        uint32_t x1 = job->width - x0 < job->tile ? job->width : x0 + job->tile;
        uint32_t y1 = job->height - y0 < job->tile ? job->height : y0 + job->tile;
        job->fn(job->context, thread, x0, y0, x1, y1);
        uint32_t done = atomic_fetch_add_explicit(&job->done, 1, memory_order_acq_rel) + 1;
        if (job->progress)
            job->progress(job->progress_context, done, job->total);
    }
}

static void *worker_main(void *arg)
{
    tile_worker *worker = arg;
    run_tiles(worker->job, worker->index);
    return NULL;
}

uint32_t rtt_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1)
        return 1;
    return n > (long)MAX_THREADS ? MAX_THREADS : (uint32_t)n;
}

void rtt_tiles_run(uint32_t width, uint32_t height, uint32_t tile, uint32_t threads, rtt_tile_fn fn,
                   void *context, rtt_progress_fn progress, void *progress_context)
{
    if (width == 0 || height == 0 || !fn)
        return;
    if (tile == 0)
        tile = DEFAULT_TILE;
    tile_job job = {
        .width = width, .height = height, .tile = tile,
        .tiles_x = (uint32_t)(((uint64_t)width + tile - 1) / tile),
        .fn = fn, .context = context,
        .progress = progress, .progress_context = progress_context,
    };
    uint32_t tiles_y = (uint32_t)(((uint64_t)height + tile - 1) / tile);
    job.total = job.tiles_x * tiles_y;   /* at most width*height, fits */
    atomic_init(&job.next, 0);
    atomic_init(&job.done, 0);

    if (threads == 0)
        threads = rtt_cpu_count();
    if (threads > MAX_THREADS)
        threads = MAX_THREADS;
    if (threads > job.total)
        threads = job.total;
    if (threads <= 1) {
        run_tiles(&job, 0);
        return;
    }

    pthread_t *ids = malloc(threads * sizeof *ids);
    tile_worker *workers = malloc(threads * sizeof *workers);
    uint32_t started = 0;
    if (ids && workers) {
        /* worker 0 is the calling thread; others are created */
        for (uint32_t i = 1; i < threads; i++) {
            workers[i] = (tile_worker){ &job, i };
            if (pthread_create(&ids[i], NULL, worker_main, &workers[i]) != 0)
                break;
            started = i;
        }
    }
    /* Without memory or threads the caller still renders every tile: fewer
     * workers, same image. */
    run_tiles(&job, 0);
    for (uint32_t i = 1; i <= started; i++)
        pthread_join(ids[i], NULL);
    free(ids);
    free(workers);
}

/* The thread pool and the tile scheduler: the one place threads live.
 *
 * rtt_parallel_run hands task indices 0..tasks-1 to up to `threads` workers
 * (the calling thread is worker 0) through an atomic counter, in shares of
 * consecutive tasks that shrink as the run goes (an eighth of what is left
 * per thread, down to one), so workers take the next share as soon as they
 * finish one and the load balances itself.
 * rtt_tiles_run cuts an image into tile x tile squares (clipped at the right
 * and bottom edges) in row-major order and runs them as tasks;
 * rtt_tiles_run_from runs only the tiles a source hands out (rtt/render.h).  Tasks are
 * independent, so results never depend on the thread count or on which
 * worker ran which task.  Every worker fences its non-temporal (streamed)
 * stores after its last task, so a task may stream its results unfenced:
 * the caller reads them after the run. */
#ifndef RTT_ENGINE_THREADS_H
#define RTT_ENGINE_THREADS_H

#include <stdint.h>

#include "rtt/render.h"

#define RTT_MAX_THREADS 1024u

/* Online cores, 1..RTT_MAX_THREADS. */
uint32_t rtt_cpu_count(void);
/* threads 0 → one per core; clamped to 1..RTT_MAX_THREADS. */
uint32_t rtt_thread_count(uint32_t threads);

typedef void (*rtt_task_fn)(void *context, uint32_t thread, uint32_t task);
/* Runs every task once; threads 0 → one per core (never more than tasks).
 * When a worker cannot be started its share runs on the others. */
void rtt_parallel_run(uint32_t tasks, uint32_t threads, rtt_task_fn fn, void *context);

typedef void (*rtt_tile_fn)(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1);
/* Called after every finished tile from the thread that finished it, possibly
 * from several at once (it must be thread-safe); `done` counts tiles
 * finished so far, calls may arrive out of order. */
typedef void (*rtt_progress_fn)(void *context, uint32_t done, uint32_t total);
void rtt_tiles_run(uint32_t width, uint32_t height, uint32_t tile, uint32_t threads, rtt_tile_fn fn,
                   void *context, rtt_progress_fn progress, void *progress_context);
/* source NULL: rtt_tiles_run.  Otherwise every worker renders the runs of
 * tiles source->take gives it, one tile at a time, until it says none are
 * left; `done` counts this process's tiles. */
void rtt_tiles_run_from(const rtt_tile_source *source, uint32_t width, uint32_t height, uint32_t tile,
                        uint32_t threads, rtt_tile_fn fn, void *context, rtt_progress_fn progress,
                        void *progress_context);

#endif

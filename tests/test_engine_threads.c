/* The thread pool and tile scheduler (engine/threads.h): every pixel once, any thread count. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "engine/threads.h"

#include "rtt/engine.h"

#include "rtt/render.h"

typedef struct coverage {
    uint32_t width, height, threads;
    atomic_uint *visits;      /* per pixel */
    atomic_uint bad_thread;   /* callbacks with thread >= threads */
    atomic_uint bad_tile;     /* empty, inverted or out-of-bounds tiles */
    atomic_uint tiles;
} coverage;

static void count_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    coverage *c = context;
    atomic_fetch_add(&c->tiles, 1);
    if (thread >= c->threads)
        atomic_fetch_add(&c->bad_thread, 1);
    if (x0 >= x1 || y0 >= y1 || x1 > c->width || y1 > c->height) {
        atomic_fetch_add(&c->bad_tile, 1);
        return;
    }
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++)
            atomic_fetch_add(&c->visits[(size_t)y * c->width + x], 1);
}

static void check_every_pixel_once(uint32_t width, uint32_t height, uint32_t tile, uint32_t threads)
{
    coverage c = { .width = width, .height = height, .threads = threads == 0 ? rtt_cpu_count() : threads };
    c.visits = calloc((size_t)width * height, sizeof *c.visits);
    assert_non_null(c.visits);
    rtt_tiles_run(width, height, tile, threads, count_tile, &c, NULL, NULL);
    for (size_t i = 0; i < (size_t)width * height; i++)
        assert_int_equal(atomic_load(&c.visits[i]), 1);
    assert_int_equal(atomic_load(&c.bad_thread), 0);
    assert_int_equal(atomic_load(&c.bad_tile), 0);
    uint32_t t = tile ? tile : 1;
    if (tile)
        assert_int_equal(atomic_load(&c.tiles), ((width + t - 1) / t) * ((height + t - 1) / t));
    free(c.visits);
}

static void test_tiles_cover_each_pixel_once_for_1_2_3_7_threads(void **state)
{
    (void)state;
    const uint32_t threads[] = { 1, 2, 3, 7 };
    for (size_t i = 0; i < sizeof threads / sizeof threads[0]; i++) {
        check_every_pixel_once(64, 48, 16, threads[i]);
        check_every_pixel_once(67, 41, 8, threads[i]);    /* odd sizes: clipped edge tiles */
        check_every_pixel_once(1, 1, 16, threads[i]);
        check_every_pixel_once(5, 300, 7, threads[i]);
    }
}

static void test_tiles_cover_each_pixel_once_with_default_threads_and_tile(void **state)
{
    (void)state;
    check_every_pixel_once(33, 17, 0, 0);
    check_every_pixel_once(33, 17, 1000, 0);   /* one tile larger than the image */
}

static void test_tiles_empty_image_calls_nothing(void **state)
{
    (void)state;
    coverage c = { .width = 0, .height = 0, .threads = 4 };
    rtt_tiles_run(0, 10, 4, 4, count_tile, &c, NULL, NULL);
    rtt_tiles_run(10, 0, 4, 4, count_tile, &c, NULL, NULL);
    assert_int_equal(atomic_load(&c.tiles), 0);
}

typedef struct progress_log {
    pthread_mutex_t lock;
    uint32_t calls, max_done, total;
    uint8_t seen[64];
    bool bad;
} progress_log;

static void log_progress(void *context, uint32_t done, uint32_t total)
{
    progress_log *log = context;
    pthread_mutex_lock(&log->lock);
    log->calls++;
    if (done == 0 || done > total || total != log->total || log->seen[done])
        log->bad = true;
    else
        log->seen[done] = 1;
    if (done > log->max_done)
        log->max_done = done;
    pthread_mutex_unlock(&log->lock);
}

static void ignore_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)context, (void)thread, (void)x0, (void)y0, (void)x1, (void)y1;
}

static void test_progress_reports_each_tile_once_with_total(void **state)
{
    (void)state;
    for (uint32_t threads = 1; threads <= 3; threads++) {
        progress_log log = { .total = 6 * 5 };
        pthread_mutex_init(&log.lock, NULL);
        rtt_tiles_run(90, 70, 16, threads, ignore_tile, NULL, log_progress, &log);   /* 6 x 5 tiles */
        assert_false(log.bad);
        assert_int_equal(log.calls, 30);
        assert_int_equal(log.max_done, 30);
        pthread_mutex_destroy(&log.lock);
    }
}

typedef struct thread_record {
    pthread_t caller;
    atomic_uint other_thread_tiles;
} thread_record;

static void record_thread(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)thread, (void)x0, (void)y0, (void)x1, (void)y1;
    thread_record *r = context;
    if (!pthread_equal(pthread_self(), r->caller))
        atomic_fetch_add(&r->other_thread_tiles, 1);
}

static void test_one_thread_runs_inline_on_the_caller(void **state)
{
    (void)state;
    thread_record r = { .caller = pthread_self() };
    rtt_tiles_run(100, 100, 8, 1, record_thread, &r, NULL, NULL);
    assert_int_equal(atomic_load(&r.other_thread_tiles), 0);
}

/* A tile source as dist/ uses one: runs of 3 tiles from every third run on
 * (a process with a third of the frame), each run's rendered callback
 * after its tiles. */
typedef struct third_source {
    atomic_uint next_run;
    atomic_uint total; /* written by every worker (the same value) */
    atomic_uint runs_rendered, bad_runs;
    coverage *c;
} third_source;

static bool take_third(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t *first, uint32_t *count)
{
    (void)thread;
    third_source *s = context;
    atomic_store_explicit(&s->total, grid->total, memory_order_relaxed);
    uint32_t run = atomic_fetch_add(&s->next_run, 1);
    if (run * 9 >= grid->total) return false;
    *first = run * 9;
    *count = 3;
    return true;
}

static void third_rendered(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t first, uint32_t count)
{
    third_source *s = context;
    if (thread >= s->c->threads || first % 9 != 0 || count != 3 || grid->tile != 5) atomic_fetch_add(&s->bad_runs, 1);
    atomic_fetch_add(&s->runs_rendered, 1);
}

static void test_tiles_from_a_source_renders_its_runs_only(void **state)
{
    (void)state;
    const uint32_t width = 53, height = 31, tile = 5, tiles_x = 11; /* 11 x 7 tiles, clipped */
    for (uint32_t threads = 1; threads <= 3; threads++) {
        coverage c = {.width = width, .height = height, .threads = threads};
        c.visits = calloc((size_t)width * height, sizeof *c.visits);
        assert_non_null(c.visits);
        third_source s = {.c = &c};
        atomic_init(&s.next_run, 0);
        rtt_tile_source source = {.take = take_third, .rendered = third_rendered, .context = &s};
        rtt_tiles_run_from(&source, width, height, tile, threads, count_tile, &c, NULL, NULL);
        assert_int_equal(atomic_load(&s.total), 77);
        for (uint32_t y = 0; y < height; y++)
            for (uint32_t x = 0; x < width; x++) {
                uint32_t t = (y / tile) * tiles_x + x / tile;
                assert_int_equal(atomic_load(&c.visits[(size_t)y * width + x]), t % 9 < 3 ? 1 : 0);
            }
        assert_int_equal(atomic_load(&s.runs_rendered), 9); /* runs at 0, 9, .., 72; the last clipped to 72..76 */
        assert_int_equal(atomic_load(&s.bad_runs), 0);
        assert_int_equal(atomic_load(&c.bad_tile), 0);
        free(c.visits);
    }
}

static void test_tile_rect_clips_at_the_edges(void **state)
{
    (void)state;
    rtt_tile_grid grid = {.width = 10, .height = 7, .tile = 4, .tiles_x = 3, .total = 6};
    uint32_t x0, y0, x1, y1;
    rtt_tile_rect(&grid, 5, &x0, &y0, &x1, &y1);
    assert_int_equal(x0, 8);
    assert_int_equal(y0, 4);
    assert_int_equal(x1, 10);
    assert_int_equal(y1, 7);
    rtt_tile_rect(&grid, 1, &x0, &y0, &x1, &y1);
    assert_int_equal(x0, 4);
    assert_int_equal(x1, 8);
    assert_int_equal(y1, 4);
}

static void test_cpu_count_is_at_least_one(void **state)
{
    (void)state;
    assert_true(rtt_cpu_count() >= 1);
}

/* ---- the persistent workers: nested and concurrent runs, many runs ---- */

typedef struct nested_job {
    atomic_uint inner_tasks;
    atomic_uint outer_tasks;
} nested_job;

static void inner_task(void *context, uint32_t thread, uint32_t task)
{
    (void)thread, (void)task;
    atomic_fetch_add(&((nested_job *)context)->inner_tasks, 1);
}

static void outer_task(void *context, uint32_t thread, uint32_t task)
{
    (void)thread, (void)task;
    nested_job *job = context;
    atomic_fetch_add(&job->outer_tasks, 1);
    rtt_parallel_run(10, 3, inner_task, job); /* runs while the outer run holds the workers */
}

static void test_nested_runs_do_every_task(void **state)
{
    (void)state;
    nested_job job;
    atomic_init(&job.inner_tasks, 0);
    atomic_init(&job.outer_tasks, 0);
    rtt_parallel_run(6, 4, outer_task, &job);
    assert_int_equal(atomic_load(&job.outer_tasks), 6);
    assert_int_equal(atomic_load(&job.inner_tasks), 60);
}

static void *concurrent_caller(void *arg)
{
    for (int i = 0; i < 50; i++) rtt_parallel_run(8, 3, inner_task, arg);
    return NULL;
}

static void test_concurrent_callers_and_many_runs(void **state)
{
    (void)state;
    nested_job a, b;
    atomic_init(&a.inner_tasks, 0);
    atomic_init(&b.inner_tasks, 0);
    pthread_t other;
    assert_int_equal(pthread_create(&other, NULL, concurrent_caller, &b), 0);
    concurrent_caller(&a);
    pthread_join(other, NULL);
    assert_int_equal(atomic_load(&a.inner_tasks), 400);
    assert_int_equal(atomic_load(&b.inner_tasks), 400);
    /* thread counts that grow and shrink between runs */
    nested_job c;
    atomic_init(&c.inner_tasks, 0);
    for (uint32_t threads = 1; threads <= 9; threads++) rtt_parallel_run(20, threads, inner_task, &c);
    for (uint32_t threads = 9; threads >= 1; threads--) rtt_parallel_run(20, threads, inner_task, &c);
    assert_int_equal(atomic_load(&c.inner_tasks), 18 * 20);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tiles_cover_each_pixel_once_for_1_2_3_7_threads),
        cmocka_unit_test(test_tiles_cover_each_pixel_once_with_default_threads_and_tile),
        cmocka_unit_test(test_tiles_empty_image_calls_nothing),
        cmocka_unit_test(test_progress_reports_each_tile_once_with_total),
        cmocka_unit_test(test_one_thread_runs_inline_on_the_caller),
        cmocka_unit_test(test_tiles_from_a_source_renders_its_runs_only),
        cmocka_unit_test(test_tile_rect_clips_at_the_edges),
        cmocka_unit_test(test_cpu_count_is_at_least_one),
        cmocka_unit_test(test_nested_runs_do_every_task),
        cmocka_unit_test(test_concurrent_callers_and_many_runs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

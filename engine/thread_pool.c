/* The thread pool (threads.h): tasks handed out by an atomic counter, the
 * calling thread working as worker 0.
 *
 * Workers persist: the first run that wants k threads starts k - 1 workers,
 * which then sleep on a condition variable between runs, so a frame of an
 * interactive loop neither creates threads nor allocates.  One run owns the
 * persistent workers at a time; a run that finds them busy (a nested run from
 * inside a task, as the tree builders make, or a second caller thread)
 * starts threads of its own for its duration, as every run did before the
 * pool persisted.  The workers are never joined: they sleep until the
 * process exits.
 *
 * Waking a sleeping thread costs tens of microseconds or more (on a
 * virtual machine, the host must schedule the idle vCPU again), which a
 * frame of several short parallel stages pays at each: a worker woken late
 * finds the run's few tasks taken by the caller.  So a worker polls for
 * the next run for POOL_SPIN_NS before it sleeps, and the caller polls for
 * the workers' end as long before it sleeps (measured: bench/results/
 * pgrid.md, "ninth session").
 *
 * Tasks go out in shares of an eighth of what is left per thread (guided),
 * not one at a time: with short tasks (the 4096 16x16 tiles of a bvh-mft
 * frame, 20-40 us each) the counter's cache line moving between the cores
 * at every task cost a sixth of a two-thread frame (bench/results/
 * bvh-mft.md, "tenth session"). */
#include <immintrin.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

#include "engine/clock.h"
#include "engine/threads.h"

#define POOL_SPIN_NS 200000u

typedef struct pool_run {
    uint32_t tasks;
    rtt_task_fn fn;
    void *context;
    uint32_t threads;   /* how many take part: the size of a share (work) */
    atomic_uint next;   /* next task to hand out */
} pool_run;

/* A worker's share of the run.  Tasks may write with non-temporal
 * (streamed) stores, which x86 orders only by a fence: not by program
 * order, and on every vendor's reading not by the locked instruction of
 * the mutex that reports the worker done.  So each worker fences its
 * streamed stores once, after its last task, and the caller reads every
 * task's results after the run; a kernel streaming a frame's hits in
 * small tiles need not fence each (optimized/bvh/bvh_kernels.h,
 * bvh_camera_block). */
static void work(pool_run *run, uint32_t thread)
{
    for (;;) {
        /* a share of what is left, an eighth of it per thread (guided):
         * the counter's line moves between cores a few dozen times a
         * run, not once a task, and the shares shrink to single tasks
         * towards the end, which keeps the threads' finish even */
        const uint32_t seen = atomic_load_explicit(&run->next, memory_order_relaxed);
        if (seen >= run->tasks) break;
        const uint64_t share = (run->tasks - seen) / (8u * (uint64_t)run->threads);
        const uint32_t count = share > 1 ? (uint32_t)share : 1u;
        const uint32_t first = atomic_fetch_add_explicit(&run->next, count, memory_order_relaxed);
        if (first >= run->tasks) break;
        const uint32_t end = run->tasks - first < count ? run->tasks : first + count;
        for (uint32_t task = first; task < end; task++) run->fn(run->context, thread, task);
    }
    _mm_sfence();
}

uint32_t rtt_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1) return 1;
    return n > (long)RTT_MAX_THREADS ? RTT_MAX_THREADS : (uint32_t)n;
}

uint32_t rtt_thread_count(uint32_t threads)
{
    if (threads == 0) return rtt_cpu_count();
    return threads > RTT_MAX_THREADS ? RTT_MAX_THREADS : threads;
}

/* ---- the persistent workers ---- */

static struct {
    pthread_mutex_t lock;
    pthread_cond_t wake, finished;
    uint32_t started;          /* workers 1..started exist */
    _Atomic uint64_t generation; /* bumped when a run is handed out (read without the lock while polling) */
    pool_run *run;             /* the run being worked, NULL between runs */
    uint32_t wanted;           /* workers 1..wanted-1 take part in it */
    atomic_uint working;       /* of those, how many have not finished (read without the lock while polling) */
    bool owned;                /* a run owns the workers */
} pool = {.lock = PTHREAD_MUTEX_INITIALIZER, .wake = PTHREAD_COND_INITIALIZER,
          .finished = PTHREAD_COND_INITIALIZER};

/* Poll *value while it equals `seen` (or, below, is not zero), for at most
 * POOL_SPIN_NS; the caller then checks again under the lock and sleeps if
 * it must. */
static void spin_while_equal64(_Atomic uint64_t *value, uint64_t seen)
{
    const uint64_t until = rtt_clock_ns() + POOL_SPIN_NS;
    for (uint32_t i = 0; atomic_load_explicit(value, memory_order_relaxed) == seen; i++)
        if ((i & 63u) == 63u && rtt_clock_ns() > until) return;
}

static void spin_while_nonzero(atomic_uint *value)
{
    const uint64_t until = rtt_clock_ns() + POOL_SPIN_NS;
    for (uint32_t i = 0; atomic_load_explicit(value, memory_order_relaxed) != 0; i++)
        if ((i & 63u) == 63u && rtt_clock_ns() > until) return;
}

static void *pool_worker_main(void *arg)
{
    const uint32_t index = (uint32_t)(uintptr_t)arg;
    uint64_t seen = 0;
    pthread_mutex_lock(&pool.lock);
    for (;;) {
        if (pool.generation == seen) { /* poll a while before sleeping */
            pthread_mutex_unlock(&pool.lock);
            spin_while_equal64(&pool.generation, seen);
            pthread_mutex_lock(&pool.lock);
        }
        while (pool.generation == seen) pthread_cond_wait(&pool.wake, &pool.lock);
        seen = pool.generation;
        if (index >= pool.wanted) continue;
        pool_run *run = pool.run;
        pthread_mutex_unlock(&pool.lock);
        work(run, index);
        pthread_mutex_lock(&pool.lock);
        if (--pool.working == 0) pthread_cond_signal(&pool.finished);
    }
    return NULL;
}

/* Takes the persistent workers for a run of `threads` and starts the
 * missing ones; returns how many threads the run has (1 + workers), or 0
 * when another run holds them. */
static uint32_t pool_acquire(uint32_t threads)
{
    pthread_mutex_lock(&pool.lock);
    if (pool.owned) {
        pthread_mutex_unlock(&pool.lock);
        return 0;
    }
    pool.owned = true;
    while (pool.started + 1 < threads) {
        pthread_t id;
        if (pthread_create(&id, NULL, pool_worker_main, (void *)(uintptr_t)(pool.started + 1)) != 0) break;
        pthread_detach(id);
        pool.started++;
    }
    pthread_mutex_unlock(&pool.lock);
    return pool.started + 1 < threads ? pool.started + 1 : threads;
}

static void pool_run_owned(pool_run *run, uint32_t threads)
{
    pthread_mutex_lock(&pool.lock);
    pool.run = run;
    pool.wanted = threads;
    pool.working = threads - 1;
    pool.generation++;
    pthread_cond_broadcast(&pool.wake);
    pthread_mutex_unlock(&pool.lock);
    work(run, 0);
    pthread_mutex_lock(&pool.lock);
    if (pool.working > 0) {
        pthread_mutex_unlock(&pool.lock);
        spin_while_nonzero(&pool.working);
        pthread_mutex_lock(&pool.lock);
    }
    while (pool.working > 0) pthread_cond_wait(&pool.finished, &pool.lock);
    pool.run = NULL;
    pool.owned = false;
    pthread_mutex_unlock(&pool.lock);
}

/* ---- threads of one run, when the persistent workers are taken ---- */

typedef struct run_worker {
    pool_run *run;
    uint32_t index;
} run_worker;

static void *run_worker_main(void *arg)
{
    run_worker *worker = arg;
    work(worker->run, worker->index);
    return NULL;
}

static void run_with_own_threads(pool_run *run, uint32_t threads)
{
    pthread_t *ids = malloc(threads * sizeof *ids);
    run_worker *workers = malloc(threads * sizeof *workers);
    uint32_t started = 1;
    if (ids && workers) {
        for (; started < threads; started++) {
            workers[started] = (run_worker){run, started};
            if (pthread_create(&ids[started], NULL, run_worker_main, &workers[started]) != 0) break;
        }
    }
    work(run, 0); /* the tasks of workers that could not start run here */
    for (uint32_t i = 1; i < started; i++) pthread_join(ids[i], NULL);
    free(ids);
    free(workers);
}

void rtt_parallel_run(uint32_t tasks, uint32_t threads, rtt_task_fn fn, void *context)
{
    if (tasks == 0 || !fn) return;
    threads = rtt_thread_count(threads);
    if (threads > tasks) threads = tasks;
    pool_run run = {.tasks = tasks, .fn = fn, .context = context, .threads = threads};
    atomic_init(&run.next, 0);
    if (threads <= 1) {
        work(&run, 0);
        return;
    }
    uint32_t pooled = pool_acquire(threads);
    if (pooled > 1) {
        pool_run_owned(&run, pooled); /* fewer than asked only when threads could not start */
        return;
    }
    if (pooled == 1) { /* holds the pool but no worker could start */
        pthread_mutex_lock(&pool.lock);
        pool.owned = false;
        pthread_mutex_unlock(&pool.lock);
        work(&run, 0);
        return;
    }
    run_with_own_threads(&run, threads);
}

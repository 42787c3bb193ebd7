/* The thread pool (threads.h): tasks handed out by an atomic counter, the
 * calling thread working as worker 0.  Threads are created per run: a run
 * is a frame or a build, long next to pthread_create's ~20 us. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "engine/threads.h"

typedef struct pool_run {
    uint32_t tasks;
    rtt_task_fn fn;
    void *context;
    atomic_uint next;   /* next task to hand out */
} pool_run;

typedef struct pool_worker {
    pool_run *run;
    uint32_t index;
} pool_worker;

static void work(pool_run *run, uint32_t thread)
{
    for (;;) {
        uint32_t task = atomic_fetch_add_explicit(&run->next, 1, memory_order_relaxed);
        if (task >= run->tasks) return;
        run->fn(run->context, thread, task);
    }
}

static void *worker_main(void *arg)
{
    pool_worker *worker = arg;
    work(worker->run, worker->index);
    return NULL;
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

void rtt_parallel_run(uint32_t tasks, uint32_t threads, rtt_task_fn fn, void *context)
{
    if (tasks == 0 || !fn) return;
    threads = rtt_thread_count(threads);
    if (threads > tasks) threads = tasks;
    pool_run run = {.tasks = tasks, .fn = fn, .context = context};
    atomic_init(&run.next, 0);
    if (threads <= 1) {
        work(&run, 0);
        return;
    }
    pthread_t *ids = malloc(threads * sizeof *ids);
    pool_worker *workers = malloc(threads * sizeof *workers);
    uint32_t started = 1;
    if (ids && workers) {
        for (; started < threads; started++) {
            workers[started] = (pool_worker){&run, started};
            if (pthread_create(&ids[started], NULL, worker_main, &workers[started]) != 0) break;
        }
    }
    work(&run, 0); /* the tasks of workers that could not start run here */
    for (uint32_t i = 1; i < started; i++) pthread_join(ids[i], NULL);
    free(ids);
    free(workers);
}

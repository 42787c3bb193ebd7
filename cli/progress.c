/* Stage progress on stderr (progress.h): one watcher thread per stage. */
#include <pthread.h>
#include <sys/prctl.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "progress.h"

#define QUIET_SECONDS 2.0
#define TICK_SECONDS 0.25

struct cli_progress {
    char stage[160], detail[96];
    double start;
    double quiet;                /* seconds before the first line */
    _Atomic uint64_t done_total; /* done << 32 | total */
    bool terminal, printed, stop;
    double last_print;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake;
};

double cli_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One progress line (without its end), with the lock held. */
static void print_line(cli_progress *p, double now)
{
    uint64_t packed = atomic_load(&p->done_total);
    uint32_t done = (uint32_t)(packed >> 32), total = (uint32_t)packed;
    double elapsed = now - p->start;
    char what[400];
    if (total > 0 && done > 0) {
        double share = (double)done / total;
        snprintf(what, sizeof what, "%s: %.0f%% after %.1f s, about %.1f s left", p->stage, 100.0 * share, elapsed,
                 elapsed * (1.0 - share) / share);
    } else {
        snprintf(what, sizeof what, "%s: %.1f s so far", p->stage, elapsed);
    }
    if (p->detail[0]) snprintf(what + strlen(what), sizeof what - strlen(what), " (%s)", p->detail);
    if (p->terminal)
        fprintf(stderr, "\rrtt: %s\033[K", what);
    else
        fprintf(stderr, "rtt: %s\n", what);
    fflush(stderr);
    p->printed = true;
    p->last_print = now;
}

/* The watcher names itself (prctl PR_SET_NAME): it computes nothing and
 * sleeps between lines, and the thread-count checks under --threads 1
 * (tests/hostile_input.sh) tell it from a worker by its name. */
#define WATCHER_NAME "rtt-progress"

static void *watch(void *opaque)
{
    cli_progress *p = opaque;
    prctl(PR_SET_NAME, WATCHER_NAME, 0, 0, 0);
    pthread_mutex_lock(&p->lock);
    while (!p->stop) {
        double now = cli_seconds(), elapsed = now - p->start;
        double interval = p->terminal ? TICK_SECONDS : (elapsed / 10 > QUIET_SECONDS ? elapsed / 10 : QUIET_SECONDS);
        if (elapsed >= p->quiet && (!p->printed || now - p->last_print >= interval)) print_line(p, now);
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += (long)(TICK_SECONDS * 1e9);
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&p->wake, &p->lock, &until);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

cli_progress *cli_progress_start(const char *stage)
{
    cli_progress *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    snprintf(p->stage, sizeof p->stage, "%s", stage);
    /* RTT_PROGRESS_AFTER=SECONDS moves the 2 s threshold (the tests use it
     * to see progress on renders a fast machine finishes within 2 s) */
    const char *after = getenv("RTT_PROGRESS_AFTER");
    char *end = NULL;
    double quiet = after ? strtod(after, &end) : QUIET_SECONDS;
    p->quiet = after && end != after && *end == '\0' && quiet >= 0.0 && quiet < 1e6 ? quiet : QUIET_SECONDS;
    p->start = cli_seconds();
    p->terminal = isatty(STDERR_FILENO);
    atomic_init(&p->done_total, 0);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    if (pthread_create(&p->thread, NULL, watch, p) != 0) {
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->wake);
        free(p);
        return NULL;
    }
    return p;
}

void cli_progress_update(void *progress, uint32_t done, uint32_t total)
{
    cli_progress *p = progress;
    if (p) atomic_store(&p->done_total, (uint64_t)done << 32 | total);
}

void cli_progress_detail(cli_progress *p, const char *detail)
{
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    snprintf(p->detail, sizeof p->detail, "%s", detail);
    pthread_mutex_unlock(&p->lock);
}

double cli_progress_finish(cli_progress *p)
{
    if (!p) return 0.0;
    pthread_mutex_lock(&p->lock);
    p->stop = true;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(p->thread, NULL);
    double seconds = cli_seconds() - p->start;
    if (p->printed) fprintf(stderr, "%srtt: %s: done in %.1f s%s\n", p->terminal ? "\r" : "", p->stage, seconds,
                            p->terminal ? "\033[K" : "");
    pthread_mutex_destroy(&p->lock);
    pthread_cond_destroy(&p->wake);
    free(p);
    return seconds;
}

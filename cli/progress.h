/* Progress of a stage that may take a while (loading, building, rendering,
 * benchmarking, checking conformance), on stderr.  Nothing is printed for a
 * stage that ends within 2 s.  After that a watcher thread prints the stage,
 * the elapsed time and, when the stage reports how far it is, the share done
 * and an estimate of the time left (elapsed * (1 - share) / share):
 *
 *   rtt: rendering: 45% after 2.1 s, about 2.6 s left
 *   rtt: loading maps/oa_dm4.bsp: 2.0 s so far
 *
 * On a terminal one line is rewritten in place; otherwise (a log, a pipe)
 * a line is added every 2 s, or every tenth of the elapsed time when that is
 * longer, so a long run stays short.  A stage that printed ends with
 * "rtt: rendering: done in 4.7 s". */
#ifndef RTT_CLI_PROGRESS_H
#define RTT_CLI_PROGRESS_H

#include <stdint.h>

typedef struct cli_progress cli_progress;

/* Starts timing `stage` (copied).  NULL when no thread can be started: the
 * other calls accept NULL and do nothing, the work goes on without progress. */
cli_progress *cli_progress_start(const char *stage);
/* How far the stage is; callable from any thread (matches the renderers'
 * progress callback: context, done, total). */
void cli_progress_update(void *progress, uint32_t done, uint32_t total);
/* What the stage is doing now, shown after the time (copied; any thread). */
void cli_progress_detail(cli_progress *progress, const char *detail);
/* Stops the watcher and frees; returns the stage's seconds. */
double cli_progress_finish(cli_progress *progress);

/* Seconds on a monotonic clock. */
double cli_seconds(void);

#endif

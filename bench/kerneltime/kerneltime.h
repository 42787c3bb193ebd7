/* What the kernel timers share (kerneltime.c): the instruction set from
 * RTT_ISA, the scene with rtt bench's camera for it, and the thread's CPU
 * clock.  Each prints one line on stderr, prefixed with the tool's name,
 * when it fails. */
#ifndef RTT_BENCH_KERNELTIME_H
#define RTT_BENCH_KERNELTIME_H

#include <stdbool.h>

#include "rtt/engine.h"

/* RTT_ISA (sse4, avx2, avx512; unset or empty: avx512), resolved to what
 * this CPU runs.  False when it names no instruction set. */
bool kerneltime_isa(const char *tool, rtt_isa *isa);
/* The scene at `path` with the view named after its file (its base name
 * without the extension, into name[256]) of the views file applied when
 * there is one, as rtt bench --views does.  NULL on failure. */
rtt_scene *kerneltime_scene(const char *tool, const char *path, const char *views_path, char name[256]);
/* CLOCK_THREAD_CPUTIME_ID in seconds: steadier than the wall clock on a
 * loaded machine. */
double kerneltime_thread_seconds(void);

#endif

/* Atomic file output (scene/atomic_file.c), for every file rtt writes:
 * images, the baked .kdt, tris.bin, hits.bin and the bench's reports.
 *
 * A writer opens "<path>.tmp.<pid>" beside the target, writes everything,
 * then commits: close, rename over the target.  On any failure it aborts:
 * the temporary is removed and an existing target is left untouched.
 *
 * Every live temporary is registered, so that
 *   - several outputs of one command are all or nothing: between
 *     rtt_atomic_files_hold() and rtt_atomic_files_release(), a commit only
 *     closes its temporary, and the release renames them all when every one
 *     is complete (keep) or removes them all (not keep);
 *   - a signal handler can remove them: rtt_atomic_files_remove_all() only
 *     calls unlink(), so it is async-signal-safe. */
#ifndef RTT_ATOMIC_FILE_H
#define RTT_ATOMIC_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "rtt/error.h"

typedef struct rtt_atomic_file {
    const char *path;   /* the final name */
    char *tmp_path;     /* the temporary beside it (owned, registered) */
    FILE *stream;       /* open for writing, binary */
} rtt_atomic_file;

bool rtt_atomic_file_open(rtt_atomic_file *file, const char *path, rtt_error *err);
/* Flushes, closes and renames (or, while held, leaves the rename to the
 * release); on failure removes the temporary. */
bool rtt_atomic_file_commit(rtt_atomic_file *file, rtt_error *err);
/* Closes and removes the temporary; safe after a failed open or a commit. */
void rtt_atomic_file_abort(rtt_atomic_file *file);

/* `size` bytes to `path` through a temporary and a rename. */
bool rtt_atomic_file_write(const char *path, const void *data, size_t size, rtt_error *err);

void rtt_atomic_files_hold(void);
/* keep: renames every held temporary over its target, in the order they
 * were committed; a failed rename removes the ones not yet renamed.  Not
 * keep: removes them all.  Either way the hold ends. */
bool rtt_atomic_files_release(bool keep, rtt_error *err);
/* Removes every registered temporary (for signal handlers). */
void rtt_atomic_files_remove_all(void);

#endif

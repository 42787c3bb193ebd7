/* Atomic file replacement for the image writers (image/ only, not public).
 *
 * A writer opens "<path>.tmp.<pid>" beside the target, writes everything,
 * then commits: close, rename over the target.  On any failure it aborts:
 * the temporary is removed and an existing target is left untouched. */
#ifndef RTT_IMAGE_ATOMIC_FILE_H
#define RTT_IMAGE_ATOMIC_FILE_H

#include <stdbool.h>
#include <stdio.h>

#include "rtt/error.h"

typedef struct rtt_atomic_file {
    const char *path;   /* the final name */
    char *tmp_path;     /* the temporary beside it (owned) */
    FILE *stream;       /* open for writing, binary */
} rtt_atomic_file;

bool rtt_atomic_file_open(rtt_atomic_file *file, const char *path, rtt_error *err);
/* Flushes, closes and renames; on failure removes the temporary. */
bool rtt_atomic_file_commit(rtt_atomic_file *file, rtt_error *err);
/* Closes and removes the temporary; safe after a failed open. */
void rtt_atomic_file_abort(rtt_atomic_file *file);

#endif

/* Input files (scene/file_read.c): rtt reads regular files only.
 *
 * A FIFO, a device or a socket as an input would block forever or read
 * without end, so every reader opens its inputs through these and refuses
 * anything else with one line, "PATH: not a regular file (a FIFO)". */
#ifndef RTT_FILES_H
#define RTT_FILES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "rtt/error.h"

/* Opens `path` for reading without blocking on a FIFO, and keeps it only
 * when it is a regular file.  NULL after filling err:
 * "PATH: cannot open: reason", "PATH: is a directory",
 * "PATH: not a regular file (a FIFO)" (a character device, a block device,
 * a socket). */
FILE *rtt_file_open_regular(const char *path, rtt_error *err);
/* The same test without keeping the file open. */
bool rtt_file_check_regular(const char *path, rtt_error *err);

/* The whole of `path`, followed by a NUL byte that is not counted in
 * *length (so text can be parsed in place; the bytes themselves may hold
 * NULs).  A file longer than max_bytes is refused ("PATH: larger than
 * 1 GiB").  The buffer comes from malloc, so it is aligned for any record
 * type; the caller frees it.  NULL after filling err. */
char *rtt_file_read(const char *path, size_t max_bytes, size_t *length, rtt_error *err);

#endif

/* Shared pieces of the `rtt` driver: exit codes, messages, argument helpers.
 * Only cli/ prints and exits; the libraries return rtt_error. */
#ifndef RTT_CLI_H
#define RTT_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/render.h"
#include "rtt/scene.h"

enum { RTT_EXIT_OK = 0, RTT_EXIT_BAD_INPUT = 1, RTT_EXIT_USAGE = 2 };

/* Prints "rtt: <message>" on stderr and returns RTT_EXIT_BAD_INPUT. */
int cli_fail(const rtt_error *err);
bool cli_is_help(const char *arg);

/* Strict number parsing for option values; false on junk or out of range. */
bool cli_parse_u32(const char *text, uint32_t lo, uint32_t hi, uint32_t *out);
bool cli_parse_float(const char *text, float *out);

/* Writes `size` bytes to path through a temporary in the same directory and
 * a rename, so an existing file is never left half-written. */
bool cli_write_file_atomic(const char *path, const void *data, size_t size, rtt_error *err);
/* Every output path checked before any work (output_check.c): its
 * directory exists and is writable, it is not a directory, a FIFO or a
 * device, not given twice, and not the same file as any of `inputs` (NULL
 * entries are skipped).  One line naming the path on failure. */
bool cli_check_outputs(const char *const *outputs, size_t output_count, const char *const *inputs,
                       size_t input_count, rtt_error *err);
/* `dir` exists, is a directory and is writable; messages name `what`. */
bool cli_check_directory(const char *dir, const char *what, rtt_error *err);
/* SIGINT, SIGTERM and SIGHUP remove every temporary output and exit 128 +
 * the signal (130, 143, 129). */
void cli_handle_signals(void);

/* Reads a whole file; *size receives its length.  NULL + err on failure. */
void *cli_read_file(const char *path, size_t *size, rtt_error *err);

/* Loads SCENE (any supported kind) with the standard load options; a
 * max_memory of 0 takes the machine's budget (rtt/memory_budget.h). */
rtt_scene *cli_load_scene(const char *path, uint32_t bezier_level, uint64_t max_memory, rtt_error *err);

/* The subcommands (options.h: cli_command), each in its cmd_*.c. */
struct cli_command;
extern const struct cli_command render_command, bake_command, info_command, triangles_command, trace_command,
    conform_command, compare_command, bench_command, view_command;

#endif

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
/* Reads a whole file; *size receives its length.  NULL + err on failure. */
void *cli_read_file(const char *path, size_t *size, rtt_error *err);

/* Loads SCENE (any supported kind) with the standard load options. */
rtt_scene *cli_load_scene(const char *path, uint32_t bezier_level, rtt_error *err);

/* The subcommands (options.h: cli_command), each in its cmd_*.c. */
struct cli_command;
extern const struct cli_command render_command, bake_command, info_command, triangles_command, trace_command,
    conform_command, compare_command, bench_command, view_command;

#endif

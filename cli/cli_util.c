/* Helpers shared by the subcommands: messages, exit codes, strict option
 * parsing and atomic file output. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "rtt/atomic_file.h"
#include "rtt/files.h"

int cli_fail(const rtt_error *err)
{
    fprintf(stderr, "rtt: %s\n", err->message[0] ? err->message : "unknown error");
    return RTT_EXIT_BAD_INPUT;
}

bool cli_is_help(const char *arg)
{
    return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0;
}

bool cli_parse_u32(const char *text, uint32_t lo, uint32_t hi, uint32_t *out)
{
    if (!text || *text < '0' || *text > '9') return false;
    errno = 0;
    char *end = NULL;
    unsigned long long value = strtoull(text, &end, 10);
    if (errno || *end != '\0' || value < lo || value > hi) return false;
    *out = (uint32_t)value;
    return true;
}

bool cli_parse_float(const char *text, float *out)
{
    if (!text || !*text) return false;
    char *end = NULL;
    float value = strtof(text, &end);
    if (*end != '\0' || !isfinite(value)) return false;
    *out = value;
    return true;
}

bool cli_write_file_atomic(const char *path, const void *data, size_t size, rtt_error *err)
{
    return rtt_atomic_file_write(path, data, size, err);
}

void *cli_read_file(const char *path, size_t *size, rtt_error *err)
{
    return rtt_file_read(path, SIZE_MAX, size, err); /* regular files only */
}

rtt_scene *cli_load_scene(const char *path, uint32_t bezier_level, uint64_t max_memory, rtt_error *err)
{
    rtt_scene_load_options opt = {.bezier_level = bezier_level, .max_memory = max_memory};
    return rtt_scene_load(path, &opt, err);
}

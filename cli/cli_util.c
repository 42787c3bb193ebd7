/* Helpers shared by the subcommands: messages, exit codes, strict option
 * parsing and atomic file output. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

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
    char temp[4096];
    if (snprintf(temp, sizeof temp, "%s.tmp.%ld", path, (long)getpid()) >= (int)sizeof temp)
        return rtt_error_set(err, "%s: path too long", path);
    FILE *file = fopen(temp, "wb");
    if (!file) return rtt_error_set(err, "%s: cannot write: %s", path, strerror(errno));
    bool ok = fwrite(data, 1, size, file) == size;
    ok = (fclose(file) == 0) && ok;
    if (!ok) {
        remove(temp);
        return rtt_error_set(err, "%s: write failed: %s", path, strerror(errno));
    }
    if (rename(temp, path) != 0) {
        int saved = errno;
        remove(temp);
        return rtt_error_set(err, "%s: cannot replace: %s", path, strerror(saved));
    }
    return true;
}

void *cli_read_file(const char *path, size_t *size, rtt_error *err)
{
    FILE *file = fopen(path, "rb");
    if (!file) {
        rtt_error_set(err, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    char *data = NULL;
    size_t length = 0, capacity = 0;
    for (;;) {
        if (length == capacity) {
            capacity = capacity ? capacity * 2 : 1 << 16;
            char *grown = realloc(data, capacity);
            if (!grown) {
                free(data);
                fclose(file);
                rtt_error_set(err, "%s: out of memory", path);
                return NULL;
            }
            data = grown;
        }
        size_t got = fread(data + length, 1, capacity - length, file);
        length += got;
        if (got == 0) break;
    }
    bool failed = ferror(file);
    fclose(file);
    if (failed) {
        free(data);
        rtt_error_set(err, "%s: read failed", path);
        return NULL;
    }
    *size = length;
    return data;
}

rtt_scene *cli_load_scene(const char *path, uint32_t bezier_level, rtt_error *err)
{
    rtt_scene_load_options opt = {.bezier_level = bezier_level};
    rtt_scene *scene = rtt_scene_load(path, &opt, err);
    if (scene && scene->collapsed_count)
        fprintf(stderr, "rtt: warning: %s: %u of %u triangles collapse to zero area when stored in float (they never hit)\n",
                path, scene->collapsed_count, scene->triangle_count);
    return scene;
}

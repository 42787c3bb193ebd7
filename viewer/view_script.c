/* The viewer's script reader (view_script.h). */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_read.h"
#include "view_script.h"

#define SCRIPT_MAX_BYTES (1u << 20)
#define SCRIPT_MAX_FRAMES 100000
#define SCRIPT_MAX_SIDE 16384

/* The line's words, split at blanks, at most `max`; false when there are more. */
static bool split_words(char *line, char **words, uint32_t max, uint32_t *count)
{
    *count = 0;
    for (char *p = strtok(line, " \t\r"); p; p = strtok(NULL, " \t\r")) {
        if (*count == max) return false;
        words[(*count)++] = p;
    }
    return true;
}

static bool parse_int(const char *text, long lo, long hi, int32_t *out)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end != '\0' || v < lo || v > hi) return false;
    *out = (int32_t)v;
    return true;
}

typedef struct command_syntax {
    const char *name;
    view_command_kind kind;
    uint32_t min_args, max_args;
    const char *usage;
} command_syntax;

static const command_syntax syntax[] = {
    {"frames", VIEW_CMD_FRAMES, 1, 1, "frames N"},
    {"key", VIEW_CMD_KEY, 1, 2, "key NAME [FRAMES]"},
    {"drag", VIEW_CMD_DRAG, 2, 2, "drag DX DY"},
    {"resize", VIEW_CMD_RESIZE, 2, 2, "resize W H"},
    {"set", VIEW_CMD_SET, 2, 2, "set traversal|shadows|isa VALUE"},
    {"converge", VIEW_CMD_CONVERGE, 0, 0, "converge"},
    {"bench", VIEW_CMD_BENCH, 1, 1, "bench N"},
    {"print-overlay", VIEW_CMD_PRINT_OVERLAY, 0, 0, "print-overlay"},
    {"print-camera", VIEW_CMD_PRINT_CAMERA, 0, 0, "print-camera"},
    {"print-choices", VIEW_CMD_PRINT_CHOICES, 0, 0, "print-choices"},
    {"screenshot", VIEW_CMD_SCREENSHOT, 1, 1, "screenshot FILE"},
};

static bool parse_command(const char *path, uint32_t line_no, char **w, uint32_t n, view_command *c, rtt_error *err)
{
    const command_syntax *s = NULL;
    for (size_t i = 0; i < sizeof syntax / sizeof syntax[0]; i++)
        if (strcmp(w[0], syntax[i].name) == 0) s = &syntax[i];
    if (!s)
        return rtt_error_set(err, "%s:%u: unknown command \"%s\" (frames, key, drag, resize, set, converge, bench, "
                                  "print-overlay, print-camera, print-choices, screenshot)", path, line_no, w[0]);
    if (n - 1 < s->min_args || n - 1 > s->max_args)
        return rtt_error_set(err, "%s:%u: expected \"%s\"", path, line_no, s->usage);
    *c = (view_command){.kind = s->kind, .line = line_no};
    switch (s->kind) {
    case VIEW_CMD_FRAMES:
    case VIEW_CMD_BENCH:
        if (!parse_int(w[1], 1, SCRIPT_MAX_FRAMES, &c->a))
            return rtt_error_set(err, "%s:%u: %s: the frame count must be a whole number from 1 to %d", path,
                                 line_no, w[0], SCRIPT_MAX_FRAMES);
        break;
    case VIEW_CMD_KEY:
        if (strlen(w[1]) >= sizeof c->text) return rtt_error_set(err, "%s:%u: key name too long", path, line_no);
        strcpy(c->text, w[1]);
        if (n == 3 && !parse_int(w[2], 1, SCRIPT_MAX_FRAMES, &c->b))
            return rtt_error_set(err, "%s:%u: key %s: the hold must be a whole number of frames from 1 to %d",
                                 path, line_no, w[1], SCRIPT_MAX_FRAMES);
        break;
    case VIEW_CMD_DRAG:
        if (!parse_int(w[1], -100000, 100000, &c->a) || !parse_int(w[2], -100000, 100000, &c->b))
            return rtt_error_set(err, "%s:%u: drag: DX and DY must be whole numbers of pixels", path, line_no);
        break;
    case VIEW_CMD_RESIZE:
        if (!parse_int(w[1], 1, SCRIPT_MAX_SIDE, &c->a) || !parse_int(w[2], 1, SCRIPT_MAX_SIDE, &c->b))
            return rtt_error_set(err, "%s:%u: resize: W and H must be whole numbers from 1 to %d", path, line_no,
                                 SCRIPT_MAX_SIDE);
        break;
    case VIEW_CMD_SET: {
        static const char *const whats[] = {"traversal", "shadows", "isa"};
        c->what = -1;
        for (int32_t i = 0; i < 3; i++)
            if (strcmp(w[1], whats[i]) == 0) c->what = i;
        if (c->what < 0)
            return rtt_error_set(err, "%s:%u: set %s: expected traversal, shadows or isa", path, line_no, w[1]);
        if (strlen(w[2]) >= sizeof c->text) return rtt_error_set(err, "%s:%u: set: value too long", path, line_no);
        strcpy(c->text, w[2]);
        break;
    }
    case VIEW_CMD_SCREENSHOT: {
        const char *dot = strrchr(w[1], '.');
        if (!dot || (strcmp(dot, ".png") != 0 && strcmp(dot, ".exr") != 0))
            return rtt_error_set(err, "%s:%u: screenshot %s: the file must end in .png or .exr", path, line_no, w[1]);
        if (strlen(w[1]) >= sizeof c->text) return rtt_error_set(err, "%s:%u: screenshot path too long", path, line_no);
        strcpy(c->text, w[1]);
        break;
    }
    default:
        break;
    }
    return true;
}

bool view_script_parse(const char *path, const char *text, view_script *out, rtt_error *err)
{
    *out = (view_script){0};
    uint32_t capacity = 0;
    uint32_t line_no = 0;
    for (const char *p = text; *p;) {
        const char *end = strchr(p, '\n');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        line_no++;
        char line[1024];
        if (len >= sizeof line) {
            view_script_free(out);
            return rtt_error_set(err, "%s:%u: line longer than %zu characters", path, line_no, sizeof line - 1);
        }
        memcpy(line, p, len);
        line[len] = '\0';
        p = end ? end + 1 : p + len;
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        char *words[4];
        uint32_t n;
        if (!split_words(line, words, 4, &n)) {
            view_script_free(out);
            return rtt_error_set(err, "%s:%u: too many words", path, line_no);
        }
        if (n == 0) continue;
        if (out->count == capacity) {
            uint32_t grown = capacity ? 2 * capacity : 16;
            view_command *commands = realloc(out->commands, grown * sizeof *commands);
            if (!commands) {
                view_script_free(out);
                return rtt_error_set(err, "%s: out of memory", path);
            }
            out->commands = commands;
            capacity = grown;
        }
        if (!parse_command(path, line_no, words, n, &out->commands[out->count], err)) {
            view_script_free(out);
            return false;
        }
        out->count++;
    }
    return true;
}

bool view_script_load(const char *path, view_script *out, rtt_error *err)
{
    *out = (view_script){0};
    size_t size = 0;
    char *text = rtt_file_read(path, SCRIPT_MAX_BYTES, &size, err);
    if (!text) return false;
    bool ok = strlen(text) == size ? view_script_parse(path, text, out, err)
                                   : rtt_error_set(err, "%s: contains a NUL byte: not a view script", path);
    free(text);
    return ok;
}

void view_script_free(view_script *script)
{
    free(script->commands);
    *script = (view_script){0};
}

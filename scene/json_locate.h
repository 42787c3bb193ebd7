/* Where a value of a JSON file is, for one-line errors "file:line: what".
 *
 * cJSON keeps no source positions.  A reader names the value it complains
 * about by a rtt_json_place chain (object member or array element, by index
 * among its siblings, up to the root), and the line is found by re-scanning
 * the text, already validated by cJSON, along that chain: positions cost
 * nothing unless a file is wrong, and duplicate or escaped keys are still
 * located exactly (a search by key name would find the wrong one). */
#ifndef RTT_SCENE_JSON_LOCATE_H
#define RTT_SCENE_JSON_LOCATE_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>

#include "rtt/error.h"

/* The member or element `index` of `parent` (key: the member's name, NULL for
 * an array element; index -1 for a member that is absent, which is located
 * at its parent); the root has no parent. */
typedef struct rtt_json_place {
    const struct rtt_json_place *parent;
    const char *key;
    int index;
} rtt_json_place;

/* Element `index` of the array at `parent`. */
static inline rtt_json_place rtt_json_element(const rtt_json_place *parent, int index)
{
    return (rtt_json_place){parent, NULL, index};
}

/* A JSON file's name and its whole text (as cJSON parsed it). */
typedef struct rtt_json_source {
    const char *path;
    const char *text;
    size_t length;
} rtt_json_source;

/* Fills err with "path:line: where<what>" and returns false: the line of
 * `line_at`, `where` the JSON path of `path_of` ("meshes[2].material").
 * The formatted `what` starts with its separator (" must be ...",
 * ": no ..."), which is dropped at the root, whose path is empty. */
bool rtt_json_error_v(const rtt_json_source *src, rtt_error *err, const rtt_json_place *line_at,
                      const rtt_json_place *path_of, const char *fmt, va_list args);

/* 1 + the newlines in [text, at). */
int rtt_json_line_at(const char *text, const char *at);

/* True when the text holds nothing but JSON white space. */
bool rtt_json_is_blank(const char *text, size_t length);

/* A cJSON parse failure as one line: at the position where cJSON stopped
 * (`at`, NULL when unknown), showing up to 24 bytes found there, or at the
 * last line that holds anything when the text ended early.  Returns false. */
bool rtt_json_syntax_error(const rtt_json_source *src, const char *at, rtt_error *err);

#endif

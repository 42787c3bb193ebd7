/* Locating values in JSON text for error messages (see json_locate.h).
 *
 * The scan relies on the text being valid JSON (cJSON accepted it), so it
 * only has to skip strings, with their escapes, and balanced brackets; it
 * never reads past the end even so.  Syntax errors are located by the
 * position cJSON reports instead. */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "json_locate.h"

static const char *skip_space(const char *s, const char *end)
{
    while (s < end && (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r')) s++;
    return s;
}

static const char *skip_string(const char *s, const char *end)
{
    for (s++; s < end && *s != '"'; s++)
        if (*s == '\\') s++;
    return s < end ? s + 1 : end;
}

static const char *skip_value(const char *s, const char *end)
{
    if (s < end && *s == '"') return skip_string(s, end);
    if (s < end && (*s == '{' || *s == '[')) {
        int depth = 0;
        while (s < end) {
            if (*s == '"') {
                s = skip_string(s, end);
                continue;
            }
            if (*s == '{' || *s == '[') depth++;
            if ((*s == '}' || *s == ']') && --depth == 0) return s + 1;
            s++;
        }
        return end;
    }
    while (s < end && *s && !strchr(",]} \t\r\n", *s)) s++;
    return s;
}

/* s points at '{' or '['; returns the start of child n (the key of an
 * object member), or NULL when there are fewer children. */
static const char *nth_child(const char *s, const char *end, int n, const char **value)
{
    bool object = *s == '{';
    s = skip_space(s + 1, end);
    for (int i = 0; s < end && *s != '}' && *s != ']'; i++) {
        const char *start = s;
        if (object) {
            s = skip_space(skip_string(s, end), end);
            s = skip_space(s + 1, end); /* past ':' */
        }
        if (i == n) {
            *value = s;
            return start;
        }
        s = skip_space(skip_value(s, end), end);
        if (s < end && *s == ',') s = skip_space(s + 1, end);
    }
    return NULL;
}

int rtt_json_line_at(const char *text, const char *at)
{
    int line = 1;
    for (const char *c = text; c < at; c++) line += *c == '\n';
    return line;
}

bool rtt_json_is_blank(const char *text, size_t length) { return skip_space(text, text + length) >= text + length; }

/* The line of a place: descend from the root along the chain; where the
 * chain cannot be followed (an absent member), the deepest place found. */
static int place_line(const rtt_json_source *src, const rtt_json_place *place)
{
    int chain[64], depth = 0;
    for (const rtt_json_place *w = place; w && w->parent && depth < 64; w = w->parent) chain[depth++] = w->index;
    const char *end = src->text + src->length;
    const char *at = skip_space(src->text, end), *value = at;
    for (int k = depth - 1; k >= 0; k--) {
        if (value >= end || (*value != '{' && *value != '[')) break;
        const char *child = nth_child(value, end, chain[k], &value);
        if (!child) break;
        at = child;
    }
    return rtt_json_line_at(src->text, at);
}

/* "materials[1].ior"; "" for the root. */
static void place_path(const rtt_json_place *place, char *out, size_t size)
{
    if (!place || !place->parent) {
        out[0] = '\0';
        return;
    }
    place_path(place->parent, out, size);
    size_t used = strlen(out);
    if (place->key)
        snprintf(out + used, size - used, "%s%s", used ? "." : "", place->key);
    else
        snprintf(out + used, size - used, "[%d]", place->index);
}

bool rtt_json_error_v(const rtt_json_source *src, rtt_error *err, const rtt_json_place *line_at,
                      const rtt_json_place *path_of, const char *fmt, va_list args)
{
    char path[256], what[384];
    place_path(path_of, path, sizeof path);
    vsnprintf(what, sizeof what, fmt, args);
    const char *shown = what;
    if (!path[0]) shown += strspn(what, ": ");
    return rtt_error_set(err, "%s:%d: %s%s", src->path, place_line(src, line_at), path, shown);
}

bool rtt_json_syntax_error(const rtt_json_source *src, const char *at, rtt_error *err)
{
    const char *text = src->text, *end = text + src->length;
    if (!at || at < text || at > end) at = end;
    if (skip_space(at, end) >= end) { /* reported on the last line that holds anything */
        while (end > text && strchr(" \t\r\n", end[-1])) end--;
        return rtt_error_set(err, "%s:%d: JSON syntax error: unexpected end of file", src->path,
                             rtt_json_line_at(text, end));
    }
    int n = 0;
    while (at + n < end && n < 24 && at[n] != '\n' && at[n] != '\r') n++;
    char near[32];
    for (int i = 0; i < n; i++) near[i] = isprint((unsigned char)at[i]) ? at[i] : '?';
    near[n] = '\0';
    if (n == 0)
        return rtt_error_set(err, "%s:%d: JSON syntax error at the end of the line", src->path,
                             rtt_json_line_at(text, at));
    return rtt_error_set(err, "%s:%d: JSON syntax error near \"%s\"", src->path, rtt_json_line_at(text, at), near);
}

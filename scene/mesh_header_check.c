/* The format header scanners of mesh_header_check.h.
 *
 * OFF (text): "[C][N][ST]OFF" then the counts "V F [E]" (on the same line or
 * the next), then V vertex lines of at least three numbers and F face lines
 * "n i0 .. i(n-1)" (extra columns, colours, are allowed), '#' comments and
 * blank lines anywhere.  Binary OFF is left to Assimp.
 * PLY: the header's elements and properties, then the body walked element
 * by element, property by property — tokens for ascii, fixed sizes and list
 * counts for binary_little_endian and binary_big_endian — so a truncated
 * body is found at the element where it ends, and every face's
 * vertex_indices are checked against the vertex count.
 * STL: binary when 84 + 50 * count is the file's size; else text starting
 * "solid", whose facets must each have three vertices and whose last word
 * must be "endsolid"; a binary header whose count disagrees with the size
 * is an error.
 * glTF (.gltf JSON, .glb container): the GLB header's length is the file's,
 * its chunks lie inside it; every buffer's byteLength fits its bytes (the
 * GLB BIN chunk, a base64 data: URI, or an external file next to the
 * .gltf); every bufferView lies inside its buffer, every accessor inside
 * its view.
 * Nothing here allocates in proportion to a count a header declares. */
#include "mesh_header_check.h"

#include <assimp/scene.h>
#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_kind.h"
#include "rtt/files.h"

typedef struct text_cursor {
    const unsigned char *at, *end;
} text_cursor;

static bool is_space(unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

/* ---- OFF ------------------------------------------------------------------ */

/* The next line that holds anything but a comment: [*line, *line_end). */
static bool next_line(text_cursor *c, const unsigned char **line, const unsigned char **line_end)
{
    while (c->at < c->end) {
        const unsigned char *start = c->at, *stop = memchr(start, '\n', (size_t)(c->end - start));
        if (!stop) stop = c->end;
        c->at = stop < c->end ? stop + 1 : c->end;
        const unsigned char *hash = memchr(start, '#', (size_t)(stop - start));
        if (hash) stop = hash;
        while (start < stop && is_space(*start)) start++;
        if (start < stop) {
            *line = start;
            *line_end = stop;
            return true;
        }
    }
    return false;
}

/* One whitespace-separated word of [*at, end). */
static bool next_word(const unsigned char **at, const unsigned char *end, const unsigned char **word, size_t *length)
{
    const unsigned char *p = *at;
    while (p < end && is_space(*p)) p++;
    if (p == end) return false;
    *word = p;
    while (p < end && !is_space(*p)) p++;
    *length = (size_t)(p - *word);
    *at = p;
    return true;
}

/* A whole number of at most 19 digits (no sign). */
static bool word_to_u64(const unsigned char *word, size_t length, uint64_t *out)
{
    if (length == 0 || length > 19) return false;
    uint64_t value = 0;
    for (size_t i = 0; i < length; i++) {
        if (word[i] < '0' || word[i] > '9') return false;
        value = value * 10 + (uint64_t)(word[i] - '0');
    }
    *out = value;
    return true;
}

static bool word_is_number(const unsigned char *word, size_t length)
{
    char text[64];
    if (length == 0 || length >= sizeof text) return false;
    memcpy(text, word, length);
    text[length] = '\0';
    char *stop = NULL;
    (void)strtod(text, &stop);
    return stop == text + length;
}

static bool scan_off(const char *path, const unsigned char *bytes, size_t size, rtt_mesh_header *out, rtt_error *err)
{
    text_cursor c = {bytes, bytes + size};
    const unsigned char *line, *end, *word;
    size_t length;
    if (!next_line(&c, &line, &end) || !next_word(&line, end, &word, &length) || length < 3 ||
        memcmp(word + length - 3, "OFF", 3) != 0)
        return rtt_error_set(err, "%s: not an OFF file (it does not start with \"OFF\")", path);
    uint64_t counts[3] = {0, 0, 0};
    unsigned got = 0;
    for (;;) { /* the counts, on the keyword's line or the lines after */
        while (got < 3 && next_word(&line, end, &word, &length)) {
            if (got == 0 && strncmp((const char *)word, "BINARY", length) == 0 && length == 6) {
                *out = (rtt_mesh_header){0}; /* binary OFF: Assimp's to read */
                return true;
            }
            if (!word_to_u64(word, length, &counts[got]))
                return rtt_error_set(err, "%s: header: \"%.*s\" is not a count (vertices faces edges)", path,
                                     (int)(length > 32 ? 32 : length), (const char *)word);
            got++;
        }
        if (got >= 2 && (got == 3 || line >= end)) break;
        if (!next_line(&c, &line, &end))
            return rtt_error_set(err, "%s: header: the file ends before the vertex and face counts", path);
    }
    const uint64_t vertices = counts[0], faces = counts[1];
    /* a vertex line is at least "0 0 0\n", a face line at least "0\n" */
    if (vertices > size / 6 || faces > size / 2 || vertices * 6 + faces * 2 > size + 1)
        return rtt_error_set(err, "%s: header: %llu vertices and %llu faces cannot fit in %zu bytes", path,
                             (unsigned long long)vertices, (unsigned long long)faces, size);
    *out = (rtt_mesh_header){.counted = true, .vertices = vertices, .faces = faces};
    for (uint64_t v = 0; v < vertices; v++) {
        if (!next_line(&c, &line, &end))
            return rtt_error_set(err, "%s: the file ends in vertex %llu of the %llu the header declares", path,
                                 (unsigned long long)v, (unsigned long long)vertices);
        for (int k = 0; k < 3; k++)
            if (!next_word(&line, end, &word, &length) || !word_is_number(word, length))
                return rtt_error_set(err, "%s: vertex %llu: coordinate %d is missing or not a number", path,
                                     (unsigned long long)v, k);
    }
    for (uint64_t f = 0; f < faces; f++) {
        uint64_t n, index;
        if (!next_line(&c, &line, &end))
            return rtt_error_set(err, "%s: the file ends in face %llu of the %llu the header declares", path,
                                 (unsigned long long)f, (unsigned long long)faces);
        if (!next_word(&line, end, &word, &length) || !word_to_u64(word, length, &n) || n > (uint64_t)(end - line))
            return rtt_error_set(err, "%s: face %llu: the corner count is not a count that fits its line", path,
                                 (unsigned long long)f);
        for (uint64_t k = 0; k < n; k++) {
            if (!next_word(&line, end, &word, &length))
                return rtt_error_set(err, "%s: face %llu: %llu of its %llu vertex indices are missing", path,
                                     (unsigned long long)f, (unsigned long long)(n - k), (unsigned long long)n);
            if (!word_to_u64(word, length, &index) || index >= vertices)
                return rtt_error_set(err, "%s: face %llu: vertex index %.*s is out of range (%llu vertices)", path,
                                     (unsigned long long)f, (int)(length > 24 ? 24 : length), (const char *)word,
                                     (unsigned long long)vertices);
        }
        if (n >= 3) out->triangles += n - 2;
    }
    return true;
}

/* ---- PLY ------------------------------------------------------------------ */

#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 64

typedef enum ply_format { PLY_ASCII, PLY_LITTLE, PLY_BIG } ply_format;

typedef struct ply_property {
    uint8_t size;       /* bytes of the value (binary) */
    uint8_t count_size; /* a list: bytes of its count; 0 for a scalar */
    bool value_float;
    bool is_index;      /* the face element's vertex_indices */
} ply_property;

typedef struct ply_element {
    char name[32];
    uint64_t count;
    uint32_t property_count;
    ply_property properties[PLY_MAX_PROPERTIES];
} ply_element;

typedef struct ply_file {
    const char *path;
    ply_format format;
    uint32_t element_count;
    ply_element elements[PLY_MAX_ELEMENTS];
    uint64_t vertices; /* the "vertex" element's count */
} ply_file;

static bool ply_type(const unsigned char *word, size_t length, uint8_t *size, bool *is_float)
{
    static const struct { const char *name; uint8_t size; bool is_float; } types[] = {
        {"char", 1, false},  {"uchar", 1, false},  {"int8", 1, false},    {"uint8", 1, false},
        {"short", 2, false}, {"ushort", 2, false}, {"int16", 2, false},   {"uint16", 2, false},
        {"int", 4, false},   {"uint", 4, false},   {"int32", 4, false},   {"uint32", 4, false},
        {"float", 4, true},  {"float32", 4, true}, {"double", 8, true},   {"float64", 8, true}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strlen(types[i].name) == length && memcmp(types[i].name, word, length) == 0) {
            *size = types[i].size;
            *is_float = types[i].is_float;
            return true;
        }
    return false;
}

static bool word_is(const unsigned char *word, size_t length, const char *text)
{
    return strlen(text) == length && memcmp(word, text, length) == 0;
}

/* The header, up to "end_header"; *body is where the elements start. */
static bool ply_header(ply_file *ply, const unsigned char *bytes, size_t size, size_t *body, rtt_error *err)
{
    const char *path = ply->path;
    const unsigned char *at = bytes, *end = bytes + size;
    bool format_seen = false;
    for (unsigned line_number = 1;; line_number++) {
        const unsigned char *stop = memchr(at, '\n', (size_t)(end - at));
        if (!stop) return rtt_error_set(err, "%s: header: the file ends before \"end_header\"", path);
        const unsigned char *line = at, *word;
        size_t length;
        at = stop + 1;
        if (!next_word(&line, stop, &word, &length)) continue;
        if (line_number == 1) {
            if (!word_is(word, length, "ply")) return rtt_error_set(err, "%s: not a ply file (it does not start with \"ply\")", path);
            continue;
        }
        if (word_is(word, length, "end_header")) break;
        if (word_is(word, length, "comment") || word_is(word, length, "obj_info")) continue;
        if (word_is(word, length, "format")) {
            if (!next_word(&line, stop, &word, &length)) return rtt_error_set(err, "%s: header line %u: format without a name", path, line_number);
            if (word_is(word, length, "ascii")) ply->format = PLY_ASCII;
            else if (word_is(word, length, "binary_little_endian")) ply->format = PLY_LITTLE;
            else if (word_is(word, length, "binary_big_endian")) ply->format = PLY_BIG;
            else return rtt_error_set(err, "%s: header line %u: unknown format \"%.*s\"", path, line_number, (int)(length > 32 ? 32 : length), (const char *)word);
            format_seen = true;
        } else if (word_is(word, length, "element")) {
            if (ply->element_count == PLY_MAX_ELEMENTS)
                return rtt_error_set(err, "%s: header line %u: more than %d elements", path, line_number, PLY_MAX_ELEMENTS);
            ply_element *e = &ply->elements[ply->element_count++];
            const unsigned char *name;
            size_t name_length;
            if (!next_word(&line, stop, &name, &name_length) || !next_word(&line, stop, &word, &length) ||
                !word_to_u64(word, length, &e->count))
                return rtt_error_set(err, "%s: header line %u: \"element NAME COUNT\" expected", path, line_number);
            snprintf(e->name, sizeof e->name, "%.*s", (int)(name_length > 31 ? 31 : name_length), (const char *)name);
            if (strcmp(e->name, "vertex") == 0) ply->vertices = e->count;
        } else if (word_is(word, length, "property")) {
            if (ply->element_count == 0) return rtt_error_set(err, "%s: header line %u: a property before any element", path, line_number);
            ply_element *e = &ply->elements[ply->element_count - 1];
            if (e->property_count == PLY_MAX_PROPERTIES)
                return rtt_error_set(err, "%s: header line %u: more than %d properties", path, line_number, PLY_MAX_PROPERTIES);
            ply_property *p = &e->properties[e->property_count++];
            bool count_float = false;
            if (!next_word(&line, stop, &word, &length)) return rtt_error_set(err, "%s: header line %u: property without a type", path, line_number);
            if (word_is(word, length, "list")) {
                if (!next_word(&line, stop, &word, &length) || !ply_type(word, length, &p->count_size, &count_float) || count_float)
                    return rtt_error_set(err, "%s: header line %u: a list's count must have an integer type", path, line_number);
                if (!next_word(&line, stop, &word, &length)) return rtt_error_set(err, "%s: header line %u: list without an item type", path, line_number);
            }
            if (!ply_type(word, length, &p->size, &p->value_float))
                return rtt_error_set(err, "%s: header line %u: unknown property type \"%.*s\"", path, line_number, (int)(length > 32 ? 32 : length), (const char *)word);
            if (!next_word(&line, stop, &word, &length)) return rtt_error_set(err, "%s: header line %u: property without a name", path, line_number);
            p->is_index = p->count_size && !p->value_float && strcmp(e->name, "face") == 0 &&
                          (word_is(word, length, "vertex_indices") || word_is(word, length, "vertex_index"));
        } else {
            return rtt_error_set(err, "%s: header line %u: unknown keyword \"%.*s\"", path, line_number, (int)(length > 32 ? 32 : length), (const char *)word);
        }
    }
    if (!format_seen) return rtt_error_set(err, "%s: header: no format line", path);
    /* items without properties take no bytes: their count would go unchecked */
    for (uint32_t e = 0; e < ply->element_count; e++)
        if (ply->elements[e].count > 0 && ply->elements[e].property_count == 0)
            return rtt_error_set(err, "%s: header: element \"%s\" declares %llu items but no properties", path,
                                 ply->elements[e].name, (unsigned long long)ply->elements[e].count);
    *body = (size_t)(at - bytes);
    return true;
}

static uint64_t read_uint(const unsigned char *p, unsigned size, bool big)
{
    uint64_t value = 0;
    for (unsigned i = 0; i < size; i++) value |= (uint64_t)p[big ? size - 1 - i : i] << (8 * i);
    return value;
}

static bool ply_truncated(const ply_file *ply, const ply_element *el, uint64_t i, rtt_error *err)
{
    return rtt_error_set(err, "%s: the file ends in %s %llu of the %llu the header declares", ply->path, el->name,
                         (unsigned long long)i, (unsigned long long)el->count);
}

/* A binary value as an index: negative (two's complement, a signed type read
 * as its bits) shows as huge, hence out of range. */
static bool ply_walk_binary(ply_file *ply, const unsigned char *at, const unsigned char *end, rtt_mesh_header *out,
                            rtt_error *err)
{
    const bool big = ply->format == PLY_BIG;
    for (uint32_t e = 0; e < ply->element_count; e++) {
        const ply_element *el = &ply->elements[e];
        if (el->property_count == 0) continue;
        for (uint64_t i = 0; i < el->count; i++) {
            for (uint32_t k = 0; k < el->property_count; k++) {
                const ply_property *p = &el->properties[k];
                uint64_t n = 1;
                if (p->count_size) {
                    if ((size_t)(end - at) < p->count_size) goto truncated;
                    n = read_uint(at, p->count_size, big);
                    at += p->count_size;
                    if (n > (uint64_t)(end - at) / p->size) goto truncated;
                    if (p->is_index && n >= 3) out->triangles += n - 2;
                }
                if (p->is_index) {
                    for (uint64_t j = 0; j < n; j++) {
                        uint64_t index = read_uint(at + j * p->size, p->size, big);
                        if (index >= ply->vertices)
                            return rtt_error_set(err, "%s: face %llu: vertex index %llu is out of range (%llu vertices)",
                                                 ply->path, (unsigned long long)i, (unsigned long long)index,
                                                 (unsigned long long)ply->vertices);
                    }
                } else if ((size_t)(end - at) < n * p->size) {
                    goto truncated;
                }
                at += n * p->size;
            }
            continue;
        truncated:
            return ply_truncated(ply, el, i, err);
        }
    }
    return true;
}

static bool ply_walk_ascii(ply_file *ply, const unsigned char *at, const unsigned char *end, rtt_mesh_header *out,
                           rtt_error *err)
{
    const unsigned char *word;
    size_t length;
    for (uint32_t e = 0; e < ply->element_count; e++) {
        const ply_element *el = &ply->elements[e];
        if (el->property_count == 0) continue;
        for (uint64_t i = 0; i < el->count; i++) {
            for (uint32_t k = 0; k < el->property_count; k++) {
                const ply_property *p = &el->properties[k];
                uint64_t n = 1;
                if (p->count_size) {
                    if (!next_word(&at, end, &word, &length)) goto truncated;
                    if (!word_to_u64(word, length, &n) || n > (uint64_t)(end - at))
                        return rtt_error_set(err, "%s: %s %llu: property %u: \"%.*s\" is not a list length", ply->path,
                                             el->name, (unsigned long long)i, k, (int)(length > 24 ? 24 : length),
                                             (const char *)word);
                    if (p->is_index && n >= 3) out->triangles += n - 2;
                }
                for (uint64_t j = 0; j < n; j++) {
                    if (!next_word(&at, end, &word, &length)) goto truncated;
                    uint64_t index;
                    if (p->is_index && (!word_to_u64(word, length, &index) || index >= ply->vertices))
                        return rtt_error_set(err, "%s: face %llu: vertex index %.*s is out of range (%llu vertices)",
                                             ply->path, (unsigned long long)i, (int)(length > 24 ? 24 : length),
                                             (const char *)word, (unsigned long long)ply->vertices);
                    if (!p->is_index && !word_is_number(word, length))
                        return rtt_error_set(err, "%s: %s %llu: property %u: \"%.*s\" is not a number", ply->path,
                                             el->name, (unsigned long long)i, k, (int)(length > 24 ? 24 : length),
                                             (const char *)word);
                }
            }
            continue;
        truncated:
            return ply_truncated(ply, el, i, err);
        }
    }
    return true;
}

static bool scan_ply(const char *path, const unsigned char *bytes, size_t size, rtt_mesh_header *out, rtt_error *err)
{
    ply_file *ply = calloc(1, sizeof *ply);
    if (!ply) return rtt_error_set(err, "%s: out of memory", path);
    ply->path = path;
    size_t body = 0;
    bool ok = ply_header(ply, bytes, size, &body, err);
    if (ok) {
        uint64_t faces = 0;
        for (uint32_t e = 0; e < ply->element_count; e++)
            if (strcmp(ply->elements[e].name, "face") == 0) faces = ply->elements[e].count;
        *out = (rtt_mesh_header){.counted = true, .vertices = ply->vertices, .faces = faces};
        ok = ply->format == PLY_ASCII ? ply_walk_ascii(ply, bytes + body, bytes + size, out, err)
                                      : ply_walk_binary(ply, bytes + body, bytes + size, out, err);
    }
    free(ply);
    return ok;
}

/* ---- STL ------------------------------------------------------------------ */

static bool scan_stl(const char *path, const unsigned char *bytes, size_t size, rtt_mesh_header *out, rtt_error *err)
{
    if (size >= 84) {
        uint64_t count = read_uint(bytes + 80, 4, false);
        if (84 + 50 * count == size) {
            *out = (rtt_mesh_header){.counted = true, .vertices = 3 * count, .faces = count, .triangles = count};
            return true;
        }
    }
    const unsigned char *at = bytes, *end = bytes + size, *word;
    size_t length;
    if (!next_word(&at, end, &word, &length) || !word_is(word, length, "solid")) {
        if (size < 84) return rtt_error_set(err, "%s: binary STL shorter than its 84-byte header (%zu bytes)", path, size);
        uint64_t count = read_uint(bytes + 80, 4, false);
        return rtt_error_set(err, "%s: binary STL header declares %llu triangles (%llu bytes) but the file has %zu bytes",
                             path, (unsigned long long)count, (unsigned long long)(84 + 50 * count), size);
    }
    uint64_t facets = 0, vertices = 0;
    bool in_facet = false, ended = false; /* ended: the last keyword was "endsolid" */
    while (next_word(&at, end, &word, &length)) {
        if (word_is(word, length, "facet")) {
            if (in_facet) break;
            in_facet = true;
            ended = false;
            vertices = 0;
        } else if (word_is(word, length, "vertex")) {
            vertices++;
        } else if (word_is(word, length, "endfacet")) {
            if (!in_facet || vertices != 3)
                return rtt_error_set(err, "%s: facet %llu: %llu vertices (a facet has 3)", path,
                                     (unsigned long long)facets, (unsigned long long)vertices);
            in_facet = false;
            facets++;
        } else if (word_is(word, length, "solid")) {
            ended = false;
        } else if (word_is(word, length, "endsolid")) {
            ended = !in_facet;
        }
    }
    if (!ended)
        return rtt_error_set(err, "%s: the file ends in facet %llu (no \"endfacet\" and \"endsolid\" after it)", path,
                             (unsigned long long)facets);
    *out = (rtt_mesh_header){.counted = true, .vertices = 3 * facets, .faces = facets, .triangles = facets};
    return true;
}

/* ---- glTF ----------------------------------------------------------------- */

static uint64_t json_u64(const cJSON *object, const char *key, uint64_t otherwise, bool *ok)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!v) return otherwise;
    if (!cJSON_IsNumber(v) || v->valuedouble < 0 || v->valuedouble > 9007199254740992.0 ||
        v->valuedouble != (double)(uint64_t)v->valuedouble) {
        *ok = false;
        return 0;
    }
    return (uint64_t)v->valuedouble;
}

/* The bytes behind buffer `b`'s uri: a base64 data: URI's decoded length, or
 * an external file's size (its directory the .gltf's). */
static bool buffer_source_size(const char *path, uint32_t b, const char *uri, uint64_t *size, rtt_error *err)
{
    if (strncmp(uri, "data:", 5) == 0) {
        const char *comma = strchr(uri, ',');
        if (!comma || !strstr(uri, ";base64"))
            return rtt_error_set(err, "%s: buffers[%u]: a data: uri that is not base64", path, b);
        size_t n = strlen(comma + 1);
        while (n > 0 && comma[n] == '=') n--; /* padding: comma[n] is the last character */
        *size = (uint64_t)n * 3 / 4;
        return true;
    }
    if (strchr(uri, '%') || strstr(uri, "://")) { /* escaped or remote: Assimp's to judge */
        *size = UINT64_MAX;
        return true;
    }
    char resolved[4096];
    rtt_path_beside(path, uri, resolved, sizeof resolved);
    rtt_error inner;
    FILE *f = rtt_file_open_regular(resolved, &inner);
    if (!f) return rtt_error_set(err, "%s: buffers[%u]: %s", path, b, inner.message);
    struct stat info;
    bool known = fstat(fileno(f), &info) == 0;
    fclose(f);
    *size = known ? (uint64_t)info.st_size : 0;
    return true;
}

static const char *const accessor_types[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
static const unsigned accessor_components[] = {1, 2, 3, 4, 4, 9, 16};

static unsigned component_size(uint64_t type)
{
    switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
    }
}

static bool scan_gltf_json(const char *path, const char *text, size_t length, uint64_t glb_bin, rtt_mesh_header *out,
                           rtt_error *err)
{
    cJSON *root = cJSON_ParseWithLength(text, length);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return rtt_error_set(err, "%s: not a glTF file (not a JSON object)", path);
    }
    bool ok = true;
    const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(root, "buffers");
    const cJSON *views = cJSON_GetObjectItemCaseSensitive(root, "bufferViews");
    const cJSON *accessors = cJSON_GetObjectItemCaseSensitive(root, "accessors");
    const int buffer_count = cJSON_IsArray(buffers) ? cJSON_GetArraySize(buffers) : 0;
    const int view_count = cJSON_IsArray(views) ? cJSON_GetArraySize(views) : 0;
    *out = (rtt_mesh_header){0};
    uint64_t *lengths = calloc((size_t)buffer_count + 1, sizeof *lengths);
    if (!lengths) ok = rtt_error_set(err, "%s: out of memory", path);
    for (int b = 0; ok && b < buffer_count; b++) {
        const cJSON *buffer = cJSON_GetArrayItem(buffers, b);
        bool valid = true;
        uint64_t declared = json_u64(buffer, "byteLength", UINT64_MAX, &valid), available = 0;
        if (!valid || declared == UINT64_MAX) {
            ok = rtt_error_set(err, "%s: buffers[%d]: byteLength is missing or not a whole number", path, b);
            break;
        }
        const cJSON *uri = cJSON_GetObjectItemCaseSensitive(buffer, "uri");
        if (cJSON_IsString(uri)) {
            ok = buffer_source_size(path, (uint32_t)b, uri->valuestring, &available, err);
        } else if (b == 0 && glb_bin != UINT64_MAX) {
            available = glb_bin;
        } else {
            ok = rtt_error_set(err, "%s: buffers[%d]: no uri and no GLB binary chunk", path, b);
        }
        if (ok && declared > available)
            ok = rtt_error_set(err, "%s: buffers[%d]: byteLength %llu but only %llu bytes are there", path, b,
                               (unsigned long long)declared, (unsigned long long)available);
        lengths[b] = declared;
        out->bytes += declared;
    }
    uint64_t *view_ends = ok ? calloc((size_t)view_count + 1, sizeof *view_ends) : NULL;
    if (ok && !view_ends) ok = rtt_error_set(err, "%s: out of memory", path);
    for (int v = 0; ok && v < view_count; v++) {
        const cJSON *view = cJSON_GetArrayItem(views, v);
        bool valid = true;
        uint64_t buffer = json_u64(view, "buffer", UINT64_MAX, &valid), offset = json_u64(view, "byteOffset", 0, &valid),
                 bytes = json_u64(view, "byteLength", UINT64_MAX, &valid);
        if (!valid || buffer >= (uint64_t)buffer_count || bytes == UINT64_MAX)
            ok = rtt_error_set(err, "%s: bufferViews[%d]: buffer or byteLength missing or out of range", path, v);
        else if (offset > lengths[buffer] || bytes > lengths[buffer] - offset)
            ok = rtt_error_set(err, "%s: bufferViews[%d]: bytes %llu..%llu lie outside buffers[%llu] (%llu bytes)", path,
                               v, (unsigned long long)offset, (unsigned long long)(offset + bytes),
                               (unsigned long long)buffer, (unsigned long long)lengths[buffer]);
        else
            view_ends[v] = bytes; /* the view's length */
    }
    const int accessor_count = cJSON_IsArray(accessors) ? cJSON_GetArraySize(accessors) : 0;
    for (int a = 0; ok && a < accessor_count; a++) {
        const cJSON *accessor = cJSON_GetArrayItem(accessors, a);
        bool valid = true;
        uint64_t view = json_u64(accessor, "bufferView", UINT64_MAX, &valid),
                 offset = json_u64(accessor, "byteOffset", 0, &valid), count = json_u64(accessor, "count", UINT64_MAX, &valid),
                 component = json_u64(accessor, "componentType", 0, &valid);
        const cJSON *type = cJSON_GetObjectItemCaseSensitive(accessor, "type");
        unsigned components = 0;
        for (size_t t = 0; cJSON_IsString(type) && t < sizeof accessor_types / sizeof accessor_types[0]; t++)
            if (strcmp(type->valuestring, accessor_types[t]) == 0) components = accessor_components[t];
        if (!valid || count == UINT64_MAX || !component_size(component) || !components) {
            ok = rtt_error_set(err, "%s: accessors[%d]: count, componentType or type missing or invalid", path, a);
            break;
        }
        if (view == UINT64_MAX) continue; /* no view: zeros (or sparse), nothing to read */
        if (view >= (uint64_t)view_count) {
            ok = rtt_error_set(err, "%s: accessors[%d]: bufferView %llu is out of range (%d views)", path, a,
                               (unsigned long long)view, view_count);
            break;
        }
        const cJSON *view_json = cJSON_GetArrayItem(views, (int)view);
        uint64_t element = (uint64_t)component_size(component) * components;
        uint64_t stride = json_u64(view_json, "byteStride", element, &valid);
        if (stride < element) stride = element;
        const uint64_t length = view_ends[view];
        /* the last element ends at offset + stride * (count - 1) + element */
        if (count > 0 && (offset > length || count - 1 > (length - offset) / stride ||
                          stride * (count - 1) + element > length - offset))
            ok = rtt_error_set(err, "%s: accessors[%d]: %llu elements of %llu bytes from byte %llu overrun "
                               "bufferViews[%llu] (%llu bytes)", path, a, (unsigned long long)count,
                               (unsigned long long)element, (unsigned long long)offset, (unsigned long long)view,
                               (unsigned long long)length);
        else if (components == 1 && count / 3 > out->triangles)
            out->triangles = count / 3; /* an index list's triangles, at most */
        else if (components == 3 && count > out->vertices)
            out->vertices = count;
    }
    free(view_ends);
    free(lengths);
    cJSON_Delete(root);
    return ok;
}

static bool scan_glb(const char *path, const unsigned char *bytes, size_t size, rtt_mesh_header *out, rtt_error *err)
{
    if (size < 20 || memcmp(bytes, "glTF", 4) != 0) return rtt_error_set(err, "%s: not a glb file (shorter than its header or no \"glTF\" magic)", path);
    uint64_t length = read_uint(bytes + 8, 4, false);
    if (length != size)
        return rtt_error_set(err, "%s: GLB header declares %llu bytes but the file has %zu", path,
                             (unsigned long long)length, size);
    uint64_t json_length = read_uint(bytes + 12, 4, false);
    if (memcmp(bytes + 16, "JSON", 4) != 0 || json_length > size - 20)
        return rtt_error_set(err, "%s: GLB chunk 0: not a JSON chunk inside the file (%llu bytes)", path,
                             (unsigned long long)json_length);
    uint64_t bin = UINT64_MAX, at = 20 + json_length;
    at = (at + 3) & ~(uint64_t)3;
    if (at + 8 <= size && memcmp(bytes + at + 4, "BIN", 4) == 0) {
        bin = read_uint(bytes + at, 4, false);
        if (bin > size - at - 8)
            return rtt_error_set(err, "%s: GLB chunk 1: BIN chunk of %llu bytes overruns the file (%llu left)", path,
                                 (unsigned long long)bin, (unsigned long long)(size - at - 8));
    }
    return scan_gltf_json(path, (const char *)bytes + 20, (size_t)json_length, bin, out, err);
}

/* ---- the entry points ----------------------------------------------------- */

bool rtt_mesh_header_scan(const char *path, const char *format, const unsigned char *bytes, size_t size,
                          rtt_mesh_header *out, rtt_error *err)
{
    *out = (rtt_mesh_header){0};
    if (strcasecmp(format, "off") == 0) return scan_off(path, bytes, size, out, err);
    if (strcasecmp(format, "ply") == 0) return scan_ply(path, bytes, size, out, err);
    if (strcasecmp(format, "stl") == 0) return scan_stl(path, bytes, size, out, err);
    if (strcasecmp(format, "gltf") == 0) return scan_gltf_json(path, (const char *)bytes, size, UINT64_MAX, out, err);
    if (strcasecmp(format, "glb") == 0) return scan_glb(path, bytes, size, out, err);
    return true;
}

bool rtt_mesh_header_check_file(const char *path, rtt_mesh_header *out, rtt_error *err)
{
    *out = (rtt_mesh_header){0};
    static const char *const formats[] = {"off", "ply", "stl", "gltf", "glb"};
    const char *ext = rtt_file_extension(path);
    bool scanned = false;
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) scanned |= strcasecmp(ext, formats[i]) == 0;
    if (!scanned) return true;
    FILE *f = rtt_file_open_regular(path, err);
    if (!f) return false;
    struct stat info;
    if (fstat(fileno(f), &info) != 0 || info.st_size <= 0) {
        fclose(f);
        return rtt_error_set(err, "%s: the file is empty", path);
    }
    const size_t size = (size_t)info.st_size;
    void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fileno(f), 0);
    fclose(f);
    if (map == MAP_FAILED) return rtt_error_set(err, "%s: cannot read: %s", path, strerror(errno));
    bool ok = rtt_mesh_header_scan(path, ext, map, size, out, err);
    munmap(map, size);
    return ok;
}

bool rtt_mesh_header_check_import(const char *path, const rtt_mesh_header *header, const struct aiScene *ai,
                                  rtt_error *err)
{
    if (!header->counted || header->triangles == 0) return true; /* no faces: "no triangles" says it */
    uint64_t triangles = 0;
    for (unsigned m = 0; m < ai->mNumMeshes; m++)
        for (unsigned f = 0; f < ai->mMeshes[m]->mNumFaces; f++)
            if (ai->mMeshes[m]->mFaces[f].mNumIndices >= 3) triangles += ai->mMeshes[m]->mFaces[f].mNumIndices - 2;
    if (triangles != header->triangles)
        return rtt_error_set(err, "%s: %llu triangles imported, the file's %llu faces make %llu", path,
                             (unsigned long long)triangles, (unsigned long long)header->faces,
                             (unsigned long long)header->triangles);
    return true;
}

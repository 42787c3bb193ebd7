/* The JSON scene file's schema (format in scene/README.md), shared by its two
 * halves: scene_schema.c (the top level, camera, image, materials, lights,
 * and the typed readers below) and scene_schema_meshes.c (meshes[i]).
 *
 * Every reader checks one value against the format and, when it is wrong,
 * fills the parser's error with "file:line: path what" located at the value
 * (json_locate.h) and returns false; the first error ends the parse. */
#ifndef RTT_SCENE_SCHEMA_H
#define RTT_SCENE_SCHEMA_H

#include <cjson/cJSON.h>

#include "json_locate.h"
#include "scene_build.h"

typedef struct rtt_schema_parser {
    rtt_scene *scene;
    rtt_json_source src;       /* the scene file: messages, and relative mesh paths */
    rtt_error *err;
    uint32_t default_material; /* UINT32_MAX until a mesh needs it */
    uint32_t bezier_level;     /* for .bsp meshes: the caller's, else the file's */
} rtt_schema_parser;

/* Reserves the memory budget of the shapes and inline meshes of the
 * "meshes" array (files reserve their own when imported); one line naming
 * the scene file when over it. */
bool rtt_schema_meshes_reserve(rtt_schema_parser *p, const cJSON *meshes);

/* The error located at and named by `place`; returns false. */
__attribute__((format(printf, 3, 4))) bool rtt_schema_fail(rtt_schema_parser *p, const rtt_json_place *place,
                                                           const char *fmt, ...);
/* The error located at `line_at` and named by `path_of` (an unknown key: the
 * key's line, its object's path). */
__attribute__((format(printf, 4, 5))) bool rtt_schema_fail_in(rtt_schema_parser *p, const rtt_json_place *line_at,
                                                              const rtt_json_place *path_of, const char *fmt, ...);

/* The member `key` of obj (NULL when absent) and its place in *out. */
const cJSON *rtt_schema_member(const cJSON *obj, const rtt_json_place *place, const char *key, rtt_json_place *out);
/* obj must be an object whose keys are all in `allowed` (NULL-terminated), each once. */
bool rtt_schema_check_object(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place,
                             const char *const *allowed);

/* Typed values: each fills *out or reports what the value must be. */
bool rtt_schema_read_nonneg(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, bool strict, float *out);
bool rtt_schema_read_uint(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double lo, double hi,
                          uint32_t *out);
bool rtt_schema_read_vec3(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_vec3 *out);
/* A position (or a transform's part) in double, each within float's range:
 * positions stay in double until the scene is centred. */
bool rtt_schema_read_point(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double out[3]);
/* A number in [lo, hi]; a colour: three non-negative numbers. */
bool rtt_schema_read_number(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double lo, double hi,
                            float *out);
bool rtt_schema_read_color(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_vec3 *out);
/* A light's [constant, linear, quadratic] fall-off: each >= 0, not all 0. */
bool rtt_schema_read_attenuation(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, float out[3]);
bool rtt_schema_read_name(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, char out[64]);

/* A "camera" object (eye, look_at, up, fov) into *out, with eye and look_at
 * in double too (out's are them rounded to float): the scene file's and the
 * views file's (views.c). */
bool rtt_schema_parse_camera(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, rtt_camera *out,
                             double eye[3], double look_at[3]);

/* The index of the scene material named by the string v. */
bool rtt_schema_material_index(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t *out);

/* Reads the JSON file at `path` and hands its root to `read` with p->src set
 * (freed again before returning): one-line errors for an empty file
 * ("file:1: the file is empty (<empty>)"), NUL bytes and syntax errors. */
typedef bool (*rtt_schema_root_reader)(rtt_schema_parser *p, const cJSON *root, void *context);
bool rtt_schema_parse_file(const char *path, const char *empty, rtt_schema_parser *p, rtt_schema_root_reader read,
                           void *context);

/* One element of "meshes" (scene_schema_meshes.c). */
/* materials[i].diffuse_map / normal_map (scene_schema_textures.c): *map as in rtt_material. */
bool rtt_schema_read_texture(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t *map);
/* meshes[i].texcoords: 2 floats per vertex into a new *out. */
bool rtt_schema_read_texcoords(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t vertex_count,
                               float **out);
bool rtt_schema_parse_mesh(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place);

/* The optional member `key` read with `read_call` when present (which sees
 * the value as `v` and its place as `at`); the target keeps its default
 * otherwise.  Returns false from the enclosing function on an error. */
#define RTT_SCHEMA_OPTIONAL(obj, place, key, read_call)                                                         \
    do {                                                                                                        \
        rtt_json_place at_;                                                                                     \
        const cJSON *v_ = rtt_schema_member((obj), (place), (key), &at_);                                       \
        if (v_) {                                                                                               \
            const rtt_json_place *at = &at_;                                                                    \
            const cJSON *v = v_;                                                                                \
            if (!(read_call)) return false;                                                                     \
        }                                                                                                       \
    } while (0)

#endif

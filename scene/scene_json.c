/* The JSON scene file: rtt_scene_parse_json (format in scene/README.md).
 *
 * cJSON parses the text; this file checks every key and value against the
 * format and fills the scene.  cJSON keeps no source positions, so an error
 * names its value by a `json_place` chain (object member or array element,
 * by index among its siblings) and the line is found by re-scanning the
 * already validated text along that chain: positions cost nothing unless a
 * file is wrong, and duplicate or escaped keys are still located exactly. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cjson/cJSON.h>

#include "scene_build.h"
#include "shapes.h"

#define MAX_IMAGE_SIDE 16384.0
#define MAX_BOUNCES 64.0
#define MAX_BEZIER_LEVEL 64.0
#define MAX_FILE_BYTES ((size_t)1 << 30)

/* Where a value sits: the member or element `index` of `parent` (key is the
 * member's name, NULL for array elements); the root has no parent. */
typedef struct json_place {
    const struct json_place *parent;
    const char *key;
    int index;
} json_place;

typedef struct json_parser {
    rtt_scene *scene;
    const char *path;       /* the scene file, for messages and relative mesh paths */
    const char *text;
    size_t length;
    rtt_error *err;
    uint32_t default_material; /* UINT32_MAX until a mesh needs it */
    uint32_t bezier_level;
} json_parser;

/* ---- locating a place in the source text ---- */

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

static int place_line(const json_parser *p, const json_place *place)
{
    int chain[64], depth = 0;
    for (const json_place *w = place; w && w->parent && depth < 64; w = w->parent) chain[depth++] = w->index;
    const char *end = p->text + p->length;
    const char *at = skip_space(p->text, end), *value = at;
    for (int k = depth - 1; k >= 0; k--) {
        if (value >= end || (*value != '{' && *value != '[')) break;
        const char *child = nth_child(value, end, chain[k], &value);
        if (!child) break;
        at = child;
    }
    int line = 1;
    for (const char *c = p->text; c < at; c++) line += *c == '\n';
    return line;
}

static void place_path(const json_place *place, char *out, size_t size)
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

/* "file:line: path<what>", the line of `line_at`, the path of `path_of`.
 * `what` starts with its separator (" must be ...", ": no ..."), which is
 * dropped for the root. */
static bool fail_v(json_parser *p, const json_place *line_at, const json_place *path_of, const char *fmt,
                   va_list args)
{
    char path[256], what[384];
    place_path(path_of, path, sizeof path);
    vsnprintf(what, sizeof what, fmt, args);
    const char *shown = what;
    if (!path[0]) shown += strspn(what, ": ");
    return rtt_error_set(p->err, "%s:%d: %s%s", p->path, place_line(p, line_at), path, shown);
}

__attribute__((format(printf, 3, 4))) static bool fail(json_parser *p, const json_place *place, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    fail_v(p, place, place, fmt, args);
    va_end(args);
    return false;
}

__attribute__((format(printf, 4, 5))) static bool fail_in(json_parser *p, const json_place *line_at,
                                                           const json_place *path_of, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    fail_v(p, line_at, path_of, fmt, args);
    va_end(args);
    return false;
}

/* ---- typed access ---- */

/* The member `key` of obj (NULL when absent) and its place. */
static const cJSON *member(const cJSON *obj, const json_place *place, const char *key, json_place *out)
{
    int index = 0;
    for (const cJSON *c = obj->child; c; c = c->next, index++) {
        if (c->string && strcmp(c->string, key) == 0) {
            *out = (json_place){place, c->string, index};
            return c;
        }
    }
    *out = (json_place){place, key, -1};
    return NULL;
}

static json_place element(const json_place *place, int index) { return (json_place){place, NULL, index}; }

/* obj must be an object whose keys are all in `allowed` (NULL-terminated), each once. */
static bool check_object(json_parser *p, const cJSON *obj, const json_place *place, const char *const *allowed)
{
    if (!cJSON_IsObject(obj)) return fail(p, place, " must be an object");
    int index = 0;
    for (const cJSON *c = obj->child; c; c = c->next, index++) {
        json_place at = {place, c->string, index};
        bool known = false;
        for (const char *const *a = allowed; *a && !known; a++) known = strcmp(*a, c->string) == 0;
        if (!known) return fail_in(p, &at, place, ": unknown key \"%s\"", c->string);
        for (const cJSON *d = obj->child; d != c; d = d->next)
            if (strcmp(d->string, c->string) == 0) return fail_in(p, &at, place, ": key \"%s\" given twice", c->string);
    }
    return true;
}

static bool read_number(json_parser *p, const cJSON *v, const json_place *at, double lo, double hi, float *out)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi))
        return fail(p, at, " must be a number between %g and %g", lo, hi);
    *out = (float)v->valuedouble;
    return true;
}

/* > 0 when strict, else >= 0; finite. */
static bool read_nonneg(json_parser *p, const cJSON *v, const json_place *at, bool strict, float *out)
{
    float value = cJSON_IsNumber(v) ? (float)v->valuedouble : -1.0f;
    if (!isfinite(value) || value < 0.0f || (strict && value == 0.0f))
        return fail(p, at, strict ? " must be a positive number" : " must be a non-negative number");
    *out = value;
    return true;
}

static bool read_uint(json_parser *p, const cJSON *v, const json_place *at, double lo, double hi, uint32_t *out)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi) ||
        v->valuedouble != floor(v->valuedouble))
        return fail(p, at, " must be an integer between %.0f and %.0f", lo, hi);
    *out = (uint32_t)v->valuedouble;
    return true;
}

static bool read_vec3(json_parser *p, const cJSON *v, const json_place *at, rtt_vec3 *out)
{
    float xyz[3];
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return fail(p, at, " must be an array of 3 finite numbers");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble) || !isfinite((float)c->valuedouble))
            return fail(p, at, " must be an array of 3 finite numbers");
        xyz[i] = (float)c->valuedouble;
    }
    *out = rtt_v3(xyz[0], xyz[1], xyz[2]);
    return true;
}

static bool read_color(json_parser *p, const cJSON *v, const json_place *at, rtt_vec3 *out)
{
    if (!read_vec3(p, v, at, out) || out->x < 0.0f || out->y < 0.0f || out->z < 0.0f)
        return fail(p, at, " must be an array of 3 non-negative numbers");
    return true;
}

static bool read_name(json_parser *p, const cJSON *v, const json_place *at, char out[64])
{
    if (!cJSON_IsString(v) || !v->valuestring[0] || strlen(v->valuestring) > 63)
        return fail(p, at, " must be a string of 1 to 63 bytes");
    strcpy(out, v->valuestring);
    return true;
}

/* The optional member `key` read with `read` when present; `out` keeps its default otherwise. */
#define OPTIONAL(p, obj, place, key, read_call)                                                                   \
    do {                                                                                                          \
        json_place at_;                                                                                           \
        const cJSON *v_ = member((obj), (place), (key), &at_);                                                    \
        if (v_) {                                                                                                 \
            const json_place *at = &at_;                                                                          \
            const cJSON *v = v_;                                                                                  \
            if (!(read_call)) return false;                                                                       \
        }                                                                                                         \
    } while (0)

/* ---- top level: image, camera and the scalars ---- */

static bool parse_image(json_parser *p, const cJSON *obj, const json_place *place)
{
    static const char *const keys[] = {"width", "height", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    OPTIONAL(p, obj, place, "width", read_uint(p, v, at, 1, MAX_IMAGE_SIDE, &p->scene->width));
    OPTIONAL(p, obj, place, "height", read_uint(p, v, at, 1, MAX_IMAGE_SIDE, &p->scene->height));
    return true;
}

static bool parse_camera(json_parser *p, const cJSON *obj, const json_place *place)
{
    static const char *const keys[] = {"eye", "look_at", "up", "fov", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    rtt_camera cam = {.up = rtt_v3(0, 1, 0), .fov_deg = RTT_DEFAULT_FOV_DEG};
    json_place eye_at, look_at, up_at;
    const cJSON *eye = member(obj, place, "eye", &eye_at), *look = member(obj, place, "look_at", &look_at);
    if (!eye) return fail(p, place, ": missing \"eye\"");
    if (!look) return fail(p, place, ": missing \"look_at\"");
    if (!read_vec3(p, eye, &eye_at, &cam.eye) || !read_vec3(p, look, &look_at, &cam.look_at)) return false;
    OPTIONAL(p, obj, place, "fov", read_number(p, v, at, 1, 179, &cam.fov_deg));
    const cJSON *up = member(obj, place, "up", &up_at);
    if (up && !read_vec3(p, up, &up_at, &cam.up)) return false;
    rtt_vec3 view = rtt_v3_sub(cam.look_at, cam.eye);
    if (rtt_v3_length(view) == 0.0f) return fail(p, &look_at, " must differ from camera.eye");
    rtt_vec3 side = rtt_v3_cross(rtt_v3_normalize(view), rtt_v3_normalize(cam.up));
    if (!(rtt_v3_length(side) > 1e-6f))
        return fail(p, up ? &up_at : place, up ? " must not be zero or parallel to the view direction"
                                               : ": the view direction is parallel to the default up [0, 1, 0]; give \"up\"");
    p->scene->camera = cam;
    return true;
}

/* ---- materials ---- */

typedef struct material_type_name {
    const char *name;
    rtt_material_type type;
    bool phong, reflective, transparent; /* which optional fields the type reads */
} material_type_name;

static const material_type_name material_types[] = {
    {"diffuse", RTT_MATERIAL_DIFFUSE, false, false, false},
    {"specular", RTT_MATERIAL_SPECULAR, true, false, false},
    {"reflective", RTT_MATERIAL_REFLECTIVE, true, true, false},
    {"transparent", RTT_MATERIAL_TRANSPARENT, false, false, true},
    {"transparent_reflective", RTT_MATERIAL_TRANSPARENT_REFLECTIVE, true, true, true},
};

static const material_type_name *find_material_type(const cJSON *v)
{
    for (size_t i = 0; v && cJSON_IsString(v) && i < sizeof material_types / sizeof *material_types; i++)
        if (strcmp(v->valuestring, material_types[i].name) == 0) return &material_types[i];
    return NULL;
}

/* A field the type does not read is a mistake, not a no-op. */
static bool check_material_fields(json_parser *p, const cJSON *obj, const json_place *place,
                                  const material_type_name *t)
{
    static const char *const phong[] = {"specular", "shininess"}, *const reflective[] = {"reflection"},
                             *const transparent[] = {"transparency", "ior"};
    struct { const char *const *keys; size_t n; bool read; } groups[] = {
        {phong, 2, t->phong}, {reflective, 1, t->reflective}, {transparent, 2, t->transparent}};
    for (size_t g = 0; g < 3; g++) {
        for (size_t k = 0; k < groups[g].n && !groups[g].read; k++) {
            json_place at;
            if (member(obj, place, groups[g].keys[k], &at))
                return fail(p, &at, " is not used by a \"%s\" material", t->name);
        }
    }
    return true;
}

static bool parse_material(json_parser *p, const cJSON *obj, const json_place *place)
{
    static const char *const keys[] = {"name", "type", "diffuse", "specular", "shininess", "reflection",
                                       "transparency", "ior", "edge_width_scale", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    rtt_material m = rtt_material_default();
    json_place name_at, type_at;
    const cJSON *name = member(obj, place, "name", &name_at);
    if (!name) return fail(p, place, ": missing \"name\"");
    if (!read_name(p, name, &name_at, m.name)) return false;
    for (uint32_t i = 0; i < p->scene->material_count; i++)
        if (strcmp(p->scene->materials[i].name, m.name) == 0)
            return fail(p, &name_at, ": duplicate material name \"%s\" (also materials[%u])", m.name, i);
    const material_type_name *t = &material_types[0];
    const cJSON *type = member(obj, place, "type", &type_at);
    if (type && !(t = find_material_type(type)))
        return fail(p, &type_at,
                    " must be one of \"diffuse\", \"specular\", \"reflective\", \"transparent\", "
                    "\"transparent_reflective\"");
    m.type = t->type;
    if (!check_material_fields(p, obj, place, t)) return false;
    OPTIONAL(p, obj, place, "diffuse", read_color(p, v, at, &m.diffuse));
    OPTIONAL(p, obj, place, "specular", read_nonneg(p, v, at, false, &m.specular));
    OPTIONAL(p, obj, place, "shininess", read_nonneg(p, v, at, false, &m.shininess));
    OPTIONAL(p, obj, place, "reflection", read_number(p, v, at, 0, 1, &m.reflection));
    OPTIONAL(p, obj, place, "transparency", read_number(p, v, at, 0, 1, &m.transparency));
    OPTIONAL(p, obj, place, "ior", read_nonneg(p, v, at, true, &m.ior));
    OPTIONAL(p, obj, place, "edge_width_scale", read_nonneg(p, v, at, true, &m.edge_width_scale));
    if (t->reflective && t->transparent && m.reflection + m.transparency > 1.0f)
        return fail(p, place, ": reflection + transparency must be at most 1 (it is %g)",
                    (double)(m.reflection + m.transparency));
    if (rtt_scene_add_material(p->scene, &m) == UINT32_MAX) return fail(p, place, ": out of memory");
    return true;
}

static bool material_index(json_parser *p, const cJSON *v, const json_place *at, uint32_t *out)
{
    if (!cJSON_IsString(v)) return fail(p, at, " must be a string (a material name)");
    for (uint32_t i = 0; i < p->scene->material_count; i++) {
        if (strcmp(p->scene->materials[i].name, v->valuestring) == 0) {
            *out = i;
            return true;
        }
    }
    return fail(p, at, ": no material named \"%s\"", v->valuestring);
}

/* ---- lights ---- */

static bool parse_light(json_parser *p, const cJSON *obj, const json_place *place)
{
    static const char *const keys[] = {"type", "position", "color", "intensity", "attenuation", "radius", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    rtt_light light = {.type = RTT_LIGHT_POINT, .color = rtt_v3(1, 1, 1), .intensity = 1.0f,
                       .attenuation = {1.0f, 0.0f, 0.0f}};
    json_place at;
    const cJSON *type = member(obj, place, "type", &at);
    if (type) {
        if (cJSON_IsString(type) && strcmp(type->valuestring, "sphere") == 0)
            light.type = RTT_LIGHT_SPHERE;
        else if (!cJSON_IsString(type) || strcmp(type->valuestring, "point") != 0)
            return fail(p, &at, " must be \"point\" or \"sphere\"");
    }
    const cJSON *position = member(obj, place, "position", &at);
    if (!position) return fail(p, place, ": missing \"position\"");
    if (!read_vec3(p, position, &at, &light.position)) return false;
    OPTIONAL(p, obj, place, "color", read_color(p, v, at, &light.color));
    OPTIONAL(p, obj, place, "intensity", read_nonneg(p, v, at, false, &light.intensity));
    const cJSON *attenuation = member(obj, place, "attenuation", &at);
    if (attenuation) {
        rtt_vec3 a;
        if (!read_vec3(p, attenuation, &at, &a) || a.x < 0.0f || a.y < 0.0f || a.z < 0.0f || a.x + a.y + a.z <= 0.0f)
            return fail(p, &at, " must be [constant, linear, quadratic], each >= 0, not all 0");
        light.attenuation[0] = a.x, light.attenuation[1] = a.y, light.attenuation[2] = a.z;
    }
    const cJSON *radius = member(obj, place, "radius", &at);
    if (light.type == RTT_LIGHT_POINT && radius) return fail(p, &at, " is only for sphere lights");
    if (light.type == RTT_LIGHT_SPHERE && !radius) return fail(p, place, ": a sphere light needs a \"radius\"");
    if (radius && !read_nonneg(p, radius, &at, true, &light.radius)) return false;
    rtt_error inner;
    if (!rtt_scene_add_light(p->scene, &light, &inner)) return fail(p, place, ": %s", inner.message);
    return true;
}

/* ---- meshes: transform, shapes, inline geometry, files ---- */

static void mat_mul(const float a[16], const float b[16], float out[16])
{
    float r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + a[4 * i + 3] * b[12 + j];
    memcpy(out, r, sizeof r);
}

/* Rotation by deg degrees about axis (0 x, 1 y, 2 z), right-handed. */
static void mat_rotation(int axis, float deg, float out[16])
{
    double rad = (double)deg * 3.14159265358979323846 / 180.0;
    float c = (float)cos(rad), s = (float)sin(rad);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    memset(out, 0, sizeof(float) * 16);
    out[0] = out[5] = out[10] = out[15] = 1.0f;
    out[4 * a + a] = c, out[4 * a + b] = -s;
    out[4 * b + a] = s, out[4 * b + b] = c;
}

/* transform = T * Rz * Ry * Rx * S (scene/README.md). */
static bool parse_transform(json_parser *p, const cJSON *obj, const json_place *place, float out[16])
{
    static const char *const keys[] = {"scale", "rotate_deg", "translate", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    rtt_vec3 scale = rtt_v3(1, 1, 1), rotate = rtt_v3(0, 0, 0), translate = rtt_v3(0, 0, 0);
    json_place at;
    const cJSON *s = member(obj, place, "scale", &at);
    if (s && cJSON_IsNumber(s)) {
        float k = (float)s->valuedouble;
        if (!isfinite(k) || k == 0.0f)
            return fail(p, &at, " must be a non-zero number or an array of 3 non-zero numbers");
        scale = rtt_v3(k, k, k);
    } else if (s && (!read_vec3(p, s, &at, &scale) || scale.x == 0.0f || scale.y == 0.0f || scale.z == 0.0f)) {
        return fail(p, &at, " must be a non-zero number or an array of 3 non-zero numbers");
    }
    OPTIONAL(p, obj, place, "rotate_deg", read_vec3(p, v, at, &rotate));
    OPTIONAL(p, obj, place, "translate", read_vec3(p, v, at, &translate));
    float m[16] = {scale.x, 0, 0, 0, 0, scale.y, 0, 0, 0, 0, scale.z, 0, 0, 0, 0, 1}, r[16];
    mat_rotation(0, rotate.x, r), mat_mul(r, m, m);
    mat_rotation(1, rotate.y, r), mat_mul(r, m, m);
    mat_rotation(2, rotate.z, r), mat_mul(r, m, m);
    m[3] = translate.x, m[7] = translate.y, m[11] = translate.z;
    memcpy(out, m, sizeof m);
    return true;
}

/* The material of a shape or inline mesh without "material": grey diffuse,
 * added once, the first time a mesh needs it. */
static bool default_material(json_parser *p, const json_place *place, uint32_t *out)
{
    if (p->default_material == UINT32_MAX) {
        rtt_material m = rtt_material_default();
        snprintf(m.name, sizeof m.name, "default");
        p->default_material = rtt_scene_add_material(p->scene, &m);
        if (p->default_material == UINT32_MAX) return fail(p, place, ": out of memory");
    }
    *out = p->default_material;
    return true;
}

typedef struct mesh_target {
    const char *name;
    uint32_t material;
    const float *transform;
} mesh_target;

static bool add_mesh(json_parser *p, const json_place *place, const mesh_target *target, const rtt_vec3 *positions,
                     const rtt_vec3 *normals, uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count)
{
    rtt_error inner;
    if (!rtt_scene_add_mesh(p->scene, p->path, target->name, positions, normals, vertex_count, indices,
                            triangle_count, NULL, target->material, target->transform, &inner))
        return fail(p, place, ": %s", inner.message);
    return true;
}

static bool require(json_parser *p, const cJSON *obj, const json_place *place, const char *key, const cJSON **v,
                    json_place *at)
{
    *v = member(obj, place, key, at);
    return *v ? true : fail(p, place, ": missing \"%s\"", key);
}

/* A shape's parameters; false after reporting an error. */
static bool build_shape(json_parser *p, const cJSON *obj, const json_place *place, const char *type,
                        rtt_shape_mesh *mesh)
{
    static const char *const quad[] = {"type", "corners", NULL}, *const box[] = {"type", "min", "max", NULL},
                             *const sphere[] = {"type", "center", "radius", "subdivisions", NULL},
                             *const cylinder[] = {"type", "center", "radius", "height", "segments", NULL},
                             *const torus[] = {"type", "center", "major_radius", "minor_radius", "segments", NULL};
    const cJSON *v;
    json_place at;
    rtt_vec3 center = rtt_v3(0, 0, 0);
    bool built;
    if (strcmp(type, "quad") == 0) {
        rtt_vec3 corners[4];
        if (!check_object(p, obj, place, quad) || !require(p, obj, place, "corners", &v, &at)) return false;
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 4) return fail(p, &at, " must be an array of 4 points");
        for (int i = 0; i < 4; i++) {
            json_place corner = element(&at, i);
            if (!read_vec3(p, cJSON_GetArrayItem(v, i), &corner, &corners[i])) return false;
        }
        built = rtt_shape_quad(corners, mesh);
    } else if (strcmp(type, "box") == 0) {
        rtt_vec3 lo, hi;
        json_place lo_at;
        if (!check_object(p, obj, place, box) || !require(p, obj, place, "min", &v, &lo_at) ||
            !read_vec3(p, v, &lo_at, &lo) || !require(p, obj, place, "max", &v, &at) || !read_vec3(p, v, &at, &hi))
            return false;
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) return fail(p, &at, " must be greater than min on every axis");
        built = rtt_shape_box(lo, hi, mesh);
    } else if (strcmp(type, "sphere") == 0) {
        float radius = 0.0f;
        uint32_t subdivisions = 3;
        if (!check_object(p, obj, place, sphere) || !require(p, obj, place, "radius", &v, &at) ||
            !read_nonneg(p, v, &at, true, &radius))
            return false;
        OPTIONAL(p, obj, place, "center", read_vec3(p, v, at, &center));
        OPTIONAL(p, obj, place, "subdivisions", read_uint(p, v, at, 0, RTT_SHAPE_MAX_SUBDIVISIONS, &subdivisions));
        built = rtt_shape_sphere(center, radius, subdivisions, mesh);
    } else if (strcmp(type, "cylinder") == 0) {
        float radius = 0.0f, height = 0.0f;
        uint32_t segments = 32;
        if (!check_object(p, obj, place, cylinder) || !require(p, obj, place, "radius", &v, &at) ||
            !read_nonneg(p, v, &at, true, &radius) || !require(p, obj, place, "height", &v, &at) ||
            !read_nonneg(p, v, &at, true, &height))
            return false;
        OPTIONAL(p, obj, place, "center", read_vec3(p, v, at, &center));
        OPTIONAL(p, obj, place, "segments", read_uint(p, v, at, RTT_SHAPE_MIN_SEGMENTS, RTT_SHAPE_MAX_SEGMENTS, &segments));
        built = rtt_shape_cylinder(center, radius, height, segments, mesh);
    } else if (strcmp(type, "torus") == 0) {
        float major = 0.0f, minor = 0.0f;
        uint32_t segments[2] = {48, 24};
        if (!check_object(p, obj, place, torus) || !require(p, obj, place, "major_radius", &v, &at) ||
            !read_nonneg(p, v, &at, true, &major) || !require(p, obj, place, "minor_radius", &v, &at) ||
            !read_nonneg(p, v, &at, true, &minor))
            return false;
        if (minor >= major) return fail(p, &at, " must be smaller than major_radius");
        OPTIONAL(p, obj, place, "center", read_vec3(p, v, at, &center));
        if ((v = member(obj, place, "segments", &at))) {
            if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2) return fail(p, &at, " must be [around, tube]");
            for (int i = 0; i < 2; i++) {
                json_place e = element(&at, i);
                if (!read_uint(p, cJSON_GetArrayItem(v, i), &e, RTT_SHAPE_MIN_SEGMENTS, RTT_SHAPE_MAX_SEGMENTS,
                               &segments[i]))
                    return false;
            }
        }
        built = rtt_shape_torus(center, major, minor, segments[0], segments[1], mesh);
    } else {
        json_place type_at;
        member(obj, place, "type", &type_at);
        return fail(p, &type_at, " must be one of \"quad\", \"box\", \"sphere\", \"cylinder\", \"torus\"");
    }
    return built ? true : fail(p, place, ": out of memory");
}

static bool parse_shape(json_parser *p, const cJSON *obj, const json_place *place, const mesh_target *target)
{
    if (!cJSON_IsObject(obj)) return fail(p, place, " must be an object");
    json_place type_at;
    const cJSON *type = member(obj, place, "type", &type_at);
    if (!type) return fail(p, place, ": missing \"type\"");
    if (!cJSON_IsString(type))
        return fail(p, &type_at, " must be one of \"quad\", \"box\", \"sphere\", \"cylinder\", \"torus\"");
    rtt_shape_mesh mesh;
    if (!build_shape(p, obj, place, type->valuestring, &mesh)) return false;
    mesh_target named = *target;
    if (!named.name) named.name = type->valuestring;
    bool ok = add_mesh(p, place, &named, mesh.positions, mesh.normals, mesh.vertex_count, mesh.indices,
                       mesh.triangle_count);
    rtt_shape_mesh_free(&mesh);
    return ok;
}

/* "vertices" / "normals": arrays of points; a NULL-free array of n. */
static bool read_points(json_parser *p, const cJSON *v, const json_place *at, rtt_vec3 **out, uint32_t *n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) == 0) return fail(p, at, " must be a non-empty array of points");
    *n = (uint32_t)cJSON_GetArraySize(v);
    if (!(*out = malloc(sizeof **out * *n))) return fail(p, at, ": out of memory");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        json_place e = element(at, i);
        if (!read_vec3(p, c, &e, &(*out)[i])) return false;
    }
    return true;
}

static bool read_triangles(json_parser *p, const cJSON *v, const json_place *at, uint32_t vertex_count,
                           uint32_t **out, uint32_t *n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) == 0)
        return fail(p, at, " must be a non-empty array of [i, j, k] index triples");
    *n = (uint32_t)cJSON_GetArraySize(v);
    if (!(*out = malloc(sizeof **out * 3u * *n))) return fail(p, at, ": out of memory");
    int t = 0;
    for (const cJSON *c = v->child; c; c = c->next, t++) {
        json_place e = element(at, t);
        if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 3)
            return fail(p, &e, " must be an array of 3 vertex indices");
        int k = 0;
        for (const cJSON *i = c->child; i; i = i->next, k++) {
            if (!cJSON_IsNumber(i) || i->valuedouble != floor(i->valuedouble))
                return fail(p, &e, " must be an array of 3 vertex indices");
            if (!(i->valuedouble >= 0.0 && i->valuedouble < (double)vertex_count))
                return fail(p, &e, ": vertex index %.0f is out of range (%u vertices)", i->valuedouble, vertex_count);
            (*out)[3 * t + k] = (uint32_t)i->valuedouble;
        }
    }
    return true;
}

static bool parse_inline(json_parser *p, const cJSON *obj, const json_place *place, const mesh_target *target)
{
    rtt_vec3 *positions = NULL, *normals = NULL;
    uint32_t *indices = NULL, vertex_count = 0, normal_count = 0, triangle_count = 0;
    json_place at, tri_at;
    const cJSON *v = member(obj, place, "vertices", &at), *tris;
    bool ok = read_points(p, v, &at, &positions, &vertex_count);
    if (ok) ok = require(p, obj, place, "triangles", &tris, &tri_at);
    if (ok) ok = read_triangles(p, tris, &tri_at, vertex_count, &indices, &triangle_count);
    if (ok && (v = member(obj, place, "normals", &at))) {
        ok = read_points(p, v, &at, &normals, &normal_count);
        if (ok && normal_count != vertex_count)
            ok = fail(p, &at, " has %u normals for %u vertices", normal_count, vertex_count);
    }
    char name[32];
    snprintf(name, sizeof name, "mesh%d", place->index);
    mesh_target named = *target;
    if (!named.name) named.name = name;
    if (ok) ok = add_mesh(p, place, &named, positions, normals, vertex_count, indices, triangle_count);
    free(positions);
    free(normals);
    free(indices);
    return ok;
}

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && strcasecmp(path + n - e, ext) == 0;
}

static bool parse_file(json_parser *p, const cJSON *v, const json_place *at, const mesh_target *target,
                       bool material_given)
{
    if (!cJSON_IsString(v) || !v->valuestring[0]) return fail(p, at, " must be a non-empty string (a path)");
    const char *file = v->valuestring;
    if (has_extension(file, ".json") || has_extension(file, ".kdt"))
        return fail(p, at, ": \"%s\" is not a mesh file (scene files and baked trees cannot be meshes)", file);
    char resolved[1024];
    const char *slash = strrchr(p->path, '/');
    if (file[0] == '/' || !slash)
        snprintf(resolved, sizeof resolved, "%s", file);
    else
        snprintf(resolved, sizeof resolved, "%.*s/%s", (int)(slash - p->path), p->path, file);
    FILE *probe = fopen(resolved, "rb");
    if (!probe) return fail(p, at, ": cannot open \"%s\" (%s): %s", file, resolved, strerror(errno));
    fclose(probe);
    rtt_error inner;
    uint32_t material = material_given ? target->material : UINT32_MAX;
    bool ok = has_extension(file, ".bsp")
                  ? rtt_import_q3bsp(p->scene, resolved, target->transform, material, p->bezier_level, &inner)
                  : rtt_import_assimp(p->scene, resolved, target->transform, material, &inner);
    return ok ? true : fail(p, at, ": %s", inner.message);
}

static bool parse_mesh(json_parser *p, const cJSON *obj, const json_place *place)
{
    static const char *const keys[] = {"file",   "shape",    "vertices",  "triangles", "normals",
                                       "name", "material", "transform", NULL};
    if (!check_object(p, obj, place, keys)) return false;
    json_place file_at, shape_at, vertices_at, at;
    const cJSON *file = member(obj, place, "file", &file_at), *shape = member(obj, place, "shape", &shape_at),
                *vertices = member(obj, place, "vertices", &vertices_at);
    if (!file && !shape && !vertices) return fail(p, place, ": needs one of \"file\", \"shape\" or \"vertices\"");
    if ((file != NULL) + (shape != NULL) + (vertices != NULL) > 1) {
        const json_place *second = file && shape ? &shape_at : &vertices_at;
        return fail_in(p, second, place, ": give only one of \"file\", \"shape\" or \"vertices\"");
    }
    if (!vertices) {
        static const char *const inline_only[] = {"triangles", "normals"};
        for (int i = 0; i < 2; i++)
            if (member(obj, place, inline_only[i], &at)) return fail(p, &at, " is only for meshes given by \"vertices\"");
    }
    float transform[16];
    char name[64];
    mesh_target target = {NULL, 0, NULL};
    const cJSON *v;
    if ((v = member(obj, place, "name", &at))) {
        if (file) return fail(p, &at, " is not allowed on a file mesh (its meshes keep the file's names)");
        if (!read_name(p, v, &at, name)) return false;
        target.name = name;
    }
    if ((v = member(obj, place, "transform", &at))) {
        if (!parse_transform(p, v, &at, transform)) return false;
        target.transform = transform;
    }
    const cJSON *material = member(obj, place, "material", &at);
    if (material ? !material_index(p, material, &at, &target.material)
                 : (!file && !default_material(p, place, &target.material)))
        return false;
    if (file) return parse_file(p, file, &file_at, &target, material != NULL);
    if (shape) return parse_shape(p, shape, &shape_at, &target);
    return parse_inline(p, obj, place, &target);
}

/* ---- the file ---- */

typedef bool (*parse_item_fn)(json_parser *p, const cJSON *item, const json_place *place);

static bool parse_list(json_parser *p, const cJSON *root, const json_place *place, const char *key,
                       parse_item_fn parse_item, bool required)
{
    json_place at;
    const cJSON *list = member(root, place, key, &at);
    if (!list) return required ? fail(p, place, ": missing \"%s\" (a scene needs geometry)", key) : true;
    if (!cJSON_IsArray(list) || (required && cJSON_GetArraySize(list) == 0))
        return fail(p, &at, required ? " must be a non-empty array" : " must be an array");
    int i = 0;
    for (const cJSON *c = list->child; c; c = c->next, i++) {
        json_place e = element(&at, i);
        if (!parse_item(p, c, &e)) return false;
    }
    return true;
}

static bool parse_root(json_parser *p, const cJSON *root)
{
    static const char *const keys[] = {"camera", "image",     "background", "ambient", "max_bounces",
                                       "bezier_level", "materials", "lights", "meshes", NULL};
    const json_place place = {NULL, NULL, -1};
    if (!cJSON_IsObject(root)) return fail(p, &place, ": the scene must be a JSON object");
    if (!check_object(p, root, &place, keys)) return false;
    rtt_scene *s = p->scene;
    s->width = RTT_DEFAULT_WIDTH;
    s->height = RTT_DEFAULT_HEIGHT;
    s->ambient = RTT_DEFAULT_AMBIENT;
    s->max_bounces = RTT_DEFAULT_MAX_BOUNCES;
    s->background = rtt_v3(0, 0, 0);
    uint32_t bezier_level = RTT_DEFAULT_BEZIER_LEVEL;
    OPTIONAL(p, root, &place, "image", parse_image(p, v, at));
    OPTIONAL(p, root, &place, "camera", parse_camera(p, v, at));
    OPTIONAL(p, root, &place, "background", read_color(p, v, at, &s->background));
    OPTIONAL(p, root, &place, "ambient", read_number(p, v, at, 0, 1, &s->ambient));
    OPTIONAL(p, root, &place, "max_bounces", read_uint(p, v, at, 0, MAX_BOUNCES, &s->max_bounces));
    OPTIONAL(p, root, &place, "bezier_level", read_uint(p, v, at, 1, MAX_BEZIER_LEVEL, &bezier_level));
    if (!p->bezier_level) p->bezier_level = bezier_level;
    return parse_list(p, root, &place, "materials", parse_material, false) &&
           parse_list(p, root, &place, "lights", parse_light, false) &&
           parse_list(p, root, &place, "meshes", parse_mesh, true);
}

char *rtt_scene_read_text(const char *path, size_t *length, rtt_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return rtt_error_set(err, "%s: cannot open: %s", path, strerror(errno)), NULL;
    size_t capacity = 4096, used = 0;
    char *text = malloc(capacity);
    while (text) {
        used += fread(text + used, 1, capacity - used - 1, f);
        if (used < capacity - 1 || capacity > MAX_FILE_BYTES) break;
        char *grown = realloc(text, capacity * 2);
        if (!grown) free(text);
        text = grown;
        capacity *= 2;
    }
    int read_errno = ferror(f) ? errno : 0;
    fclose(f);
    if (!text) return rtt_error_set(err, "%s: out of memory", path), NULL;
    if (read_errno || capacity > MAX_FILE_BYTES) {
        free(text);
        if (read_errno) rtt_error_set(err, "%s: cannot read: %s", path, strerror(read_errno));
        else rtt_error_set(err, "%s: larger than 1 GiB", path);
        return NULL;
    }
    text[used] = '\0';
    *length = used;
    return text;
}

static int line_of(const char *text, const char *at)
{
    int line = 1;
    for (const char *c = text; c < at; c++) line += *c == '\n';
    return line;
}

static bool syntax_error(const char *path, const char *text, size_t length, const char *at, rtt_error *err)
{
    if (!at || at < text || at > text + length) at = text + length;
    const char *end = text + length;
    if (skip_space(at, end) >= end) { /* reported on the last line that holds anything */
        while (end > text && strchr(" \t\r\n", end[-1])) end--;
        return rtt_error_set(err, "%s:%d: JSON syntax error: unexpected end of file", path, line_of(text, end));
    }
    int n = 0;
    while (at + n < end && n < 24 && at[n] != '\n' && at[n] != '\r') n++;
    char near[32];
    for (int i = 0; i < n; i++) near[i] = isprint((unsigned char)at[i]) ? at[i] : '?';
    near[n] = '\0';
    if (n == 0) return rtt_error_set(err, "%s:%d: JSON syntax error at the end of the line", path, line_of(text, at));
    return rtt_error_set(err, "%s:%d: JSON syntax error near \"%s\"", path, line_of(text, at), near);
}

bool rtt_scene_parse_json(rtt_scene *scene, const char *path, const rtt_scene_load_options *opt, rtt_error *err)
{
    size_t length = 0;
    char *text = rtt_scene_read_text(path, &length, err);
    if (!text) return false;
    const char *end = text + length;
    if (skip_space(text, end) >= end) {
        free(text);
        return rtt_error_set(err, "%s:1: the file is empty (a scene needs at least one mesh)", path);
    }
    if (memchr(text, '\0', length)) {
        int line = line_of(text, memchr(text, '\0', length));
        free(text);
        return rtt_error_set(err, "%s:%d: a NUL byte: this is not a text file", path, line);
    }
    /* the length includes the terminating NUL: cJSON's require_null_terminated
     * looks for it inside the buffer */
    const char *parse_end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, length + 1u, &parse_end, true);
    if (!root) {
        syntax_error(path, text, length, parse_end, err);
        free(text);
        return false;
    }
    json_parser p = {scene, path, text, length, err, UINT32_MAX, opt ? opt->bezier_level : 0};
    bool ok = parse_root(&p, root);
    cJSON_Delete(root);
    free(text);
    return ok;
}

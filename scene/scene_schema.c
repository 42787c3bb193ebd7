/* The JSON scene file: rtt_scene_parse_json (format in scene/README.md).
 *
 * cJSON parses the text; this file checks the top level, image, camera,
 * materials and lights against the format and fills the scene, and holds
 * the typed readers every part of the schema uses (scene_schema.h); meshes
 * are scene_schema_meshes.c.  Unknown and repeated keys are errors: in a
 * hand-written file they are almost always typos. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "file_read.h"
#include "rtt/shade.h"
#include "scene_schema.h"

#define MAX_IMAGE_SIDE 16384.0
#define MAX_BEZIER_LEVEL 64.0

/* ---- errors and typed access ---- */

bool rtt_schema_fail(rtt_schema_parser *p, const rtt_json_place *place, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    rtt_json_error_v(&p->src, p->err, place, place, fmt, args);
    va_end(args);
    return false;
}

bool rtt_schema_fail_in(rtt_schema_parser *p, const rtt_json_place *line_at, const rtt_json_place *path_of,
                        const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    rtt_json_error_v(&p->src, p->err, line_at, path_of, fmt, args);
    va_end(args);
    return false;
}

const cJSON *rtt_schema_member(const cJSON *obj, const rtt_json_place *place, const char *key, rtt_json_place *out)
{
    int index = 0;
    for (const cJSON *c = obj->child; c; c = c->next, index++) {
        if (c->string && strcmp(c->string, key) == 0) {
            *out = (rtt_json_place){place, c->string, index};
            return c;
        }
    }
    *out = (rtt_json_place){place, key, -1};
    return NULL;
}

bool rtt_schema_check_object(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place,
                             const char *const *allowed)
{
    if (!cJSON_IsObject(obj)) return rtt_schema_fail(p, place, " must be an object");
    int index = 0;
    for (const cJSON *c = obj->child; c; c = c->next, index++) {
        rtt_json_place at = {place, c->string, index};
        bool known = false;
        for (const char *const *a = allowed; *a && !known; a++) known = strcmp(*a, c->string) == 0;
        if (!known) return rtt_schema_fail_in(p, &at, place, ": unknown key \"%s\"", c->string);
        for (const cJSON *d = obj->child; d != c; d = d->next)
            if (strcmp(d->string, c->string) == 0)
                return rtt_schema_fail_in(p, &at, place, ": key \"%s\" given twice", c->string);
    }
    return true;
}

bool rtt_schema_read_number(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double lo, double hi,
                        float *out)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi))
        return rtt_schema_fail(p, at, " must be a number between %g and %g", lo, hi);
    *out = (float)v->valuedouble;
    return true;
}

/* > 0 when strict, else >= 0; finite. */
bool rtt_schema_read_nonneg(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, bool strict, float *out)
{
    float value = cJSON_IsNumber(v) ? (float)v->valuedouble : -1.0f;
    if (!isfinite(value) || value < 0.0f || (strict && value == 0.0f))
        return rtt_schema_fail(p, at, strict ? " must be a positive number" : " must be a non-negative number");
    *out = value;
    return true;
}

bool rtt_schema_read_uint(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double lo, double hi,
                          uint32_t *out)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi) ||
        v->valuedouble != floor(v->valuedouble))
        return rtt_schema_fail(p, at, " must be an integer between %.0f and %.0f", lo, hi);
    *out = (uint32_t)v->valuedouble;
    return true;
}

/* rtt_schema_read_point's checks, rounded to float */
bool rtt_schema_read_vec3(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_vec3 *out)
{
    double xyz[3];
    if (!rtt_schema_read_point(p, v, at, xyz)) return false;
    *out = rtt_v3((float)xyz[0], (float)xyz[1], (float)xyz[2]);
    return true;
}

bool rtt_schema_read_point(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double out[3])
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return rtt_schema_fail(p, at, " must be an array of 3 finite numbers");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble) || !isfinite((float)c->valuedouble))
            return rtt_schema_fail(p, at, " must be an array of 3 finite numbers");
        out[i] = c->valuedouble;
    }
    return true;
}

bool rtt_schema_read_color(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_vec3 *out)
{
    if (!rtt_schema_read_vec3(p, v, at, out) || out->x < 0.0f || out->y < 0.0f || out->z < 0.0f)
        return rtt_schema_fail(p, at, " must be an array of 3 non-negative numbers");
    return true;
}

bool rtt_schema_read_name(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, char out[64])
{
    if (!cJSON_IsString(v) || !v->valuestring[0] || strlen(v->valuestring) > 63)
        return rtt_schema_fail(p, at, " must be a string of 1 to 63 bytes");
    strcpy(out, v->valuestring);
    return true;
}

/* ---- top level: image, camera and the scalars ---- */

static bool parse_image(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place)
{
    static const char *const keys[] = {"width", "height", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    RTT_SCHEMA_OPTIONAL(obj, place, "width", rtt_schema_read_uint(p, v, at, 1, MAX_IMAGE_SIDE, &p->scene->width));
    RTT_SCHEMA_OPTIONAL(obj, place, "height", rtt_schema_read_uint(p, v, at, 1, MAX_IMAGE_SIDE, &p->scene->height));
    return true;
}

bool rtt_schema_parse_camera(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, rtt_camera *out,
                             double eye_out[3], double look_at_out[3])
{
    static const char *const keys[] = {"eye", "look_at", "up", "fov", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    rtt_camera cam = {.up = rtt_v3(0, 1, 0), .fov_deg = RTT_DEFAULT_FOV_DEG};
    rtt_json_place eye_at, look_at, up_at;
    const cJSON *eye = rtt_schema_member(obj, place, "eye", &eye_at),
                *look = rtt_schema_member(obj, place, "look_at", &look_at);
    if (!eye) return rtt_schema_fail(p, place, ": missing \"eye\"");
    if (!look) return rtt_schema_fail(p, place, ": missing \"look_at\"");
    double e[3], l[3];
    if (!rtt_schema_read_point(p, eye, &eye_at, e) || !rtt_schema_read_point(p, look, &look_at, l)) return false;
    cam.eye = rtt_v3((float)e[0], (float)e[1], (float)e[2]);
    cam.look_at = rtt_v3((float)l[0], (float)l[1], (float)l[2]);
    RTT_SCHEMA_OPTIONAL(obj, place, "fov", rtt_schema_read_number(p, v, at, 1, 179, &cam.fov_deg));
    const cJSON *up = rtt_schema_member(obj, place, "up", &up_at);
    if (up && !rtt_schema_read_vec3(p, up, &up_at, &cam.up)) return false;
    /* the view direction in double: eye and look_at 1e7 from the origin may
     * round to one float and still be apart */
    const double d[3] = {l[0] - e[0], l[1] - e[1], l[2] - e[2]};
    const double dl = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2])));
    rtt_vec3 view = dl > 0.0 ? rtt_v3((float)(d[0] / dl), (float)(d[1] / dl), (float)(d[2] / dl)) : rtt_v3(0, 0, 0);
    if (rtt_v3_length(view) == 0.0f) return rtt_schema_fail(p, &look_at, " must differ from camera.eye");
    rtt_vec3 side = rtt_v3_cross(rtt_v3_normalize(view), rtt_v3_normalize(cam.up));
    if (!(rtt_v3_length(side) > 1e-6f))
        return rtt_schema_fail(p, up ? &up_at : place,
                               up ? " must not be zero or parallel to the view direction"
                                  : ": the view direction is parallel to the default up [0, 1, 0]; give \"up\"");
    *out = cam;
    memcpy(eye_out, e, sizeof e);
    memcpy(look_at_out, l, sizeof l);
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
static bool check_material_fields(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place,
                                  const material_type_name *t)
{
    static const char *const phong[] = {"specular", "shininess"}, *const reflective[] = {"reflection"},
                             *const transparent[] = {"transparency", "ior"};
    struct { const char *const *keys; size_t n; bool read; } groups[] = {
        {phong, 2, t->phong}, {reflective, 1, t->reflective}, {transparent, 2, t->transparent}};
    for (size_t g = 0; g < 3; g++) {
        for (size_t k = 0; k < groups[g].n && !groups[g].read; k++) {
            rtt_json_place at;
            if (rtt_schema_member(obj, place, groups[g].keys[k], &at))
                return rtt_schema_fail(p, &at, " is not used by a \"%s\" material", t->name);
        }
    }
    return true;
}

static bool parse_material(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place)
{
    static const char *const keys[] = {"name", "type", "diffuse", "specular", "shininess", "reflection",
                                       "transparency", "ior", "edge_width_scale", "diffuse_map", "normal_map", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    rtt_material m = rtt_material_default();
    rtt_json_place name_at, type_at;
    const cJSON *name = rtt_schema_member(obj, place, "name", &name_at);
    if (!name) return rtt_schema_fail(p, place, ": missing \"name\"");
    if (!rtt_schema_read_name(p, name, &name_at, m.name)) return false;
    for (uint32_t i = 0; i < p->scene->material_count; i++)
        if (strcmp(p->scene->materials[i].name, m.name) == 0)
            return rtt_schema_fail(p, &name_at, ": duplicate material name \"%s\" (also materials[%u])", m.name, i);
    const material_type_name *t = &material_types[0];
    const cJSON *type = rtt_schema_member(obj, place, "type", &type_at);
    if (type && !(t = find_material_type(type)))
        return rtt_schema_fail(p, &type_at,
                               " must be one of \"diffuse\", \"specular\", \"reflective\", \"transparent\", "
                               "\"transparent_reflective\"");
    m.type = t->type;
    if (!check_material_fields(p, obj, place, t)) return false;
    RTT_SCHEMA_OPTIONAL(obj, place, "diffuse", rtt_schema_read_color(p, v, at, &m.diffuse));
    RTT_SCHEMA_OPTIONAL(obj, place, "specular", rtt_schema_read_nonneg(p, v, at, false, &m.specular));
    RTT_SCHEMA_OPTIONAL(obj, place, "shininess", rtt_schema_read_nonneg(p, v, at, false, &m.shininess));
    RTT_SCHEMA_OPTIONAL(obj, place, "reflection", rtt_schema_read_number(p, v, at, 0, 1, &m.reflection));
    RTT_SCHEMA_OPTIONAL(obj, place, "transparency", rtt_schema_read_number(p, v, at, 0, 1, &m.transparency));
    RTT_SCHEMA_OPTIONAL(obj, place, "ior", rtt_schema_read_nonneg(p, v, at, true, &m.ior));
    RTT_SCHEMA_OPTIONAL(obj, place, "edge_width_scale", rtt_schema_read_nonneg(p, v, at, true, &m.edge_width_scale));
    RTT_SCHEMA_OPTIONAL(obj, place, "diffuse_map", rtt_schema_read_texture(p, v, at, &m.diffuse_map));
    RTT_SCHEMA_OPTIONAL(obj, place, "normal_map", rtt_schema_read_texture(p, v, at, &m.normal_map));
    if (t->reflective && t->transparent && m.reflection + m.transparency > 1.0f)
        return rtt_schema_fail(p, place, ": reflection + transparency must be at most 1 (it is %g)",
                               (double)(m.reflection + m.transparency));
    if (rtt_scene_add_material(p->scene, &m) == UINT32_MAX) return rtt_schema_fail(p, place, ": out of memory");
    return true;
}

bool rtt_schema_material_index(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t *out)
{
    if (!cJSON_IsString(v)) return rtt_schema_fail(p, at, " must be a string (a material name)");
    for (uint32_t i = 0; i < p->scene->material_count; i++) {
        if (strcmp(p->scene->materials[i].name, v->valuestring) == 0) {
            *out = i;
            return true;
        }
    }
    return rtt_schema_fail(p, at, ": no material named \"%s\"", v->valuestring);
}

/* ---- lights ---- */

bool rtt_schema_read_attenuation(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, float out[3])
{
    rtt_vec3 a = rtt_v3(0, 0, 0);
    if (!rtt_schema_read_vec3(p, v, at, &a) || a.x < 0.0f || a.y < 0.0f || a.z < 0.0f || a.x + a.y + a.z <= 0.0f)
        return rtt_schema_fail(p, at, " must be [constant, linear, quadratic], each >= 0, not all 0");
    out[0] = a.x, out[1] = a.y, out[2] = a.z;
    return true;
}

/* "edge_u" and "edge_v": required on quad lights, not allowed on others; the
 * quad they span must have area. */
static bool parse_quad_edges(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, rtt_light *light)
{
    static const char *const names[2] = {"edge_u", "edge_v"};
    rtt_vec3 *edges[2] = {&light->edge_u, &light->edge_v};
    for (int i = 0; i < 2; i++) {
        rtt_json_place at;
        const cJSON *edge = rtt_schema_member(obj, place, names[i], &at);
        if (light->type != RTT_LIGHT_QUAD && edge) return rtt_schema_fail(p, &at, " is only for quad lights");
        if (light->type != RTT_LIGHT_QUAD) continue;
        if (!edge) return rtt_schema_fail(p, place, ": a quad light needs \"%s\"", names[i]);
        if (!rtt_schema_read_vec3(p, edge, &at, edges[i])) return false;
    }
    if (light->type == RTT_LIGHT_QUAD && !rtt_light_has_area(light))
        return rtt_schema_fail(p, place, ": the quad light's edge_u and edge_v span no finite area (parallel, zero or too long)");
    return true;
}

static bool parse_light(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place)
{
    static const char *const keys[] = {"type",   "position", "color",  "intensity", "attenuation",
                                       "attenuation_distance", "radius", "edge_u", "edge_v", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    rtt_light light = {.type = RTT_LIGHT_POINT, .color = rtt_v3(1, 1, 1), .intensity = 1.0f,
                       .attenuation = {1.0f, 0.0f, 0.0f}};
    rtt_json_place at;
    const cJSON *type = rtt_schema_member(obj, place, "type", &at);
    if (type) {
        if (cJSON_IsString(type) && strcmp(type->valuestring, "sphere") == 0)
            light.type = RTT_LIGHT_SPHERE;
        else if (cJSON_IsString(type) && strcmp(type->valuestring, "quad") == 0)
            light.type = RTT_LIGHT_QUAD;
        else if (!cJSON_IsString(type) || strcmp(type->valuestring, "point") != 0)
            return rtt_schema_fail(p, &at, " must be \"point\", \"sphere\" or \"quad\"");
    }
    const cJSON *position = rtt_schema_member(obj, place, "position", &at);
    if (!position) return rtt_schema_fail(p, place, ": missing \"position\"");
    double exact[3];
    if (!rtt_schema_read_point(p, position, &at, exact)) return false;
    light.position = rtt_v3((float)exact[0], (float)exact[1], (float)exact[2]);
    RTT_SCHEMA_OPTIONAL(obj, place, "color", rtt_schema_read_color(p, v, at, &light.color));
    RTT_SCHEMA_OPTIONAL(obj, place, "intensity", rtt_schema_read_nonneg(p, v, at, false, &light.intensity));
    RTT_SCHEMA_OPTIONAL(obj, place, "attenuation", rtt_schema_read_attenuation(p, v, at, light.attenuation));
    RTT_SCHEMA_OPTIONAL(obj, place, "attenuation_distance",
                        rtt_schema_read_nonneg(p, v, at, true, &light.attenuation_distance));
    const cJSON *radius = rtt_schema_member(obj, place, "radius", &at);
    if (light.type != RTT_LIGHT_SPHERE && radius) return rtt_schema_fail(p, &at, " is only for sphere lights");
    if (light.type == RTT_LIGHT_SPHERE && !radius)
        return rtt_schema_fail(p, place, ": a sphere light needs a \"radius\"");
    if (radius && !rtt_schema_read_nonneg(p, radius, &at, true, &light.radius)) return false;
    if (!parse_quad_edges(p, obj, place, &light)) return false;
    rtt_error inner;
    if (!rtt_scene_add_light_at(p->scene, &light, exact, &inner))
        return rtt_schema_fail(p, place, ": %s", inner.message);
    return true;
}

/* ---- the file ---- */

typedef bool (*parse_item_fn)(rtt_schema_parser *p, const cJSON *item, const rtt_json_place *place);

static bool parse_list(rtt_schema_parser *p, const cJSON *root, const rtt_json_place *place, const char *key,
                       parse_item_fn parse_item, bool required)
{
    rtt_json_place at;
    const cJSON *list = rtt_schema_member(root, place, key, &at);
    if (!list) return required ? rtt_schema_fail(p, place, ": missing \"%s\" (a scene needs geometry)", key) : true;
    if (!cJSON_IsArray(list) || (required && cJSON_GetArraySize(list) == 0))
        return rtt_schema_fail(p, &at, required ? " must be a non-empty array" : " must be an array");
    int i = 0;
    for (const cJSON *c = list->child; c; c = c->next, i++) {
        rtt_json_place e = rtt_json_element(&at, i);
        if (!parse_item(p, c, &e)) return false;
    }
    return true;
}

static bool parse_root(rtt_schema_parser *p, const cJSON *root)
{
    static const char *const keys[] = {"camera", "image",     "background", "ambient", "max_bounces",
                                       "bezier_level", "materials", "lights", "meshes", NULL};
    const rtt_json_place place = {NULL, NULL, -1};
    rtt_json_place camera_at;
    if (!cJSON_IsObject(root)) return rtt_schema_fail(p, &place, ": the scene must be a JSON object");
    if (!rtt_schema_check_object(p, root, &place, keys)) return false;
    rtt_scene *s = p->scene;
    s->width = RTT_DEFAULT_WIDTH;
    s->height = RTT_DEFAULT_HEIGHT;
    s->ambient = RTT_DEFAULT_AMBIENT;
    s->max_bounces = RTT_DEFAULT_MAX_BOUNCES;
    s->background = rtt_v3(0, 0, 0);
    uint32_t bezier_level = RTT_DEFAULT_BEZIER_LEVEL;
    RTT_SCHEMA_OPTIONAL(root, &place, "image", parse_image(p, v, at));
    const cJSON *camera = rtt_schema_member(root, &place, "camera", &camera_at);
    rtt_camera file_camera;
    double eye[3], look_at[3];
    if (camera && !rtt_schema_parse_camera(p, camera, &camera_at, &file_camera, eye, look_at)) return false;
    if (camera) rtt_scene_set_file_camera(s, &file_camera, eye, look_at);
    RTT_SCHEMA_OPTIONAL(root, &place, "background", rtt_schema_read_color(p, v, at, &s->background));
    RTT_SCHEMA_OPTIONAL(root, &place, "ambient", rtt_schema_read_number(p, v, at, 0, 1, &s->ambient));
    RTT_SCHEMA_OPTIONAL(root, &place, "max_bounces",
                        rtt_schema_read_uint(p, v, at, 0, RTT_MAX_BOUNCES, &s->max_bounces));
    RTT_SCHEMA_OPTIONAL(root, &place, "bezier_level",
                        rtt_schema_read_uint(p, v, at, 1, MAX_BEZIER_LEVEL, &bezier_level));
    if (!p->bezier_level) p->bezier_level = bezier_level;
    return rtt_schema_meshes_reserve(p, cJSON_GetObjectItemCaseSensitive(root, "meshes")) &&
           parse_list(p, root, &place, "materials", parse_material, false) &&
           parse_list(p, root, &place, "lights", parse_light, false) &&
           parse_list(p, root, &place, "meshes", rtt_schema_parse_mesh, true);
}

bool rtt_schema_parse_file(const char *path, const char *empty, rtt_schema_parser *p, rtt_schema_root_reader read,
                           void *context)
{
    size_t length = 0;
    char *text = rtt_file_read(path, RTT_FILE_TEXT_MAX, &length, p->err);
    if (!text) return false;
    p->src = (rtt_json_source){path, text, length};
    bool ok = false;
    const char *nul = memchr(text, '\0', length);
    if (rtt_json_is_blank(text, length)) {
        rtt_error_set(p->err, "%s:1: the file is empty (%s)", path, empty);
    } else if (nul) {
        rtt_error_set(p->err, "%s:%d: a NUL byte: this is not a text file", path, rtt_json_line_at(text, nul));
    } else {
        /* the length includes the terminating NUL: cJSON's require_null_terminated
         * looks for it inside the buffer */
        const char *parse_end = NULL;
        cJSON *root = cJSON_ParseWithLengthOpts(text, length + 1u, &parse_end, true);
        if (!root) {
            rtt_json_syntax_error(&p->src, parse_end, p->err);
        } else {
            ok = read(p, root, context);
            cJSON_Delete(root);
        }
    }
    free(text);
    p->src.text = NULL;
    return ok;
}

static bool read_scene_root(rtt_schema_parser *p, const cJSON *root, void *context)
{
    (void)context;
    return parse_root(p, root);
}

bool rtt_scene_parse_json(rtt_scene *scene, const char *path, const rtt_scene_load_options *opt, rtt_error *err)
{
    rtt_schema_parser p = {scene, {path, NULL, 0}, err, UINT32_MAX, opt ? opt->bezier_level : 0};
    return rtt_schema_parse_file(path, "a scene needs at least one mesh", &p, read_scene_root, NULL);
}

/* The JSON scene file's meshes[i] (format in scene/README.md): each mesh
 * gives its geometry in exactly one way (a mesh file, a built-in shape or
 * inline vertices and triangles), with an optional name, material and
 * transform.  Part of the schema of scene_schema.h.
 *
 * A file reference goes to the importer its kind names (rtt_file_kind_of);
 * its path is relative to the scene file's directory, and the file is
 * opened first so that a missing one is named by the scene file's line. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/files.h"
#include "file_kind.h"
#include "rtt/memory_budget.h"
#include "scene_schema.h"
#include "shapes.h"
#include "textures.h"
#include "transform.h"

/* transform = T * Rz * Ry * Rx * S (scene/README.md). */
static bool parse_transform(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, double out[16])
{
    static const char *const keys[] = {"scale", "rotate_deg", "translate", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    double scale[3] = {1, 1, 1}, rotate[3] = {0, 0, 0}, translate[3] = {0, 0, 0};
    rtt_json_place at;
    const cJSON *s = rtt_schema_member(obj, place, "scale", &at);
    if (s && cJSON_IsNumber(s)) {
        double k = s->valuedouble;
        if (!isfinite((float)k) || (float)k == 0.0f)
            return rtt_schema_fail(p, &at, " must be a non-zero number or an array of 3 non-zero numbers");
        scale[0] = scale[1] = scale[2] = k;
    } else if (s && (!rtt_schema_read_point(p, s, &at, scale) || (float)scale[0] == 0.0f ||
                     (float)scale[1] == 0.0f || (float)scale[2] == 0.0f)) {
        return rtt_schema_fail(p, &at, " must be a non-zero number or an array of 3 non-zero numbers");
    }
    RTT_SCHEMA_OPTIONAL(obj, place, "rotate_deg", rtt_schema_read_point(p, v, at, rotate));
    RTT_SCHEMA_OPTIONAL(obj, place, "translate", rtt_schema_read_point(p, v, at, translate));
    rtt_transform_compose(scale, rotate, translate, out);
    return true;
}

/* The material of a shape or inline mesh without "material": grey diffuse,
 * added once, the first time a mesh needs it. */
static bool default_material(rtt_schema_parser *p, const rtt_json_place *place, uint32_t *out)
{
    if (p->default_material == UINT32_MAX) {
        rtt_material m = rtt_material_default();
        snprintf(m.name, sizeof m.name, "default");
        p->default_material = rtt_scene_add_material(p->scene, &m);
        if (p->default_material == UINT32_MAX) return rtt_schema_fail(p, place, ": out of memory");
    }
    *out = p->default_material;
    return true;
}

typedef struct mesh_target {
    const char *name;
    uint32_t material;
    const double *transform;
} mesh_target;

/* positions in float (shapes), or exact_positions in double (3 per vertex:
 * inline vertices) when positions is NULL */
static bool add_mesh(rtt_schema_parser *p, const rtt_json_place *place, const mesh_target *target,
                     const rtt_vec3 *positions, const double *exact_positions, const rtt_vec3 *normals,
                     uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count)
{
    rtt_error inner;
    bool ok = positions ? rtt_scene_add_mesh(p->scene, p->src.path, target->name, positions, normals, vertex_count,
                                             indices, triangle_count, NULL, target->material, target->transform,
                                             &inner)
                        : rtt_scene_add_mesh_exact(p->scene, p->src.path, target->name, exact_positions, normals,
                                                   vertex_count, indices, triangle_count, target->material,
                                                   target->transform, &inner);
    if (!ok) return rtt_schema_fail(p, place, ": %s", inner.message);
    return true;
}

static bool require(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, const char *key,
                    const cJSON **v, rtt_json_place *at)
{
    *v = rtt_schema_member(obj, place, key, at);
    return *v ? true : rtt_schema_fail(p, place, ": missing \"%s\"", key);
}

/* ---- shapes ---- */

#define SHAPE_TYPES " must be one of \"quad\", \"box\", \"sphere\", \"cylinder\", \"torus\""

/* A shape's parameters; false after reporting an error. */
static bool build_shape(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, const char *type,
                        rtt_shape_mesh *mesh)
{
    static const char *const quad[] = {"type", "corners", NULL}, *const box[] = {"type", "min", "max", NULL},
                             *const sphere[] = {"type", "center", "radius", "subdivisions", NULL},
                             *const cylinder[] = {"type", "center", "radius", "height", "segments", NULL},
                             *const torus[] = {"type", "center", "major_radius", "minor_radius", "segments", NULL};
    const cJSON *v;
    rtt_json_place at;
    rtt_vec3 center = rtt_v3(0, 0, 0);
    bool built;
    if (strcmp(type, "quad") == 0) {
        rtt_vec3 corners[4];
        if (!rtt_schema_check_object(p, obj, place, quad) || !require(p, obj, place, "corners", &v, &at))
            return false;
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 4)
            return rtt_schema_fail(p, &at, " must be an array of 4 points");
        for (int i = 0; i < 4; i++) {
            rtt_json_place corner = rtt_json_element(&at, i);
            if (!rtt_schema_read_vec3(p, cJSON_GetArrayItem(v, i), &corner, &corners[i])) return false;
        }
        built = rtt_shape_quad(corners, mesh);
    } else if (strcmp(type, "box") == 0) {
        rtt_vec3 lo, hi;
        rtt_json_place lo_at;
        if (!rtt_schema_check_object(p, obj, place, box) || !require(p, obj, place, "min", &v, &lo_at) ||
            !rtt_schema_read_vec3(p, v, &lo_at, &lo) || !require(p, obj, place, "max", &v, &at) ||
            !rtt_schema_read_vec3(p, v, &at, &hi))
            return false;
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            return rtt_schema_fail(p, &at, " must be greater than min on every axis");
        built = rtt_shape_box(lo, hi, mesh);
    } else if (strcmp(type, "sphere") == 0) {
        float radius = 0.0f;
        uint32_t subdivisions = 3;
        if (!rtt_schema_check_object(p, obj, place, sphere) || !require(p, obj, place, "radius", &v, &at) ||
            !rtt_schema_read_nonneg(p, v, &at, true, &radius))
            return false;
        RTT_SCHEMA_OPTIONAL(obj, place, "center", rtt_schema_read_vec3(p, v, at, &center));
        RTT_SCHEMA_OPTIONAL(obj, place, "subdivisions",
                            rtt_schema_read_uint(p, v, at, 0, RTT_SHAPE_MAX_SUBDIVISIONS, &subdivisions));
        built = rtt_shape_sphere(center, radius, subdivisions, mesh);
    } else if (strcmp(type, "cylinder") == 0) {
        float radius = 0.0f, height = 0.0f;
        uint32_t segments = 32;
        if (!rtt_schema_check_object(p, obj, place, cylinder) || !require(p, obj, place, "radius", &v, &at) ||
            !rtt_schema_read_nonneg(p, v, &at, true, &radius) || !require(p, obj, place, "height", &v, &at) ||
            !rtt_schema_read_nonneg(p, v, &at, true, &height))
            return false;
        RTT_SCHEMA_OPTIONAL(obj, place, "center", rtt_schema_read_vec3(p, v, at, &center));
        RTT_SCHEMA_OPTIONAL(obj, place, "segments",
                            rtt_schema_read_uint(p, v, at, RTT_SHAPE_MIN_SEGMENTS, RTT_SHAPE_MAX_SEGMENTS, &segments));
        built = rtt_shape_cylinder(center, radius, height, segments, mesh);
    } else if (strcmp(type, "torus") == 0) {
        float major = 0.0f, minor = 0.0f;
        uint32_t segments[2] = {48, 24};
        if (!rtt_schema_check_object(p, obj, place, torus) || !require(p, obj, place, "major_radius", &v, &at) ||
            !rtt_schema_read_nonneg(p, v, &at, true, &major) || !require(p, obj, place, "minor_radius", &v, &at) ||
            !rtt_schema_read_nonneg(p, v, &at, true, &minor))
            return false;
        if (minor >= major) return rtt_schema_fail(p, &at, " must be smaller than major_radius");
        RTT_SCHEMA_OPTIONAL(obj, place, "center", rtt_schema_read_vec3(p, v, at, &center));
        if ((v = rtt_schema_member(obj, place, "segments", &at))) {
            if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
                return rtt_schema_fail(p, &at, " must be [around, tube]");
            for (int i = 0; i < 2; i++) {
                rtt_json_place e = rtt_json_element(&at, i);
                if (!rtt_schema_read_uint(p, cJSON_GetArrayItem(v, i), &e, RTT_SHAPE_MIN_SEGMENTS,
                                          RTT_SHAPE_MAX_SEGMENTS, &segments[i]))
                    return false;
            }
        }
        built = rtt_shape_torus(center, major, minor, segments[0], segments[1], mesh);
    } else {
        rtt_json_place type_at;
        rtt_schema_member(obj, place, "type", &type_at);
        return rtt_schema_fail(p, &type_at, SHAPE_TYPES);
    }
    return built ? true : rtt_schema_fail(p, place, ": out of memory");
}

static bool parse_shape(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place,
                        const mesh_target *target)
{
    if (!cJSON_IsObject(obj)) return rtt_schema_fail(p, place, " must be an object");
    rtt_json_place type_at;
    const cJSON *type = rtt_schema_member(obj, place, "type", &type_at);
    if (!type) return rtt_schema_fail(p, place, ": missing \"type\"");
    if (!cJSON_IsString(type))
        return rtt_schema_fail(p, &type_at, SHAPE_TYPES);
    rtt_shape_mesh mesh;
    if (!build_shape(p, obj, place, type->valuestring, &mesh)) return false;
    mesh_target named = *target;
    if (!named.name) named.name = type->valuestring;
    bool ok = add_mesh(p, place, &named, mesh.positions, NULL, mesh.normals, mesh.vertex_count, mesh.indices,
                       mesh.triangle_count);
    rtt_shape_mesh_free(&mesh);
    return ok;
}

/* ---- inline geometry ---- */

/* "vertices" / "normals": a non-empty array of n points. */
static bool read_points(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_vec3 **out, uint32_t *n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) == 0)
        return rtt_schema_fail(p, at, " must be a non-empty array of points");
    *n = (uint32_t)cJSON_GetArraySize(v);
    if (!(*out = malloc(sizeof **out * *n))) return rtt_schema_fail(p, at, ": out of memory");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        rtt_json_place e = rtt_json_element(at, i);
        if (!rtt_schema_read_vec3(p, c, &e, &(*out)[i])) return false;
    }
    return true;
}

/* "vertices": the same in double, 3 per point, as the file gives them. */
static bool read_exact_points(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, double **out,
                              uint32_t *n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) == 0)
        return rtt_schema_fail(p, at, " must be a non-empty array of points");
    *n = (uint32_t)cJSON_GetArraySize(v);
    if (!(*out = malloc(3 * sizeof **out * *n))) return rtt_schema_fail(p, at, ": out of memory");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        rtt_json_place e = rtt_json_element(at, i);
        if (!rtt_schema_read_point(p, c, &e, &(*out)[3 * (size_t)i])) return false;
    }
    return true;
}

static bool read_triangles(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t vertex_count,
                           uint32_t **out, uint32_t *n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) == 0)
        return rtt_schema_fail(p, at, " must be a non-empty array of [i, j, k] index triples");
    *n = (uint32_t)cJSON_GetArraySize(v);
    if (!(*out = malloc(sizeof **out * 3u * *n))) return rtt_schema_fail(p, at, ": out of memory");
    int t = 0;
    for (const cJSON *c = v->child; c; c = c->next, t++) {
        rtt_json_place e = rtt_json_element(at, t);
        if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 3)
            return rtt_schema_fail(p, &e, " must be an array of 3 vertex indices");
        int k = 0;
        for (const cJSON *i = c->child; i; i = i->next, k++) {
            if (!cJSON_IsNumber(i) || i->valuedouble != floor(i->valuedouble))
                return rtt_schema_fail(p, &e, " must be an array of 3 vertex indices");
            if (!(i->valuedouble >= 0.0 && i->valuedouble < (double)vertex_count))
                return rtt_schema_fail(p, &e, ": vertex index %.0f is out of range (%u vertices)", i->valuedouble,
                                       vertex_count);
            (*out)[3 * t + k] = (uint32_t)i->valuedouble;
        }
    }
    return true;
}

static bool parse_inline(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place,
                         const mesh_target *target)
{
    rtt_vec3 *normals = NULL;
    double *positions = NULL;
    uint32_t *indices = NULL, vertex_count = 0, normal_count = 0, triangle_count = 0;
    rtt_json_place at, tri_at;
    const cJSON *v = rtt_schema_member(obj, place, "vertices", &at), *tris;
    bool ok = read_exact_points(p, v, &at, &positions, &vertex_count);
    if (ok) ok = require(p, obj, place, "triangles", &tris, &tri_at);
    if (ok) ok = read_triangles(p, tris, &tri_at, vertex_count, &indices, &triangle_count);
    if (ok && (v = rtt_schema_member(obj, place, "normals", &at))) {
        ok = read_points(p, v, &at, &normals, &normal_count);
        if (ok && normal_count != vertex_count)
            ok = rtt_schema_fail(p, &at, " has %u normals for %u vertices", normal_count, vertex_count);
    }
    float *texcoords = NULL;
    if (ok && (v = rtt_schema_member(obj, place, "texcoords", &at)))
        ok = rtt_schema_read_texcoords(p, v, &at, vertex_count, &texcoords);
    char name[32];
    snprintf(name, sizeof name, "mesh%d", place->index);
    mesh_target named = *target;
    if (!named.name) named.name = name;
    const uint32_t first_vertex = p->scene->vertex_count;
    if (ok) ok = add_mesh(p, place, &named, NULL, positions, normals, vertex_count, indices, triangle_count);
    rtt_error inner;
    if (ok && texcoords && !rtt_scene_set_texcoords(p->scene, first_vertex, texcoords, vertex_count, &inner))
        ok = rtt_schema_fail(p, place, ": %s", inner.message);
    free(texcoords);
    free(positions);
    free(normals);
    free(indices);
    return ok;
}

/* ---- mesh files ---- */

static bool parse_file(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, const mesh_target *target,
                       bool material_given)
{
    if (!cJSON_IsString(v) || !v->valuestring[0]) return rtt_schema_fail(p, at, " must be a non-empty string (a path)");
    const char *file = v->valuestring;
    rtt_file_kind kind = rtt_file_kind_of(file);
    if (kind == RTT_FILE_SCENE_JSON || kind == RTT_FILE_KDT)
        return rtt_schema_fail(p, at, ": \"%s\" is not a mesh file (scene files and baked trees cannot be meshes)",
                               file);
    char resolved[1024];
    rtt_path_beside(p->src.path, file, resolved, sizeof resolved);
    rtt_error inner;
    FILE *probe = rtt_file_open_regular(resolved, &inner);
    if (!probe && errno == ENOENT)
        return rtt_schema_fail(p, at, ": cannot open \"%s\" (%s): %s", file, resolved, strerror(errno));
    if (!probe) return rtt_schema_fail(p, at, ": %s", inner.message);
    fclose(probe);
    uint32_t material = material_given ? target->material : UINT32_MAX;
    bool ok = kind == RTT_FILE_Q3BSP
                  ? rtt_import_q3bsp(p->scene, resolved, target->transform, material, p->bezier_level, &inner)
                  : rtt_import_assimp(p->scene, resolved, target->transform, material, &inner);
    return ok ? true : rtt_schema_fail(p, at, ": %s", inner.message);
}

/* ---- one mesh ---- */

bool rtt_schema_parse_mesh(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place)
{
    static const char *const keys[] = {"file",   "shape",    "vertices",  "triangles", "normals", "texcoords",
                                       "name", "material", "transform", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    rtt_json_place file_at, shape_at, vertices_at, at;
    const cJSON *file = rtt_schema_member(obj, place, "file", &file_at),
                *shape = rtt_schema_member(obj, place, "shape", &shape_at),
                *vertices = rtt_schema_member(obj, place, "vertices", &vertices_at);
    if (!file && !shape && !vertices)
        return rtt_schema_fail(p, place, ": needs one of \"file\", \"shape\" or \"vertices\"");
    if ((file != NULL) + (shape != NULL) + (vertices != NULL) > 1) {
        const rtt_json_place *second = file && shape ? &shape_at : &vertices_at;
        return rtt_schema_fail_in(p, second, place, ": give only one of \"file\", \"shape\" or \"vertices\"");
    }
    if (!vertices) {
        static const char *const inline_only[] = {"triangles", "normals", "texcoords"};
        for (int i = 0; i < 3; i++)
            if (rtt_schema_member(obj, place, inline_only[i], &at))
                return rtt_schema_fail(p, &at, " is only for meshes given by \"vertices\"");
    }
    double transform[16];
    char name[64];
    mesh_target target = {NULL, 0, NULL};
    const cJSON *v;
    if ((v = rtt_schema_member(obj, place, "name", &at))) {
        if (file) return rtt_schema_fail(p, &at, " is not allowed on a file mesh (its meshes keep the file's names)");
        if (!rtt_schema_read_name(p, v, &at, name)) return false;
        target.name = name;
    }
    if ((v = rtt_schema_member(obj, place, "transform", &at))) {
        if (!parse_transform(p, v, &at, transform)) return false;
        target.transform = transform;
    }
    const cJSON *material = rtt_schema_member(obj, place, "material", &at);
    if (material ? !rtt_schema_material_index(p, material, &at, &target.material)
                 : (!file && !default_material(p, place, &target.material)))
        return false;
    if (file) return parse_file(p, file, &file_at, &target, material != NULL);
    if (shape) return parse_shape(p, shape, &shape_at, &target);
    return parse_inline(p, obj, place, &target);
}

/* ---- the memory budget, before any mesh is built ---- */

static uint32_t member_uint(const cJSON *obj, const char *key, uint32_t otherwise, uint32_t lo, uint32_t hi)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi)) return otherwise; /* the parse says why */
    return (uint32_t)v->valuedouble;
}

bool rtt_schema_meshes_reserve(rtt_schema_parser *p, const cJSON *meshes)
{
    uint64_t triangles = 0;
    const cJSON *mesh;
    cJSON_ArrayForEach(mesh, meshes) {
        const cJSON *shape = cJSON_GetObjectItemCaseSensitive(mesh, "shape");
        const cJSON *inline_triangles = cJSON_GetObjectItemCaseSensitive(mesh, "triangles");
        const cJSON *type = cJSON_GetObjectItemCaseSensitive(shape, "type");
        if (cJSON_IsString(type)) {
            const cJSON *segments = cJSON_GetObjectItemCaseSensitive(shape, "segments");
            uint32_t around = 48, tube = 24;
            if (cJSON_IsArray(segments) && cJSON_GetArraySize(segments) == 2) {
                const cJSON *a = cJSON_GetArrayItem(segments, 0), *t = cJSON_GetArrayItem(segments, 1);
                if (cJSON_IsNumber(a) && a->valuedouble >= RTT_SHAPE_MIN_SEGMENTS && a->valuedouble <= RTT_SHAPE_MAX_SEGMENTS)
                    around = (uint32_t)a->valuedouble;
                if (cJSON_IsNumber(t) && t->valuedouble >= RTT_SHAPE_MIN_SEGMENTS && t->valuedouble <= RTT_SHAPE_MAX_SEGMENTS)
                    tube = (uint32_t)t->valuedouble;
            }
            triangles += rtt_shape_triangle_count(
                type->valuestring, member_uint(shape, "subdivisions", 3, 0, RTT_SHAPE_MAX_SUBDIVISIONS),
                member_uint(shape, "segments", 32, RTT_SHAPE_MIN_SEGMENTS, RTT_SHAPE_MAX_SEGMENTS), around, tube);
        } else if (cJSON_IsArray(inline_triangles)) {
            triangles += (uint64_t)cJSON_GetArraySize(inline_triangles);
        }
    }
    return rtt_scene_budget_reserve(p->scene, p->src.path, triangles, 0, p->err);
}

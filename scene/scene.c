/* The scene model: assembling a scene from what the loaders find, filling in
 * the defaults of docs/ARCHITECTURE.md ("model only what a scene requires"), and
 * loading any supported file with the reader its kind names
 * (rtt_file_kind_of, file_kind.c).
 *
 * Geometry is appended mesh by mesh in the global triangle order; every
 * vertex is validated (finite after the transform) and every index checked
 * before it is stored, so engines never see a bad index or a NaN. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/files.h"
#include "rtt/memory_budget.h"
#include "rtt/scene.h"
#include "rtt/shade.h"
#include "scene_build.h"
#include "rtt/views.h"
#include "textures.h"
#include "transform.h"

/* Scenes larger than this are refused: indices stay far from overflow and a
 * hostile file cannot ask for unbounded memory through the counts. */
#define SCENE_MAX_TRIANGLES (1u << 28)
#define SCENE_MAX_VERTICES (1u << 28)

rtt_material rtt_material_default(void)
{
    rtt_material m;
    memset(&m, 0, sizeof m);
    strcpy(m.name, "default");
    m.type = RTT_MATERIAL_DIFFUSE;
    m.diffuse = rtt_v3(0.7f, 0.7f, 0.7f);
    m.specular = 0.5f;
    m.shininess = 32.0f;
    m.reflection = 0.5f;
    m.transparency = 0.8f;
    m.ior = 1.5f;
    m.edge_width_scale = 1.0f;
    return m;
}

/* A scene under construction: the public scene and its vertices in double
 * (the file's coordinates after each mesh's transform), kept until
 * rtt_scene_finish stores them in float relative to the scene's centre. */
typedef struct scene_builder {
    rtt_scene scene;
    double *exact;      /* 3 per vertex; NULL once finished (or for a .kdt) */
    /* the positions of the lights and of the file's camera the loaders gave,
     * in the scene's own coordinates, in double, until finish moves them */
    double *light_exact;          /* 3 per light */
    uint32_t light_exact_count;   /* lights light_exact covers */
    bool camera_exact_given;
    double camera_exact[2][3];    /* eye, look_at */
    bool centred;                 /* finish has moved everything to the stored frame */
} scene_builder;

static scene_builder *builder_of(rtt_scene *scene) { return (scene_builder *)scene; }

rtt_scene *rtt_scene_new(const char *path, rtt_error *err)
{
    scene_builder *builder = calloc(1, sizeof *builder);
    rtt_scene *scene = builder ? &builder->scene : NULL;
    if (!scene) {
        rtt_error_set(err, "%s: out of memory", path);
        return NULL;
    }
    snprintf(scene->path, sizeof scene->path, "%s", path);
    scene->bounds = rtt_bounds_empty();
    scene->background = rtt_v3(0.0f, 0.0f, 0.0f);
    scene->ambient = RTT_DEFAULT_AMBIENT;
    scene->max_bounces = RTT_DEFAULT_MAX_BOUNCES;
    return scene;
}

void rtt_scene_free(rtt_scene *scene)
{
    if (!scene) return;
    if (scene->baked && scene->baked_free) scene->baked_free(scene->baked);
    free(scene->vertices);
    free(scene->normals);
    free(scene->triangles);
    free(scene->triangle_material);
    free(scene->triangle_mesh);
    free(scene->meshes);
    free(scene->materials);
    free(scene->lights);
    rtt_scene_textures_free(scene);
    free(builder_of(scene)->exact);
    free(builder_of(scene)->light_exact);
    free(builder_of(scene));
}

/* Grows *array (of `size`-byte elements) to hold `needed`; *capacity tracks it. */
static bool grow(void **array, size_t size, uint32_t *capacity, uint64_t needed)
{
    if (needed <= *capacity) return true;
    uint64_t cap = *capacity ? *capacity : 16;
    while (cap < needed) cap *= 2;
    if (cap > UINT32_MAX) cap = UINT32_MAX;
    void *p = realloc(*array, (size_t)cap * size);
    if (!p) return false;
    *array = p;
    *capacity = (uint32_t)cap;
    return true;
}

uint32_t rtt_scene_add_material(rtt_scene *scene, const rtt_material *material)
{
    uint32_t cap = scene->material_count;
    if (!grow((void **)&scene->materials, sizeof *scene->materials, &cap, (uint64_t)scene->material_count + 1))
        return UINT32_MAX;
    scene->materials[scene->material_count] = *material;
    return scene->material_count++;
}

bool rtt_scene_add_light_at(rtt_scene *scene, const rtt_light *light, const double position[3], rtt_error *err)
{
    scene_builder *builder = builder_of(scene);
    rtt_light *p = realloc(scene->lights, ((size_t)scene->light_count + 1) * sizeof *p);
    if (!p) return rtt_error_set(err, "%s: out of memory for lights", scene->path);
    scene->lights = p;
    if (!builder->centred) { /* before finish: kept in double until the scene is centred */
        double *exact = realloc(builder->light_exact, 3 * ((size_t)scene->light_count + 1) * sizeof *exact);
        if (!exact) return rtt_error_set(err, "%s: out of memory for lights", scene->path);
        builder->light_exact = exact;
        memcpy(&exact[3 * (size_t)scene->light_count], position, 3 * sizeof *exact);
        builder->light_exact_count = scene->light_count + 1;
    }
    scene->lights[scene->light_count] = *light;
    scene->lights[scene->light_count].position = rtt_v3((float)position[0], (float)position[1], (float)position[2]);
    scene->light_count++;
    return true;
}

bool rtt_scene_add_light(rtt_scene *scene, const rtt_light *light, rtt_error *err)
{
    const double position[3] = {light->position.x, light->position.y, light->position.z};
    return rtt_scene_add_light_at(scene, light, position, err);
}

void rtt_scene_set_file_camera(rtt_scene *scene, const rtt_camera *camera, const double eye[3],
                               const double look_at[3])
{
    scene_builder *builder = builder_of(scene);
    scene->camera = *camera;
    scene->camera.eye = rtt_v3((float)eye[0], (float)eye[1], (float)eye[2]);
    scene->camera.look_at = rtt_v3((float)look_at[0], (float)look_at[1], (float)look_at[2]);
    memcpy(builder->camera_exact[0], eye, sizeof builder->camera_exact[0]);
    memcpy(builder->camera_exact[1], look_at, sizeof builder->camera_exact[1]);
    builder->camera_exact_given = true;
}

/* Capacities of the growing geometry arrays live beside the counts: the
 * arrays are reallocated to exact size per mesh, which keeps the struct free
 * of bookkeeping fields and costs one realloc per mesh. */
static bool resize(void **array, size_t count, size_t size)
{
    if (count == 0) return true;
    void *p = realloc(*array, count * size);
    if (!p) return false;
    *array = p;
    return true;
}

static bool check_mesh_input(const rtt_scene *scene, const char *source, const rtt_vec3 *positions,
                             const double *exact_positions, uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count,
                             const uint32_t *triangle_materials, uint32_t material, rtt_error *err)
{
    if ((uint64_t)scene->triangle_count + triangle_count > SCENE_MAX_TRIANGLES)
        return rtt_error_set(err, "%s: too many triangles (the limit is %u)", source, SCENE_MAX_TRIANGLES);
    if ((uint64_t)scene->vertex_count + vertex_count > SCENE_MAX_VERTICES)
        return rtt_error_set(err, "%s: too many vertices (the limit is %u)", source, SCENE_MAX_VERTICES);
    for (uint32_t i = 0; i < vertex_count; i++)
        if (positions ? !rtt_v3_is_finite(positions[i])
                      : !(isfinite(exact_positions[3 * (size_t)i]) && isfinite(exact_positions[3 * (size_t)i + 1]) &&
                          isfinite(exact_positions[3 * (size_t)i + 2])))
            return rtt_error_set(err, "%s: vertex %u has a NaN or infinite coordinate", source, i);
    for (uint32_t f = 0; f < triangle_count; f++)
        for (int k = 0; k < 3; k++)
            if (indices[3 * (size_t)f + k] >= vertex_count)
                return rtt_error_set(err, "%s: face %u: vertex index %u is out of range (%u vertices)", source, f,
                                     indices[3 * (size_t)f + k], vertex_count);
    if (!triangle_materials && material >= scene->material_count)
        return rtt_error_set(err, "%s: material index %u is out of range", source, material);
    for (uint32_t f = 0; triangle_materials && f < triangle_count; f++)
        if (triangle_materials[f] >= scene->material_count)
            return rtt_error_set(err, "%s: face %u: material index %u is out of range", source, f,
                                 triangle_materials[f]);
    return true;
}

/* rtt_scene_add_mesh and rtt_scene_add_mesh_exact: positions in float, or
 * exact_positions (3 doubles per vertex) when positions is NULL. */
static bool add_mesh(rtt_scene *scene, const char *source, const char *name, const rtt_vec3 *positions,
                     const double *exact_positions, const rtt_vec3 *normals, uint32_t vertex_count,
                     const uint32_t *indices, uint32_t triangle_count, const uint32_t *triangle_materials,
                     uint32_t material, const double transform[16], rtt_error *err)
{
    if (!check_mesh_input(scene, source, positions, exact_positions, vertex_count, indices, triangle_count,
                          triangle_materials, material, err))
        return false;
    const uint32_t v0 = scene->vertex_count, t0 = scene->triangle_count;
    const size_t vertices = (size_t)v0 + vertex_count, triangles = (size_t)t0 + triangle_count;
    const bool had_normals = scene->normals != NULL;
    if (!resize((void **)&scene->vertices, vertices, sizeof *scene->vertices) ||
        !resize((void **)&scene->triangles, triangles, sizeof *scene->triangles) ||
        !resize((void **)&scene->triangle_material, triangles, sizeof *scene->triangle_material) ||
        !resize((void **)&scene->triangle_mesh, triangles, sizeof *scene->triangle_mesh) ||
        !resize((void **)&scene->meshes, (size_t)scene->mesh_count + 1, sizeof *scene->meshes) ||
        ((normals || had_normals) && !resize((void **)&scene->normals, vertices, sizeof *scene->normals)))
        return rtt_error_set(err, "%s: out of memory for %u triangles", source, triangle_count);

    scene_builder *builder = builder_of(scene);
    if (!resize((void **)&builder->exact, 3 * vertices, sizeof *builder->exact))
        return rtt_error_set(err, "%s: out of memory for %u triangles", source, triangle_count);
    for (uint32_t i = 0; i < vertex_count; i++) {
        double *p = &builder->exact[3 * ((size_t)v0 + i)], given[3];
        if (positions) {
            given[0] = positions[i].x, given[1] = positions[i].y, given[2] = positions[i].z;
        } else {
            memcpy(given, &exact_positions[3 * (size_t)i], sizeof given);
        }
        if (transform) {
            rtt_transform_point_exact(transform, given, p);
        } else {
            memcpy(p, given, sizeof given);
        }
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || fabs(p[0]) > FLT_MAX || fabs(p[1]) > FLT_MAX ||
            fabs(p[2]) > FLT_MAX)
            return rtt_error_set(err, "%s: vertex %u is not finite after the transform", source, i);
        scene->vertices[v0 + i] = rtt_v3((float)p[0], (float)p[1], (float)p[2]); /* until finish centres them */
    }
    if (normals && !had_normals) /* earlier meshes get their geometric normals at finish */
        for (uint32_t i = 0; i < v0; i++) scene->normals[i] = rtt_v3(0.0f, 0.0f, 0.0f);
    if (normals || had_normals)
        for (uint32_t i = 0; i < vertex_count; i++) {
            rtt_vec3 n = normals ? normals[i] : rtt_v3(0.0f, 0.0f, 0.0f);
            if (!rtt_v3_is_finite(n)) n = rtt_v3(0.0f, 0.0f, 0.0f);
            scene->normals[v0 + i] = transform && normals ? rtt_transform_normal(transform, n) : rtt_v3_normalize(n);
        }
    for (uint32_t f = 0; f < triangle_count; f++) {
        for (int k = 0; k < 3; k++) scene->triangles[t0 + f].v[k] = v0 + indices[3 * (size_t)f + k];
        scene->triangle_material[t0 + f] = triangle_materials ? triangle_materials[f] : material;
        scene->triangle_mesh[t0 + f] = scene->mesh_count;
    }
    rtt_mesh *mesh = &scene->meshes[scene->mesh_count++];
    memset(mesh, 0, sizeof *mesh);
    snprintf(mesh->name, sizeof mesh->name, "%s", name ? name : "mesh");
    mesh->first_triangle = t0;
    mesh->triangle_count = triangle_count;
    mesh->material = triangle_materials ? (triangle_count ? triangle_materials[0] : 0) : material;
    scene->vertex_count = (uint32_t)vertices;
    scene->triangle_count = (uint32_t)triangles;
    return true;
}

bool rtt_scene_add_mesh(rtt_scene *scene, const char *source, const char *name, const rtt_vec3 *positions,
                        const rtt_vec3 *normals, uint32_t vertex_count, const uint32_t *indices,
                        uint32_t triangle_count, const uint32_t *triangle_materials, uint32_t material,
                        const double transform[16], rtt_error *err)
{
    return add_mesh(scene, source, name, positions, NULL, normals, vertex_count, indices, triangle_count,
                    triangle_materials, material, transform, err);
}

bool rtt_scene_add_mesh_exact(rtt_scene *scene, const char *source, const char *name, const double *positions,
                              const rtt_vec3 *normals, uint32_t vertex_count, const uint32_t *indices,
                              uint32_t triangle_count, uint32_t material, const double transform[16],
                              rtt_error *err)
{
    return add_mesh(scene, source, name, NULL, positions, normals, vertex_count, indices, triangle_count, NULL,
                    material, transform, err);
}

bool rtt_triangle_is_degenerate(const rtt_vec3 tri[3])
{
    for (int i = 0; i < 3; i++)
        if (!rtt_v3_is_finite(tri[i])) return true;
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)rtt_v3_get(tri[1], a) - (double)rtt_v3_get(tri[0], a);
        e2[a] = (double)rtt_v3_get(tri[2], a) - (double)rtt_v3_get(tri[0], a);
    }
    double cx = e1[1] * e2[2] - e1[2] * e2[1];
    double cy = e1[2] * e2[0] - e1[0] * e2[2];
    double cz = e1[0] * e2[1] - e1[1] * e2[0];
    return cx == 0.0 && cy == 0.0 && cz == 0.0;
}

/* ---- closedness: every edge of a mesh shared by exactly two of its
 * non-degenerate triangles, with vertices identified by position (importers
 * split vertices at normal or uv seams; a seam is not a hole) ---- */

typedef struct position_key {
    uint32_t bits[3];
    uint32_t vertex;
} position_key;

static int compare_position_keys(const void *a, const void *b)
{
    const position_key *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->bits[i] != y->bits[i]) return x->bits[i] < y->bits[i] ? -1 : 1;
    return (x->vertex > y->vertex) - (x->vertex < y->vertex);
}

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static uint32_t float_bits(float f)
{
    if (f == 0.0f) f = 0.0f; /* -0.0 and +0.0 are one position */
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* canonical[v] = the smallest vertex index at v's exact position. */
static uint32_t *canonical_vertices(const rtt_scene *scene)
{
    position_key *keys = malloc((size_t)scene->vertex_count * sizeof *keys + 1);
    uint32_t *canonical = malloc((size_t)scene->vertex_count * sizeof *canonical + 1);
    if (!keys || !canonical) {
        free(keys);
        free(canonical);
        return NULL;
    }
    for (uint32_t i = 0; i < scene->vertex_count; i++) {
        rtt_vec3 p = scene->vertices[i];
        keys[i] = (position_key){{float_bits(p.x), float_bits(p.y), float_bits(p.z)}, i};
    }
    qsort(keys, scene->vertex_count, sizeof *keys, compare_position_keys);
    for (uint32_t i = 0; i < scene->vertex_count; i++) {
        bool same = i > 0 && memcmp(keys[i].bits, keys[i - 1].bits, sizeof keys[i].bits) == 0;
        canonical[keys[i].vertex] = same ? canonical[keys[i - 1].vertex] : keys[i].vertex;
    }
    free(keys);
    return canonical;
}

static bool mesh_is_closed(const rtt_scene *scene, const rtt_mesh *mesh, const uint32_t *canonical,
                           uint64_t *edges)
{
    size_t count = 0;
    for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, t, tri);
        if (rtt_triangle_is_degenerate(tri)) continue;
        for (int k = 0; k < 3; k++) {
            uint64_t a = canonical[scene->triangles[t].v[k]], b = canonical[scene->triangles[t].v[(k + 1) % 3]];
            edges[count++] = a < b ? (a << 32 | b) : (b << 32 | a);
        }
    }
    if (count == 0) return false;
    qsort(edges, count, sizeof *edges, compare_u64);
    for (size_t i = 0; i < count;) {
        size_t j = i;
        while (j < count && edges[j] == edges[i]) j++;
        if (j - i != 2) return false;
        i = j;
    }
    return true;
}

static bool classify_meshes(rtt_scene *scene, rtt_error *err)
{
    uint32_t *canonical = canonical_vertices(scene);
    uint32_t largest = 0;
    for (uint32_t m = 0; m < scene->mesh_count; m++)
        if (scene->meshes[m].triangle_count > largest) largest = scene->meshes[m].triangle_count;
    uint64_t *edges = malloc((size_t)largest * 3 * sizeof *edges + 1);
    if (!canonical || !edges) {
        free(canonical);
        free(edges);
        return rtt_error_set(err, "%s: out of memory", scene->path);
    }
    for (uint32_t m = 0; m < scene->mesh_count; m++)
        scene->meshes[m].closed = mesh_is_closed(scene, &scene->meshes[m], canonical, edges);
    free(canonical);
    free(edges);
    return true;
}

/* ---- defaults ---- */

static bool has_camera(const rtt_scene *scene) { return scene->camera.fov_deg > 0.0f; }

static void default_camera(rtt_scene *scene)
{
    rtt_bounds b = scene->bounds;
    /* halves first: lo + hi overflows to inf for coordinates beyond FLT_MAX / 2 */
    rtt_vec3 centre = rtt_v3_add(rtt_v3_scale(b.lo, 0.5f), rtt_v3_scale(b.hi, 0.5f));
    float radius = 0.5f * rtt_v3_length(rtt_v3_sub(b.hi, b.lo));
    if (!(radius > 0.0f) || !isfinite(radius)) radius = 1.0f;
    float half_fov = 0.5f * RTT_DEFAULT_FOV_DEG * 3.14159265f / 180.0f;
    /* looking down -z at the centre, from a little above, so that boxes show depth */
    rtt_vec3 offset = rtt_v3_normalize(rtt_v3(0.35f, 0.3f, 1.0f));
    /* bounds near float's limit: the eye comes in as far as it must to stay finite */
    /* in double: the distance itself overflows float for bounds near FLT_MAX */
    double d = (double)radius / sin((double)half_fov) * 1.05, eye[3];
    for (int i = 0; i < 256; i++, d *= 0.5) {
        eye[0] = (double)centre.x + (double)offset.x * d;
        eye[1] = (double)centre.y + (double)offset.y * d;
        eye[2] = (double)centre.z + (double)offset.z * d;
        if (fabs(eye[0]) <= FLT_MAX && fabs(eye[1]) <= FLT_MAX && fabs(eye[2]) <= FLT_MAX) break;
    }
    scene->camera.eye = rtt_v3((float)eye[0], (float)eye[1], (float)eye[2]);
    scene->camera.look_at = centre;
    scene->camera.up = rtt_v3(0.0f, 1.0f, 0.0f);
    scene->camera.fov_deg = RTT_DEFAULT_FOV_DEG;
}


static void fill_vertex_normals(rtt_scene *scene)
{
    /* Vertices of meshes without normals got zero: use the geometric normal
     * of the first triangle that references them (flat shading). */
    for (uint32_t t = 0; t < scene->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            rtt_vec3 *n = &scene->normals[scene->triangles[t].v[k]];
            if (n->x == 0.0f && n->y == 0.0f && n->z == 0.0f) *n = rtt_scene_geometric_normal(scene, t);
        }
}

rtt_vec3 rtt_scene_point_to_stored(const rtt_scene *scene, const double p[3])
{
    return rtt_v3((float)(p[0] - scene->origin[0]), (float)(p[1] - scene->origin[1]), (float)(p[2] - scene->origin[2]));
}

void rtt_scene_point_from_stored(const rtt_scene *scene, rtt_vec3 p, double out[3])
{
    out[0] = (double)p.x + scene->origin[0];
    out[1] = (double)p.y + scene->origin[1];
    out[2] = (double)p.z + scene->origin[2];
}

static bool exact_triangle_is_degenerate(const double *exact, const rtt_triangle *t)
{
    const double *a = &exact[3 * (size_t)t->v[0]], *b = &exact[3 * (size_t)t->v[1]], *c = &exact[3 * (size_t)t->v[2]];
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return e1[1] * e2[2] - e1[2] * e2[1] == 0.0 && e1[2] * e2[0] - e1[0] * e2[2] == 0.0 &&
           e1[0] * e2[1] - e1[1] * e2[0] == 0.0;
}

/* Stores the vertices in float relative to the centre of their bounds
 * (computed in double) and moves the camera and the lights the files gave
 * along; counts the triangles that collapse on the way. */
static void centre_scene(rtt_scene *scene)
{
    scene_builder *builder = builder_of(scene);
    builder->centred = true;
    if (!builder->exact) return; /* a .kdt: stored coordinates and origin come from the file */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t t = 0; t < scene->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) {
                const double x = builder->exact[3 * (size_t)scene->triangles[t].v[k] + a];
                lo[a] = x < lo[a] ? x : lo[a];
                hi[a] = x > hi[a] ? x : hi[a];
            }
    /* Centred only when the centre lies farther from the origin than the
     * scene is large: nearer, centring would gain less than a bit of
     * precision, and the stored coordinates stay the file's own (most
     * scenes).  The origin is rounded to float, so it is a point the
     * stored coordinates can name exactly. */
    double extent = 0.0, offset = 0.0;
    for (int a = 0; a < 3; a++) {
        if (!(lo[a] <= hi[a])) continue;
        extent = fmax(extent, hi[a] - lo[a]);
        offset = fmax(offset, fabs(0.5 * lo[a] + 0.5 * hi[a]));
    }
    for (int a = 0; a < 3; a++)
        scene->origin[a] = offset > extent && lo[a] <= hi[a] ? (double)(float)(0.5 * lo[a] + 0.5 * hi[a]) : 0.0;
    for (uint32_t i = 0; i < scene->vertex_count; i++)
        scene->vertices[i] = rtt_scene_point_to_stored(scene, &builder->exact[3 * (size_t)i]);
    scene->collapsed_count = 0;
    for (uint32_t t = 0; t < scene->triangle_count; t++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, t, tri);
        scene->collapsed_count += rtt_triangle_is_degenerate(tri) &&
                                  !exact_triangle_is_degenerate(builder->exact, &scene->triangles[t]);
    }
    if (has_camera(scene) && !builder->camera_exact_given) { /* a loader set it in float (a map's entities) */
        const rtt_camera *c = &scene->camera;
        const double eye[3] = {c->eye.x, c->eye.y, c->eye.z}, look_at[3] = {c->look_at.x, c->look_at.y, c->look_at.z};
        memcpy(builder->camera_exact[0], eye, sizeof eye);
        memcpy(builder->camera_exact[1], look_at, sizeof look_at);
    }
    if (has_camera(scene)) {
        scene->camera.eye = rtt_scene_point_to_stored(scene, builder->camera_exact[0]);
        scene->camera.look_at = rtt_scene_point_to_stored(scene, builder->camera_exact[1]);
    }
    for (uint32_t l = 0; l < scene->light_count; l++) {
        const rtt_vec3 p = scene->lights[l].position;
        const double given[3] = {p.x, p.y, p.z};
        scene->lights[l].position =
            rtt_scene_point_to_stored(scene, l < builder->light_exact_count ? &builder->light_exact[3 * (size_t)l] : given);
    }
    free(builder->exact);
    builder->exact = NULL;
    free(builder->light_exact);
    builder->light_exact = NULL;
    builder->light_exact_count = 0;
}

/* After centre_scene: every stored point fits in float.  A file's points are
 * finite, but relative to the centre of the triangles' bounds a point the
 * triangles do not bound (an unused vertex, the camera, a light) can lie
 * beyond float's range. */
static bool stored_points_are_finite(const rtt_scene *scene, rtt_error *err)
{
    for (uint32_t i = 0; i < scene->vertex_count; i++)
        if (!rtt_v3_is_finite(scene->vertices[i]))
            return rtt_error_set(err, "%s: vertex %u lies beyond float's range from the scene's centre", scene->path,
                                 i);
    if (has_camera(scene) && !(rtt_v3_is_finite(scene->camera.eye) && rtt_v3_is_finite(scene->camera.look_at)))
        return rtt_error_set(err, "%s: the camera lies beyond float's range from the scene's centre", scene->path);
    for (uint32_t l = 0; l < scene->light_count; l++)
        if (!rtt_light_is_finite(&scene->lights[l]))
            return rtt_error_set(err, "%s: light %u lies beyond float's range from the scene's centre", scene->path,
                                 l);
    return true;
}

bool rtt_scene_finish(rtt_scene *scene, rtt_error *err)
{
    if (scene->triangle_count == 0) return rtt_error_set(err, "%s: the scene has no triangles", scene->path);
    centre_scene(scene);
    if (!stored_points_are_finite(scene, err)) return false;
    if (scene->material_count == 0) {
        rtt_material m = rtt_material_default();
        if (rtt_scene_add_material(scene, &m) == UINT32_MAX)
            return rtt_error_set(err, "%s: out of memory", scene->path);
    }
    scene->bounds = rtt_bounds_empty();
    scene->degenerate_count = 0;
    for (uint32_t t = 0; t < scene->triangle_count; t++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, t, tri);
        for (int k = 0; k < 3; k++) scene->bounds = rtt_bounds_grow(scene->bounds, tri[k]);
        if (rtt_triangle_is_degenerate(tri)) scene->degenerate_count++;
    }
    if (scene->normals) fill_vertex_normals(scene);
    if (!rtt_scene_textures_finish(scene, err)) return false;
    if (!classify_meshes(scene, err)) return false;
    if (!has_camera(scene)) {
        default_camera(scene);
        scene->camera_source = RTT_CAMERA_FRAMING;
    }
    if (scene->width == 0) scene->width = RTT_DEFAULT_WIDTH;
    if (scene->height == 0) scene->height = RTT_DEFAULT_HEIGHT;
    if (scene->light_count == 0 && !rtt_scene_use_camera_light(scene, err)) return false;
    return true;
}

rtt_scene *rtt_scene_from_triangles(const float *xyz9, uint32_t triangle_count, rtt_error *err)
{
    if (triangle_count > SCENE_MAX_TRIANGLES / 3) {
        rtt_error_set(err, "triangles: too many triangles (%u)", triangle_count);
        return NULL;
    }
    rtt_scene *scene = rtt_scene_new("triangles", err);
    if (scene && !rtt_scene_budget_reserve(scene, "triangles", triangle_count, 0, err)) {
        rtt_scene_free(scene);
        return NULL;
    }
    uint32_t *indices = malloc((size_t)triangle_count * 3 * sizeof *indices + 1);
    rtt_material m = rtt_material_default();
    if (!scene || !indices || rtt_scene_add_material(scene, &m) == UINT32_MAX) {
        if (scene) rtt_error_set(err, "triangles: out of memory");
        free(indices);
        rtt_scene_free(scene);
        return NULL;
    }
    for (uint32_t i = 0; i < triangle_count * 3; i++) indices[i] = i;
    bool ok = rtt_scene_add_mesh(scene, "triangles", "triangles", (const rtt_vec3 *)xyz9, NULL, triangle_count * 3,
                                 indices, triangle_count, NULL, 0, NULL, err) &&
              rtt_scene_finish(scene, err);
    free(indices);
    if (!ok) {
        rtt_scene_free(scene);
        return NULL;
    }
    return scene;
}

_Static_assert(sizeof(rtt_vec3) == 3 * sizeof(float), "rtt_vec3 is three packed floats");

rtt_scene *rtt_scene_load(const char *path, const rtt_scene_load_options *opt, rtt_error *err)
{
    const rtt_file_kind kind = rtt_file_kind_of(path);
    if (!rtt_file_check_regular(path, err)) return NULL;
    rtt_scene_load_options defaults = {.bezier_level = 0};
    if (!opt) opt = &defaults;
    if (kind == RTT_FILE_KDT) { /* the file holds the tree: its triangles are all there is to reserve */
        rtt_scene *baked = rtt_kdt_read_scene(path, err);
        if (baked) baked->memory_budget = opt->max_memory;
        if (baked && !rtt_scene_budget_reserve(baked, path, baked->triangle_count, 0, err)) {
            rtt_scene_free(baked);
            return NULL;
        }
        return baked;
    }

    uint32_t level = opt->bezier_level ? opt->bezier_level : RTT_DEFAULT_BEZIER_LEVEL;
    rtt_scene *scene = rtt_scene_new(path, err);
    if (!scene) return NULL;
    scene->memory_budget = opt->max_memory;
    bool ok;
    if (kind == RTT_FILE_SCENE_JSON) {
        ok = rtt_scene_parse_json(scene, path, opt, err); /* bezier_level 0: the file's own, else the default */
    } else if (kind == RTT_FILE_Q3BSP) {
        ok = rtt_import_q3bsp(scene, path, NULL, UINT32_MAX, level, err) && rtt_q3bsp_read_entities(scene, path, err);
    } else { /* a mesh, or a file of unknown kind that Assimp may recognise by its content */
        ok = rtt_import_assimp(scene, path, NULL, UINT32_MAX, err);
    }
    if (!ok || !rtt_scene_finish(scene, err)) {
        rtt_scene_free(scene);
        return NULL;
    }
    return scene;
}

float rtt_scene_ray_epsilon(const rtt_scene *scene)
{
    /* Relative to the scene's extent so scaled scenes behave alike; the
     * magnitude of the coordinates also counts, because far from the origin
     * a float's spacing grows with |x| however small the scene is. */
    rtt_bounds b = scene->bounds;
    float extent = rtt_bounds_is_empty(b) ? 1.0f : rtt_v3_length(rtt_v3_sub(b.hi, b.lo));
    float magnitude = 0.0f;
    if (!rtt_bounds_is_empty(b)) {
        rtt_vec3 lo = b.lo, hi = b.hi;
        magnitude = fmaxf(fmaxf(fmaxf(fabsf(lo.x), fabsf(hi.x)), fmaxf(fabsf(lo.y), fabsf(hi.y))),
                          fmaxf(fabsf(lo.z), fabsf(hi.z)));
    }
    float eps = fmaxf(1e-5f * extent, 1e-6f * magnitude);
    return eps > 0.0f && isfinite(eps) ? eps : 1e-5f;
}

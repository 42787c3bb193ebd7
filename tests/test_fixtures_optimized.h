/* The fixtures shared by the tests that check optimized traversal kernels
 * against the reference engine, ray by ray, at every instruction set
 * (test_optimized_frustum.c, test_optimized_kernels.c, test_optimized_isa.c):
 * a triangle soup with both engines built on it,
 * the ray sets traced through it, and the tolerance a hit is compared with.
 *
 * Agreement: both miss, or both hit with |t - t_ref| <= 1e-5 * max(1, |t_ref|).
 * A different prim is a tie only when both triangles are hit by the ray
 * within that tolerance (prim_hit_at).  A hit within tolerance of tnear or
 * tfar is unspecified (docs/ARCHITECTURE.md, near_interval_end). */
#ifndef RTT_TEST_FIXTURES_OPTIMIZED_H
#define RTT_TEST_FIXTURES_OPTIMIZED_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "engine_optimized.h"
#include "packet.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "kernels.h"
#include "test_isa.h"
#include "test_random.h"

#define TOLERANCE 1e-5f

/* ---- scenes: both engines on one triangle soup ---- */

typedef struct fixture {
    rtt_scene *scene;
    rtt_engine *optimized, *reference;
    const kd_tree *tree;
} fixture;

/* Both engines on `scene`, which the fixture then owns, the optimized one
 * with triangle test `isect` (RTT_ISECT_DEFAULT: its own choice). */
static inline int setup_engines_with(void **state, rtt_scene *scene, rtt_isect isect)
{
    rtt_error err = {{0}};
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    f->scene = scene;
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.isect = isect;
    f->optimized = rtt_optimized_engine_create(f->scene, &opt, &err);
    if (!f->optimized) fail_msg("optimized engine: %s", err.message);
    opt.isect = RTT_ISECT_DEFAULT;
    f->reference = rtt_reference_engine_create(f->scene, &opt, &err);
    if (!f->reference) fail_msg("reference engine: %s", err.message);
    f->tree = kd_engine_tree(f->optimized);
    assert_non_null(f->tree);
    *state = f;
    return 0;
}

static inline int setup_engines(void **state, rtt_scene *scene)
{
    return setup_engines_with(state, scene, RTT_ISECT_DEFAULT);
}

/* Both engines on the triangles, the optimized one with triangle test `isect`. */
static inline int setup_triangles_with(void **state, const float *xyz, uint32_t count, rtt_isect isect)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, count, &err);
    if (!scene) fail_msg("scene: %s", err.message);
    return setup_engines_with(state, scene, isect);
}

static inline int setup_triangles(void **state, const float *xyz, uint32_t count)
{
    return setup_triangles_with(state, xyz, count, RTT_ISECT_DEFAULT);
}

/* `count` random triangles of size ~`size` in the cube [-1, 1]^3, plus a
 * large floor (two triangles at y = -1.2, the box's bottom face) so that
 * many rays hit; the optimized engine with triangle test `isect`. */
static inline int setup_soup_with(void **state, uint32_t count, float size, uint64_t seed, rtt_isect isect)
{
    rng r = {seed};
    float *xyz = malloc((size_t)(count + 2) * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t i = 0; i < count; i++) {
        float c[3] = {rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1)};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) xyz[9 * i + 3 * v + a] = c[a] + rng_range(&r, -size, size);
    }
    const float floor_tris[18] = {-2, -1.2f, -2, 2, -1.2f, -2, 2, -1.2f, 2, -2, -1.2f, -2, 2, -1.2f, 2, -2, -1.2f, 2};
    memcpy(&xyz[9 * count], floor_tris, sizeof floor_tris);
    int rc = setup_triangles_with(state, xyz, count + 2, isect);
    free(xyz);
    return rc;
}

/* `count` tiny triangles, 4e-6 to 4e-4 across, near the origin (within
 * 0.01), every fourth in an axis plane y = c (a fuzzed scene's case). */
static inline float *tiny_far_triangles(uint32_t count, uint64_t seed)
{
    float *xyz = malloc(9 * (size_t)count * sizeof *xyz);
    assert_non_null(xyz);
    rng r = {seed};
    for (uint32_t t = 0; t < count; t++) {
        const float size = 4e-6f * powf(100.0f, rng_float(&r));
        const float c[3] = {rng_range(&r, -0.01f, 0.01f), rng_range(&r, -0.01f, 0.01f), rng_range(&r, -0.01f, 0.01f)};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) xyz[9 * t + 3 * v + a] = c[a] + size * rng_range(&r, -1.0f, 1.0f);
        if (t % 4 == 0)
            for (int v = 0; v < 3; v++) xyz[9 * t + 3 * v + 1] = c[1];
    }
    return xyz;
}

/* Rays at tiny_far_triangles from about 20 units off: sixteen per origin
 * (8 to 14 from the centre per axis), each aimed at a point of a random
 * triangle (every fourth within 1e-3 of an edge), t in [0, inf); every
 * fourth origin's directions unnormalised (the point minus the origin).
 * Seen from there the edge planes through the origin are cross products of
 * long, nearly parallel vectors, and the slab distances to a triangle's box
 * are rounded on the scale of the origin's distance, not the box's size. */
static inline rtt_ray *rays_at_tiny_far_triangles(const float *xyz, uint32_t tris, uint32_t count, uint64_t seed)
{
    rtt_ray *rays = malloc((size_t)count * sizeof *rays);
    assert_non_null(rays);
    rng r = {seed};
    float org[3] = {0};
    for (uint32_t i = 0; i < count; i++) {
        if (i % 16 == 0)
            for (int a = 0; a < 3; a++) org[a] = rng_range(&r, 8.0f, 14.0f) * (rng_float(&r) < 0.5f ? -1.0f : 1.0f);
        const float *v = &xyz[9 * ((uint32_t)(rng_float(&r) * (float)tris) % tris)];
        float a = rng_float(&r), b = rng_float(&r);
        if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
        if (i % 4 == 0) b = 1e-3f * b; /* near the edge from v0 to v1 */
        float d[3];
        for (int k = 0; k < 3; k++) d[k] = v[k] + a * (v[3 + k] - v[k]) + b * (v[6 + k] - v[k]) - org[k];
        const float len = (i / 16) % 4 ? sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) : 1.0f;
        rays[i] = (rtt_ray){{org[0], org[1], org[2]}, {d[0] / len, d[1] / len, d[2] / len}, 0.0f, INFINITY};
    }
    return rays;
}

static inline int setup_soup(void **state, uint32_t count, float size, uint64_t seed)
{
    return setup_soup_with(state, count, size, seed, RTT_ISECT_DEFAULT);
}

static inline int setup_small_soup(void **state) { return setup_soup(state, 2000, 0.08f, 0x9e3779b97f4a7c15ull); }
/* The same soup traced with Wald's projected test instead of the default. */
static inline int setup_small_soup_projected(void **state)
{
    return setup_soup_with(state, 2000, 0.08f, 0x9e3779b97f4a7c15ull, RTT_ISECT_PROJECTED);
}

/* A closed octahedron of radius 1 around (0.3, -0.2, 0.1), far enough from
 * the origin that its corners are not round numbers: 8 faces, every edge
 * shared by two. */
#define OCTAHEDRON_CENTRE_X 0.3f
#define OCTAHEDRON_CENTRE_Y (-0.2f)
#define OCTAHEDRON_CENTRE_Z 0.1f
static inline int setup_octahedron(void **state)
{
    const float c[3] = {OCTAHEDRON_CENTRE_X, OCTAHEDRON_CENTRE_Y, OCTAHEDRON_CENTRE_Z};
    float v[6][3];
    for (int i = 0; i < 6; i++)
        for (int a = 0; a < 3; a++) v[i][a] = c[a] + (a == i / 2 ? (i % 2 ? -1.0f : 1.0f) : 0.0f);
    float tris[8 * 9];
    for (int f = 0; f < 8; f++) {
        const int corner[3] = {f & 1, 2 + (f >> 1 & 1), 4 + (f >> 2 & 1)};
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) tris[9 * f + 3 * k + a] = v[corner[k]][a];
    }
    return setup_triangles(state, tris, 8);
}

/* Rays from inside the octahedron (within 0.3 of its centre per axis) aimed
 * exactly at its faces' corners, at their edges' midpoints and at random
 * points of their edges: a watertight test lets none of them out.  Each run
 * of `group` consecutive rays shares one origin (1: every ray its own; 16:
 * the BVH's multi-frusta find a common origin). */
static inline rtt_ray *octahedron_corner_and_edge_rays(const rtt_scene *scene, uint32_t count, uint32_t group,
                                                       uint64_t seed)
{
    rtt_ray *rays = malloc(count * sizeof *rays);
    assert_non_null(rays);
    rng r = {seed};
    for (uint32_t i = 0; i < count; i++) {
        rtt_vec3 p[3];
        rtt_scene_triangle(scene, i % 8, p);
        const int edge = (int)(i / 8 % 3); /* edge edge..edge+1 of the face */
        const float w = i % 3 == 0 ? 0.0f : i % 3 == 1 ? 0.5f : rng_range(&r, 0.0f, 1.0f);
        const rtt_vec3 target = rtt_v3_add(rtt_v3_scale(p[edge], 1.0f - w), rtt_v3_scale(p[(edge + 1) % 3], w));
        const rtt_vec3 org = i % group ? rtt_v3(rays[i - 1].org[0], rays[i - 1].org[1], rays[i - 1].org[2])
                                       : rtt_v3(OCTAHEDRON_CENTRE_X + rng_range(&r, -0.3f, 0.3f),
                                                OCTAHEDRON_CENTRE_Y + rng_range(&r, -0.3f, 0.3f),
                                                OCTAHEDRON_CENTRE_Z + rng_range(&r, -0.3f, 0.3f));
        const rtt_vec3 dir = rtt_v3_sub(target, org);
        rays[i] = (rtt_ray){{org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, 0.0f, INFINITY};
    }
    return rays;
}

static inline int teardown(void **state)
{
    fixture *f = *state;
    rtt_engine_destroy(f->optimized);
    rtt_engine_destroy(f->reference);
    rtt_scene_free(f->scene);
    free(f);
    return 0;
}

/* ---- ray sets ---- */

/* Rays of a camera at `eye` looking at the origin through a W x W grid,
 * `fov_scale` the half-width of the view at distance 1: tile by tile
 * (`tile` divides `width`), one 2x2 pixel quad per four consecutive rays,
 * quads in row-major order inside a tile.  `tile` = `width` is one tile:
 * quads in row-major order over the whole grid. */
static inline rtt_ray *primary_rays(uint32_t width, uint32_t tile, rtt_vec3 eye, float fov_scale, uint32_t *count)
{
    rtt_ray *rays = malloc((size_t)width * width * sizeof *rays);
    assert_non_null(rays);
    rtt_vec3 fwd = rtt_v3_normalize(rtt_v3_scale(eye, -1.0f));
    rtt_vec3 right = rtt_v3_normalize(rtt_v3_cross(fwd, rtt_v3(0, 1, 0)));
    rtt_vec3 up = rtt_v3_cross(right, fwd);
    uint32_t n = 0;
    for (uint32_t ty = 0; ty < width; ty += tile)
        for (uint32_t tx = 0; tx < width; tx += tile)
            for (uint32_t q = 0; q < tile * tile / 4; q++)
                for (uint32_t l = 0; l < 4; l++) {
                    uint32_t px = tx + 2 * (q % (tile / 2)) + (l & 1), py = ty + 2 * (q / (tile / 2)) + (l >> 1);
                    float sx = ((float)px + 0.5f) / (float)width * 2.0f - 1.0f;
                    float sy = ((float)py + 0.5f) / (float)width * 2.0f - 1.0f;
                    rtt_vec3 d = rtt_v3_normalize(rtt_v3_add(fwd, rtt_v3_add(rtt_v3_scale(right, fov_scale * sx),
                                                                              rtt_v3_scale(up, -fov_scale * sy))));
                    rays[n++] = (rtt_ray){{eye.x, eye.y, eye.z}, {d.x, d.y, d.z}, 0.0f, INFINITY};
                }
    *count = n;
    return rays;
}

/* Which special rays random_rays mixes in. */
typedef enum random_ray_specials {
    NAN_AND_ZERO_SPECIALS, /* NaN origins, zero and axis-parallel directions */
    ALL_SPECIALS,          /* also Inf and NaN in every field, tnear > tfar, negative tnear */
} random_ray_specials;

/* Random origins in [-1.5, 1.5]^3, random directions, every fifth with a
 * finite tfar; mixed in: every 37th ray with a NaN origin, every 41st with a
 * zero direction, every 11th axis-parallel (+-0.0 parts); with ALL_SPECIALS
 * also one +-0.0 direction component, negative tnear, tnear > tfar, an empty
 * interval, Inf origins and directions, NaN tfar and NaN directions.  The
 * same seed gives the same rays for the same `specials`. */
static inline rtt_ray *random_rays(uint32_t count, uint64_t seed, random_ray_specials specials)
{
    rng r = {seed};
    rtt_ray *rays = malloc((size_t)count * sizeof *rays);
    assert_non_null(rays);
    for (uint32_t i = 0; i < count; i++) {
        rtt_ray *ray = &rays[i];
        for (int a = 0; a < 3; a++) ray->org[a] = rng_range(&r, -1.5f, 1.5f), ray->dir[a] = rng_range(&r, -1, 1);
        ray->tnear = 0.0f;
        ray->tfar = (i % 5 == 0) ? rng_range(&r, 0.1f, 2.0f) : INFINITY;
        if (i % 11 == 3) {
            int axis = (int)(i % 3);
            for (int a = 0; a < 3; a++) ray->dir[a] = a == axis ? (i % 2 ? 1.0f : -1.0f) : (i % 4 < 2 ? 0.0f : -0.0f);
        }
        if (specials == ALL_SPECIALS) {
            if (i % 13 == 4) ray->dir[i % 3] = (i % 2) ? -0.0f : 0.0f; /* one axis-parallel component */
            if (i % 17 == 6) ray->tnear = rng_range(&r, -3.0f, -0.5f);
            if (i % 19 == 8) ray->tnear = 5.0f, ray->tfar = 1.0f;
            if (i % 23 == 9) ray->tnear = ray->tfar = 0.5f;
        }
        if (i % 37 == 5) ray->org[i % 3] = NAN;
        if (i % 41 == 7) ray->dir[0] = ray->dir[1] = ray->dir[2] = 0.0f;
        if (specials == ALL_SPECIALS) {
            if (i % 43 == 10) ray->dir[i % 3] = (i % 2) ? INFINITY : -INFINITY;
            if (i % 47 == 11) ray->org[i % 3] = -INFINITY;
            if (i % 53 == 12) ray->tfar = NAN;
            if (i % 59 == 13) ray->dir[i % 3] = NAN;
        }
    }
    return rays;
}

/* Shadow-like rays: from random points toward one light point, normalized,
 * tnear small, tfar just short of the light.  Consecutive rays start close
 * together (a surface patch), as a tile's shadow rays do. */
static inline rtt_ray *shadow_rays(uint32_t count, rtt_vec3 light, uint64_t seed)
{
    rng r = {seed};
    rtt_ray *rays = malloc((size_t)count * sizeof *rays);
    assert_non_null(rays);
    rtt_vec3 patch = rtt_v3(0, 0, 0);
    for (uint32_t i = 0; i < count; i++) {
        if (i % 64 == 0)
            patch = rtt_v3(rng_range(&r, -1.2f, 1.2f), rng_range(&r, -1.2f, 1.2f), rng_range(&r, -1.2f, 1.2f));
        rtt_vec3 p = rtt_v3_add(patch, rtt_v3(rng_range(&r, -0.05f, 0.05f), rng_range(&r, -0.05f, 0.05f),
                                              rng_range(&r, -0.05f, 0.05f)));
        rtt_vec3 to = rtt_v3_sub(light, p);
        float d = rtt_v3_length(to);
        to = rtt_v3_scale(to, 1.0f / d);
        rays[i] = (rtt_ray){{p.x, p.y, p.z}, {to.x, to.y, to.z}, 1e-4f, d - 1e-4f};
    }
    return rays;
}

/* ---- comparison with the reference ---- */

static inline float t_tolerance(float t) { return TOLERANCE * fmaxf(1.0f, fabsf(t)); }

static inline int near_interval_end(const rtt_ray *ray, float t)
{
    return fabsf(t - ray->tnear) <= t_tolerance(t) || (isfinite(ray->tfar) && fabsf(t - ray->tfar) <= t_tolerance(t));
}

/* 1 when triangle `prim` is hit by `ray` at `t`, within tolerance. */
static inline int prim_hit_at(const fixture *f, const rtt_ray *ray, uint32_t prim, float t)
{
    rtt_vec3 tri[3];
    rtt_scene_triangle(f->scene, prim, tri);
    rtt_ray wide = *ray;
    wide.tnear = t - 4 * t_tolerance(t);
    wide.tfar = t + 4 * t_tolerance(t);
    float tt, u, v;
    return rtt_reference_intersect_triangle(&wide, tri, &tt, &u, &v) && fabsf(tt - t) <= 2 * t_tolerance(t);
}

/* A kernel under test: a name of the descriptor table and the instruction
 * set whose copy is traced. */
typedef struct kernel_case {
    const char *name;
    rtt_isa isa;
} kernel_case;

/* The kernels named at every instruction set this CPU runs, SSE4 first
 * (so out[0..n) are the SSE4 copies), into out (room for n * 3); prints a
 * note for each set it skips.  Returns the number of cases. */
static inline size_t kernel_cases_every_isa(const char *const *names, size_t n, kernel_case *out)
{
    size_t count = 0;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        for (size_t i = 0; i < n; i++) out[count++] = (kernel_case){names[i], isa};
    }
    return count;
}

/* The row of exactly that copy. */
static inline const kd_kernel *kernel_row(const kernel_case *k)
{
    const kd_kernel *row = kd_kernel_find(k->name, k->isa);
    assert_non_null(row);
    assert_int_equal(row->isa, k->isa);
    return row;
}

static inline void kernel_closest(const kernel_case *k, const kd_tree *tree, const ray_packet4 *packets,
                                  hit_packet4 *hits, uint32_t count, int leaf_culling, kd_counters *counters)
{
    const kd_query q = {.packets = packets, .packet_count = count, .hits = hits, .leaf_culling = leaf_culling,
                        .counters = counters};
    kernel_row(k)->trace(tree, &q);
}

static inline void kernel_occluded(const kernel_case *k, const kd_tree *tree, const ray_packet4 *packets,
                                   uint8_t *occluded, uint32_t count, int leaf_culling, kd_counters *counters)
{
    const kd_query q = {.packets = packets, .packet_count = count, .occluded = occluded,
                        .leaf_culling = leaf_culling, .counters = counters};
    kernel_row(k)->trace(tree, &q);
}

#endif

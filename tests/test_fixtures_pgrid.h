/* The perspective light grids' test fixture (--shadows pgrid and pgrid:N):
 * scenes from scenes/, a seeded random stream, the brute force over every
 * triangle (the reference's watertight test), the shader proxy's shadow
 * segment and the shadow rays' origins (eye-ray hits and points all over
 * the scene's box).  Included by test_optimized_pgrid_shadows.c and
 * test_optimized_pgrid_soft.c (and its load_scene by test_optimized_pgrid.c). */
#ifndef RTT_TEST_FIXTURES_PGRID_H
#define RTT_TEST_FIXTURES_PGRID_H

#include <stdio.h>
#include <stdlib.h>

#include "rtt/reference.h"
#include "rtt/shade.h"

static inline rtt_scene *load_scene(const char *name)
{
    char path[600];
    snprintf(path, sizeof path, "%s/scenes/%s", RTT_SOURCE_DIR, name);
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    if (!s) fail_msg("%s: %s", path, err.message);
    return s;
}

static inline uint32_t next_random(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static inline float random_in(uint32_t *state, float lo, float hi)
{
    return lo + (hi - lo) * (float)next_random(state) / (float)(1u << 24);
}

/* Brute force: any triangle with tnear < t < tfar. */
static inline uint8_t brute_force_occluded(const rtt_scene *s, const rtt_ray *r)
{
    for (uint32_t i = 0; i < s->triangle_count; i++) {
        rtt_vec3 c[3];
        rtt_scene_triangle(s, i, c);
        float t, u, v;
        if (rtt_reference_intersect_triangle(r, c, &t, &u, &v)) return 1;
    }
    return 0;
}

/* The shader proxy's shadow ray from p to target; false when none fits. */
static inline bool shadow_ray(const rtt_scene *s, rtt_vec3 p, rtt_vec3 target, rtt_ray *out)
{
    const float epsilon = rtt_scene_ray_epsilon(s);
    rtt_vec3 to = rtt_v3_sub(target, p);
    float distance = rtt_v3_length(to);
    if (!(distance > 2.0f * epsilon)) return false;
    rtt_vec3 dir = rtt_v3_scale(to, 1.0f / distance);
    *out = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, epsilon, distance - epsilon};
    return true;
}

/* expected[i]: the brute force's answer for rays[i], which must be the
 * reference engine's (engine[i], scratch); returns how many are occluded. */
static inline uint32_t expected_occlusion(const rtt_scene *s, rtt_engine *ref, const rtt_ray *rays, uint32_t n,
                                          uint8_t *expected, uint8_t *engine, const char *what)
{
    uint32_t blocked = 0;
    rtt_engine_occluded(ref, rays, engine, n);
    for (uint32_t i = 0; i < n; i++) {
        expected[i] = brute_force_occluded(s, &rays[i]);
        if (expected[i] != (engine[i] != 0))
            fail_msg("%s: ray %u: the brute force says %u, the reference engine %u", what, i, expected[i], engine[i]);
        blocked += expected[i];
    }
    return blocked;
}

/* Origins: the eye rays' hits at w x h, then `extra` points in the scene's box grown by a quarter. */
static inline rtt_vec3 *shadow_origins(const rtt_scene *s, rtt_engine *ref, uint32_t w, uint32_t h, uint32_t extra,
                                uint32_t *count, uint32_t seed, uint32_t **prims)
{
    rtt_vec3 *points = malloc(((size_t)w * h + extra) * sizeof *points);
    *prims = malloc(((size_t)w * h + extra) * sizeof **prims);
    assert_non_null(points);
    assert_non_null(*prims);
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    uint32_t n = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            rtt_ray r = rtt_camera_ray(&frame, x, y);
            rtt_hit hit;
            rtt_engine_intersect(ref, &r, &hit, 1);
            if (hit.prim == RTT_MISS) continue;
            (*prims)[n] = hit.prim;
            points[n++] = (rtt_vec3){r.org[0] + hit.t * r.dir[0], r.org[1] + hit.t * r.dir[1], r.org[2] + hit.t * r.dir[2]};
        }
    const rtt_vec3 lo = s->bounds.lo, hi = s->bounds.hi, grow = rtt_v3_scale(rtt_v3_sub(hi, lo), 0.25f);
    for (uint32_t i = 0; i < extra; i++, (*prims)[n - 1] = RTT_MISS)
        points[n++] = (rtt_vec3){random_in(&seed, lo.x - grow.x, hi.x + grow.x),
                                 random_in(&seed, lo.y - grow.y, hi.y + grow.y),
                                 random_in(&seed, lo.z - grow.z, hi.z + grow.z)};
    *count = n;
    return points;
}

/* 300 random triangles around the origin, every tenth huge, every third
 * tiny, their coordinates times `scale`. */
static inline rtt_scene *triangle_soup_scaled(uint32_t *seed, float scale)
{
    enum { COUNT = 300 };
    float *xyz = malloc(COUNT * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t i = 0; i < COUNT; i++) {
        const float size = i % 10 == 0 ? 4.0f : i % 3 == 0 ? 0.01f : 0.3f;
        const float c[3] = {random_in(seed, -1, 1), random_in(seed, -1, 1), random_in(seed, -1, 1)};
        for (int k = 0; k < 9; k++) xyz[9 * i + k] = (c[k % 3] + random_in(seed, -size, size)) * scale;
    }
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_from_triangles(xyz, COUNT, &err);
    free(xyz);
    if (!s) fail_msg("soup: %s", err.message);
    return s;
}

static inline rtt_scene *triangle_soup(uint32_t *seed) { return triangle_soup_scaled(seed, 1.0f); }

#endif

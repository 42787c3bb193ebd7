/* The ray sets of the conformance suite: primary (the scene's camera, in
 * 8x8 tile order so that frustum kernels see coherent blocks), shadow (from
 * the reference's primary hits to every light centre), random (fixed seed)
 * and extreme (the patterns of Embree's verify tool and pbrt's tests). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "conform.h"
#include "conform_random.h"
#include "rtt/shade.h"

#define DEFAULT_MAX_RAYS 65536u
#define TILE 8u

static const char *const set_names[RTT_CONFORM_RAY_SET_COUNT] = {"primary", "shadow", "random", "extreme", "file"};

const char *rtt_conform_ray_set_name(rtt_conform_ray_set set)
{
    return (unsigned)set < RTT_CONFORM_RAY_SET_COUNT ? set_names[set] : "unknown";
}

int rtt_conform_ray_set_parse(const char *name)
{
    for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++)
        if (i != RTT_CONFORM_FILE && strcmp(name, set_names[i]) == 0) return i;
    return -1;
}

static rtt_ray make_ray(rtt_vec3 org, rtt_vec3 dir, float tnear, float tfar)
{
    return (rtt_ray){{org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, tnear, tfar};
}

/* The bounds grown by a quarter of their extent on each side. */
static rtt_bounds around_bounds(const rtt_scene *s)
{
    rtt_bounds b = s->bounds;
    if (rtt_bounds_is_empty(b)) return (rtt_bounds){rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1)};
    rtt_vec3 grow = rtt_v3_scale(rtt_v3_sub(b.hi, b.lo), 0.25f);
    float m = fmaxf(grow.x, fmaxf(grow.y, grow.z));
    if (!(m > 0.0f)) m = fmaxf(1e-6f * rtt_conform_scene_magnitude(s), 1e-30f);
    grow = rtt_v3_max(grow, rtt_v3(m * 0.1f, m * 0.1f, m * 0.1f));
    return (rtt_bounds){rtt_v3_sub(b.lo, grow), rtt_v3_add(b.hi, grow)};
}

static rtt_vec3 random_point(uint64_t *state, rtt_bounds b)
{
    rtt_vec3 e = rtt_v3_sub(b.hi, b.lo);
    return rtt_v3(b.lo.x + e.x * next_unit(state), b.lo.y + e.y * next_unit(state), b.lo.z + e.z * next_unit(state));
}

static rtt_vec3 random_surface_point(const rtt_scene *s, uint64_t *state, uint32_t *prim)
{
    *prim = next_below(state, s->triangle_count);
    rtt_vec3 t[3];
    rtt_scene_triangle(s, *prim, t);
    float a = next_unit(state), b = next_unit(state);
    if (a + b > 1.0f) {
        a = 1.0f - a;
        b = 1.0f - b;
    }
    return rtt_v3_add(t[0], rtt_v3_add(rtt_v3_scale(rtt_v3_sub(t[1], t[0]), a), rtt_v3_scale(rtt_v3_sub(t[2], t[0]), b)));
}

static bool primary_rays(const rtt_scene *s, size_t max, rtt_ray *out, size_t *count)
{
    uint32_t w = s->width ? s->width : RTT_DEFAULT_WIDTH, h = s->height ? s->height : RTT_DEFAULT_HEIGHT;
    if ((size_t)w * h > max) {
        double k = sqrt((double)max / ((double)w * h));
        w = (uint32_t)fmax(1.0, floor(w * k));
        h = (uint32_t)fmax(1.0, floor(h * k));
    }
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    size_t n = 0;
    for (uint32_t ty = 0; ty < h; ty += TILE)
        for (uint32_t tx = 0; tx < w; tx += TILE)
            for (uint32_t y = ty; y < ty + TILE && y < h; y++)
                for (uint32_t x = tx; x < tx + TILE && x < w; x++) out[n++] = rtt_camera_ray(&frame, x, y);
    *count = n;
    return true;
}

static bool shadow_rays(const rtt_scene *s, rtt_engine *reference, size_t max, rtt_ray *out, size_t *count,
                        rtt_error *err)
{
    size_t n_primary = 0;
    rtt_ray *primary = malloc(max * sizeof *primary);
    rtt_hit *hits = malloc(max * sizeof *hits);
    if (!primary || !hits) {
        free(primary);
        free(hits);
        return rtt_error_set(err, "%s: out of memory for shadow rays", s->path);
    }
    primary_rays(s, max, primary, &n_primary);
    rtt_engine_intersect(reference, primary, hits, n_primary);
    float eps = rtt_scene_ray_epsilon(s);
    size_t n = 0;
    for (size_t i = 0; i < n_primary && n < max; i++) {
        if (hits[i].prim == RTT_MISS) continue;
        rtt_vec3 p = rtt_v3_madd(rtt_v3(primary[i].org[0], primary[i].org[1], primary[i].org[2]),
                                 rtt_v3(primary[i].dir[0], primary[i].dir[1], primary[i].dir[2]), hits[i].t);
        for (uint32_t l = 0; l < s->light_count && n < max; l++) {
            rtt_vec3 to = rtt_v3_sub(s->lights[l].position, p);
            float d = rtt_v3_length(to);
            if (!(d > 2.0f * eps)) continue;
            out[n++] = make_ray(p, rtt_v3_scale(to, 1.0f / d), eps, d - eps);
        }
    }
    free(primary);
    free(hits);
    *count = n;
    return true;
}

static void random_rays(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out, size_t *count)
{
    uint64_t state = seed;
    rtt_bounds around = around_bounds(s);
    for (size_t i = 0; i < max; i++) {
        rtt_vec3 org = random_point(&state, around), dir;
        if (i % 2 == 1 && s->triangle_count) { /* half aimed at a surface: many more hits */
            uint32_t prim;
            dir = rtt_v3_normalize(rtt_v3_sub(random_surface_point(s, &state, &prim), org));
            if (!(rtt_v3_length(dir) > 0.0f)) dir = random_direction(&state);
        } else {
            dir = random_direction(&state);
        }
        out[i] = make_ray(org, dir, 0.0f, INFINITY);
    }
    *count = max;
}

/* Rays no engine may hit with, crash on or hang on. */
static size_t invalid_rays(rtt_vec3 centre, rtt_ray *out)
{
    const float nan = NAN, inf = INFINITY;
    const rtt_ray list[] = {
        {{nan, centre.y, centre.z}, {0, 0, 1}, 0, inf},
        {{centre.x, centre.y, centre.z}, {nan, nan, nan}, 0, inf},
        {{centre.x, centre.y, centre.z}, {0, 0, 0}, 0, inf},
        {{centre.x, centre.y, centre.z}, {-0.0f, -0.0f, -0.0f}, 0, inf},
        {{inf, centre.y, centre.z}, {-1, 0, 0}, 0, inf},
        {{-inf, -inf, -inf}, {1, 1, 1}, 0, inf},
        {{centre.x, centre.y, centre.z}, {inf, 0, 0}, 0, inf},
        {{centre.x, centre.y, centre.z}, {inf, -inf, inf}, 0, inf},
        {{centre.x, centre.y, centre.z}, {1, 0, 0}, nan, inf},
        {{centre.x, centre.y, centre.z}, {1, 0, 0}, 0, nan},
        {{centre.x, centre.y, centre.z}, {0, 1, 0}, 5, 1},
        {{centre.x, centre.y, centre.z}, {0, 0, 1}, inf, inf},
        {{centre.x, centre.y, centre.z}, {0, 0, -1}, -inf, -inf},
        {{nan, nan, nan}, {nan, nan, nan}, nan, nan},
    };
    memcpy(out, list, sizeof list);
    return sizeof list / sizeof list[0];
}

static void extreme_rays(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out, size_t *count)
{
    uint64_t state = seed ^ 0xE7E7E7E7ull;
    rtt_bounds around = around_bounds(s);
    rtt_vec3 centre = rtt_v3_add(rtt_v3_scale(around.lo, 0.5f), rtt_v3_scale(around.hi, 0.5f)); /* no overflow near FLT_MAX */
    size_t n = 0;
    if (max >= 14) n = invalid_rays(centre, out);
    while (n < max && s->triangle_count) {
        uint32_t prim = next_below(&state, s->triangle_count), corner = next_below(&state, 3);
        rtt_vec3 t[3];
        rtt_scene_triangle(s, prim, t);
        rtt_vec3 vertex = t[corner], mid = rtt_v3_add(rtt_v3_scale(t[corner], 0.5f), rtt_v3_scale(t[(corner + 1) % 3], 0.5f));
        rtt_vec3 org = random_point(&state, around);
        switch (n % 6) {
        case 0: /* aimed exactly at a vertex */
            out[n++] = make_ray(org, rtt_v3_sub(vertex, org), 0.0f, INFINITY);
            break;
        case 1: /* aimed exactly at an edge midpoint */
            out[n++] = make_ray(org, rtt_v3_sub(mid, org), 0.0f, INFINITY);
            break;
        case 2: { /* axis-parallel through a vertex, from outside, with -0.0 / +0.0 elsewhere */
            int axis = (int)next_below(&state, 3);
            bool up = next_below(&state, 2);
            rtt_vec3 o = vertex, d = rtt_v3(next_below(&state, 2) ? -0.0f : 0.0f,
                                            next_below(&state, 2) ? -0.0f : 0.0f,
                                            next_below(&state, 2) ? -0.0f : 0.0f);
            rtt_v3_set(&o, axis, up ? rtt_v3_get(around.lo, axis) : rtt_v3_get(around.hi, axis));
            rtt_v3_set(&d, axis, up ? 1.0f : -1.0f);
            out[n++] = make_ray(o, d, 0.0f, INFINITY);
            break;
        }
        case 3: { /* origin on split-plane-like values: every coordinate a vertex coordinate */
            rtt_vec3 o = rtt_v3(0.0f, 0.0f, 0.0f); /* every axis set below */
            for (int a = 0; a < 3; a++) {
                rtt_vec3 u[3];
                rtt_scene_triangle(s, next_below(&state, s->triangle_count), u);
                rtt_v3_set(&o, a, rtt_v3_get(u[next_below(&state, 3)], a));
            }
            out[n++] = make_ray(o, random_direction(&state), 0.0f, INFINITY);
            break;
        }
        case 4: { /* origin on a triangle's surface */
            uint32_t p;
            out[n++] = make_ray(random_surface_point(s, &state, &p), random_direction(&state), 0.0f, INFINITY);
            break;
        }
        default: { /* axis-parallel from a random origin: one non-zero component */
            int axis = (int)next_below(&state, 3);
            rtt_vec3 d = rtt_v3(-0.0f, 0.0f, -0.0f);
            rtt_v3_set(&d, axis, next_below(&state, 2) ? 1.0f : -1.0f);
            out[n++] = make_ray(org, d, 0.0f, INFINITY);
            break;
        }
        }
    }
    *count = n;
}

bool rtt_conform_make_rays(const rtt_scene *scene, rtt_conform_ray_set set, rtt_engine *reference,
                           size_t max_rays, uint64_t seed, rtt_ray **rays, size_t *count, rtt_error *err)
{
    size_t max = max_rays ? max_rays : DEFAULT_MAX_RAYS;
    *rays = NULL;
    *count = 0;
    rtt_ray *out = malloc((max < 16 ? 16 : max) * sizeof *out);
    if (!out) return rtt_error_set(err, "%s: out of memory for %zu rays", scene->path, max);
    bool ok = true;
    switch (set) {
    case RTT_CONFORM_PRIMARY: ok = primary_rays(scene, max, out, count); break;
    case RTT_CONFORM_SHADOW: ok = shadow_rays(scene, reference, max, out, count, err); break;
    case RTT_CONFORM_RANDOM: random_rays(scene, seed, max, out, count); break;
    case RTT_CONFORM_EXTREME: extreme_rays(scene, seed, max, out, count); break;
    default: ok = rtt_error_set(err, "unknown ray set %d", (int)set);
    }
    if (!ok) {
        free(out);
        return false;
    }
    *rays = out;
    return true;
}

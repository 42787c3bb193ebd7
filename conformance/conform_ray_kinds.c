/* The ray sets of the conformance suite by name, one kind at a time, for
 * `rtt rays` (conform.h: rtt_conform_make_kind).  Every kind is made by the
 * generator the suite itself uses (conform_rays.c for the hit-by-hit sets,
 * extremes_scenes.c for the extremes' patterns), so a rays.bin reproduces
 * what `rtt conform` traces. */
#include <stdlib.h>
#include <string.h>

#include "conform.h"
#include "conform_random.h"
#include "extremes_internal.h"

typedef size_t (*pattern_fn)(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);

typedef struct ray_kind {
    const char *name, *what;
    int set;            /* an rtt_conform_ray_set, or -1 */
    pattern_fn pattern; /* an extremes pattern, or NULL */
} ray_kind;

static const ray_kind kinds[] = {
    {"primary", "one ray per pixel of the scene's camera in 8x8 tile order (fewer pixels to fit N)",
     RTT_CONFORM_PRIMARY, NULL},
    {"shadow", "from the reference's primary hits to every light", RTT_CONFORM_SHADOW, NULL},
    {"random", "origins in and around the bounds, random directions, half aimed at surfaces", RTT_CONFORM_RANDOM,
     NULL},
    {"axis", "axis-parallel through vertices and edge midpoints, other components +0.0 or -0.0", -1,
     rtt_ext_rays_axis_parallel},
    {"surface", "origins on triangle surfaces and at vertices, random directions", -1, rtt_ext_rays_on_surface},
    {"inside", "from a point inside a closed mesh to every vertex and edge midpoint", -1, NULL},
    {"inside-random", "from a point inside a closed mesh in random directions", -1, NULL},
    {"vertex", "from random points around the bounds exactly at vertices and edge midpoints", -1,
     rtt_ext_rays_vertex_aimed},
    {"split-planes", "origins whose coordinates are vertex coordinates", -1, rtt_ext_rays_split_planes},
    {"extreme", "the extreme set of rtt conform: all of the above mixed, with NaN and Inf rays",
     RTT_CONFORM_EXTREME, NULL},
};

#define KIND_COUNT (sizeof kinds / sizeof kinds[0])

const char *rtt_conform_kind_name(size_t i) { return i < KIND_COUNT ? kinds[i].name : NULL; }
const char *rtt_conform_kind_summary(size_t i) { return i < KIND_COUNT ? kinds[i].what : NULL; }

/* From the inside point: at every vertex and edge midpoint, or (random)
 * in uniformly random directions. */
static bool inside_rays(const rtt_scene *scene, bool random, uint64_t seed, size_t max, rtt_ray **rays, size_t *count,
                        rtt_error *err)
{
    float inside[3];
    if (!rtt_ext_inside_point(scene, 0, inside))
        return rtt_error_set(err, "%s: no point found inside a closed mesh (rays of kind inside need one)",
                             scene->path);
    if (!random) {
        *rays = rtt_extremes_watertight_rays(scene, inside, max, count);
        return *rays ? true : rtt_error_set(err, "%s: out of memory for %zu rays", scene->path, max);
    }
    if (!(*rays = malloc((max ? max : 1) * sizeof **rays)))
        return rtt_error_set(err, "%s: out of memory for %zu rays", scene->path, max);
    uint64_t state = seed;
    for (size_t i = 0; i < max; i++) {
        rtt_vec3 d = random_direction(&state);
        (*rays)[i] = (rtt_ray){{inside[0], inside[1], inside[2]}, {d.x, d.y, d.z}, 0.0f, INFINITY};
    }
    *count = max;
    return true;
}

/* The generators work in the scene's stored coordinates (what engines
 * trace); rays.bin holds the scene's own, which rtt trace moves back. */
static bool kind_rays(const rtt_scene *scene, size_t kind, rtt_engine *reference, size_t n, uint64_t seed,
                      rtt_ray **rays, size_t *count, rtt_error *err)
{
    *rays = NULL;
    *count = 0;
    if (kind >= KIND_COUNT) return rtt_error_set(err, "unknown ray kind %zu", kind);
    const ray_kind *k = &kinds[kind];
    if (k->set >= 0) return rtt_conform_make_rays(scene, (rtt_conform_ray_set)k->set, reference, n, seed, rays, count, err);
    if (!k->pattern) return inside_rays(scene, strcmp(k->name, "inside-random") == 0, seed, n, rays, count, err);
    *rays = malloc((n ? n : 1) * sizeof **rays);
    if (!*rays) return rtt_error_set(err, "%s: out of memory for %zu rays", scene->path, n);
    *count = k->pattern(scene, seed, n, *rays);
    return true;
}

bool rtt_conform_make_kind(const rtt_scene *scene, size_t kind, rtt_engine *reference, size_t n, uint64_t seed,
                           rtt_ray **rays, size_t *count, rtt_error *err)
{
    if (!kind_rays(scene, kind, reference, n, seed, rays, count, err)) return false;
    rtt_rays_from_stored(scene, *rays, *count);
    return true;
}

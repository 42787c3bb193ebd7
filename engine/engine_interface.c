/* The engine-independent half of the engine interface: dispatch through the
 * vtable, option defaults and the names of accels.  Construction by name is
 * engine_registry.c's; kernel names belong to each engine's descriptor
 * table. */
#include <math.h>
#include <string.h>

#include "rtt/engine.h"

static const char *const accel_names[RTT_ACCEL_COUNT] = {"default", "kd", "bvh", "pgrid"};
static const char *const isect_names[RTT_ISECT_COUNT] = {"default", "watertight", "projected"};

void rtt_engine_intersect(rtt_engine *engine, const rtt_ray *rays, rtt_hit *hits, size_t n)
{
    engine->vt->intersect(engine, rays, hits, n);
}

void rtt_engine_occluded(rtt_engine *engine, const rtt_ray *rays, uint8_t *occluded, size_t n)
{
    engine->vt->occluded(engine, rays, occluded, n);
}

void rtt_engine_destroy(rtt_engine *engine)
{
    if (engine) engine->vt->destroy(engine);
}

bool rtt_engine_tree_info(rtt_engine *engine, rtt_tree_info *info)
{
    memset(info, 0, sizeof *info);
    return engine->vt->tree_info ? engine->vt->tree_info(engine, info) : false;
}

uint32_t rtt_kd_default_max_depth(uint32_t triangles)
{
    double depth = round(2.0 + log2(triangles > 1 ? (double)triangles : 1.0));
    return depth < 8.0 ? 8u : depth > 64.0 ? 64u : (uint32_t)depth;
}

const char *rtt_engine_kernel_name(rtt_engine *engine)
{
    return engine->vt->kernel_name ? engine->vt->kernel_name(engine) : "";
}

void rtt_rays_to_stored(const rtt_scene *scene, rtt_ray *rays, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const double org[3] = {rays[i].org[0], rays[i].org[1], rays[i].org[2]};
        const rtt_vec3 stored = rtt_scene_point_to_stored(scene, org);
        rays[i].org[0] = stored.x, rays[i].org[1] = stored.y, rays[i].org[2] = stored.z;
    }
}

void rtt_rays_from_stored(const rtt_scene *scene, rtt_ray *rays, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        double org[3];
        rtt_scene_point_from_stored(scene, rtt_v3(rays[i].org[0], rays[i].org[1], rays[i].org[2]), org);
        for (int a = 0; a < 3; a++) rays[i].org[a] = (float)org[a];
    }
}

const char *rtt_engine_isect_name(rtt_engine *engine)
{
    return engine->vt->isect_name ? engine->vt->isect_name(engine) : "";
}

void rtt_engine_options_default(rtt_engine_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->tile = 8;
    opt->leaf_culling = 1;
}

const char *rtt_accel_name(rtt_accel accel)
{
    return (unsigned)accel < RTT_ACCEL_COUNT ? accel_names[accel] : "unknown";
}

/* The index of `name` among names[1..count-1] (0, "default", is not a name
 * a caller may give), or -1. */
static int name_index(const char *const *names, int count, const char *name)
{
    for (int i = 1; i < count; i++)
        if (name && strcmp(name, names[i]) == 0) return i;
    return -1;
}

bool rtt_accel_parse(const char *name, rtt_accel *out)
{
    const int i = name_index(accel_names, RTT_ACCEL_COUNT, name);
    if (i > 0) *out = (rtt_accel)i;
    return i > 0;
}

const char *rtt_isect_name(rtt_isect isect)
{
    return (unsigned)isect < RTT_ISECT_COUNT ? isect_names[isect] : "unknown";
}

bool rtt_isect_parse(const char *name, rtt_isect *out)
{
    const int i = name_index(isect_names, RTT_ISECT_COUNT, name);
    if (i > 0) *out = (rtt_isect)i;
    return i > 0;
}

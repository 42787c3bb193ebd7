/* The engine-independent half of the engine interface: dispatch through the
 * vtable, option defaults and the names of accels.  Construction by name is
 * engine_registry.c's; kernel names belong to each engine's descriptor
 * table. */
#include <math.h>
#include <string.h>

#include "rtt/engine.h"

static const char *const accel_names[RTT_ACCEL_COUNT] = {"default", "kd", "pgrid"};

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

bool rtt_accel_parse(const char *name, rtt_accel *out)
{
    for (int i = RTT_ACCEL_DEFAULT + 1; i < RTT_ACCEL_COUNT; i++)
        if (name && strcmp(name, accel_names[i]) == 0) {
            *out = (rtt_accel)i;
            return true;
        }
    return false;
}

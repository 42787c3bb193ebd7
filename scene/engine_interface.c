/* The engine-independent half of the engine interface: dispatch through the
 * vtable, option defaults and names.  Engine construction by name lives in
 * conformance/engine_registry.c, the only layer that sees every engine. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/render.h"

static const char *const traversal_names[RTT_TRAVERSAL_COUNT] = {
    "mono", "packet", "omni", "frustum", "mft", "cone", "mft-cone",
};

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

void rtt_engine_options_default(rtt_engine_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->traversal = RTT_TRAVERSAL_MONO;
    opt->tile = 8;
    opt->leaf_culling = 1;
}

const char *rtt_traversal_name(rtt_traversal t)
{
    return (unsigned)t < RTT_TRAVERSAL_COUNT ? traversal_names[t] : "unknown";
}

int rtt_traversal_parse(const char *name)
{
    for (int i = 0; i < RTT_TRAVERSAL_COUNT; i++)
        if (strcmp(name, traversal_names[i]) == 0) return i;
    return -1;
}

void rtt_render_options_default(rtt_render_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->shadows = RTT_SHADOWS_HARD;
    opt->shadow_samples = 16;
    rtt_engine_options_default(&opt->engine);
}

/* Parses the count after "method:" into 1..RTT_MAX_SHADOW_SAMPLES. */
static bool parse_sample_count(const char *text, const char *count, rtt_render_options *opt, rtt_error *err)
{
    char *end = NULL;
    long n = strtol(count, &end, 10);
    if (*count == '\0' || *end != '\0' || n < 1 || n > (long)RTT_MAX_SHADOW_SAMPLES)
        return rtt_error_set(err, "--shadows %s: the sample count must be a whole number from 1 to %u", text,
                             RTT_MAX_SHADOW_SAMPLES);
    opt->shadow_samples = (uint32_t)n;
    return true;
}

bool rtt_shadow_method_parse(const char *text, rtt_render_options *opt, rtt_error *err)
{
    static const struct { const char *name; rtt_shadow_method method; } counted[] = {
        {"multi:", RTT_SHADOWS_MULTI}, {"cone:", RTT_SHADOWS_CONE}, {"pyramid:", RTT_SHADOWS_PYRAMID},
    };
    if (strcmp(text, "none") == 0) { opt->shadows = RTT_SHADOWS_NONE; return true; }
    if (strcmp(text, "hard") == 0) { opt->shadows = RTT_SHADOWS_HARD; return true; }
    for (size_t i = 0; i < sizeof counted / sizeof counted[0]; i++) {
        size_t len = strlen(counted[i].name);
        if (strncmp(text, counted[i].name, len) == 0) {
            opt->shadows = counted[i].method;
            return parse_sample_count(text, text + len, opt, err);
        }
    }
    if (strcmp(text, "edgewidth") == 0) { opt->shadows = RTT_SHADOWS_EDGEWIDTH; return true; }
    if (strncmp(text, "edgewidth:", 10) == 0) {
        char *end = NULL;
        float r = strtof(text + 10, &end);
        if (text[10] == '\0' || *end != '\0' || !(r > 0.0f) || r > 1e30f)
            return rtt_error_set(err, "--shadows %s: the radius R must be a positive number", text);
        opt->shadows = RTT_SHADOWS_EDGEWIDTH;
        opt->edge_radius = r;
        return true;
    }
    return rtt_error_set(err, "--shadows %s: expected none, hard, multi:N, cone:N, pyramid:N or edgewidth[:R]",
                         text);
}

static const char *sampled_method_name(rtt_shadow_method m)
{
    return m == RTT_SHADOWS_MULTI ? "multi" : m == RTT_SHADOWS_CONE ? "cone" : m == RTT_SHADOWS_PYRAMID ? "pyramid" : NULL;
}

bool rtt_render_check(const rtt_scene *scene, const rtt_render_options *opt, const rtt_image *out, uint32_t width,
                      uint32_t height, rtt_error *err)
{
    const char *sampled = sampled_method_name(opt->shadows);
    if ((unsigned)opt->shadows > RTT_SHADOWS_EDGEWIDTH)
        return rtt_error_set(err, "unknown shadow method %d", (int)opt->shadows);
    if (sampled && (opt->shadow_samples < 1 || opt->shadow_samples > RTT_MAX_SHADOW_SAMPLES))
        return rtt_error_set(err, "--shadows %s:%u: the sample count must be a whole number from 1 to %u", sampled,
                             opt->shadow_samples, RTT_MAX_SHADOW_SAMPLES);
    if (opt->shadows == RTT_SHADOWS_EDGEWIDTH && !(opt->edge_radius >= 0.0f && opt->edge_radius <= 1e30f))
        return rtt_error_set(err, "--shadows edgewidth:%g: R must be a positive number", (double)opt->edge_radius);
    if (width == 0 || height == 0)
        return rtt_error_set(err, "%s: the image size %ux%u is empty", scene->path, width, height);
    if (out->width != width || out->height != height)
        return rtt_error_set(err, "%s: the output image is %ux%u but the render is %ux%u", scene->path, out->width,
                             out->height, width, height);
    if (!out->rgb) return rtt_error_set(err, "%s: the output image has no colour plane", scene->path);
    if (((opt->aovs & RTT_AOV_DEPTH) && !out->depth) || ((opt->aovs & RTT_AOV_PRIM) && !out->prim) ||
        ((opt->aovs & RTT_AOV_NORMAL) && !out->normal))
        return rtt_error_set(err, "%s: the output image lacks an AOV plane the options ask for", scene->path);
    if (scene->triangle_count > 0 && (!scene->materials || !scene->triangle_material))
        return rtt_error_set(err, "%s: the scene has no materials (rtt_scene_finish was not called)", scene->path);
    return true;
}

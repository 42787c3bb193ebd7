/* Render options: defaults, the shadow-method syntax, and the checks every
 * renderer relies on; rtt_render, the one render entry. */
#include <stdlib.h>
#include <string.h>

#include "rtt/image.h"
#include "rtt/interleaved.h"
#include "rtt/render.h"

void rtt_render_options_default(rtt_render_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->shadows = RTT_SHADOWS_HARD;
    opt->shadow_samples = 16;
    opt->spp = 1;
    opt->shadow_filter = true;
    opt->max_bounces = RTT_BOUNCES_OF_SCENE;
    rtt_engine_options_default(&opt->engine);
}

/* Parses the count after "method:" into 1..RTT_MAX_SHADOW_SAMPLES. */
static bool parse_sample_count(const char *text, const char *count, rtt_render_options *opt, rtt_error *err)
{
    char *end = NULL;
    long n = strtol(count, &end, 10);
    if (*count == '\0' || *end != '\0' || n < 1 || n > (long)RTT_MAX_SHADOW_SAMPLES)
        return rtt_error_set(err, "shadow method \"%s\": the sample count must be a whole number from 1 to %u", text,
                             RTT_MAX_SHADOW_SAMPLES);
    opt->shadow_samples = (uint32_t)n;
    return true;
}

/* "[:N][:nofilter|:refine]" after "interleaved" or "frusta": N in 4..32 (default 16), the filter on unless
 * :nofilter, the refining second pass with :refine. */
static bool parse_interleaved(const char *text, const char *rest, rtt_shadow_method method, rtt_render_options *opt,
                              rtt_error *err)
{
    const char *name = method == RTT_SHADOWS_FRUSTA ? "frusta" : "interleaved";
    uint32_t n = RTT_INTERLEAVED_DEFAULT_SAMPLES;
    bool filter = true, refine = false;
    if (*rest == ':' && rest[1] >= '0' && rest[1] <= '9') {
        char *end = NULL;
        long v = strtol(rest + 1, &end, 10);
        if (v < (long)RTT_INTERLEAVED_MIN_SAMPLES || v > (long)RTT_INTERLEAVED_MAX_SAMPLES || (*end && *end != ':'))
            return rtt_error_set(err, "shadow method \"%s\": the sample count must be a whole number from %u to %u",
                                 text, RTT_INTERLEAVED_MIN_SAMPLES, RTT_INTERLEAVED_MAX_SAMPLES);
        n = (uint32_t)v;
        rest = end;
    }
    if (strcmp(rest, ":nofilter") == 0)
        filter = false;
    else if (strcmp(rest, ":refine") == 0)
        refine = true;
    else if (*rest != '\0')
        return rtt_error_set(err, "shadow method \"%s\": expected %s[:N][:nofilter|:refine], N from %u to %u", text,
                             name, RTT_INTERLEAVED_MIN_SAMPLES, RTT_INTERLEAVED_MAX_SAMPLES);
    opt->shadows = method;
    opt->shadow_samples = n;
    opt->shadow_filter = filter;
    opt->shadow_refine = refine;
    return true;
}

bool rtt_shadow_method_parse(const char *text, rtt_render_options *opt, rtt_error *err)
{
    static const struct { const char *name; rtt_shadow_method method; } counted[] = {
        {"multi:", RTT_SHADOWS_MULTI}, {"cone:", RTT_SHADOWS_CONE}, {"pyramid:", RTT_SHADOWS_PYRAMID},
        {"pgrid:", RTT_SHADOWS_PGRID_SOFT},
    };
    if (strcmp(text, "none") == 0) { opt->shadows = RTT_SHADOWS_NONE; return true; }
    if (strcmp(text, "hard") == 0) { opt->shadows = RTT_SHADOWS_HARD; return true; }
    if (strcmp(text, "pgrid") == 0) { opt->shadows = RTT_SHADOWS_PGRID; return true; }
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
            return rtt_error_set(err, "shadow method \"%s\": the radius R must be a positive number", text);
        opt->shadows = RTT_SHADOWS_EDGEWIDTH;
        opt->edge_radius = r;
        return true;
    }
    if (strcmp(text, "interleaved") == 0 || strncmp(text, "interleaved:", 12) == 0)
        return parse_interleaved(text, text + 11, RTT_SHADOWS_INTERLEAVED, opt, err);
    if (strcmp(text, "frusta") == 0 || strncmp(text, "frusta:", 7) == 0)
        return parse_interleaved(text, text + 6, RTT_SHADOWS_FRUSTA, opt, err);
    return rtt_error_set(err,
                         "shadow method \"%s\": expected none, hard, multi:N, cone:N, pyramid:N, edgewidth[:R], "
                         "interleaved[:N][:nofilter|:refine], frusta[:N][:nofilter|:refine], pgrid or pgrid:N",
                         text);
}

static const char *const method_names[] = {
    [RTT_SHADOWS_NONE] = "none",           [RTT_SHADOWS_HARD] = "hard",
    [RTT_SHADOWS_MULTI] = "multi",         [RTT_SHADOWS_CONE] = "cone",
    [RTT_SHADOWS_PYRAMID] = "pyramid",     [RTT_SHADOWS_EDGEWIDTH] = "edgewidth",
    [RTT_SHADOWS_INTERLEAVED] = "interleaved", [RTT_SHADOWS_FRUSTA] = "frusta",
    [RTT_SHADOWS_PGRID] = "pgrid",         [RTT_SHADOWS_PGRID_SOFT] = "pgrid"};
_Static_assert(sizeof method_names / sizeof method_names[0] == RTT_SHADOW_METHOD_COUNT, "a name per shadow method");

/* A value of the enum with a name. */
static bool method_known(rtt_shadow_method method)
{
    return (unsigned)method < RTT_SHADOW_METHOD_COUNT && method_names[method] != NULL;
}

const char *rtt_shadow_method_name(rtt_shadow_method method)
{
    return method_known(method) ? method_names[method] : "unknown";
}

static const char *sampled_method_name(rtt_shadow_method m)
{
    return m == RTT_SHADOWS_MULTI || m == RTT_SHADOWS_CONE || m == RTT_SHADOWS_PYRAMID || m == RTT_SHADOWS_PGRID_SOFT
               ? method_names[m]
               : NULL;
}

bool rtt_render_check(const rtt_scene *scene, const rtt_render_options *opt, const rtt_image *out, uint32_t width,
                      uint32_t height, rtt_error *err)
{
    const char *sampled = sampled_method_name(opt->shadows);
    if (!method_known(opt->shadows))
        return rtt_error_set(err, "unknown shadow method %d", (int)opt->shadows);
    if (sampled && (opt->shadow_samples < 1 || opt->shadow_samples > RTT_MAX_SHADOW_SAMPLES))
        return rtt_error_set(err, "shadow method %s:%u: the sample count must be a whole number from 1 to %u", sampled,
                             opt->shadow_samples, RTT_MAX_SHADOW_SAMPLES);
    if ((opt->shadows == RTT_SHADOWS_INTERLEAVED || opt->shadows == RTT_SHADOWS_FRUSTA) &&
        (opt->shadow_samples < RTT_INTERLEAVED_MIN_SAMPLES || opt->shadow_samples > RTT_INTERLEAVED_MAX_SAMPLES))
        return rtt_error_set(err, "shadow method %s:%u: the sample count must be a whole number from %u to %u",
                             method_names[opt->shadows], opt->shadow_samples, RTT_INTERLEAVED_MIN_SAMPLES,
                             RTT_INTERLEAVED_MAX_SAMPLES);
    if (opt->shadows == RTT_SHADOWS_EDGEWIDTH && !(opt->edge_radius >= 0.0f && opt->edge_radius <= 1e30f))
        return rtt_error_set(err, "shadow method edgewidth:%g: R must be a positive number", (double)opt->edge_radius);
    if (opt->spp > RTT_MAX_SPP)
        return rtt_error_set(err, "%u samples per pixel: at most %u", opt->spp, RTT_MAX_SPP);
    if (opt->shadows == RTT_SHADOWS_EDGEWIDTH)
        for (uint32_t i = 0; i < scene->light_count; i++)
            if (scene->lights[i].type == RTT_LIGHT_QUAD)
                return rtt_error_set(err, "%s: light %u is a quad light: edgewidth shadows draw sphere and point lights only",
                                     scene->path, i);
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

uint32_t rtt_render_bounces(const rtt_render_options *opt, const rtt_scene *scene)
{
    return opt->max_bounces == RTT_BOUNCES_OF_SCENE ? scene->max_bounces : opt->max_bounces;
}

uint32_t rtt_render_spp(const rtt_render_options *opt) { return opt->spp ? opt->spp : 1u; }

bool rtt_render_options_check(const char *name, const rtt_render_options *opt, rtt_error *err)
{
    if (!rtt_engine_options_check(name, &opt->engine, err)) return false;
    const rtt_engine_class *cls = rtt_engine_find(name);
    if (!method_known(opt->shadows))
        return rtt_error_set(err, "unknown shadow method %d", (int)opt->shadows);
    if (!(cls->shadow_methods & (1u << opt->shadows)))
        return rtt_error_set(err, "engine \"%s\" does not render %s shadows", name,
                             rtt_shadow_method_name(opt->shadows));
    /* the group and edge-width kernels walk the kd-tree; a BVH has none */
    if (opt->engine.accel == RTT_ACCEL_BVH && (opt->shadows == RTT_SHADOWS_CONE ||
                                                opt->shadows == RTT_SHADOWS_PYRAMID ||
                                                opt->shadows == RTT_SHADOWS_EDGEWIDTH))
        return rtt_error_set(err, "%s shadows need the kd-tree (--accel kd), not the bvh",
                             rtt_shadow_method_name(opt->shadows));
    /* the soft-shadow frusta walk the BVH */
    if (opt->shadows == RTT_SHADOWS_FRUSTA && opt->engine.accel != RTT_ACCEL_BVH)
        return rtt_error_set(err, "frusta shadows trace multi-frusta through the BVH: they need --accel bvh");
    if (opt->max_bounces != RTT_BOUNCES_OF_SCENE && opt->max_bounces > RTT_MAX_BOUNCES)
        return rtt_error_set(err, "max bounces %u: at most %u", opt->max_bounces, RTT_MAX_BOUNCES);
    if (opt->spp > RTT_MAX_SPP)
        return rtt_error_set(err, "%u samples per pixel: at most %u", opt->spp, RTT_MAX_SPP);
    return true;
}

bool rtt_render(rtt_engine *engine, const rtt_render_options *opt, rtt_image *out, rtt_render_stats *stats,
                rtt_error *err)
{
    rtt_render_options defaults;
    if (!opt) {
        rtt_render_options_default(&defaults);
        opt = &defaults;
    }
    if (!engine || !out) return rtt_error_set(err, "render: no engine or no image given");
    if (!engine->vt->render) return rtt_error_set(err, "engine \"%s\" cannot render", engine->vt->name);
    if (!rtt_render_options_check(engine->vt->name, opt, err)) return false;
    /* the renderer checks the image (rtt_render_check) and fills the stats:
     * it may be called directly too */
    return engine->vt->render(engine, opt, out, stats, err);
}

/* The reference Whitted renderer: exactly the shading model of
 * include/rtt/shade.h (Thesis 4.2.1's five fixed-function shader types,
 * traced one ray at a time), written for obviousness.
 *
 * One primary ray per pixel through its centre; at a hit the shading normal
 * is turned to face the ray, the local colour sums the ambient term and every
 * light times its visibility, and reflective/transparent materials recurse up
 * to max_bounces.  Whether a refracted ray enters or leaves the object is
 * decided by the geometric normal against the ray.  Visibility:
 *   none      1
 *   hard      one shadow ray to the light's centre (sphere lights too)
 *   multi:N   N rays to rtt_light_sample(light, p, i, N, pixel) on sphere
 *             and quad lights, the mean of their transmissions; one ray for
 *             point lights.
 *   interleaved:N[:nofilter|:refine]  N rays to the samples of the
 *             pixel's 4x4 interleaved set (rtt/interleaved.h) on lights with
 *             area, one ray for the others; the primary hit's light terms
 *             go to rtt_shadow_planes, whose visibility is filtered by the
 *             4x4 discontinuity filter (unless :nofilter) and composed once
 *             every tile is done; with :refine the pixels the filter moved
 *             past their samples' noise are retraced first with all 16 sets
 *             (rtt_engine_refined_visibilities, one pixel after another).
 * A shadow ray's transmission is 1 when it is clear; when it is occluded in
 * a scene with transparent materials, the ray is traced again for its
 * closest hits, one surface after the other (tnear moved to each hit), and
 * carries the product of their transparencies (shade.h).
 *   edgewidth[:R]  Edge Width Soft Shadows (Thesis chapter 5; quad lights
 *             are refused): on sphere
 *             lights 1 - the occlusion of rtt_edge_width_reference along
 *             the ray from the light's centre to p, through a reference
 *             kd-tree of its own (the tracer may be any engine, but edge
 *             widths need every crossing; transparent occluders count as
 *             opaque there); hard for point lights.
 * A light whose unoccluded contribution is exactly zero casts no shadow rays
 * (vis would multiply zero).  Every ray goes through the `tracer` engine,
 * which may be any engine (Embree renders the reference image this way).
 *
 * Tiles of 16x16 pixels go to threads through rtt_tiles_run; a pixel depends
 * on nothing but its own rays, so the image is bit-identical for any thread
 * count.  Ray counts are summed per tile and added atomically. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "engine/clock.h"
#include "engine/threads.h"

#include "edge_width_reference.h"
#include "rtt/interleaved.h"
#include "rtt/reference.h"
#include "rtt/shade.h"

#define REFERENCE_TILE 16u

typedef struct ray_counts {
    uint64_t primary, shadow, secondary;
} ray_counts;

typedef struct render_job {
    const rtt_scene *scene;
    rtt_engine *tracer;
    rtt_image *out;
    rtt_camera_frame frame;
    uint32_t width, height;
    uint32_t max_bounces;
    rtt_shadow_method shadows;
    uint32_t shadow_samples;
    uint32_t spp;                        /* anti-aliasing samples per pixel */
    float epsilon;
    bool transparent_shadows;            /* shadow rays pass transparent surfaces */
    const rtt_kd_tree *edge_tree;        /* edgewidth only */
    rtt_edge_width_model edge_model;
    rtt_shadow_planes *planes;           /* interleaved only */
    _Atomic uint64_t primary, shadow, secondary;
} render_job;

static rtt_hit trace_closest(const render_job *job, const rtt_ray *ray)
{
    rtt_hit hit;
    rtt_engine_intersect(job->tracer, ray, &hit, 1);
    return hit;
}

/* How much light passes the segment from p to target (both ends
 * excluded): 1 when it is clear, 0 when an opaque surface blocks it, and in
 * scenes with transparent materials the product of the transparencies of
 * the surfaces it crosses, nearest first (shade.h). */
static float segment_transmission(const render_job *job, rtt_vec3 p, rtt_vec3 target, ray_counts *counts)
{
    return rtt_engine_segment_transmission(job->tracer, job->scene, p, target, job->epsilon, job->transparent_shadows,
                                           &counts->shadow);
}

/* vis in [0, 1] of the light from p by the chosen shadow method. */
static float light_visibility(const render_job *job, const rtt_light *light, rtt_vec3 p, uint32_t pixel,
                              ray_counts *counts)
{
    switch (job->shadows) {
    case RTT_SHADOWS_NONE:
        return 1.0f;
    case RTT_SHADOWS_INTERLEAVED:
        if (rtt_light_has_area(light)) {
            const uint32_t set = rtt_interleaved_set(pixel % job->width, pixel / job->width), n = job->shadow_samples;
            const rtt_light_frame frame = rtt_light_sample_frame(light, p);
            float clear = 0.0f;
            for (uint32_t i = 0; i < n; i++) {
                float s[2], xy[2];
                rtt_interleaved_sample(set, i, n, s);
                rtt_light_sample_coords(light, s, xy);
                clear += segment_transmission(job, p, rtt_light_frame_point(&frame, xy[0], xy[1]), counts);
            }
            return clear / (float)n;
        }
        return segment_transmission(job, p, light->position, counts);
    case RTT_SHADOWS_MULTI:
        if (light->type != RTT_LIGHT_POINT) {
            float clear = 0.0f;
            for (uint32_t i = 0; i < job->shadow_samples; i++)
                clear += segment_transmission(job, p, rtt_light_sample(light, p, i, job->shadow_samples, pixel), counts);
            return clear / (float)job->shadow_samples;
        }
        return segment_transmission(job, p, light->position, counts);
    case RTT_SHADOWS_EDGEWIDTH:
        if (light->type == RTT_LIGHT_SPHERE && light->radius > 0.0f) {
            rtt_ray ray;
            if (!rtt_edge_width_ray(light->position, p, job->epsilon, &ray)) return 1.0f;
            counts->shadow++;
            return 1.0f - rtt_edge_width_reference(job->edge_tree, &job->edge_model, &ray, NULL);
        }
        return segment_transmission(job, p, light->position, counts);
    default: /* hard */
        return segment_transmission(job, p, light->position, counts);
    }
}

static rtt_vec3 trace_colour(const render_job *job, const rtt_ray *ray, uint32_t depth, uint32_t pixel,
                             ray_counts *counts);

/* The ambient term plus every light's contribution times its visibility;
 * with `planes` (interleaved, primary hits) the ambient term alone, each
 * light's contribution times `weight` and its visibility going to the
 * planes instead. */
static rtt_vec3 local_colour(const render_job *job, const rtt_surface *s, uint32_t pixel, ray_counts *counts,
                             rtt_shadow_planes *planes, float weight)
{
    const rtt_scene *scene = job->scene;
    rtt_vec3 colour = rtt_v3_scale(s->diffuse, scene->ambient);
    if (planes) { /* the shadow rays' origin, for the refining pass */
        planes->point[3 * (size_t)pixel + 0] = s->point.x;
        planes->point[3 * (size_t)pixel + 1] = s->point.y;
        planes->point[3 * (size_t)pixel + 2] = s->point.z;
    }
    for (uint32_t i = 0; i < scene->light_count; i++) {
        const rtt_light *light = &scene->lights[i];
        rtt_vec3 to_light = rtt_v3_sub(light->position, s->point);
        float distance = rtt_v3_length(to_light);
        if (!(distance > 0.0f)) continue;
        rtt_vec3 contribution = rtt_shade_light(s, rtt_v3_scale(to_light, 1.0f / distance), light, distance);
        if (contribution.x == 0.0f && contribution.y == 0.0f && contribution.z == 0.0f) continue;
        float vis = light_visibility(job, light, s->point, pixel, counts);
        if (planes) {
            const size_t at = (size_t)planes->width * planes->height * i + pixel;
            planes->visibility[at] = vis;
            rtt_vec3 c = rtt_v3_scale(contribution, weight);
            planes->contribution[3 * at + 0] = c.x;
            planes->contribution[3 * at + 1] = c.y;
            planes->contribution[3 * at + 2] = c.z;
        } else {
            colour = rtt_v3_madd(colour, contribution, vis);
        }
    }
    return colour;
}

static rtt_vec3 secondary_colour(const render_job *job, rtt_vec3 origin, rtt_vec3 dir, uint32_t depth,
                                 uint32_t pixel, ray_counts *counts)
{
    dir = rtt_v3_normalize(dir);
    rtt_ray ray = {{origin.x, origin.y, origin.z}, {dir.x, dir.y, dir.z}, job->epsilon, INFINITY};
    counts->secondary++;
    return trace_colour(job, &ray, depth, pixel, counts);
}

/* colour = (1 - wr - wt) local + wr reflected + wt refracted (shade.h) */
static rtt_vec3 shade_hit(const render_job *job, const rtt_ray *ray, const rtt_hit *hit, uint32_t depth,
                          uint32_t pixel, ray_counts *counts)
{
    rtt_surface s = rtt_surface_at(job->scene, ray, hit);
    float wr, wt;
    rtt_shade_weights(s.material, depth, job->max_bounces, &wr, &wt);
    rtt_shadow_planes *planes = depth == 0 ? job->planes : NULL;
    rtt_vec3 colour = rtt_v3_scale(local_colour(job, &s, pixel, counts, planes, 1.0f - wr - wt), 1.0f - wr - wt);
    if (wr > 0.0f) {
        rtt_vec3 reflected = rtt_v3_reflect(s.dir, s.normal);
        colour = rtt_v3_madd(colour, secondary_colour(job, s.point, reflected, depth + 1, pixel, counts), wr);
    }
    if (wt > 0.0f) {
        const float ior = s.material->ior;
        const float eta_from = s.entering ? 1.0f : ior, eta_to = s.entering ? ior : 1.0f;
        rtt_vec3 refracted = rtt_refract(s.dir, s.normal, eta_from, eta_to);
        colour = rtt_v3_madd(colour, secondary_colour(job, s.point, refracted, depth + 1, pixel, counts), wt);
    }
    return colour;
}

static rtt_vec3 trace_colour(const render_job *job, const rtt_ray *ray, uint32_t depth, uint32_t pixel,
                             ray_counts *counts)
{
    rtt_hit hit = trace_closest(job, ray);
    if (hit.prim == RTT_MISS) return job->scene->background;
    return shade_hit(job, ray, &hit, depth, pixel, counts);
}

/* The pixel's colour is the mean of its spp samples (rtt_pixel_sample: a box
 * filter); depth, prim and normal are those of its first sample. */
static void render_pixel(render_job *job, uint32_t px, uint32_t py, ray_counts *counts)
{
    const uint32_t pixel = py * job->width + px;
    rtt_ray ray;
    rtt_hit hit;
    rtt_vec3 colour = rtt_v3(0.0f, 0.0f, 0.0f);
    for (uint32_t i = job->spp; i-- > 0;) { /* the last traced is sample 0, whose hit the AOVs keep */
        float offset[2];
        rtt_pixel_sample(i, job->spp, pixel, offset);
        ray = rtt_camera_ray_at(&job->frame, px, py, offset);
        hit = trace_closest(job, &ray);
        counts->primary++;
        colour = rtt_v3_add(colour, hit.prim == RTT_MISS ? job->scene->background
                                                         : shade_hit(job, &ray, &hit, 0, pixel, counts));
    }
    if (job->spp > 1) colour = rtt_v3_scale(colour, 1.0f / (float)job->spp);

    rtt_image *out = job->out;
    out->rgb[3 * (size_t)pixel + 0] = colour.x;
    out->rgb[3 * (size_t)pixel + 1] = colour.y;
    out->rgb[3 * (size_t)pixel + 2] = colour.z;
    if (out->depth) out->depth[pixel] = hit.prim == RTT_MISS ? INFINITY : hit.t;
    if (out->prim) out->prim[pixel] = hit.prim;
    if (job->planes) {
        rtt_shadow_planes *planes = job->planes;
        planes->rest[3 * (size_t)pixel + 0] = colour.x;
        planes->rest[3 * (size_t)pixel + 1] = colour.y;
        planes->rest[3 * (size_t)pixel + 2] = colour.z;
        if (hit.prim != RTT_MISS) {
            rtt_vec3 n = rtt_surface_at(job->scene, &ray, &hit).normal;
            planes->depth[pixel] = hit.t;
            planes->normal[3 * (size_t)pixel + 0] = n.x;
            planes->normal[3 * (size_t)pixel + 1] = n.y;
            planes->normal[3 * (size_t)pixel + 2] = n.z;
        }
    }
    if (out->normal) {
        rtt_vec3 n = rtt_v3(0.0f, 0.0f, 0.0f);
        if (hit.prim != RTT_MISS) n = rtt_surface_at(job->scene, &ray, &hit).normal;
        out->normal[3 * (size_t)pixel + 0] = n.x;
        out->normal[3 * (size_t)pixel + 1] = n.y;
        out->normal[3 * (size_t)pixel + 2] = n.z;
    }
}

static void render_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)thread;
    render_job *job = context;
    ray_counts counts = {0, 0, 0};
    for (uint32_t py = y0; py < y1; py++)
        for (uint32_t px = x0; px < x1; px++) render_pixel(job, px, py, &counts);
    atomic_fetch_add(&job->primary, counts.primary);
    atomic_fetch_add(&job->shadow, counts.shadow);
    atomic_fetch_add(&job->secondary, counts.secondary);
}

/* The refining pass (rtt/interleaved.h), one pixel after another. */
static bool refine_pixels(void *context, uint32_t light, const uint32_t *pixel, size_t count, float *vis)
{
    render_job *job = context;
    uint64_t rays = 0;
    rtt_engine_refined_visibilities(job->tracer, job->scene, job->planes, light, pixel, count, job->shadow_samples,
                                    job->epsilon, job->transparent_shadows, vis, &rays);
    atomic_fetch_add(&job->shadow, rays);
    return true;
}

static const char *shadow_method_text(const rtt_render_options *opt, char *buffer, size_t size)
{
    switch (opt->shadows) {
    case RTT_SHADOWS_CONE: snprintf(buffer, size, "cone:%u", opt->shadow_samples); break;
    case RTT_SHADOWS_PYRAMID: snprintf(buffer, size, "pyramid:%u", opt->shadow_samples); break;
    default: snprintf(buffer, size, "method %d", (int)opt->shadows); break;
    }
    return buffer;
}

/* Options and image checked before any ray is traced. */
static bool check_request(const rtt_scene *scene, const rtt_render_options *opt, const rtt_image *out,
                          uint32_t width, uint32_t height, rtt_error *err)
{
    if ((unsigned)opt->shadows >= RTT_SHADOW_METHOD_COUNT || !(RTT_REFERENCE_SHADOW_METHODS & (1u << opt->shadows))) {
        char method[64];
        return rtt_error_set(err, "shadow method %s is not drawn by the reference renderer (the optimized one draws it)",
                             shadow_method_text(opt, method, sizeof method));
    }
    return rtt_render_check(scene, opt, out, width, height, err);
}

bool rtt_reference_render(const rtt_scene *scene, rtt_engine *tracer, const rtt_render_options *opt,
                          rtt_image *out, rtt_render_stats *stats, rtt_error *err)
{
    const double start = rtt_clock_seconds();
    rtt_render_options defaults;
    if (!opt) {
        rtt_render_options_default(&defaults);
        opt = &defaults;
    }
    if (!scene || !tracer || !out) return rtt_error_set(err, "reference renderer: no scene, engine or image given");
    const uint32_t width = opt->width ? opt->width : scene->width;
    const uint32_t height = opt->height ? opt->height : scene->height;
    if (!check_request(scene, opt, out, width, height, err)) return false;

    render_job job = {
        .scene = scene,
        .tracer = tracer,
        .out = out,
        .frame = rtt_camera_frame_make(&scene->camera, width, height),
        .width = width,
        .height = height,
        .max_bounces = rtt_render_bounces(opt, scene),
        .shadows = opt->shadows,
        .shadow_samples = opt->shadow_samples,
        .epsilon = rtt_scene_ray_epsilon(scene),
        .transparent_shadows = rtt_scene_has_transparent_shadows(scene),
        .spp = rtt_render_spp(opt),
    };
    rtt_kd_tree edge_tree = {0};
    if (opt->shadows == RTT_SHADOWS_EDGEWIDTH) {
        rtt_kd_build_options build = {.max_depth = opt->engine.max_tree_depth};
        if (!rtt_kd_reference_build(scene, &build, &edge_tree, err)) return false;
        job.edge_tree = &edge_tree;
        job.edge_model = rtt_edge_width_model_make(scene, opt->edge_radius, opt->edge_leak_fix);
    }
    rtt_shadow_planes planes;
    if (opt->shadows == RTT_SHADOWS_INTERLEAVED) {
        if (!rtt_shadow_planes_create(&planes, scene, width, height, err)) return false;
        job.planes = &planes;
    }
    atomic_init(&job.primary, 0);
    atomic_init(&job.shadow, 0);
    atomic_init(&job.secondary, 0);
    rtt_tiles_run_from(opt->tile_source, width, height, REFERENCE_TILE, opt->threads, render_tile, &job,
                       opt->progress, opt->progress_context);
    if (job.edge_tree) rtt_kd_reference_free(&edge_tree);
    if (job.planes) {
        bool resolved = opt->shadow_refine && opt->shadow_filter
                            ? rtt_shadow_planes_resolve_refined(&planes, job.shadow_samples, NULL, refine_pixels, &job,
                                                                out->rgb, NULL)
                            : rtt_shadow_planes_resolve(&planes, opt->shadow_filter, NULL, out->rgb);
        rtt_shadow_planes_free(&planes);
        if (!resolved) return rtt_error_set(err, "%s: out of memory for the shadow filter", scene->path);
    }

    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->primary_rays = atomic_load(&job.primary);
        stats->shadow_rays = atomic_load(&job.shadow);
        stats->secondary_rays = atomic_load(&job.secondary);
        stats->seconds_total = rtt_clock_seconds() - start;
    }
    return true;
}

bool rtt_reference_render_engine(rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                                 rtt_render_stats *stats, rtt_error *err)
{
    return rtt_reference_render(engine->scene, engine, opt, out, stats, err);
}

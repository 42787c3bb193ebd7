/* Thesis 3.3 and Figure 3.2: the optimized renderer's pipeline.  Tiles go
 * to threads through rtt_tiles_run; per tile: primary rays in 2x2 packets
 * (quads in row-major order), traced as one block by the kernel of the
 * chosen traversal (the frustum kernels bound the tile by its frusta/cones,
 * cull packets at leaves and intersect the rest), then the shader proxy
 * (shader_proxy.c): shadow packets (hard, multi:N, cone:N, pyramid:N,
 * edgewidth[:R], interleaved:N), secondary omni packets, colours.  For
 * interleaved:N the tiles fill rtt_shadow_planes (the primary hits' light
 * terms, depth, normal and the rest of the colour), and one pass after the
 * last tile filters and composes the image as the reference does (with
 * :refine retracing the pixels the filter smeared first, refine_pixels).
 *
 * Primary rays are rtt_camera_ray's, the same as the reference renderer's.
 * Scratch is per thread (indexed by the tile callback's thread argument) and
 * a pixel depends only on its own rays, so the image is the same for any
 * thread count.  Statistics: ray counts per kind; packets, traversal steps
 * and intersection tests of the primary 2x2 packets (Tables 4.1 - 4.5: N =
 * steps / packets, I = tests / packets); stage times as Table 3.1 summed
 * over threads (CPU seconds): primary traversal, primary intersection (leaf
 * visits, measured inside the proxy kernels only; the mono/packet/omni
 * kernels report their whole time as traversal), shading (shader proxy
 * without tracing) and secondary (shadow and secondary ray tracing).
 * Timers run only when stats are requested and never change results. */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "engine/render_cache.h"
#include "engine/threads.h"
#include "engine_optimized.h"
#include "kernels.h"
#include "render_pgrid.h"
#include "rtt/optimized.h"
#include "shader_proxy.h"
#include "sp_frusta.h"

typedef struct render_job {
    const rtt_scene *scene;
    rtt_image *out;
    rtt_camera_frame frame;
    uint32_t width, height, tile;
    uint32_t spp;                   /* anti-aliasing samples per pixel */
    sp_shading shading;
    sp_tracer tracer;
    sp_scratch **scratch;           /* one per thread */
    uint32_t threads;
    pgrid_render *pgrid;            /* --accel pgrid: the frame's grid, its cells the tiles; else NULL */
} render_job;

/* Primary rays of the tile as quads, for anti-aliasing sample `sample` of
 * every pixel (rtt_pixel_sample): packet q holds pixels (x, y), (x+1, y),
 * (x, y+1), (x+1, y+1) of quad q; lanes off the image are left out (the
 * packet of a quad wholly off the image has none), so the block is always
 * the tile's (tile/2)^2 packets.  One sample of every pixel of the tile makes
 * one block: its rays are as coherent as one ray per pixel, and its frusta as
 * tight (the multi-frusta paper's way to trace multi-sample anti-aliasing). */
static void push_primary_packets(const render_job *job, sp_scratch *s, uint32_t x0, uint32_t y0, uint32_t x1,
                                 uint32_t y1, uint32_t sample)
{
    uint32_t side = job->tile / 2u, packets = side * side;
    for (uint32_t q = 0; q < packets; q++) {
        uint32_t qx = x0 + 2u * (q % side), qy = y0 + 2u * (q / side);
        rtt_ray rays[4];
        uint32_t pixels[4], count = 0;
        for (uint32_t l = 0; l < 4; l++) {
            uint32_t px = qx + (l & 1u), py = qy + (l >> 1);
            if (px >= x1 || py >= y1) continue;
            float offset[2];
            rtt_pixel_sample(sample, job->spp, py * job->width + px, offset);
            rays[count] = rtt_camera_ray_at(&job->frame, px, py, offset);
            pixels[count++] = py * job->width + px;
        }
        sp_primary_push(s, rays, pixels, count);
    }
}

/* Adds a sample's colour to its pixel (the first one of a pixel sets it);
 * the AOVs come from sample 0, the last one traced, as in the reference. */
static void write_sample(const render_job *job, const sp_node *n, bool first, bool aovs)
{
    rtt_image *out = job->out;
    size_t pixel = n->pixel;
    float *rgb = &out->rgb[3 * pixel];
    rgb[0] = (first ? 0.0f : rgb[0]) + n->colour.x;
    rgb[1] = (first ? 0.0f : rgb[1]) + n->colour.y;
    rgb[2] = (first ? 0.0f : rgb[2]) + n->colour.z;
    if (!aovs) return;
    if (out->depth) out->depth[pixel] = n->hit.prim == RTT_MISS ? INFINITY : n->hit.t;
    if (out->prim) out->prim[pixel] = n->hit.prim;
    rtt_shadow_planes *planes = job->shading.planes;
    if (planes) {
        planes->rest[3 * pixel + 0] = n->colour.x;
        planes->rest[3 * pixel + 1] = n->colour.y;
        planes->rest[3 * pixel + 2] = n->colour.z;
        if (n->hit.prim != RTT_MISS) {
            rtt_vec3 normal = rtt_surface_at(job->scene, &n->ray, &n->hit).normal;
            planes->depth[pixel] = n->hit.t;
            planes->normal[3 * pixel + 0] = normal.x;
            planes->normal[3 * pixel + 1] = normal.y;
            planes->normal[3 * pixel + 2] = normal.z;
        }
    }
    if (out->normal) {
        rtt_vec3 normal = rtt_v3(0.0f, 0.0f, 0.0f);
        if (n->hit.prim != RTT_MISS) normal = rtt_surface_at(job->scene, &n->ray, &n->hit).normal;
        out->normal[3 * pixel + 0] = normal.x;
        out->normal[3 * pixel + 1] = normal.y;
        out->normal[3 * pixel + 2] = normal.z;
    }
}

/* The per-thread scratch of a frame; kept in the caller's rtt_render_cache
 * between frames when it passes one (and reused while the thread count,
 * bounce depth and timing stay the same). */
typedef struct frame_memory {
    uint32_t threads, levels;
    bool timing;
    sp_scratch *scratch[];
} frame_memory;

static void frame_memory_free(void *data)
{
    frame_memory *m = data;
    if (!m) return;
    for (uint32_t t = 0; t < m->threads; t++) sp_scratch_destroy(m->scratch[t]);
    free(m);
}

static frame_memory *frame_memory_get(rtt_render_cache *cache, uint32_t threads, uint32_t levels, bool timing)
{
    frame_memory *m = rtt_render_cache_take(cache, &rtt_optimized_engine_class);
    if (m && m->threads == threads && m->levels == levels && m->timing == timing) {
        for (uint32_t t = 0; t < threads; t++) sp_scratch_begin_frame(m->scratch[t]);
        return m;
    }
    frame_memory_free(m);
    m = calloc(1, sizeof *m + threads * sizeof m->scratch[0]);
    if (!m) return NULL;
    *m = (frame_memory){.threads = threads, .levels = levels, .timing = timing};
    for (uint32_t t = 0; t < threads; t++)
        if (!(m->scratch[t] = sp_scratch_create(levels, timing))) {
            frame_memory_free(m);
            return NULL;
        }
    return m;
}

/* Tiles go to threads first come, first served, so which thread's scratch
 * meets the largest tile changes from frame to frame: before the scratch
 * is kept, every thread's is grown to the largest of each array, and the
 * next frame of the same image grows none. */
static bool frame_memory_even_out(frame_memory *m)
{
    for (uint32_t t = 1; t < m->threads; t++)
        if (!sp_scratch_match(m->scratch[0], m->scratch[t])) return false;
    for (uint32_t t = 1; t < m->threads; t++)
        if (!sp_scratch_match(m->scratch[t], m->scratch[0])) return false;
    return true;
}

/* bvh-mft with one sample per pixel: the kernel makes the tile's primary
 * rays itself from the camera frame (bvh_camera_block), rtt_camera_ray's
 * bits, and the shader gets them with their hits. */
static bool camera_rays_in_kernel(const render_job *job)
{
    return job->tracer.bvh && job->tracer.bvh_kernel->trace_camera && job->spp == 1;
}

static void trace_camera_tile(const render_job *job, sp_scratch *s, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    const uint64_t t0 = rtt_clock_ns();
    const rtt_camera_frame *c = &job->frame;
    const bvh_camera_block block = {{c->eye.x, c->eye.y, c->eye.z}, {c->corner.x, c->corner.y, c->corner.z},
                                    {c->du.x, c->du.y, c->du.z}, {c->dv.x, c->dv.y, c->dv.z}, x0, y0, x1, y1,
                                    false /* the tile is shaded at once: kept in cache */};
    rtt_hit hits[RTT_TILE_MAX * RTT_TILE_MAX];
    bvh_counters counters = {0};
    const bool counting = sp_tile_counting(s);
    job->tracer.bvh_kernel->trace_camera(job->tracer.bvh, &block, hits, counting ? &counters : NULL);
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) {
            const rtt_ray ray = rtt_camera_ray(c, x, y);
            sp_primary_push_hit(s, &ray, &hits[(y - y0) * (x1 - x0) + (x - x0)], y * job->width + x);
        }
    sp_primary_hits_done(s, rtt_clock_ns() - t0);
    /* per 2x2 packet of the tile's rays, as sp_primary_trace counts a BVH row's */
    if (counting) sp_primary_hits_counted(s, ((x1 - x0 + 1) / 2) * ((y1 - y0 + 1) / 2), counters.aabb_tests,
                                          counters.isect_tests);
}

static void render_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    render_job *job = context;
    sp_scratch *s = job->scratch[thread];
    if (sp_scratch_failed(s)) return;
    const uint32_t side = job->tile / 2u;
    sp_tile_begin(s, job->pgrid ? 0 : side * side * job->spp);
    if (job->pgrid) { /* one eye ray per pixel centre: spp is 1 (refused otherwise) */
        pgrid_render_cell(job->pgrid, thread, s, x0, y0, x1, y1);
    } else if (camera_rays_in_kernel(job)) {
        trace_camera_tile(job, s, x0, y0, x1, y1);
    } else {
        /* samples in the reference's order, last to first: the same sums */
        for (uint32_t sample = job->spp; sample-- > 0;) push_primary_packets(job, s, x0, y0, x1, y1, sample);
        sp_primary_trace(&job->tracer, s);
    }
    sp_tile_shade(&job->shading, &job->tracer, s);
    const uint32_t pixels = (x1 - x0) * (y1 - y0), count = sp_tile_pixel_count(s);
    for (uint32_t i = 0; i < count; i++) write_sample(job, sp_tile_pixel(s, i), i < pixels, i >= count - pixels);
    if (job->spp == 1 || count == 0) return;
    const float mean = 1.0f / (float)job->spp;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t c = 3 * (y * job->width + x0); c < 3 * (y * job->width + x1); c++) job->out->rgb[c] *= mean;
    /* interleaved planes: the rest of the colour is the samples' mean, as
     * the reference's (the light terms are sample 0's, in the planes) */
    rtt_shadow_planes *planes = job->shading.planes;
    if (planes)
        for (uint32_t y = y0; y < y1; y++)
            memcpy(&planes->rest[3 * (size_t)(y * job->width + x0)], &job->out->rgb[3 * (size_t)(y * job->width + x0)],
                   3 * (size_t)(x1 - x0) * sizeof(float));
}

static void gather_stats(const render_job *job, rtt_render_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    for (uint32_t t = 0; t < job->threads; t++) {
        const sp_stats *s = sp_scratch_stats(job->scratch[t]);
        stats->primary_rays += s->primary_rays;
        stats->shadow_rays += s->shadow_rays;
        stats->secondary_rays += s->secondary_rays;
        stats->packets += s->primary.packets;
        stats->traversal_steps += s->primary.steps;
        stats->intersection_tests += s->primary.isects;
        stats->seconds_primary_traversal += 1e-9 * (double)s->ns_primary_traversal;
        stats->seconds_primary_intersection += 1e-9 * (double)s->ns_primary_intersection;
        stats->seconds_shading += 1e-9 * (double)s->ns_shading;
        stats->seconds_secondary += 1e-9 * (double)s->ns_secondary;
    }
}

/* The refining pass of interleaved:N:refine and frusta:N:refine
 * (rtt/interleaved.h), after the tiles, on the frame's threads in tasks of
 * REFINE_TASK pixels: frusta:N's lights through the soft-shadow frusta
 * (sp_frusta_refine), the others' samples ray by ray through the engine
 * (rtt_engine_refined_visibilities).  A pixel's answer is its own, so the
 * image does not depend on the thread count. */
#define REFINE_TASK 64u

typedef struct refine_job {
    const render_job *job;
    rtt_engine *engine;
    const rtt_shadow_planes *planes;
    /* the light and pixels of the current call */
    uint32_t light;
    const uint32_t *pixel;
    size_t count;
    float *vis;
    _Atomic uint64_t rays;
    atomic_bool failed;
} refine_job;

static void refine_task(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    refine_job *r = context;
    const sp_shading *sh = &r->job->shading;
    const rtt_light *L = &r->job->scene->lights[r->light];
    const size_t first = (size_t)task * REFINE_TASK, n = r->count - first < REFINE_TASK ? r->count - first : REFINE_TASK;
    uint64_t rays = 0;
    if (sp_frusta_soft(sh, L)) {
        if (!sp_frusta_refine(sh, &r->job->tracer, r->light, r->planes->point, r->pixel + first, n, r->vis + first,
                              &rays))
            atomic_store(&r->failed, true);
    } else {
        rtt_engine_refined_visibilities(r->engine, r->job->scene, r->planes, r->light, r->pixel + first, n,
                                        sh->shadow_samples, sh->epsilon, sh->transparent_shadows, r->vis + first, &rays);
    }
    atomic_fetch_add(&r->rays, rays);
}

static bool refine_pixels(void *context, uint32_t light, const uint32_t *pixel, size_t count, float *vis)
{
    refine_job *r = context;
    r->light = light, r->pixel = pixel, r->count = count, r->vis = vis;
    const size_t tasks = (count + REFINE_TASK - 1) / REFINE_TASK;
    if (tasks > UINT32_MAX) return false;
    rtt_parallel_run((uint32_t)tasks, r->job->threads, refine_task, r);
    return !atomic_load(&r->failed);
}

/* A frame's light grids back: the engine's to the engine (kept for the
 * next frame), the frame's own freed. */
static void light_grids_release(rtt_engine *engine, pgrid_shadows *grids, bool lent)
{
    if (lent) optimized_engine_light_grids_return(engine);
    else pgrid_shadows_free(grids);
}

bool rtt_optimized_render(rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                          rtt_render_stats *stats, rtt_error *err)
{
    const uint64_t start = rtt_clock_ns();
    rtt_render_options defaults;
    if (!opt) {
        rtt_render_options_default(&defaults);
        opt = &defaults;
    }
    if (!engine || !out) return rtt_error_set(err, "optimized renderer: no engine or image given");
    const rtt_scene *scene = engine->scene;
    const kd_tree *tree = kd_engine_tree(engine);
    const bvh_tree *bvh = bvh_engine_tree(engine);
    if (!scene || (!tree && !bvh)) return rtt_error_set(err, "optimized renderer: the engine is not an optimized engine");
    const uint32_t width = opt->width ? opt->width : scene->width;
    const uint32_t height = opt->height ? opt->height : scene->height;
    /* the kernel, tile and culling are the render's: one tree serves every traversal */
    const rtt_engine_options *engine_opt = &opt->engine;
    const uint32_t tile = engine_opt->tile ? engine_opt->tile : 8u;
    if (!rtt_engine_class_check(&rtt_optimized_engine_class, engine_opt, err)) return false;
    if (!rtt_render_check(scene, opt, out, width, height, err)) return false;
    const rtt_isa isa = rtt_isa_resolve(engine_opt->isa);
    /* the BVH traces packets of any rays; the group and edge kernels are the
     * kd-tree's (rtt_render_options_check refused them) */
    if (bvh && (opt->shadows == RTT_SHADOWS_CONE || opt->shadows == RTT_SHADOWS_PYRAMID ||
                opt->shadows == RTT_SHADOWS_EDGEWIDTH))
        return rtt_error_set(err, "%s: %s shadows need the kd-tree (--accel kd)", scene->path,
                             rtt_shadow_method_name(opt->shadows));

    render_job job = {
        .scene = scene,
        .out = out,
        .frame = rtt_camera_frame_make(&scene->camera, width, height),
        .width = width,
        .height = height,
        .tile = tile,
        .spp = rtt_render_spp(opt),
        .shading = {.scene = scene,
                    .max_bounces = rtt_render_bounces(opt, scene),
                    .shadows = opt->shadows,
                    .shadow_samples = opt->shadow_samples,
                    .epsilon = rtt_scene_ray_epsilon(scene),
                    .transparent_shadows = rtt_scene_has_transparent_shadows(scene),
                    .edge_model = rtt_edge_width_model_make(scene, opt->edge_radius, opt->edge_leak_fix),
                    .width = width},
        .tracer = {.tree = tree,
                   /* under pgrid the traversal names the grid's kernel: shadows take the kd default */
                   .kernel = kd_kernel_find(engine_opt->accel == RTT_ACCEL_PGRID ? "" : engine_opt->traversal, isa),
                   .secondary = kd_kernel_for_secondary_rays(isa),
                   .pyramid = kd_kernel_for_pyramid_groups(isa),
                   .shadows = kd_shadow_kernels_find(isa),
                   .block_packets = (tile / 2u) * (tile / 2u),
                   .leaf_culling = engine_opt->leaf_culling,
                   .bvh = bvh,
                   .bvh_kernel = bvh ? bvh_kernel_find(engine_opt->traversal, isa) : NULL,
                   .bvh_shadows = bvh ? bvh_shadow_kernel_find(isa) : NULL},
    };
    if (bvh && !job.tracer.bvh_kernel)
        return rtt_error_set(err, "%s: traversal \"%s\" is not a BVH kernel", scene->path, engine_opt->traversal);
    if (engine_opt->accel == RTT_ACCEL_PGRID && job.spp > 1)
        return rtt_error_set(err, "%s: the perspective grid traces one eye ray through each pixel centre: %u samples "
                                  "per pixel need --accel kd or bvh", scene->path, job.spp);
    if (opt->shadows == RTT_SHADOWS_FRUSTA && !bvh)
        return rtt_error_set(err, "%s: frusta shadows trace multi-frusta through the BVH: they need --accel bvh",
                             scene->path);
    bvh_shadow_sets *frusta_sets = NULL;
    if (opt->shadows == RTT_SHADOWS_FRUSTA &&
        !(frusta_sets = sp_frusta_sets_create(scene, opt->shadow_samples)))
        return rtt_error_set(err, "%s: out of memory in the optimized renderer", scene->path);
    job.shading.frusta_sets = frusta_sets;
    rtt_shadow_planes planes;
    if (opt->shadows == RTT_SHADOWS_INTERLEAVED || opt->shadows == RTT_SHADOWS_FRUSTA) {
        if (!rtt_shadow_planes_create(&planes, scene, width, height, err)) {
            free(frusta_sets);
            return false;
        }
        job.shading.planes = &planes;
    }
    /* --shadows pgrid: the light grids, the lights' built per frame (part of
     * its time); the scene's half and the arrays the engine's, kept between
     * frames (a frame's own when another frame holds the engine's) */
    pgrid_shadows own_grids = {0}, *light_grids = &own_grids;
    bool grids_lent = false;
    if (opt->shadows == RTT_SHADOWS_PGRID) {
        const pgrid_kernel *grid_kernel = pgrid_kernel_find("", isa);
        bool failed = false;
        pgrid_shadows *kept = optimized_engine_light_grids_lend(engine, scene, err, &failed);
        bool built = !failed;
        if (kept) light_grids = kept, grids_lent = true;
        else if (built) built = pgrid_shadows_prepare(&own_grids, scene, optimized_engine_degenerate(engine), err);
        if (built) { /* the lights' grids on the frame's threads */
            light_grids->threads = rtt_thread_count(opt->threads);
            light_grids->prints = grid_kernel->light_prints;
            built = pgrid_shadows_build_lights(light_grids, scene, 0, err);
        }
        if (!built) {
            light_grids_release(engine, light_grids, grids_lent);
            if (job.shading.planes) rtt_shadow_planes_free(&planes);
            return false;
        }
        job.tracer.light_grids = light_grids;
        job.tracer.light_grid_occluded = grid_kernel->shadow_occluded;
    }
    /* --shadows pgrid:N: the 3D light grids, built per frame too */
    pgrid_soft soft_grids = {0};
    if (opt->shadows == RTT_SHADOWS_PGRID_SOFT) {
        if (!pgrid_soft_build(&soft_grids, scene, optimized_engine_degenerate(engine), 0, 0, err)) {
            if (job.shading.planes) rtt_shadow_planes_free(&planes);
            return false;
        }
        job.tracer.soft_grids = &soft_grids;
        job.tracer.soft_grid_occluded = pgrid_kernel_find("", isa)->soft_occluded;
    }
    const uint32_t threads = rtt_thread_count(opt->threads);
    job.threads = threads;
    frame_memory *memory = frame_memory_get(opt->cache, threads, job.shading.max_bounces + 1,
                                            opt->stats || stats != NULL);
    bool ok = memory != NULL;
    /* --accel pgrid: the frame's grid is built here, its cells are the tiles
     * (its arrays are the frame's own: a render cache keeps none of them) */
    pgrid_render pgrid;
    const bool use_pgrid = engine_opt->accel == RTT_ACCEL_PGRID;
    if (ok && use_pgrid) {
        job.pgrid = &pgrid;
        if (!pgrid_render_begin(&pgrid, pgrid_kernel_find(engine_opt->traversal, isa), scene,
                                optimized_engine_degenerate(engine), &job.frame, width, height, 0, threads, err)) {
            pgrid_render_end(&pgrid);
            light_grids_release(engine, light_grids, grids_lent);
            pgrid_soft_free(&soft_grids);
            frame_memory_free(memory);
            if (job.shading.planes) rtt_shadow_planes_free(&planes);
            free(frusta_sets);
            return false;
        }
    }
    if (ok) {
        job.scratch = memory->scratch;
        rtt_tiles_run_from(opt->tile_source, width, height, use_pgrid ? pgrid.grid.cell : tile, threads, render_tile,
                           &job, opt->progress, opt->progress_context);
        for (uint32_t t = 0; t < threads; t++) ok = ok && !sp_scratch_failed(job.scratch[t]);
    }
    refine_job refine = {.job = &job, .engine = engine, .planes = &planes};
    atomic_init(&refine.rays, 0);
    atomic_init(&refine.failed, false);
    const uint64_t refine_start = rtt_clock_ns();
    if (job.shading.planes) {
        if (opt->shadow_refine && opt->shadow_filter)
            ok = ok && rtt_shadow_planes_resolve_refined(&planes, job.shading.shadow_samples, NULL, refine_pixels,
                                                         &refine, out->rgb, NULL);
        else
            ok = ok && rtt_shadow_planes_resolve(&planes, opt->shadow_filter, NULL, out->rgb);
        rtt_shadow_planes_free(&planes);
    }
    const double refine_seconds = 1e-9 * (double)(rtt_clock_ns() - refine_start);
    free(frusta_sets);
    if (ok && stats) {
        gather_stats(&job, stats);
        if (use_pgrid) stats->seconds_primary_traversal += pgrid.build_seconds;
        stats->seconds_secondary += light_grids->build_seconds + soft_grids.build_seconds;
        const uint64_t refine_rays = atomic_load(&refine.rays);
        if (refine_rays) stats->shadow_rays += refine_rays, stats->seconds_secondary += refine_seconds;
        stats->seconds_total = 1e-9 * (double)(rtt_clock_ns() - start);
    }
    if (job.pgrid) pgrid_render_end(job.pgrid);
    light_grids_release(engine, light_grids, grids_lent);
    pgrid_soft_free(&soft_grids);
    if (ok && opt->cache && frame_memory_even_out(memory))
        rtt_render_cache_keep(opt->cache, &rtt_optimized_engine_class, memory, frame_memory_free);
    else
        frame_memory_free(memory);
    if (!ok) return rtt_error_set(err, "%s: out of memory in the optimized renderer", scene->path);
    return true;
}

/* Render options and statistics shared by the renderers (reference,
 * optimized, and the reference renderer driven by Embree). */
#ifndef RTT_RENDER_H
#define RTT_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/interleaved.h"

typedef enum rtt_shadow_method {
    RTT_SHADOWS_NONE = 0,
    RTT_SHADOWS_HARD,       /* one ray to each light's centre */
    RTT_SHADOWS_MULTI,      /* N samples on each sphere light (reference ground truth) */
    RTT_SHADOWS_CONE,       /* N samples traced under one cone (thesis 4.1.6-4.1.9) */
    RTT_SHADOWS_PYRAMID,    /* the same samples under a pyramid frustum (Table 4.6) */
    RTT_SHADOWS_EDGEWIDTH,  /* Edge Width Soft Shadows (thesis chapter 5) */
    RTT_SHADOWS_INTERLEAVED, /* N samples from the pixel's 4x4 interleaved set, filtered (rtt/interleaved.h) */
    RTT_SHADOWS_FRUSTA,      /* interleaved's samples and filter traced as multi-frusta (optimized, --accel bvh) */
    RTT_SHADOWS_PGRID,       /* hard shadows through a perspective grid per light (Hunt & Mark 2008, 5.2) */
    RTT_SHADOWS_PGRID_SOFT   /* multi:N's samples through a 3D perspective grid per light (5.3; optimized) */
} rtt_shadow_method;

#define RTT_MAX_SHADOW_SAMPLES 256u
#define RTT_MAX_SPP 256u
#define RTT_SHADOW_METHOD_COUNT 10u            /* rtt_shadow_method values */
#define RTT_SHADOWS_ALL 0x3FFu                /* every rtt_shadow_method bit */
#define RTT_BOUNCES_OF_SCENE UINT32_MAX        /* max_bounces: the scene's own */

typedef enum rtt_aov {
    RTT_AOV_DEPTH = 1 << 0,
    RTT_AOV_PRIM = 1 << 1,
    RTT_AOV_NORMAL = 1 << 2
} rtt_aov;

/* The tile grid of a render: tile x tile squares of a width x height image,
 * clipped at the right and bottom edges, numbered row-major 0..total-1. */
typedef struct rtt_tile_grid {
    uint32_t width, height, tile, tiles_x, total;
} rtt_tile_grid;

/* Tile t's pixels: columns x0..x1-1, rows y0..y1-1. */
void rtt_tile_rect(const rtt_tile_grid *grid, uint32_t t, uint32_t *x0, uint32_t *y0, uint32_t *x1, uint32_t *y1);

/* Where a render's tiles come from when this process renders only some of
 * them (dist/: tiles handed out by another process).  Each worker asks
 * `take` for a run of consecutive tiles [*first, *first + *count) until it
 * returns false, and calls `rendered` after the run's last tile.  Both are
 * called from the render's workers, possibly at once. */
typedef struct rtt_tile_source {
    bool (*take)(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t *first, uint32_t *count);
    void (*rendered)(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t first, uint32_t count);
    void *context;
} rtt_tile_source;

/* Working memory a renderer keeps from one frame to the next, so that an
 * interactive loop renders without allocating (rtt view).  Optional: a
 * render without one allocates and frees its own.  A cache serves one
 * render at a time. */
typedef struct rtt_render_cache rtt_render_cache;
rtt_render_cache *rtt_render_cache_create(void);
void rtt_render_cache_destroy(rtt_render_cache *cache);

typedef struct rtt_render_options {
    uint32_t width, height;          /* 0 → the scene's */
    uint32_t threads;                /* 0 → one per core */
    rtt_shadow_method shadows;       /* default hard */
    uint32_t shadow_samples;         /* multi/cone/pyramid: N, 1..256; interleaved: 4..32 (default 16) */
    bool shadow_filter;              /* interleaved: the 4x4 discontinuity filter (default on; :nofilter) */
    bool shadow_refine;              /* interleaved: a second pass retraces the pixels the filter smeared (:refine;
                                      * rtt/interleaved.h, rtt_shadow_planes_resolve_refined) */
    uint32_t spp;                    /* anti-aliasing samples per pixel, 1..RTT_MAX_SPP (rtt_pixel_sample); 0 → 1 */
    float edge_radius;               /* edgewidth: R, early-exit width (0 → default) */
    bool edge_leak_fix;              /* edgewidth: entry/exit must share a vertex */
    uint32_t max_bounces;            /* 0..RTT_MAX_BOUNCES; RTT_BOUNCES_OF_SCENE → the scene's (default) */
    uint32_t aovs;                   /* rtt_aov bits */
    bool stats;                      /* gather counters (never changes results) */
    rtt_engine_options engine;       /* traversal, tile, leaf culling */
    /* Optional progress report, passed on to rtt_tiles_run (called from
     * worker threads with tiles done / total). */
    void (*progress)(void *context, uint32_t done, uint32_t total);
    void *progress_context;
    /* NULL: this process renders every tile (the default) */
    const rtt_tile_source *tile_source;
    rtt_render_cache *cache;         /* optional: memory kept between frames */
} rtt_render_options;

/* Counters of the thesis' tables.  N = traversal steps per 2x2 packet,
 * I = intersection tests per 2x2 packet (Tables 4.1 to 4.5); stage times as
 * in Table 3.1. */
typedef struct rtt_render_stats {
    uint64_t primary_rays, shadow_rays, secondary_rays;
    uint64_t packets;                /* 2x2 packets traced */
    uint64_t traversal_steps;        /* summed over packets */
    uint64_t intersection_tests;     /* summed over packets */
    double seconds_total;
    double seconds_primary_traversal, seconds_primary_intersection;
    double seconds_shading, seconds_secondary;
} rtt_render_stats;

void rtt_render_options_default(rtt_render_options *opt);
struct rtt_image;

/* The one render entry: checks the options for the engine
 * (rtt_render_options_check), then renders through the engine's own
 * renderer, which checks the image (rtt_render_check) and fills the stats.
 * stats may be NULL. */
bool rtt_render(rtt_engine *engine, const rtt_render_options *opt, struct rtt_image *out, rtt_render_stats *stats,
                rtt_error *err);

/* The render options engine `name` can honour: its engine options
 * (rtt_engine_options_check), a shadow method its renderer draws, a sample
 * count and radius in range, bounces 0..RTT_MAX_BOUNCES or the scene's. */
bool rtt_render_options_check(const char *name, const rtt_render_options *opt, rtt_error *err);
/* The bounce limit a render uses: the options' unless they leave it to the scene. */
uint32_t rtt_render_bounces(const rtt_render_options *opt, const rtt_scene *scene);
/* The samples per pixel a render takes: the options' spp, 0 meaning 1. */
uint32_t rtt_render_spp(const rtt_render_options *opt);
const char *rtt_shadow_method_name(rtt_shadow_method method);
/* The checks every renderer makes before it starts: a known shadow method
 * with a sample count in 1..RTT_MAX_SHADOW_SAMPLES (multi, cone, pyramid)
 * or RTT_INTERLEAVED_MIN_SAMPLES..RTT_INTERLEAVED_MAX_SAMPLES (interleaved, frusta),
 * or a valid edge-width radius and no quad light (edge widths are for
 * sphere and point lights), a non-empty width x height that `out` has, with
 * the AOV planes the options ask for, and a finished scene. */
bool rtt_render_check(const rtt_scene *scene, const rtt_render_options *opt, const struct rtt_image *out,
                      uint32_t width, uint32_t height, rtt_error *err);

/* Parses "none", "hard", "multi:N", "cone:N", "pyramid:N", "edgewidth[:R]",
 * "interleaved[:N][:nofilter]", "frusta[:N][:nofilter]". */
bool rtt_shadow_method_parse(const char *text, rtt_render_options *opt, rtt_error *err);

/* The shadow segment from p to target (rtt/shade.h: tnear = epsilon, tfar
 * = |target - p| - epsilon; nothing when |target - p| <= 2 epsilon) through
 * engine: the light that passes it, 1 clear, 0 blocked and, with
 * `transparent` (rtt_scene_has_transparent_shadows), the product of the
 * transmissions of the surfaces it crosses, nearest first, at most
 * RTT_SHADOW_MAX_LAYERS.  *rays counts the segments traced.  The reference
 * renderer's shadow ray. */
float rtt_engine_segment_transmission(rtt_engine *engine, const rtt_scene *scene, rtt_vec3 p, rtt_vec3 target,
                                      float epsilon, bool transparent, uint64_t *rays);
/* The refined visibility of rtt/interleaved.h of the `count` pixels
 * pixel[i] of planes for light `light` into vis[i]: from the pixel's
 * planes->point, the light's 16 sets of n samples, each segment's
 * transmission (as above) summed set by set, sample by sample, over 16 n. */
void rtt_engine_refined_visibilities(rtt_engine *engine, const rtt_scene *scene, const rtt_shadow_planes *planes,
                                     uint32_t light, const uint32_t *pixel, size_t count, uint32_t n, float epsilon,
                                     bool transparent, float *vis, uint64_t *rays);

#endif

/* The shader proxy (Thesis 4.2.1, Figure 3.2): what the tiled renderer
 * (render_optimized.c) asks of a tile.  It takes the tile's primary rays,
 * traces them as one block, shades their hits, builds and traces their
 * shadow packets, spawns reflection and refraction rays as
 * omni-directional 2x2 packets, combines the colours bottom-up and hands
 * back one finished node per primary ray.  The shading model is exactly
 * include/rtt/shade.h as the reference renderer (reference/render_whitted.c)
 * evaluates it, with the same arithmetic in the same order, so an optimized
 * image differs from the reference one only where the engines pick a
 * different hit.
 *
 * Per tile:  sp_tile_begin, sp_primary_push per 2x2 quad, sp_primary_trace,
 * sp_tile_shade, then sp_tile_pixel for i < sp_tile_pixel_count.  Every step
 * does nothing once the scratch has failed (out of memory). */
#ifndef RTT_OPTIMIZED_SHADER_PROXY_H
#define RTT_OPTIMIZED_SHADER_PROXY_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_kernels.h"
#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"
#include "pgrid_light.h"
#include "pgrid_soft.h"
#include "rtt/edge_width.h"
#include "rtt/interleaved.h"
#include "rtt/render.h"
#include "rtt/shade.h"
#include "shadow_kernels.h"

/* How rays reach the tree: rows of the descriptor tables (kernels.h,
 * shadow_kernels.h), all of one instruction set. */
typedef struct sp_tracer {
    const kd_tree *tree;
    const kd_kernel *kernel;        /* primary rays and hard shadow packets: the chosen traversal */
    const kd_kernel *secondary;     /* reflection and refraction rays: omni */
    const kd_kernel *pyramid;       /* pyramid:N sample groups: one frustum each */
    const kd_shadow_kernels *shadows; /* cone:N / pyramid:N groups, edge width */
    uint32_t block_packets;         /* tile*tile/4 */
    int leaf_culling;
    /* --accel bvh: every packet (primary, shadow, secondary) through this
     * BVH kernel instead of the kd rows above (tree NULL then) */
    const bvh_tree *bvh;
    const bvh_kernel *bvh_kernel;
    const bvh_shadow_kernel *bvh_shadows; /* frusta:N's soft-shadow frusta (bvh only) */
    /* --shadows pgrid: the frame's light grids and their kernel (hard
     * shadow rays go there instead of the kernels above) */
    const pgrid_shadows *light_grids;
    pgrid_occluded_fn light_grid_occluded;
    /* --shadows pgrid:N: the frame's 3D light grids and their slice
     * traverser (every shadow ray goes there) */
    const pgrid_soft *soft_grids;
    pgrid_soft_occluded_fn soft_grid_occluded;
} sp_tracer;

typedef struct sp_shading {
    const rtt_scene *scene;
    uint32_t max_bounces;
    rtt_shadow_method shadows;
    uint32_t shadow_samples;
    float epsilon;
    bool transparent_shadows;        /* shadow rays pass transparent surfaces (shade.h) */
    rtt_edge_width_model edge_model; /* edgewidth: R, leak fix */
    uint32_t width;                  /* the image's: a pixel's interleaved set from its index */
    rtt_shadow_planes *planes;       /* interleaved, frusta: the primary hits' light terms go here */
    const bvh_shadow_sets *frusta_sets; /* frusta: per light, the sets' domain coordinates (sp_frusta.h) */
} sp_shading;

/* One traced ray of a pixel's shading tree (80 bytes: levels are arrays of
 * them, read in order).  After shading, `colour` holds (1 - wr - wt) *
 * local; once the tile is shaded, the ray's full colour. */
typedef struct sp_node {
    rtt_ray ray;
    rtt_hit hit;
    rtt_vec3 colour;
    float wr, wt;
    int32_t reflected, refracted;   /* child indices in the next level, -1 none */
    uint32_t pixel;                 /* py * width + px: seeds the light samples */
} sp_node;
_Static_assert(sizeof(sp_node) == 80, "sp_node: ray 32 + hit 16 + colour 12 + 20");

/* Per-thread ray counts (always kept: an add per packet) and the timers
 * and N / I counters (only when `timing` is on). */
typedef struct sp_stats {
    uint64_t primary_rays, shadow_rays, secondary_rays;
    kd_counters primary;            /* N and I of the primary packets */
    uint64_t ns_primary_traversal, ns_primary_intersection, ns_shading, ns_secondary;
} sp_stats;

/* Per-thread scratch: a tile's shading trees level by level, its packets
 * and shadow rays, grown on demand (sp_scratch.c). */
typedef struct sp_scratch sp_scratch;

/* level_count = max_bounces + 1; timing turns the stage timers and the
 * primary counters on.  NULL when out of memory. */
sp_scratch *sp_scratch_create(uint32_t level_count, bool timing);
void sp_scratch_destroy(sp_scratch *s);
/* Clears the statistics of a scratch kept from an earlier frame. */
void sp_scratch_begin_frame(sp_scratch *s);
/* Grows every array of s to other's size, so that scratch kept between
 * frames fits any tile any thread met; false when out of memory. */
bool sp_scratch_match(sp_scratch *s, sp_scratch *other);
/* True once an allocation has failed: the tile's results are void. */
bool sp_scratch_failed(const sp_scratch *s);
const sp_stats *sp_scratch_stats(const sp_scratch *s);

/* Starts a tile of `packets` primary packets (the kernel's block). */
void sp_tile_begin(sp_scratch *s, uint32_t packets);
/* Appends the next primary packet: `count` (0..4) rays in lanes 0.. and
 * the pixel each belongs to; the other lanes are inactive. */
void sp_primary_push(sp_scratch *s, const rtt_ray *rays, const uint32_t *pixels, uint32_t count);
/* Traces the pushed packets through tracer->kernel as blocks of
 * tracer->block_packets (timed and counted with timing on). */
void sp_primary_trace(const sp_tracer *tracer, sp_scratch *s);
/* Instead of push and trace, for primary hits found elsewhere (the
 * perspective grid): appends a primary ray with its hit... */
void sp_primary_push_hit(sp_scratch *s, const rtt_ray *ray, const rtt_hit *hit, uint32_t pixel);
/* ...and once the tile's are in, counts them and the `ns` spent finding them. */
void sp_primary_hits_done(sp_scratch *s, uint64_t ns);
/* Whether the tile's stats are kept (timing on): then the finder of those
 * hits may add its counters (N and I, as sp_primary_trace counts them). */
bool sp_tile_counting(const sp_scratch *s);
void sp_primary_hits_counted(sp_scratch *s, uint64_t packets, uint64_t steps, uint64_t isects);
/* Shades the primary hits and every level below, then combines colours. */
void sp_tile_shade(const sp_shading *shading, const sp_tracer *tracer, sp_scratch *s);
/* The tile's primary rays, in push order, with their hits and colours. */
uint32_t sp_tile_pixel_count(const sp_scratch *s);
const sp_node *sp_tile_pixel(const sp_scratch *s, uint32_t i);

#endif

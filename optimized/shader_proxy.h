/* The shader proxy (Thesis 4.2.1, Figure 3.2): shades the hits of a tile's
 * rays, builds and traces their shadow packets, spawns reflection and
 * refraction rays as omni-directional 2x2 packets, and combines the colours
 * bottom-up.  The shading model is exactly include/rtt/shade.h as the
 * reference renderer (reference/render_whitted.c) evaluates it, with the
 * same arithmetic in the same order, so an optimized image differs from the
 * reference one only where the engines pick a different hit. */
#ifndef RTT_OPTIMIZED_SHADER_PROXY_H
#define RTT_OPTIMIZED_SHADER_PROXY_H

#include <stdbool.h>
#include <stdint.h>

#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"
#include "rtt/edge_width.h"
#include "rtt/render.h"
#include "rtt/shade.h"

/* How rays reach the tree: kernels of the descriptor table (kernels.h),
 * all of one instruction set. */
typedef struct sp_tracer {
    const kd_tree *tree;
    const kd_kernel *kernel;        /* primary rays and hard shadow packets: the chosen traversal */
    const kd_kernel *secondary;     /* reflection and refraction rays: omni */
    const kd_kernel *pyramid;       /* pyramid:N sample groups: one frustum each */
    uint32_t block_packets;         /* tile*tile/4 */
    int leaf_culling;
} sp_tracer;

/* One traced ray of a pixel's shading tree (80 bytes).  After
 * shading, `colour` holds (1 - wr - wt) * local; after sp_resolve, the
 * ray's full colour. */
typedef struct sp_node {
    rtt_ray ray;
    rtt_hit hit;
    rtt_vec3 colour;
    float wr, wt;
    int32_t reflected, refracted;   /* child indices in the next level, -1 none */
    uint32_t pixel;                 /* py * width + px: seeds the light samples */
} sp_node;
_Static_assert(sizeof(sp_node) == 80, "sp_node: ray 32 + hit 16 + colour 12 + 20");

typedef struct sp_level {
    sp_node *nodes;
    uint32_t count, capacity;
} sp_level;

/* Per-thread ray counts (always kept: an add per packet) and the timers
 * and N / I counters (only when `timing` is on). */
typedef struct sp_stats {
    uint64_t primary_rays, shadow_rays, secondary_rays;
    kd_counters primary;            /* N and I of the primary packets */
    uint64_t ns_primary_traversal, ns_primary_intersection, ns_shading, ns_secondary;
} sp_stats;

/* Per-thread scratch: shading trees level by level, packets, shadow rays.
 * Grown on demand; `failed` is set when an allocation fails. */
typedef struct sp_scratch {
    sp_level *levels;               /* max_bounces + 1 */
    uint32_t level_count;
    ray_packet4 *packets;
    hit_packet4 *hits;
    uint8_t *occluded;
    uint32_t packet_capacity, hit_capacity, occluded_capacity;
    rtt_ray *shadow_rays;
    uint8_t *shadow_clear;
    uint32_t shadow_capacity, clear_capacity;
    rtt_surface *surfaces;
    struct sp_light_request *requests;
    uint32_t surface_capacity, request_capacity;
    /* cone:N / pyramid:N: rays of group g are shadow_rays[group_first[g] ..
     * group_first[g+1]) (one shading point and light) */
    uint32_t *group_first;
    uint32_t group_capacity;
    /* edgewidth: one ray per shading point and sphere light, from its centre */
    rtt_ray *edge_rays;
    uint32_t *edge_order;           /* edge rays sorted by light (one origin per packet) */
    uint32_t *edge_light;
    float *edge_occlusion;
    uint32_t edge_ray_capacity, edge_order_capacity, edge_light_capacity, edge_occlusion_capacity;
    bool failed;
    bool timing;
    sp_stats stats;
} sp_scratch;

typedef struct sp_shading {
    const rtt_scene *scene;
    uint32_t max_bounces;
    rtt_shadow_method shadows;
    uint32_t shadow_samples;
    float epsilon;
    rtt_edge_width_model edge_model; /* edgewidth: R, leak fix */
} sp_shading;

bool sp_scratch_init(sp_scratch *s, uint32_t level_count, bool timing);
void sp_scratch_free(sp_scratch *s);

/* Appends a node for `ray` to level `level` (hit unset); returns its index
 * or -1 when out of memory. */
int32_t sp_level_push(sp_scratch *s, uint32_t level, const rtt_ray *ray, uint32_t pixel);

/* Room for `packets` packets, hits and occlusion masks. */
bool sp_ensure_packets(sp_scratch *s, uint32_t packets);

/* Traces levels 1..: shades level 0 (whose hits the caller traced), and
 * every level below, then combines colours so that level 0 nodes hold the
 * pixel colours. */
void sp_shade_tree(const sp_shading *shading, const sp_tracer *tracer, sp_scratch *s);

/* The closest-hit and occlusion kernels of a traversal mode. */
void sp_trace_packets(const sp_tracer *tracer, const kd_kernel *kernel, const ray_packet4 *packets,
                      hit_packet4 *hits, uint32_t packet_count, kd_counters *counters, uint64_t *isect_ns);
void sp_trace_packets_occluded(const sp_tracer *tracer, const kd_kernel *kernel, const ray_packet4 *packets,
                               uint8_t *occluded, uint32_t packet_count);


#endif

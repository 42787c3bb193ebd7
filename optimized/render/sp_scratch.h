/* The shader proxy's per-thread scratch (sp_scratch.c), private to the
 * proxy's files (shader_proxy.c, sp_scratch.c): the renderer sees it only
 * through shader_proxy.h.  Every array is an rtt_buffer (engine/buffer.h),
 * the one place scratch grows; a failed growth marks the scratch failed. */
#ifndef RTT_OPTIMIZED_SP_SCRATCH_H
#define RTT_OPTIMIZED_SP_SCRATCH_H

#include <stdbool.h>
#include <stdint.h>

#include "engine/buffer.h"
#include "shader_proxy.h"

/* The rays of one bounce of a tile's shading trees. */
typedef struct sp_level {
    rtt_buffer nodes;               /* sp_node */
    uint32_t count;
} sp_level;

struct sp_scratch {
    sp_level *levels;               /* max_bounces + 1 */
    uint32_t level_count;
    rtt_buffer packets, hits, occluded; /* ray_packet4, hit_packet4, uint8_t lane masks */
    rtt_buffer primary_lanes;       /* uint8_t: rays in each primary packet */
    uint32_t primary_packets;       /* packets pushed since sp_tile_begin */
    rtt_buffer shadow_rays;         /* rtt_ray */
    rtt_buffer shadow_clear;        /* uint8_t per shadow ray */
    /* transparent shadows (scenes with transparent materials only) */
    rtt_buffer shadow_transmission; /* float per shadow ray */
    rtt_buffer shadow_pending;      /* uint32_t: rays still inside transparent surfaces */
    rtt_buffer surfaces;            /* rtt_surface per node of a chunk */
    rtt_buffer requests;            /* shader_proxy.c's light requests, per node and light */
    /* cone:N / pyramid:N: rays of group g are shadow_rays[group_first[g] ..
     * group_first[g+1]) (one shading point and light) */
    rtt_buffer group_first;         /* uint32_t */
    /* edgewidth: one ray per shading point and sphere light, from its centre */
    rtt_buffer edge_rays;           /* rtt_ray */
    rtt_buffer edge_order;          /* uint32_t: edge rays sorted by light (one origin per packet) */
    rtt_buffer edge_light;          /* uint32_t */
    rtt_buffer edge_occlusion;      /* float */
    /* frusta:N and hard shadows through bvh-mft (sp_frusta.c) */
    rtt_buffer frusta_points;       /* bvh_shadow_point per shading point and light */
    rtt_buffer frusta_light;        /* uint32_t: its light */
    rtt_buffer frusta_pixel;        /* uint32_t: its pixel */
    rtt_buffer frusta_mask;         /* uint32_t: its occluded samples */
    rtt_buffer frusta_order;        /* sp_frusta.c's sort records */
    rtt_buffer frusta_sorted;       /* the points or rays in that order */
    rtt_buffer frusta_answer;       /* the kernel's answers in that order */
    uint32_t frusta_count;
    bool failed;
    bool timing;
    sp_stats stats;
};

/* The elements of a buffer as `type` (what it was reserved for). */
#define SP_ARRAY(buffer, type) ((type *)(buffer).data)

/* Room for `count` elements in one of the scratch's buffers; false (and s
 * failed) when out of memory.  Inline: it runs per ray, only growth leaves.
 * SP_RESERVE is the typed form: room for `count` of `type` in s->field. */
static inline bool sp_reserve(sp_scratch *s, rtt_buffer *buffer, size_t count, size_t element, size_t align)
{
    if (rtt_buffer_reserve(buffer, count, element, align)) return true;
    s->failed = true;
    return false;
}
#define SP_RESERVE(s, field, count, type) sp_reserve((s), &(s)->field, (count), sizeof(type), _Alignof(type))

/* Appends a node for `ray` to level `level` (hit unset); returns its index
 * or -1 when out of memory. */
int32_t sp_level_push(sp_scratch *s, uint32_t level, const rtt_ray *ray, uint32_t pixel);
static inline sp_node *sp_level_nodes(const sp_scratch *s, uint32_t level)
{
    return SP_ARRAY(s->levels[level].nodes, sp_node);
}

/* Room for `packets` packets, hits and occlusion masks. */
bool sp_ensure_packets(sp_scratch *s, uint32_t packets);

/* Closest hits (cleared first) or occlusion masks of `packet_count`
 * packets through `kernel`, cut into the blocks it reads. */
void sp_trace_packets(const sp_tracer *tracer, const kd_kernel *kernel, const ray_packet4 *packets,
                      hit_packet4 *hits, uint32_t packet_count, kd_counters *counters, uint64_t *isect_ns);
void sp_trace_packets_occluded(const sp_tracer *tracer, const kd_kernel *kernel, const ray_packet4 *packets,
                               uint8_t *occluded, uint32_t packet_count);

/* The hits of the first `packet_count` packets into the level's nodes,
 * which are the packets' lanes in order: packet p holds lanes[p] of them
 * (lanes NULL: four each, the level's node count cutting the last short). */
void sp_store_hits(sp_scratch *s, uint32_t level, const uint8_t *lanes, uint32_t packet_count);

#endif

/* The shadow kernels' descriptor table: the cone:N / pyramid:N sample
 * groups (shadow_cone.c; Thesis 4.1.6 - 4.1.9, Figure 4.5, Table 4.6) and
 * Edge Width Soft Shadows (edge_width.c; Thesis chapter 5, Listing 5.1),
 * one row per instruction set they are compiled for (kernel_isa.h), as the
 * traversal kernels' table (kernels.h).  Baseline code reaches them only
 * through kd_shadow_kernels_find. */
#ifndef RTT_OPTIMIZED_SHADOW_KERNELS_H
#define RTT_OPTIMIZED_SHADOW_KERNELS_H

#include <stdint.h>

#include "kd_tree.h"
#include "kernels.h"
#include "packet.h"
#include "rtt/edge_width.h"
#include "rtt/engine.h"

/* Occlusion of rays grouped by shading point and light: group g is rays
 * [group_first[g], group_first[g+1]) (at most 4 * KD_BLOCK_MAX_PACKETS),
 * traced as one block of packets under one proxy: the group's cone
 * (cone:N) when `pyramid` is NULL, else through the frustum kernel
 * `pyramid` (pyramid:N, a row of the same instruction set).  `packets` and
 * `lane_masks` are scratch of sc_group_packets(...) entries; occluded[i] =
 * 1 when ray i is blocked.  The result of every ray is exactly the
 * occlusion kernels' (the proxies are conservative, the triangle test the
 * same), so cone:N and pyramid:N see the same samples as multi:N. */
typedef void (*kd_shadow_groups_fn)(const kd_tree *tree, const kd_kernel *pyramid, const rtt_ray *rays,
                                    const uint32_t *group_first, uint32_t groups, ray_packet4 *packets,
                                    uint8_t *lane_masks, uint8_t *occluded, int leaf_culling, kd_counters *counters);

/* Edge width (semantics: include/rtt/edge_width.h; the scalar twin for
 * conformance: reference/edge_width_reference.c).  Occlusion in [0, 1] of
 * up to four edge-width rays (rtt_edge_width_ray) that share one origin,
 * the light's centre; lanes past `count` are ignored.  counters (may be
 * NULL) get one packet, the nodes visited and the triangle tests. */
typedef void (*kd_edge_width4_fn)(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays,
                                  uint32_t count, float occlusion[4], kd_counters *counters);
/* Occlusion of rays[order[i]] for i < n into occlusion[order[i]]: runs of
 * consecutive rays (in `order`) with one origin go four to a packet. */
typedef void (*kd_edge_width_stream_fn)(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays,
                                        const uint32_t *order, uint32_t n, float *occlusion, kd_counters *counters);

typedef struct kd_shadow_kernels {
    kd_shadow_groups_fn trace_groups;
    kd_edge_width4_fn edge_width4;
    kd_edge_width_stream_fn edge_width_stream;
    rtt_isa isa;                /* the instruction set their objects were compiled for */
} kd_shadow_kernels;

/* The row of the widest instruction set not wider than `isa` (resolved)
 * that this CPU runs; never NULL (SSE4.1 is the baseline). */
const kd_shadow_kernels *kd_shadow_kernels_find(rtt_isa isa);
/* The i-th row (from 0), whatever this CPU runs; NULL past the last (for
 * tests). */
const kd_shadow_kernels *kd_shadow_kernels_row_at(uint32_t i);

/* Packets needed for the groups: sum over groups of ceil(rays / 4). */
static inline uint32_t sc_group_packets(const uint32_t *group_first, uint32_t groups)
{
    uint32_t packets = 0;
    for (uint32_t g = 0; g < groups; g++) packets += (group_first[g + 1] - group_first[g] + 3u) / 4u;
    return packets;
}

/* The kernels, one copy per instruction set: sc_trace_groups_sse4, ... */
#define KD_SHADOW_PROTOTYPES(isa)                                                                                 \
    void sc_trace_groups_##isa(const kd_tree *tree, const kd_kernel *pyramid, const rtt_ray *rays,                \
                               const uint32_t *group_first, uint32_t groups, ray_packet4 *packets,                \
                               uint8_t *lane_masks, uint8_t *occluded, int leaf_culling, kd_counters *counters);  \
    void ew_occlusion4_##isa(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays,         \
                             uint32_t count, float occlusion[4], kd_counters *counters);                          \
    void ew_occlusion_stream_##isa(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays,   \
                                   const uint32_t *order, uint32_t n, float *occlusion, kd_counters *counters);
KD_SHADOW_PROTOTYPES(sse4)
KD_SHADOW_PROTOTYPES(avx2)
KD_SHADOW_PROTOTYPES(avx512)

#endif

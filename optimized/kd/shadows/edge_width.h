/* Edge Width Soft Shadows, SSE packet version (Thesis chapter 5, Listing
 * 5.1) for the optimized renderer.  Semantics: include/rtt/edge_width.h;
 * the scalar twin for conformance: reference/edge_width_reference.c. */
#ifndef RTT_OPTIMIZED_EDGE_WIDTH_H
#define RTT_OPTIMIZED_EDGE_WIDTH_H

#include <stdint.h>

#include "kd_tree.h"
#include "packet.h"
#include "rtt/edge_width.h"

/* Occlusion in [0, 1] of up to four edge-width rays (rtt_edge_width_ray)
 * that share one origin, the light's centre.  Lanes past `count` are
 * ignored.  counters (may be NULL) get one packet, the nodes visited and
 * the triangle tests. */
void ew_occlusion4(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays, uint32_t count,
                   float occlusion[4], kd_counters *counters);

/* Occlusion of rays[order[i]] for i < n into occlusion[order[i]]: runs of
 * consecutive rays (in `order`) with one origin go four to a packet. */
void ew_occlusion_stream(const kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *rays,
                         const uint32_t *order, uint32_t n, float *occlusion, kd_counters *counters);

#endif

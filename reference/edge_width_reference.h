/* The scalar Edge Width Soft Shadows of the reference (Thesis chapter 5):
 * what the SSE packet version (optimized/kd/shadows/edge_width.c) is checked against.
 * Private to reference/ and its tests. */
#ifndef RTT_REFERENCE_EDGE_WIDTH_REFERENCE_H
#define RTT_REFERENCE_EDGE_WIDTH_REFERENCE_H

#include "kd_reference.h"
#include "rtt/edge_width.h"

/* Occlusion in [0, 1] of an edge-width ray (rtt_edge_width_ray) by the
 * semantics of rtt/edge_width.h: every crossing of the segment found with
 * the watertight test in every leaf the segment touches, once per triangle,
 * sorted by (t, prim), fed to the shared pairing.  No early exit (it cannot
 * change the result).  `max_width`, when non-NULL, receives the largest
 * width paired before the occlusion was decided (the exact widths of the
 * path when R is huge and the leak fix off). */
float rtt_edge_width_reference(const rtt_kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *ray,
                               float *max_width);

#endif

/* Clipping for perfect splits (kd_clip.c). */
#ifndef RTT_OPTIMIZED_KD_CLIP_H
#define RTT_OPTIMIZED_KD_CLIP_H

#include <stdbool.h>

#include "rtt/vec3.h"

/* The triangle's axis-aligned bounds. */
rtt_bounds kd_triangle_bounds(const rtt_vec3 p[3]);

/* Bounds of the part of the triangle inside box (boundary included), never
 * smaller than the exact ones and never inverted (see kd_clip.c). */
rtt_bounds kd_clip_triangle_to_box(const rtt_vec3 tri[3], rtt_bounds box);

/* The builder's side rule (kd_build_sah.c): with the triangle's clipped
 * bounds [lo, hi] on the split axis and plane p, below when lo < p or
 * lo == hi <= p, above when hi > p and not flat below it. */
static inline bool kd_goes_below(float lo, float hi, float p) { return lo < p || (lo == hi && lo <= p); }
static inline bool kd_goes_above(float lo, float hi, float p) { return lo == hi ? lo > p : hi > p; }

#endif

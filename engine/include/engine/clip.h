/* The bounds of the part of a triangle inside a box: the geometry of perfect
 * splits (Thesis 2.2.1, Figure 2.12) that both kd-tree builders, and the
 * check of baked trees, compute alike. */
#ifndef RTT_ENGINE_CLIP_H
#define RTT_ENGINE_CLIP_H

#include <stdbool.h>

#include "rtt/vec3.h"

/* The triangle clipped to `box` (boundary included) in double
 * (Sutherland-Hodgman against the six planes), its bounds rounded outwards
 * to float and cut to the box: never smaller than the exact bounds.  False
 * (out untouched) when rounding or the box leaves nothing. */
bool rtt_clip_triangle_bounds(const rtt_vec3 tri[3], rtt_bounds box, rtt_bounds *out);

#endif

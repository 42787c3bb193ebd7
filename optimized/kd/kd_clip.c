/* Perfect splits' clipping (Thesis 2.2.1, Figure 2.12): the bounds of the
 * part of a triangle inside a box, shared by the builder (kd_build_sah.c)
 * and the check of baked trees (kdt_verify.c), which must distribute the
 * triangles exactly as the builder did. */
#include <math.h>
#include <string.h>

#include "engine/clip.h"
#include "kd_clip.h"

rtt_bounds kd_triangle_bounds(const rtt_vec3 p[3])
{
    rtt_bounds b = rtt_bounds_empty();
    for (int i = 0; i < 3; i++) b = rtt_bounds_grow(b, p[i]);
    return b;
}

/* The triangle's bounds cut to the box, never inverted: on an axis where
 * the triangle lies wholly outside the box, the box face nearest to it. */
static rtt_bounds triangle_bounds_in_box(const rtt_vec3 tri[3], rtt_bounds box)
{
    rtt_bounds whole = rtt_bounds_intersection(kd_triangle_bounds(tri), box);
    for (int a = 0; a < 3; a++) {
        float lo = rtt_v3_get(whole.lo, a), hi = rtt_v3_get(whole.hi, a);
        if (lo > hi) {
            float face = fminf(lo, rtt_v3_get(box.hi, a));
            rtt_v3_set(&whole.lo, a, face);
            rtt_v3_set(&whole.hi, a, face);
        }
    }
    return whole;
}

/* Bounds of the part of the triangle inside box (boundary included), never
 * smaller than the exact ones.  When rounding leaves nothing (the triangle
 * grazes the box), the triangle's bounds cut to the box: still a superset
 * of its true part, which is all correctness needs.  Those may be empty when
 * the outward-rounded bounds of the parent made the triangle straddle a
 * plane it only touches or misses (coordinates of 1e20 next to 1e-28); the
 * sweep has counted it on both sides, so it keeps a flat box on the child's
 * face rather than an inverted one, whose end event would sort before its
 * start and desynchronise the counts from the events (fuzz regression
 * kd_build/straddler_outside_child_inverted_bounds). */
rtt_bounds kd_clip_triangle_to_box(const rtt_vec3 tri[3], rtt_bounds box)
{
    rtt_bounds b;
    return rtt_clip_triangle_bounds(tri, box, &b) ? b : triangle_bounds_in_box(tri, box);
}

/* Perfect splits' clipping (Thesis 2.2.1, Figure 2.12): the bounds of the
 * part of a triangle inside a box, shared by the builder (kd_build_sah.c)
 * and the check of baked trees (kdt_verify.c), which must distribute the
 * triangles exactly as the builder did. */
#include <math.h>
#include <string.h>

#include "kd_clip.h"

typedef struct clip_polygon {
    double v[12][3]; /* a triangle clipped by 6 planes has at most 9 corners */
    int count;
} clip_polygon;

/* Keeps the part of the polygon with sign * (x[axis] - plane) >= 0. */
static void clip_against_plane(clip_polygon *poly, int axis, double plane, double sign)
{
    int inside = 0;
    for (int i = 0; i < poly->count; i++) inside += sign * (poly->v[i][axis] - plane) >= 0.0;
    if (inside == poly->count) return;
    if (inside == 0) {
        poly->count = 0;
        return;
    }
    clip_polygon out = {.count = 0};
    for (int i = 0; i < poly->count; i++) {
        const double *cur = poly->v[i], *next = poly->v[(i + 1) % poly->count];
        bool cur_in = sign * (cur[axis] - plane) >= 0.0, next_in = sign * (next[axis] - plane) >= 0.0;
        if (cur_in) memcpy(out.v[out.count++], cur, sizeof out.v[0]);
        if (cur_in != next_in) {
            double s = (plane - cur[axis]) / (next[axis] - cur[axis]);
            double *p = out.v[out.count++];
            for (int a = 0; a < 3; a++) p[a] = cur[a] + s * (next[a] - cur[a]);
            p[axis] = plane; /* exactly on the plane, whatever the rounding */
        }
    }
    *poly = out;
}

static float round_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float round_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

static rtt_bounds bounds_intersection(rtt_bounds a, rtt_bounds b)
{
    return (rtt_bounds){rtt_v3_max(a.lo, b.lo), rtt_v3_min(a.hi, b.hi)};
}

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
    rtt_bounds whole = bounds_intersection(kd_triangle_bounds(tri), box);
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
    clip_polygon poly = {.count = 3};
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 3; a++) poly.v[i][a] = rtt_v3_get(tri[i], a);
    for (int a = 0; a < 3 && poly.count > 0; a++) {
        clip_against_plane(&poly, a, rtt_v3_get(box.lo, a), 1.0);
        if (poly.count > 0) clip_against_plane(&poly, a, rtt_v3_get(box.hi, a), -1.0);
    }
    rtt_bounds whole = triangle_bounds_in_box(tri, box);
    if (poly.count == 0) return whole;
    rtt_bounds b;
    for (int a = 0; a < 3; a++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < poly.count; i++) {
            lo = fmin(lo, poly.v[i][a]);
            hi = fmax(hi, poly.v[i][a]);
        }
        rtt_v3_set(&b.lo, a, round_down(lo));
        rtt_v3_set(&b.hi, a, round_up(hi));
    }
    b = bounds_intersection(b, box);
    return rtt_bounds_is_empty(b) ? whole : b;
}

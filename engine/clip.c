/* Clipping a triangle to a box (clip.h).  In double, so a corner computed on
 * a plane lies on it; the result rounded outwards, so float bounds contain
 * the exact ones whatever the rounding. */
#include <math.h>
#include <string.h>

#include "engine/clip.h"

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

bool rtt_clip_triangle_bounds(const rtt_vec3 tri[3], rtt_bounds box, rtt_bounds *out)
{
    clip_polygon poly = {.count = 3};
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 3; a++) poly.v[i][a] = rtt_v3_get(tri[i], a);
    for (int a = 0; a < 3 && poly.count > 0; a++) {
        clip_against_plane(&poly, a, rtt_v3_get(box.lo, a), 1.0);
        if (poly.count > 0) clip_against_plane(&poly, a, rtt_v3_get(box.hi, a), -1.0);
    }
    if (poly.count == 0) return false;
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
    b = rtt_bounds_intersection(b, box);
    if (rtt_bounds_is_empty(b)) return false;
    *out = b;
    return true;
}

/* A ray's crossing with a scene triangle in double precision, for the
 * tests that judge ties (test_optimized_pgrid.c, test_optimized_bvh.c). */
#ifndef RTT_TEST_DOUBLE_CROSSING_H
#define RTT_TEST_DOUBLE_CROSSING_H

#include <math.h>
#include <stdbool.h>

#include "rtt/scene.h"

/* Moller-Trumbore in double, unclamped: false only for a ray parallel to
 * the plane. */
static inline bool ray_triangle_double(const rtt_scene *s, uint32_t prim, const rtt_ray *r, double *t, double *u, double *v)
{
    rtt_vec3 c[3];
    rtt_scene_triangle(s, prim, c);
    double e1[3], e2[3], o[3], d[3], p[3], q[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)rtt_v3_get(c[1], k) - rtt_v3_get(c[0], k);
        e2[k] = (double)rtt_v3_get(c[2], k) - rtt_v3_get(c[0], k);
        o[k] = (double)r->org[k] - rtt_v3_get(c[0], k);
        d[k] = r->dir[k];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1], p[1] = d[2] * e2[0] - d[0] * e2[2], p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) return false;
    q[0] = o[1] * e1[2] - o[2] * e1[1], q[1] = o[2] * e1[0] - o[0] * e1[2], q[2] = o[0] * e1[1] - o[1] * e1[0];
    *u = (o[0] * p[0] + o[1] * p[1] + o[2] * p[2]) / det;
    *v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return true;
}

/* Smallest barycentric of the ray's crossing with prim, or -inf. */
static inline double crossing(const rtt_scene *s, uint32_t prim, const rtt_ray *r, double *t)
{
    double u, v;
    if (!ray_triangle_double(s, prim, r, t, &u, &v)) return -INFINITY;
    double w = 1.0 - u - v;
    return fmin(w, fmin(u, v));
}

#endif

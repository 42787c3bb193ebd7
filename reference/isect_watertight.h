/* The watertight ray/triangle test of the reference engine (Woop, Benthin,
 * Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1), section 3 and
 * its appendix listing).  Private to reference/: the public entry point is
 * rtt_reference_intersect_triangle in include/rtt/reference.h. */
#ifndef RTT_REFERENCE_ISECT_WATERTIGHT_H
#define RTT_REFERENCE_ISECT_WATERTIGHT_H

#include <stdbool.h>

#include "rtt/engine.h"
#include "rtt/vec3.h"

/* What the test precomputes once per ray: the axis permutation (kz = the
 * dominant axis of dir, kx and ky swapped when dir[kz] < 0 to keep the
 * winding) and the shear that maps dir onto +z. */
typedef struct rtt_watertight_ray {
    float org[3];
    int kx, ky, kz;
    float sx, sy, sz;
    float tnear, tfar;
} rtt_watertight_ray;

void rtt_watertight_ray_setup(const rtt_ray *ray, rtt_watertight_ray *out);

/* True on a hit with tnear < t < tfar (tfar may be narrowed by the caller);
 * t, u, v are written only on a hit. */
bool rtt_watertight_intersect(const rtt_watertight_ray *ray, const rtt_vec3 tri[3], float *t, float *u, float *v);

/* Zero-area (cross product of the edges exactly zero in double precision)
 * or non-finite: such triangles never hit and never enter a leaf. */
bool rtt_reference_triangle_is_degenerate(const rtt_vec3 tri[3]);

#endif

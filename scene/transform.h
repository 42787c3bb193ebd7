/* Matrix maths for instance transforms: every transform in scene/ is a
 * row-major 4x4 double matrix (m[4 * row + col]) applied to column vectors,
 * p' = M p, with the translation in the last column.  The JSON scene file's
 * "transform", Assimp's node hierarchy and rtt_scene_add_mesh share these
 * so that a point is moved the same way whichever loader brought it. */
#ifndef RTT_SCENE_TRANSFORM_H
#define RTT_SCENE_TRANSFORM_H

#include "rtt/vec3.h"

/* out = a * b; out may be a or b. */
void rtt_transform_multiply(const double a[16], const double b[16], double out[16]);

/* T * Rz * Ry * Rx * S: scale first, then rotations about X, Y and Z by
 * rotate_deg (degrees, right-handed), then the translation (scene/README.md). */
void rtt_transform_compose(const double scale[3], const double rotate_deg[3], const double translate[3],
                           double out[16]);

/* out = M p (x, y, z), in double, so that a small mesh moved far from the
 * origin keeps its shape until the scene is centred (rtt_scene_finish). */
void rtt_transform_point_exact(const double m[16], const double p[3], double out[3]);

/* A normal moves by the inverse transpose of the upper 3x3; the result is
 * normalized (and zero stays zero). */
rtt_vec3 rtt_transform_normal(const double m[16], rtt_vec3 n);

#endif

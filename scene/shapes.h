/* Built-in procedural shapes for scene files (`"shape"` in a mesh, see
 * scene/README.md).  Each builder returns an indexed triangle mesh in the
 * shape's own coordinates; the scene parser appends it with
 * rtt_scene_add_mesh and the mesh's transform.
 *
 * Box, sphere, cylinder and torus are closed: every edge belongs to exactly
 * two triangles, wound counter-clockwise seen from outside.  The scene
 * identifies vertices by exact position (closedness in scene.c, the leak fix
 * of Edge Width Soft Shadows), so where a flat face needs its own copy of a
 * vertex to carry its normal (box faces, cylinder caps) the copy has the
 * bit-identical position; sphere and torus share vertex indices outright.
 * Every shape carries vertex normals, so it shades right next to smooth
 * meshes (a scene with any normals interpolates them everywhere). */
#ifndef RTT_SHAPES_H
#define RTT_SHAPES_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/vec3.h"

typedef struct rtt_shape_mesh {
    rtt_vec3 *positions;
    rtt_vec3 *normals;   /* per vertex, unit length */
    uint32_t *indices;   /* 3 per triangle */
    uint32_t vertex_count, triangle_count;
} rtt_shape_mesh;

/* Limits the parser enforces (and the builders assume). */
#define RTT_SHAPE_MAX_SUBDIVISIONS 7u
#define RTT_SHAPE_MIN_SEGMENTS 3u
#define RTT_SHAPE_MAX_SEGMENTS 1024u

/* Each returns false only when out of memory (out is then empty). */
/* Two triangles (0,1,2), (0,2,3); open; one normal from the winding. */
bool rtt_shape_quad(const rtt_vec3 corners[4], rtt_shape_mesh *out);
/* Axis-aligned box: 12 triangles, 4 vertices per face. */
bool rtt_shape_box(rtt_vec3 lo, rtt_vec3 hi, rtt_shape_mesh *out);
/* Icosphere: the icosahedron subdivided `subdivisions` times, 20 * 4^s triangles. */
bool rtt_shape_sphere(rtt_vec3 center, float radius, uint32_t subdivisions, rtt_shape_mesh *out);
/* Capped cylinder on the base centre, axis +Y, smooth sides, flat caps. */
bool rtt_shape_cylinder(rtt_vec3 base, float radius, float height, uint32_t segments, rtt_shape_mesh *out);
/* Torus in the XZ plane: `around` segments along the ring, `tube` around the tube. */
bool rtt_shape_torus(rtt_vec3 center, float major_radius, float minor_radius, uint32_t around, uint32_t tube,
                     rtt_shape_mesh *out);

void rtt_shape_mesh_free(rtt_shape_mesh *mesh);

/* The triangles a shape of `type` makes with these parameters (what the
 * builder above allocates), for the memory budget before any is built;
 * `segments` is the cylinder's, `around` and `tube` the torus's.  0 for an
 * unknown type. */
uint64_t rtt_shape_triangle_count(const char *type, uint32_t subdivisions, uint32_t segments, uint32_t around,
                                  uint32_t tube);

#endif

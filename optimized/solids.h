/* The closed, consistently oriented surfaces of a scene's meshes: what every
 * back-face culling stands on (the perspective grids' eye rays,
 * pgrid_build.c, and hard shadows, pgrid_light_build.c; bvh-mft's camera
 * path, bvh/traverse_mft.c).  A mesh qualifies when rtt says it is
 * closed (rtt_mesh.closed) and every directed edge of its non-degenerate
 * triangles, by vertex index, has its reverse exactly once; each connected
 * part (triangles sharing vertices) is then the boundary of a solid, its
 * outward side the sign of its signed volume.  Meshes split at seams, open
 * ones and inconsistent windings do not qualify: they keep both faces,
 * which costs speed, never exactness.  Assumed, not checked: a part does
 * not pass through itself. */
#ifndef RTT_OPTIMIZED_SOLIDS_H
#define RTT_OPTIMIZED_SOLIDS_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/scene.h"

/* Whether `mesh` qualifies (without the closedness flag's check), and the
 * outward side of the whole mesh (+1: its winding's normal, -1: the
 * opposite).  False also when out of memory. */
bool scene_mesh_oriented(const rtt_scene *scene, const uint8_t *degenerate, const rtt_mesh *mesh, int8_t *outward);

/* The box of the mesh's vertices (lo xyz, hi xyz). */
void scene_mesh_box(const rtt_scene *scene, const rtt_mesh *mesh, float box[6]);

/* A scene's solids, worked out once per scene. */
typedef struct scene_solids {
    /* per scene triangle: +1 when its winding's normal points out of its
     * part's solid, -1 the opposite, 0 when its mesh does not qualify (or
     * the part has no volume) */
    int8_t *triangle_outward;
    /* per mesh: 1 when it qualifies, and the box of its vertices (lo xyz, hi xyz) */
    uint8_t *mesh_solid;
    float (*mesh_box)[6];
    uint32_t solid_count;      /* meshes that qualify */
} scene_solids;

/* Fills `solids` for the scene's triangles not flagged in `degenerate`
 * (NULL: none).  False when out of memory (then nothing is kept). */
bool scene_solids_find(scene_solids *solids, const rtt_scene *scene, const uint8_t *degenerate);
void scene_solids_free(scene_solids *solids);

#endif

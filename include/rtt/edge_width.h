/* Edge Width Soft Shadows (Thesis chapter 5): the semantics both engines
 * implement, in one place.  The reference (reference/edge_width_reference.c)
 * and the SSE packet version (optimized/kd/shadows/edge_width.c) only differ
 * in how they find the crossings of a ray; what a crossing means is decided
 * here.
 *
 * The ray.  One ray per shading point and sphere light, from the light's
 * centre to the point, direction = point - centre unnormalised, so t is the
 * fraction of the way (Listing 5.1); tnear = epsilon / d, tfar = 1 - epsilon
 * / d with the renderers' shadow epsilon.  Point lights (and sphere lights
 * of radius 0) have no penumbra: they get the hard shadow ray.
 *
 * The crossings, fed in increasing t (Listing 5.1's sorted distances, paired
 * across leaves).  The ray starts outside every object and toggles between
 * outside and inside at each crossing; an entry and the next crossing (the
 * exit) make an edge width  w = (t_exit - t_entry) * max(scale_entry,
 * scale_exit)  with scale = the material's edge_width_scale (4.2 "Light
 * Leaks": thin occluders made wider by the scene designer).  Beyond the
 * listing, because real rays hit meshes on their edges:
 *   - crossings closer than RTT_EDGE_WIDTH_CLUSTER in t are one cluster; in
 *     a cluster only the first crossing of each facing (geometric normal
 *     against the ray) counts, so a ray through the edge shared by two
 *     front faces enters once, and one grazing a silhouette (a front and a
 *     back face) enters and leaves with width 0.  This assumes consistently
 *     oriented meshes; the toggling itself never looks at facing.
 *   - a crossing of a triangle of an open mesh (rtt_mesh.closed false) has
 *     no inside: the light is fully occluded (hard shadow), as the thesis
 *     says of malformed geometry.
 *   - leak fix (option): an entry and exit that share no vertex (by
 *     position, as closedness is decided) give an infinite width.
 * Occlusion: 1 once the largest width exceeds R (early exit), 1 when the ray
 * ends inside an object, else Equation 5.1 of the largest width.  Light
 * visibility = 1 - occlusion.
 *
 * R is a fraction of the light-to-point distance, as the thesis' `radius`
 * (Listing 5.1); the thesis gives no number, ours is
 * RTT_EDGE_WIDTH_DEFAULT_RADIUS (edgewidth with no :R). */
#ifndef RTT_EDGE_WIDTH_H
#define RTT_EDGE_WIDTH_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/scene.h"

#define RTT_EDGE_WIDTH_DEFAULT_RADIUS 0.02f /* the best of 0.02, 0.05, 0.1 in bench/results/shadows.md */
/* Crossings this close in t (a fraction of the ray) are one cluster. */
#define RTT_EDGE_WIDTH_CLUSTER 4e-5f

typedef struct rtt_edge_width_model {
    const rtt_scene *scene;
    float radius;        /* R, > 0 */
    bool leak_fix;
} rtt_edge_width_model;

/* The pairing state of one ray (Listing 5.1's maxEdgeWidth and
 * distances[0]), plus the current cluster. */
typedef struct rtt_edge_width_state {
    float dir[3];                /* the ray's direction, for facing */
    float max_width;
    float entry_t;
    uint32_t entry_prim;
    bool inside;
    bool decided;                /* occlusion is 1 whatever follows */
    float cluster_t;             /* t of the cluster's first crossing, -inf before any */
    uint32_t cluster_prim;
    uint32_t cluster_facing;     /* bit 0 front, bit 1 back seen; 0 = not yet computed */
} rtt_edge_width_state;

/* radius 0 → the default; leak_fix as given. */
rtt_edge_width_model rtt_edge_width_model_make(const rtt_scene *scene, float radius, bool leak_fix);

/* The ray of the point p from light centre c; false when the segment is too
 * short for anything to fit (then vis = 1, as for shadow rays). */
bool rtt_edge_width_ray(rtt_vec3 light_centre, rtt_vec3 p, float epsilon, rtt_ray *out);

void rtt_edge_width_start(rtt_edge_width_state *s, const float dir[3]);
/* One crossing of triangle prim at t; returns true once the occlusion is
 * decided (1), after which nothing else need be fed. */
bool rtt_edge_width_feed(const rtt_edge_width_model *m, rtt_edge_width_state *s, float t, uint32_t prim);
/* Occlusion in [0, 1] after the last crossing. */
float rtt_edge_width_finish(const rtt_edge_width_model *m, const rtt_edge_width_state *s);

/* Equation 5.1: 0 for width <= 0, width / R up to R, 1 beyond. */
float rtt_edge_width_occlusion(float width, float radius);
/* Do triangles a and b share a corner position? */
bool rtt_edge_width_share_vertex(const rtt_scene *scene, uint32_t a, uint32_t b);

#endif

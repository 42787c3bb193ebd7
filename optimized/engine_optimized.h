/* The optimized engine (engine_optimized.c): the kd-tree of kd_build_sah.c
 * (or adopted from a baked .kdt) behind the engine interface, and the
 * accessors the optimized renderer and the tests use. */
#ifndef RTT_OPTIMIZED_ENGINE_OPTIMIZED_H
#define RTT_OPTIMIZED_ENGINE_OPTIMIZED_H

#include "bvh_kernels.h"
#include "kd_tree.h"
#include "kernels.h"
#include "pgrid_eye.h"
#include "pgrid_light.h"
#include "rtt/engine.h"

/* NULL when `engine` is not an optimized engine. */
const kd_tree *kd_engine_tree(rtt_engine *engine);
const kd_kernel *kd_engine_kernel(rtt_engine *engine);
/* With --accel bvh: the BVH and its kernel row (NULL otherwise; the kd
 * accessors above are NULL for such an engine). */
const bvh_tree *bvh_engine_tree(rtt_engine *engine);
const bvh_kernel *bvh_engine_kernel(rtt_engine *engine);
/* Per triangle 1 when it never hits (rtt_triangle_is_degenerate); NULL when
 * the scene has no such triangle or `engine` is not an optimized engine. */
const uint8_t *optimized_engine_degenerate(rtt_engine *engine);
/* The eye rays' cell kernel of an engine created with --accel pgrid, else NULL. */
const pgrid_kernel *pgrid_engine_kernel(rtt_engine *engine);
/* --shadows pgrid: the engine's light grids, lent to one frame of `scene`
 * at a time and kept between frames: their scene half (pgrid_shadows_
 * prepare: the corners in Morton order, the culled meshes) made at the
 * first frame that asks, the lights' arrays regrown in place by each
 * frame's pgrid_shadows_build_lights, so a frame after the first allocates
 * nothing for them (the interactive loop: a frame paid 28-39 ms of
 * prepare on the meshes, mostly first touches of fresh pages).  NULL with
 * *failed false when `engine` is not an optimized engine or another frame
 * holds them (the caller makes its own); NULL with *failed true (err
 * filled) when out of memory.  Every grid lent goes back through
 * optimized_engine_light_grids_return. */
pgrid_shadows *optimized_engine_light_grids_lend(rtt_engine *engine, const rtt_scene *scene, rtt_error *err,
                                                bool *failed);
void optimized_engine_light_grids_return(rtt_engine *engine);

#endif

/* The scalar reference (reference/): written for obviousness, it is what the
 * optimized path and Embree are checked against. */
#ifndef RTT_REFERENCE_H
#define RTT_REFERENCE_H

#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/render.h"

/* SAH kd-tree with perfect splits, recursive traversal (Thesis Listing 2.1),
 * watertight triangle test (Woop, Benthin, Wald 2013). */
rtt_engine *rtt_reference_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err);

/* Whitted renderer of shade.h.  Traces every ray through `tracer`, which is
 * normally the reference engine but may be any engine (Embree renders this
 * way).  Shadows: none, hard, multi:N; other methods belong to the optimized
 * renderer and are refused with a message.  Deterministic for any thread
 * count.  `out` must have the options' size (or the scene's) and the AOV
 * planes the options ask for.  stats may be NULL. */
bool rtt_reference_render(const rtt_scene *scene, rtt_engine *tracer, const rtt_render_options *opt,
                          rtt_image *out, rtt_render_stats *stats, rtt_error *err);

/* rtt_reference_render of the engine's own scene through the engine: the
 * render entry of every engine that has no renderer of its own. */
bool rtt_reference_render_engine(rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                                 rtt_render_stats *stats, rtt_error *err);

/* Woop, Benthin, Wald 2013 watertight ray/triangle test against one
 * triangle: true when the ray hits it (either side) with tnear < t < tfar;
 * t, u, v (barycentrics of vertices 1 and 2) are written on a hit only.
 * Zero-area triangles and NaN rays never hit.  The brute-force oracle of the
 * conformance suite and the fuzzers. */
bool rtt_reference_intersect_triangle(const rtt_ray *ray, const rtt_vec3 tri[3], float *t, float *u, float *v);

/* The shadow methods rtt_reference_render draws. */
#define RTT_REFERENCE_SHADOW_METHODS                                                                             \
    ((1u << RTT_SHADOWS_NONE) | (1u << RTT_SHADOWS_HARD) | (1u << RTT_SHADOWS_MULTI) | (1u << RTT_SHADOWS_EDGEWIDTH) | \
     (1u << RTT_SHADOWS_INTERLEAVED))

/* The reference engine for the registry (rtt_engine_register). */
extern const rtt_engine_class rtt_reference_engine_class;

#endif

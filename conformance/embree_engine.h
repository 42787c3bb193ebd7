/* Embree 3 behind the engine interface: the oracle and performance peer. */
#ifndef RTT_EMBREE_ENGINE_H
#define RTT_EMBREE_ENGINE_H

#include "rtt/engine.h"

/* Robust scene flag, high build quality; closest hit and occlusion. */
rtt_engine *rtt_embree_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err);
extern const rtt_engine_class rtt_embree_engine_class;
/* Whether the adapter hands ray r (in stored coordinates) to Embree: a
 * finite origin and direction with every component below 1.844e18 (beyond
 * it Embree aborts on an assertion), no NaN bound, a non-empty interval
 * with tfar > 0, a non-zero direction.  Every other ray is answered as a
 * miss without asking Embree; rtt conform counts the ones an rtt engine
 * takes as "unspecified" for Embree. */
bool rtt_embree_ray_in_range(const rtt_ray *r);

#ifdef RTT_HAVE_EMBREE
#include <stdbool.h>
#include <embree3/rtcore.h>

/* Attaches the scene's triangles, in global order, as geometry 0 of
 * `target`: vertices and indices are copied into Embree-owned buffers (which
 * carry the padding Embree reads past the end).  The engine and the
 * benchmark peer build their scenes with it, so both trace the same
 * geometry.  False when Embree refuses a buffer. */
bool rtt_embree_attach_triangles(RTCDevice device, RTCScene target, const rtt_scene *scene);
#endif

#endif

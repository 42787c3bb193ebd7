/* Embree 3 behind the engine interface: the oracle and performance peer. */
#ifndef RTT_EMBREE_ENGINE_H
#define RTT_EMBREE_ENGINE_H

#include "rtt/engine.h"

/* Robust scene flag, high build quality; closest hit and occlusion. */
rtt_engine *rtt_embree_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err);

#endif

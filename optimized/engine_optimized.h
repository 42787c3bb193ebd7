/* The optimized engine (engine_optimized.c): the kd-tree of kd_build_sah.c
 * (or adopted from a baked .kdt) behind the engine interface, and the
 * accessors the optimized renderer and the tests use. */
#ifndef RTT_OPTIMIZED_ENGINE_OPTIMIZED_H
#define RTT_OPTIMIZED_ENGINE_OPTIMIZED_H

#include "kd_tree.h"
#include "kernels.h"
#include "rtt/engine.h"

/* NULL when `engine` is not an optimized engine. */
const kd_tree *kd_engine_tree(rtt_engine *engine);
const kd_kernel *kd_engine_kernel(rtt_engine *engine);

#endif

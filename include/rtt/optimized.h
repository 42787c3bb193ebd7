/* The SSE production path (optimized/). */
#ifndef RTT_OPTIMIZED_H
#define RTT_OPTIMIZED_H

#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/render.h"

/* O(N log N) perfect-split SAH kd-tree, SSE kernels; uses scene->baked when
 * the scene came from a .kdt. */
rtt_engine *rtt_optimized_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err);

/* Tiles to threads, frusta, traversal, leaf culling, packet intersection,
 * shader proxy with secondary packets (Thesis Figure 3.2).  `engine` must
 * come from rtt_optimized_engine_create. */
bool rtt_optimized_render(rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                          rtt_render_stats *stats, rtt_error *err);

/* The optimized engine for the registry (rtt_engine_register). */
extern const rtt_engine_class rtt_optimized_engine_class;

/* Builds the tree and writes the versioned .kdt ("RTTest offline"). */
bool rtt_optimized_bake(const rtt_scene *scene, const rtt_engine_options *opt, const char *path, rtt_error *err);

#endif

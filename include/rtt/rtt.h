/* rtt as a library: every public header, and the one call that makes the
 * built-in engines known by name.
 *
 *   rtt_builtin_engines_register(NULL);
 *   rtt_scene *scene = rtt_scene_load("scene.json", NULL, &err);
 *   rtt_engine *engine = rtt_engine_create("optimized", scene, NULL, &err);
 *   rtt_engine_intersect(engine, rays, hits, n);
 */
#ifndef RTT_RTT_H
#define RTT_RTT_H

#include "rtt/engine.h"
#include "rtt/error.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "rtt/render.h"
#include "rtt/scene.h"

#define RTT_VERSION_MAJOR 0
#define RTT_VERSION_MINOR 2
#define RTT_VERSION_PATCH 0
#define RTT_VERSION_STRING "0.2.0"

/* Registers "reference" and "optimized" (idempotent, thread-safe). */
bool rtt_builtin_engines_register(rtt_error *err);

#endif

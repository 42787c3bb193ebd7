/* The memory budget of a scene (scene/memory_budget.c).
 *
 * Every scene carries a budget in bytes; each loader reserves what its part
 * of the scene will cost — RTT_BYTES_PER_TRIANGLE for each triangle (the
 * scene's arrays, the kd-tree's references and nodes at their build peak,
 * the renderer's records), plus the bytes of its textures and buffers —
 * before it allocates them, from the counts a header or a shape's
 * parameters give.  A scene over its budget is refused before the work with
 * one line saying what it would need:
 *   "big.json: needs about 39.0 GiB for 65536000 triangles, over the memory budget of 17.6 GiB" */
#ifndef RTT_MEMORY_BUDGET_H
#define RTT_MEMORY_BUDGET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/scene.h"

/* Peak bytes per triangle of loading, building and rendering, measured on
 * procedural spheres (1.6M triangles: 806 MB peak, 490 bytes each) and a
 * scanned mesh (89k triangles: 550 bytes each over the process's base), with
 * room to spare. */
#define RTT_BYTES_PER_TRIANGLE 640u

/* The default budget: the machine's physical memory, or the process's
 * address-space or data limit (ulimit -v, ulimit -d) when lower. */
uint64_t rtt_memory_budget_default(void);

/* Adds `triangles` triangles and `bytes` other bytes to what `scene` has
 * reserved; refuses, naming `source`, when that passes its budget. */
bool rtt_scene_budget_reserve(rtt_scene *scene, const char *source, uint64_t triangles, uint64_t bytes,
                              rtt_error *err);

/* The same test for a part not yet in a scene: `triangles` and `bytes`
 * against `budget` (0: the default). */
bool rtt_memory_budget_check(const char *source, uint64_t triangles, uint64_t bytes, uint64_t budget,
                             rtt_error *err);

/* "17.6 GiB", "512 MiB", "900 bytes": one decimal past the largest unit. */
void rtt_memory_size_format(uint64_t bytes, char *out, size_t size);
/* "4G", "512M", "1.5GiB", "800000000": a size in bytes (K, M, G, T are
 * binary, an optional "iB" or "B" after them); false on junk, zero or more
 * than 2^60. */
bool rtt_memory_size_parse(const char *text, uint64_t *out);

#endif

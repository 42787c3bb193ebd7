/* Fuzz target: the baked kd-tree loader (.kdt through rtt_scene_load).
 *
 * The loader must validate every count, offset and index before use
 * (docs/ARCHITECTURE.md): a bad file is refused with one line; an accepted one must be
 * a sound scene whose tree the engines can trace.  Accepted files are traced
 * with a pinhole bundle and checked against brute force, so a tree that
 * passes validation but drops triangles or points outside its arrays is
 * caught here too.  Mutated files are also loaded with their checksum
 * repaired (load_repaired), or the fuzzer would never get past it. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "rtt/rtt.h"
#include "fuzz_oracle.h"
#include "rtt/engine.h"
#include "../scene/kdt_format.h"   /* the header layout and checksum, to repair mutated files */

#define GRID 6u

/* An accepted file's tree, traced with a pinhole bundle and checked against
 * brute force.  The optimized engine checks a baked tree against its
 * triangles before adopting it (optimized/kd/kdt_verify.c: records, root box,
 * leaf boxes, no triangle left out), so a re-checksummed file whose records
 * disagree with its vertices is refused with one line, not traced. */
static void trace_bundle(const rtt_scene *scene)
{
    rtt_vec3 lo = scene->bounds.lo, hi = scene->bounds.hi;
    rtt_vec3 centre = rtt_v3_add(rtt_v3_scale(lo, 0.5f), rtt_v3_scale(hi, 0.5f));
    rtt_vec3 extent = rtt_v3_sub(hi, lo);
    float size = fmaxf(extent.x, fmaxf(extent.y, extent.z));
    rtt_vec3 eye = rtt_v3_add(centre, rtt_v3(0.3f * size, 0.2f * size, 2.0f * size + 1.0f));
    rtt_ray rays[GRID * GRID];
    for (uint32_t y = 0; y < GRID; y++)
        for (uint32_t x = 0; x < GRID; x++) {
            rtt_vec3 target = rtt_v3_add(centre, rtt_v3(((float)x / (GRID - 1) - 0.5f) * size,
                                                        ((float)y / (GRID - 1) - 0.5f) * size, 0.0f));
            rtt_vec3 d = rtt_v3_sub(target, eye);
            rays[y * GRID + x] = (rtt_ray){ { eye.x, eye.y, eye.z }, { d.x, d.y, d.z }, 0.0f, INFINITY };
        }
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.threads = 1;
    rtt_error err = { "" };
    rtt_engine *engine = rtt_engine_create("optimized", scene, &opt, &err);
    if (!engine) {
        if (!err.message[0] || strchr(err.message, '\n'))
            fuzz_fail("optimized engine refused a loaded .kdt without a one-line message");
        return;
    }
    fuzz_check_tree_info(engine, "optimized(kdt)", scene, true);
    fuzz_oracle *oracle = fuzz_oracle_create(scene, rays, GRID * GRID);
    fuzz_oracle_check(oracle, engine, "optimized(kdt)", true);
    fuzz_oracle_free(oracle);
    rtt_engine_destroy(engine);
}

static void load_and_check(const uint8_t *data, size_t size)
{
    rtt_error err;
    rtt_scene *scene = fuzz_load_scene_bytes(data, size, ".kdt", &err);
    if (!scene)
        return;
    fuzz_check_scene(scene);
    if (scene->triangle_count > 0 && scene->triangle_count <= 4096 && rtt_v3_is_finite(scene->bounds.lo) &&
        rtt_v3_is_finite(scene->bounds.hi))
        trace_bundle(scene);
    rtt_scene_free(scene);
}

/* A mutated file almost never keeps its checksum (or its size field), and
 * the loader rightly stops there.  So that mutations reach the validation
 * of counts, offsets and indices behind it, the bytes are loaded twice: as
 * they are, and with file_size and checksum repaired (FNV-1a 64 as in
 * scene/kdt_format.h). */
static void load_repaired(const uint8_t *data, size_t size)
{
    if (size < KDT_CHECKSUM_START)
        return;
    uint8_t *copy = malloc(size);
    if (!copy)
        fuzz_fail("out of memory");
    memcpy(copy, data, size);
    uint64_t file_size = size;
    memcpy(copy + offsetof(kdt_header, file_size), &file_size, sizeof file_size);
    uint64_t sum = rtt_kdt_checksum_update(KDT_CHECKSUM_INIT, copy + KDT_CHECKSUM_START, size - KDT_CHECKSUM_START);
    memcpy(copy + offsetof(kdt_header, checksum), &sum, sizeof sum);
    if (memcmp(copy, data, KDT_CHECKSUM_START) != 0)
        load_and_check(copy, size);
    free(copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!rtt_builtin_engines_register(NULL)) fuzz_fail("cannot register the built-in engines");
    if (size > 1 << 20)
        return 0;
    load_and_check(data, size);
    load_repaired(data, size);
    return 0;
}

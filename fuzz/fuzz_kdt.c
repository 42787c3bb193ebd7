/* Fuzz target: the baked kd-tree loader (.kdt through rtt_scene_load).
 *
 * The loader must validate every count, offset and index before use
 * (DESIGN.md): a bad file is refused with one line; an accepted one must be
 * a sound scene whose tree the engines can trace.  Accepted files are traced
 * with a pinhole bundle and checked against brute force, so a tree that
 * passes validation but drops triangles or points outside its arrays is
 * caught here too. */
#include <math.h>
#include <string.h>

#include "fuzz_common.h"
#include "fuzz_oracle.h"
#include "rtt/engine.h"

#define GRID 6u

static void trace_bundle(const rtt_scene *scene)
{
    rtt_vec3 lo = scene->bounds.lo, hi = scene->bounds.hi;
    rtt_vec3 centre = rtt_v3_scale(rtt_v3_add(lo, hi), 0.5f);
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
    fuzz_oracle *oracle = fuzz_oracle_create(scene, rays, GRID * GRID);
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.threads = 1;
    rtt_error err = { "" };
    rtt_engine *engine = rtt_engine_create("optimized", scene, &opt, &err);
    if (engine) {
        fuzz_check_tree_info(engine, "optimized(kdt)", scene);
        fuzz_oracle_check(oracle, engine, "optimized(kdt)", true);
        rtt_engine_destroy(engine);
    } else if (!err.message[0] || strchr(err.message, '\n')) {
        fuzz_fail("optimized engine refused a loaded .kdt without a one-line message");
    }
    fuzz_oracle_free(oracle);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20)
        return 0;
    rtt_error err;
    rtt_scene *scene = fuzz_load_scene_bytes(data, size, ".kdt", &err);
    if (!scene)
        return 0;
    fuzz_check_scene(scene);
    if (scene->triangle_count > 0 && scene->triangle_count <= 4096 && rtt_v3_is_finite(scene->bounds.lo) &&
        rtt_v3_is_finite(scene->bounds.hi))
        trace_bundle(scene);
    rtt_scene_free(scene);
    return 0;
}

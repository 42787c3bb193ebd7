/* rtt trace: rays.bin through an engine to hits.bin (the outside-tool seam
 * of docs/ARCHITECTURE.md: any program can check any engine's hits). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rtt/engine.h"

static const char trace_help[] =
    "usage: rtt trace SCENE --rays rays.bin -o hits.bin [--engine E] [--occluded]\n"
    "                 [--traversal T] [--tile N] [--leaf-culling on|off]\n"
    "\n"
    "Traces little-endian rtt_ray records (org[3], dir[3], tnear, tfar: 8 float32)\n"
    "and writes one rtt_hit record per ray (t, u, v as float32, prim as uint32;\n"
    "prim 0xFFFFFFFF and t = inf on a miss), or with --occluded one byte per ray\n"
    "(1 = something lies in (tnear, tfar)).  SCENE may also be a tris.bin of raw\n"
    "triangles as written by rtt triangles.\n"
    "\n"
    "  --engine E       optimized (default), reference or embree\n"
    "  --traversal T    optimized kernel (default mono): mono, packet, omni,\n"
    "                   frustum, mft, cone, mft-cone\n"
    "  --tile N         rays per frustum block side: 4, 8 (default), 16, 32\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

static bool ends_with(const char *text, const char *suffix)
{
    size_t n = strlen(text), m = strlen(suffix);
    return n >= m && strcmp(text + n - m, suffix) == 0;
}

/* A scene from raw triangles (rtt triangles' output format). */
static rtt_scene *load_triangle_file(const char *path, rtt_error *err)
{
    size_t size = 0;
    float *xyz = cli_read_file(path, &size, err);
    if (!xyz) return NULL;
    rtt_scene *scene = NULL;
    if (size % (9 * sizeof(float)) != 0)
        rtt_error_set(err, "%s: size %zu is not a multiple of 36 bytes (9 float32 per triangle)", path, size);
    else if (size / 36 > UINT32_MAX)
        rtt_error_set(err, "%s: too many triangles", path);
    else
        scene = rtt_scene_from_triangles(xyz, (uint32_t)(size / 36), err);
    if (!scene && size % 36 == 0) {
        rtt_error inner = *err;
        rtt_error_set(err, "%s: %s", path, inner.message);
    }
    free(xyz);
    return scene;
}

int cmd_trace(int argc, char **argv)
{
    const char *scene_path = NULL, *rays_path = NULL, *out_path = NULL, *engine_name = "optimized";
    bool occluded = false;
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (cli_is_help(arg)) {
            fputs(trace_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(arg, "--occluded") == 0) {
            occluded = true;
            continue;
        }
        if (arg[0] != '-') {
            if (scene_path) return cli_usage_error("trace", "more than one SCENE given");
            scene_path = arg;
            continue;
        }
        if (i + 1 >= argc) return cli_usage_error("trace", "%s needs a value", arg);
        const char *value = argv[++i];
        if (strcmp(arg, "--rays") == 0) rays_path = value;
        else if (strcmp(arg, "-o") == 0) out_path = value;
        else if (strcmp(arg, "--engine") == 0) {
            if (strcmp(value, "reference") && strcmp(value, "optimized") && strcmp(value, "embree"))
                return cli_usage_error("trace", "--engine %s: expected reference, optimized or embree", value);
            engine_name = value;
        } else if (strcmp(arg, "--traversal") == 0) {
            if (strlen(value) >= sizeof opt.traversal)
                return cli_usage_error("trace", "--traversal %s: no kernel has so long a name", value);
            strcpy(opt.traversal, value);
            opt.given |= RTT_OPTION_TRAVERSAL;
        } else if (strcmp(arg, "--tile") == 0) {
            if (!cli_parse_u32(value, 4, 32, &opt.tile) || (opt.tile & (opt.tile - 1)))
                return cli_usage_error("trace", "--tile %s: expected 4, 8, 16 or 32", value);
        } else if (strcmp(arg, "--leaf-culling") == 0) {
            if (strcmp(value, "on") && strcmp(value, "off"))
                return cli_usage_error("trace", "--leaf-culling %s: expected on or off", value);
            opt.leaf_culling = strcmp(value, "on") == 0;
        } else {
            return cli_usage_error("trace", "unknown option \"%s\"", arg);
        }
    }
    if (!scene_path) return cli_usage_error("trace", "no SCENE given");
    if (!rays_path) return cli_usage_error("trace", "no rays given (--rays rays.bin)");
    if (!out_path) return cli_usage_error("trace", "no output given (-o hits.bin)");

    rtt_error err = {0};
    size_t size = 0;
    rtt_ray *rays = cli_read_file(rays_path, &size, &err);
    if (!rays) return cli_fail(&err);
    if (size % sizeof(rtt_ray) != 0) {
        free(rays);
        rtt_error_set(&err, "%s: size %zu is not a multiple of 32 bytes (rtt_ray records)", rays_path, size);
        return cli_fail(&err);
    }
    size_t count = size / sizeof(rtt_ray);
    rtt_scene *scene = ends_with(scene_path, ".bin") ? load_triangle_file(scene_path, &err)
                                                     : cli_load_scene(scene_path, 0, &err);
    rtt_engine *engine = scene ? rtt_engine_create(engine_name, scene, &opt, &err) : NULL;
    size_t record = occluded ? 1 : sizeof(rtt_hit);
    void *results = engine ? malloc(count * record + 1) : NULL;
    bool ok = results != NULL;
    if (engine && !results) rtt_error_set(&err, "%s: out of memory for %zu rays", rays_path, count);
    if (ok) {
        if (occluded) rtt_engine_occluded(engine, rays, results, count);
        else rtt_engine_intersect(engine, rays, results, count);
        ok = cli_write_file_atomic(out_path, results, count * record, &err);
    }
    free(results);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
    free(rays);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

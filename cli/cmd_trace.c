/* rtt trace: rays.bin through an engine to hits.bin (the outside-tool seam
 * of docs/ARCHITECTURE.md: any program can check any engine's hits). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>

#include "cli.h"
#include "options.h"
#include "rtt/engine.h"
#include "rtt/memory_budget.h"

typedef struct trace_args {
    const char *scene_path, *rays_path, *out_path, *engine_name;
    bool occluded;
    rtt_engine_options engine;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
} trace_args;

static const cli_option trace_options[] = {
    {.name = "--rays", .value_name = "FILE", .help = "the rtt_ray records to trace (required)",
     .kind = CLI_STRING, CLI_FIELD(trace_args, rays_path)},
    {.name = "--output", .short_name = 'o', .value_name = "FILE",
     .help = "the hits (or occlusion bytes) to write (required)",
     .kind = CLI_STRING, CLI_FIELD(trace_args, out_path)},
    {.name = "--occluded", .help = "one byte per ray: 1 when something lies in (tnear, tfar)",
     .kind = CLI_FLAG, CLI_FIELD(trace_args, occluded)},
    CLI_OPTION_ENGINE(trace_args, engine_name),
    CLI_OPTIONS_KD_ENGINE(trace_args, engine),
    CLI_OPTION_BUILD_THREADS(trace_args, engine),
    CLI_OPTION_MAX_MEMORY(trace_args, max_memory),
};

static bool ends_with(const char *text, const char *suffix)
{
    size_t n = strlen(text), m = strlen(suffix);
    return n >= m && strcmp(text + n - m, suffix) == 0;
}

/* A scene from raw triangles (rtt triangles' output format). */
static rtt_scene *load_triangle_file(const char *path, uint64_t max_memory, rtt_error *err)
{
    size_t size = 0;
    struct stat info;
    if (stat(path, &info) == 0 && S_ISREG(info.st_mode) &&
        !rtt_memory_budget_check(path, (uint64_t)info.st_size / 36, 0, max_memory, err))
        return NULL;
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

static void trace_defaults(void *opaque)
{
    trace_args *args = opaque;
    args->engine_name = "optimized";
    rtt_engine_options_default(&args->engine);
}

static int trace(void *opaque, const cli_parsed *parsed)
{
    const trace_args *args = opaque;
    int rc;
    if (!args->rays_path) return cli_refuse(parsed, NULL, "no rays given (--rays rays.bin)");
    if (!args->out_path) return cli_refuse(parsed, NULL, "no output given (-o hits.bin)");
    if ((rc = cli_check_engine_options(parsed, args->engine_name, &args->engine)) != CLI_CONTINUE) return rc;
    if ((rc = cli_check_scene_options(parsed, args->scene_path, args->engine_name)) != CLI_CONTINUE) return rc;

    rtt_error err = {0};
    const char *inputs[] = {args->scene_path, args->rays_path};
    if (!cli_check_outputs(&args->out_path, 1, inputs, 2, &err)) return cli_fail(&err);
    size_t size = 0;
    rtt_ray *rays = cli_read_file(args->rays_path, &size, &err);
    if (!rays) return cli_fail(&err);
    if (size % sizeof(rtt_ray) != 0) {
        free(rays);
        rtt_error_set(&err, "%s: size %zu is not a multiple of 32 bytes (rtt_ray records)", args->rays_path, size);
        return cli_fail(&err);
    }
    size_t count = size / sizeof(rtt_ray);
    rtt_scene *scene = ends_with(args->scene_path, ".bin") ? load_triangle_file(args->scene_path, args->max_memory, &err)
                                                          : cli_load_scene(args->scene_path, 0, args->max_memory, &err);
    rtt_engine *engine = scene ? rtt_engine_create(args->engine_name, scene, &args->engine, &err) : NULL;
    size_t record = args->occluded ? 1 : sizeof(rtt_hit);
    void *results = engine ? malloc(count * record + 1) : NULL;
    bool ok = results != NULL;
    if (engine && !results) rtt_error_set(&err, "%s: out of memory for %zu rays", args->rays_path, count);
    if (ok) {
        if (args->occluded) rtt_engine_occluded(engine, rays, results, count);
        else rtt_engine_intersect(engine, rays, results, count);
        ok = cli_write_file_atomic(args->out_path, results, count * record, &err);
    }
    free(results);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
    free(rays);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command trace_command = {
    .name = "trace", .summary = "trace rays.bin through an engine, write hits.bin", .run = trace,
    CLI_ARGS(trace_args, trace_defaults), CLI_ROWS(trace_options), CLI_SCENE_OPERAND(trace_args),
    .engine_offset = offsetof(trace_args, engine),
    .synopsis = "SCENE --rays rays.bin -o hits.bin [options]",
    .description = "Traces little-endian rtt_ray records (org[3], dir[3], tnear, tfar: 8 float32)\n"
                   "and writes one rtt_hit record per ray (t, u, v as float32, prim as uint32;\n"
                   "prim 0xFFFFFFFF and t = inf on a miss), or with --occluded one byte per ray.\n"
                   "SCENE may also be a tris.bin of raw triangles as written by rtt triangles.\n"
                   "The rays go to the kernel in blocks of consecutive 2x2 packets, a tile's worth\n"
                   "for the kernels that trace whole tiles.\n",
};

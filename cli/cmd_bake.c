/* rtt bake: build the optimized kd-tree offline and save it with the scene
 * as a .kdt ("RTTest offline", Thesis 3.2), which `rtt render` and every
 * other command load without rebuilding. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "options.h"
#include "rtt/engine.h"
#include "rtt/optimized.h"

typedef struct bake_args {
    const char *scene_path, *out_path;
    uint32_t bezier_level;
    rtt_engine_options engine;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
} bake_args;

static bool parse_kdt_path(const char *value, void *field, rtt_error *why)
{
    const char *dot = strrchr(value, '.');
    if (!dot || strcasecmp(dot, ".kdt") != 0) return rtt_error_set(why, "the output must end in .kdt");
    *(const char **)field = value;
    return true;
}

static const cli_option bake_options[] = {
    {.name = "--output", .short_name = 'o', .value_name = "FILE", .help = "the .kdt to write (required)",
     .kind = CLI_CUSTOM, CLI_FIELD(bake_args, out_path), .parse = parse_kdt_path},
    CLI_OPTIONS_KD_TREE(bake_args, engine),
    CLI_OPTION_BEZIER_LEVEL(bake_args, bezier_level),
    CLI_OPTION_BUILD_THREADS(bake_args, engine),
    CLI_OPTION_MAX_MEMORY(bake_args, max_memory),
};

static void bake_defaults(void *args)
{
    rtt_engine_options_default(&((bake_args *)args)->engine);
}

static int bake(void *opaque, const cli_parsed *parsed)
{
    const bake_args *args = opaque;
    int rc;
    if (!args->out_path) return cli_refuse(parsed, NULL, "no output given (-o scene.kdt)");
    /* the tree is the optimized engine's: its options check applies */
    if ((rc = cli_check_engine_options(parsed, "optimized", &args->engine)) != CLI_CONTINUE) return rc;
    if ((rc = cli_check_scene_options(parsed, args->scene_path, NULL)) != CLI_CONTINUE) return rc;

    rtt_error err = {0};
    const char *inputs[] = {args->scene_path};
    if (!cli_check_outputs(&args->out_path, 1, inputs, 1, &err)) return cli_fail(&err);
    rtt_scene *scene = cli_load_scene(args->scene_path, args->bezier_level, args->max_memory, &err);
    if (!scene) return cli_fail(&err);
    bool ok = rtt_optimized_bake(scene, &args->engine, args->out_path, &err);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command bake_command = {
    .name = "bake", .summary = "build the kd-tree offline and save it as .kdt", .run = bake,
    CLI_ARGS(bake_args, bake_defaults), CLI_ROWS(bake_options), CLI_SCENE_OPERAND(bake_args),
    .engine_offset = offsetof(bake_args, engine),
    .synopsis = "SCENE -o scene.kdt [options]",
    .description = "Builds the optimized engine's SAH kd-tree (perfect splits, C_trav = 1,\n"
                   "C_isect = 5) for SCENE and writes it, with the whole scene (geometry,\n"
                   "materials, lights, camera), as a versioned, checksummed .kdt.  The output\n"
                   "is written to a temporary and renamed, so an existing file is replaced only\n"
                   "by a complete one.  SCENE may be a .kdt itself: its tree is built anew.\n",
};

/* rtt conform: hit-by-hit agreement of the engines on one scene, or the
 * numerical-extremes suite (--extremes).  The work is in conformance/;
 * this file parses options, prints the report and picks the exit code. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera_options.h"
#include "cli.h"
#include "options.h"
#include "progress.h"
#include "conform.h"
#include "extremes.h"

typedef struct conform_args {
    const char *scene_path, *meshes;
    const char *failing_rays_path; /* --failing-rays: the errors of failing rows, as rays.bin */
    const char *rays_from_path;    /* --rays-from: a rays.bin to trace instead of the sets */
    bool json, extremes;
    uint32_t max_rays, seed;
    rtt_conform_config config;
    rtt_engine_options engine; /* what --isa sets, for the engines that read it */
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
    cli_camera_args camera;    /* the camera of the primary set */
} conform_args;

static bool parse_sets(const char *text, void *field, rtt_error *why)
{
    bool *sets = field, known = true;
    char buffer[128];
    if (strlen(text) >= sizeof buffer) return rtt_error_set(why, "too long a list");
    strcpy(buffer, text);
    for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++) sets[i] = false;
    char *save = NULL;
    int named = 0;
    for (char *item = strtok_r(buffer, ",", &save); item && known; item = strtok_r(NULL, ",", &save), named++) {
        int set = strcmp(item, "all") == 0 ? RTT_CONFORM_RAY_SET_COUNT : rtt_conform_ray_set_parse(item);
        known = set >= 0;
        for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++)
            sets[i] |= set == i || (set == RTT_CONFORM_RAY_SET_COUNT && i != RTT_CONFORM_FILE);
    }
    return named > 0 && known ? true
                              : rtt_error_set(why, "expected primary, shadow, random, extreme, a comma list, or all");
}

static bool parse_engines(const char *value, void *field, rtt_error *why)
{
    if (!rtt_conform_engines_valid(value, why)) return false;
    *(const char **)field = value;
    return true;
}

static const cli_option conform_options[] = {
    {.name = "--rays", .value_name = "SET", .help = "primary, shadow, random, extreme, a comma list, or all (default)",
     .kind = CLI_CUSTOM, CLI_FIELD(conform_args, config.sets), .parse = parse_sets},
    {.name = "--engines", .value_name = "LIST",
     .help = "comma list of engines: optimized (every traversal kernel, tile 8), optimized/KERNEL, embree, "
             "reference (default: optimized,embree)",
     .kind = CLI_CUSTOM, CLI_FIELD(conform_args, config.engines), .parse = parse_engines},
    {.name = "--rays-from", .value_name = "FILE",
     .help = "trace the rays of FILE (rays.bin, the scene's own coordinates: rtt rays, --failing-rays) instead of the "
             "sets, judged as the random set",
     .kind = CLI_STRING, CLI_FIELD(conform_args, rays_from_path)},
    {.name = "--failing-rays", .value_name = "FILE",
     .help = "write every ray a failing row fails on, each once, as rays.bin in the scene's own coordinates "
             "(rtt trace SCENE --rays FILE replays them; empty when nothing fails)",
     .kind = CLI_STRING, CLI_FIELD(conform_args, failing_rays_path)},
    {.name = "--referee-all",
     .help = "the double-precision referee decides every ray, not only disagreements (rays x triangles tests, "
             "within its budget of 2e9)",
     .kind = CLI_FLAG, CLI_FIELD(conform_args, config.referee_every_ray)},
    CLI_OPTION_ISA(conform_args, engine),
    CLI_OPTION_ISECT(conform_args, engine),
    {.name = "--max-rays", .value_name = "N",
     .help = "rays per set, 16 to 100000000 (default 65536; primary renders smaller to fit)",
     .kind = CLI_U32, CLI_FIELD(conform_args, max_rays), .lo = 16, .hi = 100000000u},
    {.name = "--seed", .value_name = "N", .help = "seed of the random and extreme sets",
     .kind = CLI_U32, CLI_FIELD(conform_args, seed), .lo = 0, .hi = UINT32_MAX},
    {.name = "--json", .help = "the report as JSON on stdout", .kind = CLI_FLAG, CLI_FIELD(conform_args, json)},
    {.name = "--extremes",
     .help = "scaled and translated scenes, degenerate triangles, a deep tree, NaN/Inf input, watertightness "
             "from inside closed meshes",
     .kind = CLI_FLAG, CLI_FIELD(conform_args, extremes)},
    {.name = "--meshes", .value_name = "DIR",
     .help = "with --extremes: benchmark meshes for watertightness (default "
             "${RTT_DATA_DIR:-~/.cache/rtt-data}/meshes; skipped when absent)",
     .kind = CLI_STRING, CLI_FIELD(conform_args, meshes)},
    CLI_OPTION_MAX_MEMORY(conform_args, max_memory),
    CLI_OPTIONS_CAMERA(conform_args, camera),
};

/* --isa and --isect go to the listed engines that read them: at least one
 * must, and each must accept them. */
static int check_engine_option(const cli_parsed *parsed, const conform_args *args, const char *name, uint32_t bit,
                               const char *what)
{
    if (!cli_given(parsed, name)) return CLI_CONTINUE;
    const char *list = args->config.engines ? args->config.engines : rtt_conform_default_engines();
    rtt_conform_engine_spec specs[64];
    rtt_error err = {{0}};
    int count = rtt_conform_expand_engines(list, specs, 64, &err);
    if (count < 0) return cli_refuse(parsed, "--engines", "%s", err.message);
    rtt_conform_specs_set_isa(specs, count, args->engine.isa, args->engine.isect);
    int readers = 0;
    for (int i = 0; i < count; i++) {
        if (!(specs[i].opt.given & bit)) continue;
        readers++;
        int rc = cli_check_engine_options(parsed, specs[i].name, &specs[i].opt);
        if (rc != CLI_CONTINUE) return rc;
    }
    return readers ? CLI_CONTINUE : cli_refuse(parsed, name, "none of the engines %s reads %s", list, what);
}

static int check_isa(const cli_parsed *parsed, const conform_args *args)
{
    int rc = check_engine_option(parsed, args, "--isa", RTT_OPTION_ISA, "an instruction-set choice");
    return rc != CLI_CONTINUE ? rc : check_engine_option(parsed, args, "--isect", RTT_OPTION_ISECT, "a triangle-test choice");
}

/* The options one mode reads and the other does not. */
static int check_applicable(const cli_parsed *parsed, conform_args *args)
{
    if (args->extremes) {
        if (args->scene_path) return cli_refuse(parsed, "--extremes", "builds its own scenes: give no SCENE");
        if (cli_given(parsed, "--rays")) return cli_refuse(parsed, "--rays", "--extremes traces rays of its own");
        if (cli_given(parsed, "--seed")) return cli_refuse(parsed, "--seed", "--extremes has no random rays to seed");
        if (args->rays_from_path) return cli_refuse(parsed, "--rays-from", "--extremes traces rays of its own");
        if (args->config.referee_every_ray)
            return cli_refuse(parsed, "--referee-all", "--extremes compares with its own brute force");
        if (args->failing_rays_path)
            return cli_refuse(parsed, "--failing-rays", "--extremes builds its own scenes: give SCENE without --extremes");
        static const char *const camera[] = {"--eye", "--look-at", "--up", "--fov", "--view", "--lights"};
        for (int i = 0; i < 6; i++)
            if (cli_given(parsed, camera[i]))
                return cli_refuse(parsed, camera[i], "--extremes builds its own scenes and cameras");
    } else {
        if (!args->scene_path) return cli_refuse(parsed, NULL, "no SCENE given");
        if (cli_given(parsed, "--meshes")) return cli_refuse(parsed, "--meshes", "only --extremes reads meshes");
        if (args->rays_from_path && cli_given(parsed, "--rays"))
            return cli_refuse(parsed, "--rays", "--rays-from gives the rays: name no set");
        if (args->rays_from_path && (cli_given(parsed, "--max-rays") || cli_given(parsed, "--seed")))
            return cli_refuse(parsed, cli_given(parsed, "--seed") ? "--seed" : "--max-rays",
                              "--rays-from traces every ray of its file, unseeded");
    }
    int rc = check_isa(parsed, args);
    return rc != CLI_CONTINUE || args->extremes ? rc : cli_camera_check(parsed, &args->camera, args->scene_path);
}

static int print_and_free(char *text)
{
    if (!text) {
        fprintf(stderr, "rtt conform: out of memory formatting the report\n");
        return RTT_EXIT_BAD_INPUT;
    }
    fputs(text, stdout);
    if (text[0] && text[strlen(text) - 1] != '\n') fputc('\n', stdout);
    free(text);
    return RTT_EXIT_OK;
}

static int run_extremes(const conform_args *args)
{
    rtt_extremes_config config;
    rtt_extremes_config_default(&config);
    if (args->config.engines) config.engines = args->config.engines;
    if (args->meshes) config.mesh_dir = args->meshes;
    if (args->max_rays) config.max_rays = args->max_rays;
    config.isa = args->engine.isa;
    config.isect = args->engine.isect;
    rtt_extremes_report report;
    rtt_error err = {{0}};
    cli_progress *progress = cli_progress_start("conform --extremes");
    bool ran = rtt_extremes_run(&config, &report, &err);
    cli_progress_finish(progress);
    if (!ran) return cli_fail(&err);
    int rc = print_and_free(args->json ? rtt_extremes_report_json(&report) : rtt_extremes_report_table(&report));
    bool pass = report.pass;
    rtt_extremes_report_free(&report);
    return rc != RTT_EXIT_OK ? rc : pass ? RTT_EXIT_OK : RTT_EXIT_BAD_INPUT;
}

static void conform_defaults(void *opaque)
{
    conform_args *args = opaque;
    rtt_conform_config_default(&args->config);
    rtt_engine_options_default(&args->engine);
}

static int conform(void *opaque, const cli_parsed *parsed)
{
    conform_args *args = opaque;
    int rc = check_applicable(parsed, args);
    if (rc != CLI_CONTINUE) return rc;
    if (args->extremes) return run_extremes(args);
    if (args->max_rays) args->config.max_rays = args->max_rays;
    if (cli_given(parsed, "--seed")) args->config.seed = args->seed;
    args->config.isa = args->engine.isa;
    args->config.isect = args->engine.isect;

    rtt_error err = {{0}};
    const char *inputs[] = {args->scene_path, args->rays_from_path};
    if (args->failing_rays_path &&
        !cli_check_outputs(&args->failing_rays_path, 1, inputs, args->rays_from_path ? 2 : 1, &err))
        return cli_fail(&err);
    rtt_ray *file_rays = NULL;
    if (args->rays_from_path) {
        size_t size = 0;
        if (!(file_rays = cli_read_file(args->rays_from_path, &size, &err))) return cli_fail(&err);
        if (size % sizeof(rtt_ray) != 0 || size == 0) {
            free(file_rays);
            rtt_error_set(&err, "%s: size %zu is not a positive multiple of 32 bytes (rtt_ray records)",
                          args->rays_from_path, size);
            return cli_fail(&err);
        }
        args->config.file_rays = file_rays;
        args->config.file_ray_count = size / sizeof(rtt_ray);
    }
    rtt_scene *scene = cli_load_scene(args->scene_path, 0, args->max_memory, &err);
    rc = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (rc != CLI_CONTINUE) {
        rtt_scene_free(scene);
        free(file_rays);
        return rc;
    }
    rtt_conform_report report;
    cli_progress *progress = cli_progress_start("conform");
    bool ran = rtt_conform_run(scene, &args->config, &report, &err);
    cli_progress_finish(progress);
    rtt_scene_free(scene);
    free(file_rays);
    if (!ran) return cli_fail(&err);
    if (args->failing_rays_path &&
        !cli_write_file_atomic(args->failing_rays_path, report.failing_rays,
                               report.failing_ray_count * sizeof *report.failing_rays, &err)) {
        rtt_conform_report_free(&report);
        return cli_fail(&err);
    }
    int rc_print = print_and_free(args->json ? rtt_conform_report_json(&report) : rtt_conform_report_table(&report));
    bool pass = report.pass;
    rtt_conform_report_free(&report);
    return rc_print != RTT_EXIT_OK ? rc_print : pass ? RTT_EXIT_OK : RTT_EXIT_BAD_INPUT;
}

const cli_command conform_command = {
    .name = "conform", .summary = "hit-by-hit agreement of the engines", .run = conform,
    CLI_ARGS(conform_args, conform_defaults), CLI_ROWS(conform_options),
    .engine_offset = offsetof(conform_args, engine),
    .synopsis = "SCENE [options]\n--extremes [options]",
    .description =
        "Traces the same rays through each engine and compares every hit with the\n"
        "reference's: agree, tie (a neighbour hit at the same point: both triangles'\n"
        "planes crossed at the same t), boundary (a hit within tolerance of tnear or\n"
        "tfar), t-mismatch, and hit/miss disagreements split into grazing (the hit lies\n"
        "on an edge, or one engine slipped past an edge to a farther hit) and other.\n"
        "Every disagreement is decided by a double-precision brute force over all\n"
        "triangles (the referee, the watertight test in double): a row counts only its\n"
        "own errors, and rays where Embree is wrong and rtt right are counted apart as\n"
        "embree wrong (on the embree row the reference is the rtt side judged).  Rays\n"
        "outside Embree's range are not handed to it: unspecified.  A row fails when its\n"
        "errors hold a t-mismatch, a non-grazing hit/miss or an occluded() disagreement,\n"
        "or more grazing hit/miss than 0.05% (optimized) or 1% (embree) of the primary,\n"
        "shadow, random and --rays-from rays; the report names its first failing rays\n"
        "(origin, direction, tnear, tfar, each engine's and the referee's prim and t).\n"
        "On the extreme set, and in the --extremes checks that aim at vertices and edges\n"
        "or run along planes, grazing hit/miss is reported, not bounded (the rays graze\n"
        "by design); watertightness is checked apart.  Rules: conformance/README.md.\n",
    .operand = "SCENE", .operand_min = 0, .operand_max = 1, .operand_offset = offsetof(conform_args, scene_path),
    .exit_status = "0 conformant, 1 a threshold exceeded or bad input, 2 bad usage.",
};

/* rtt bench: the papers' tables on one scene, raced against Embree on the
 * same rays.  The work is in bench/; this file parses options, prints the
 * report and writes the optional Markdown and TSV files. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "camera_options.h"
#include "cli.h"
#include "rtt/atomic_file.h"
#include "options.h"
#include "progress.h"

typedef struct bench_args {
    const char *scene_path, *views, *markdown, *tsv;
    bool json, progress, no_embree;
    uint32_t size, height, kinds; /* kinds: bit k for kind_names[k] */
    rtt_bench_config config;
    rtt_engine_options engine; /* the optimized engine's options the bench takes */
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
    cli_camera_args camera;
} bench_args;

/* A comma-separated list of up to `most` whole numbers in [lo, hi] into out[0 .. *count). */
static bool parse_u32_list(const char *text, uint32_t *out, uint32_t *count, uint32_t most, uint32_t lo, uint32_t hi,
                           rtt_error *why)
{
    char buffer[64];
    bool valid = strlen(text) < sizeof buffer;
    if (valid) strcpy(buffer, text);
    *count = 0;
    for (char *save = NULL, *item = valid ? strtok_r(buffer, ",", &save) : NULL; item && valid;
         item = strtok_r(NULL, ",", &save)) {
        valid = *count < most && cli_parse_u32(item, lo, hi, &out[*count]);
        (*count)++;
    }
    return valid && *count > 0
               ? true
               : rtt_error_set(why, "expected up to %u whole numbers from %u to %u, comma-separated", most, lo, hi);
}

static bool parse_threads(const char *text, void *field, rtt_error *why)
{
    rtt_bench_config *config = field;
    return parse_u32_list(text, config->threads, &config->thread_count, RTT_BENCH_MAX_THREADS, 1, 1024, why);
}

static bool parse_light_res(const char *text, void *field, rtt_error *why)
{
    rtt_bench_config *config = field;
    return parse_u32_list(text, config->pgrid_light_res, &config->pgrid_light_res_count, RTT_BENCH_MAX_LIGHT_RES, 1,
                          RTT_BENCH_LIGHT_RES_MOST, why);
}

/* --only's names, in rtt_bench_kind order */
static const char *const kind_names[RTT_BENCH_KIND_COUNT + 1] = {"primary", "shadow", "render", "build", "soft",
                                                                    NULL};

static const cli_option bench_options[] = {
    {.name = "--json", .help = "the report as JSON on stdout (default: a text table)",
     .kind = CLI_FLAG, CLI_FIELD(bench_args, json)},
    {.name = "--size", .value_name = "N",
     .help = "render N x N, 8 to 16384 (the benchmarks use 512 and 1024; default: the scene's)",
     .kind = CLI_U32, CLI_FIELD(bench_args, size), .lo = 8, .hi = 16384},
    {.name = "--height", .value_name = "N", .help = "with --size: render SIZE x N instead (1920 x 1200: Hunt & Mark's)",
     .kind = CLI_U32, CLI_FIELD(bench_args, height), .lo = 8, .hi = 16384},
    {.name = "--accel", .value_name = "NAME",
     .help = "only our rows of this acceleration structure (default: every one's):", .kind = CLI_CUSTOM,
     CLI_FIELD(bench_args, config.accel), .parse = cli_parse_accel, .help_more = cli_help_accels},
    {.name = "--pgrid-cell", .value_name = "N",
     .help = "the perspective grid's cell side in pixels, a multiple of 4 from 4 to 512 (default: 256 when the image has 4 such cells a thread and a cell's depth and triangle buffers fit in a quarter of the L2, or in half of it when 256 cuts the triangles' references to 4/5, else 128)",
     .kind = CLI_U32, CLI_FIELD(bench_args, config.pgrid_cell), .lo = 4, .hi = 512},
    {.name = "--pgrid-light-res", .value_name = "LIST",
     .help = "the pgrid shadow rows' light grid: N x N cells per face, 1 to 2048, a row pair per N (default: by the scene's triangle count)",
     .kind = CLI_CUSTOM, CLI_FIELD(bench_args, config), .parse = parse_light_res},
    {.name = "--frames", .value_name = "N", .help = "timed frames per row, 1 to 64, median reported (default 5)",
     .kind = CLI_U32, CLI_FIELD(bench_args, config.frames), .lo = 1, .hi = 64},
    {.name = "--warmup", .value_name = "N", .help = "untimed frames before them, 0 to 64 (default 1)",
     .kind = CLI_U32, CLI_FIELD(bench_args, config.warmup), .lo = 0, .hi = 64},
    CLI_OPTION_MAX_DEPTH(bench_args, engine),
    CLI_OPTION_ISA(bench_args, engine),
    CLI_OPTION_ISECT(bench_args, engine),
    {.name = "--threads", .value_name = "LIST", .help = "thread counts, each row runs at each (default 1,2)",
     .kind = CLI_CUSTOM, CLI_FIELD(bench_args, config), .parse = parse_threads},
    {.name = "--quick",
     .help = "one frame, no warm-up, tile 8 only, one Embree variant, one thread unless --threads is given "
             "(a smoke run)",
     .kind = CLI_FLAG, CLI_FIELD(bench_args, config.quick)},
    {.name = "--views", .value_name = "FILE",
     .help = "the same as --view FILE: the view named after the scene file (bench/views.json)",
     .kind = CLI_STRING, CLI_FIELD(bench_args, views)},
    CLI_OPTIONS_CAMERA(bench_args, camera),
    {.name = "--only", .value_name = "KINDS", .help = "comma list of primary, shadow, render, build, soft (default all)",
     .kind = CLI_CHOICE_LIST, CLI_FIELD(bench_args, kinds), .choices = kind_names},
    {.name = "--no-embree", .help = "do not race Embree", .kind = CLI_FLAG, CLI_FIELD(bench_args, no_embree)},
    {.name = "--markdown", .value_name = "FILE", .help = "also write the thesis' tables as Markdown",
     .kind = CLI_STRING, CLI_FIELD(bench_args, markdown)},
    {.name = "--tsv", .value_name = "FILE", .help = "also write one line per row for plotting",
     .kind = CLI_STRING, CLI_FIELD(bench_args, tsv)},
    {.name = "--images", .value_name = "DIR", .help = "write each full render as DIR/<method>_<shadows>_t<threads>.exr",
     .kind = CLI_STRING, CLI_FIELD(bench_args, config.image_dir)},
    {.name = "--compare-isects",
     .help = "time every kernel row with the watertight and with the projected triangle test, one after the "
             "other in this run (the test's column says which)",
     .kind = CLI_FLAG, CLI_FIELD(bench_args, config.compare_isects)},
    {.name = "--progress", .help = "name each row on stderr as it starts", .kind = CLI_FLAG,
     CLI_FIELD(bench_args, progress)},
    CLI_OPTION_MAX_MEMORY(bench_args, max_memory),
};

/* What --quick, --only and the scene file make meaningless. */
static int check_applicable(const cli_parsed *parsed, bench_args *a)
{
    if (a->views && a->camera.view) return cli_refuse(parsed, "--views", "does not go with --view");
    if (a->config.compare_isects && cli_given(parsed, "--isect"))
        return cli_refuse(parsed, "--compare-isects", "times both triangle tests: give no --isect");
    if (cli_given(parsed, "--height") && !cli_given(parsed, "--size"))
        return cli_refuse(parsed, "--height", "needs --size N");
    if (a->config.pgrid_cell % 4u) return cli_refuse(parsed, "--pgrid-cell", "must be a multiple of 4");
    if (a->config.quick && cli_given(parsed, "--frames"))
        return cli_refuse(parsed, "--frames", "--quick times one frame per row");
    if (a->config.quick && cli_given(parsed, "--warmup"))
        return cli_refuse(parsed, "--warmup", "--quick warms up none");
    if (a->config.image_dir && !a->config.kinds[RTT_BENCH_RENDER])
        return cli_refuse(parsed, "--images", "--only leaves out the render rows, the only ones with images");
    /* the bench measures the optimized engine's kernels and renders */
    int rc = cli_check_engine_options(parsed, "optimized", &a->engine);
    if (rc == CLI_CONTINUE) rc = cli_check_scene_options(parsed, a->scene_path, "optimized");
    if (a->views) a->camera.view = a->views;
    return rc != CLI_CONTINUE ? rc : cli_camera_check(parsed, &a->camera, a->scene_path);
}

static void bench_defaults(void *opaque)
{
    bench_args *a = opaque;
    rtt_bench_config_default(&a->config);
    rtt_engine_options_default(&a->engine);
}

/* The parsed options into the bench's config; CLI_CONTINUE when they apply. */
static int configure(bench_args *a, const cli_parsed *parsed)
{
    for (int k = 0; k < RTT_BENCH_KIND_COUNT && cli_given(parsed, "--only"); k++)
        a->config.kinds[k] = (a->kinds >> k) & 1u;
    int rc = check_applicable(parsed, a);
    if (rc != CLI_CONTINUE) return rc;
    if (a->no_embree) a->config.embree = false;
    if (a->config.quick && !cli_given(parsed, "--threads")) {
        a->config.threads[0] = 1;
        a->config.thread_count = 1;
    }
    a->config.width = a->config.height = a->size;
    if (a->height) a->config.height = a->height;
    a->config.max_tree_depth = a->engine.max_tree_depth;
    a->config.isa = a->engine.isa;
    a->config.isect = a->engine.isect;
    return CLI_CONTINUE;
}

/* --progress names each row as it starts; the stage's progress lines (past
 * 2 s) show the row running. */
typedef struct bench_progress {
    cli_progress *stage;
    bool rows;
} bench_progress;

static void print_progress(void *context, const char *row)
{
    bench_progress *p = context;
    if (p->rows) fprintf(stderr, "bench: %s\n", row);
    cli_progress_detail(p->stage, row);
}

static bool write_text(const char *path, char *text, rtt_error *err)
{
    if (!text) return rtt_error_set(err, "%s: out of memory formatting the report", path);
    bool ok = cli_write_file_atomic(path, text, strlen(text), err);
    free(text);
    return ok;
}

static int bench(void *opaque, const cli_parsed *parsed)
{
    bench_args *args = opaque;
    int status = configure(args, parsed);
    if (status != CLI_CONTINUE) return status;

    rtt_error err = {{0}};
    const char *outputs[] = {args->markdown, args->tsv}, *inputs[] = {args->scene_path, args->views};
    const bool writable = cli_check_outputs(outputs, 2, inputs, 2, &err) &&
                          (!args->config.image_dir || cli_check_directory(args->config.image_dir, "--images", &err));
    rtt_scene *scene = writable ? cli_load_scene(args->scene_path, 0, args->max_memory, &err) : NULL;
    char view[64] = "";
    /* the view's camera, light and size as the benchmarks define them, then
     * whatever the camera options change */
    if (scene && args->camera.chosen && !rtt_bench_apply_view(scene, args->camera.chosen, &err)) {
        rtt_scene_free(scene);
        scene = NULL;
    }
    if (args->camera.chosen) snprintf(view, sizeof view, "%s", args->camera.chosen->name);
    status = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (status != CLI_CONTINUE) {
        rtt_scene_free(scene);
        return status;
    }
    rtt_bench_report report;
    bench_progress progress = {cli_progress_start("bench"), args->progress};
    args->config.progress = print_progress;
    args->config.progress_context = &progress;
    bool ok = rtt_bench_run(scene, &args->config, &report, &err);
    cli_progress_finish(progress.stage);
    rtt_scene_free(scene);
    if (!ok) return cli_fail(&err);
    snprintf(report.view, sizeof report.view, "%s", view);
    rtt_atomic_files_hold(); /* the reports: both or neither */
    if (args->markdown) ok = write_text(args->markdown, rtt_bench_report_markdown(&report), &err);
    if (ok && args->tsv) ok = write_text(args->tsv, rtt_bench_report_tsv(&report), &err);
    ok = rtt_atomic_files_release(ok, &err) && ok;
    char *text = ok ? (args->json ? rtt_bench_report_json(&report) : rtt_bench_report_table(&report)) : NULL;
    if (ok && !text) ok = rtt_error_set(&err, "rtt bench: out of memory formatting the report");
    if (text) {
        fputs(text, stdout);
        if (text[0] && text[strlen(text) - 1] != '\n') fputc('\n', stdout);
        free(text);
    }
    rtt_bench_report_free(&report);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command bench_command = {
    .name = "bench", .summary = "the papers' tables on a scene, raced against Embree", .run = bench,
    CLI_ARGS(bench_args, bench_defaults), CLI_ROWS(bench_options), CLI_SCENE_OPERAND(bench_args),
    .engine_offset = offsetof(bench_args, engine),
    .synopsis = "SCENE [options]",
    .description =
        "Measures the thesis' tables on SCENE (scene .json, mesh, Quake III .bsp or .kdt):\n"
        "  primary  the traversal kernels alone on the camera's primary rays: mono, 2x2\n"
        "           packets, omni, frustum at tiles 4/8/16/32 with leaf culling on and off,\n"
        "           MFT, cone and MFT cone at the same tiles (Tables 4.1 - 4.5); Embree's\n"
        "           rtcIntersect1/4/8/16 on the very same rays, native ISA and SSE4.2,\n"
        "           robust and default scene flags; the BVH kernels (bvh-mono, the\n"
        "           16/8/4-wide bvh-packet) on the same rays in 4x4 pixel blocks\n"
        "  shadow   hard-shadow rays through our occlusion kernels (kd-tree, BVH and\n"
        "           the pgrid shadow method's light grid, built every frame) and\n"
        "           rtcOccluded1/16\n"
        "  render   full frames per traversal, and per shadow method (none, hard,\n"
        "           multi:4/16/32, cone:16, pyramid:16, edgewidth; methods the renderer\n"
        "           refuses are listed as skipped) (Tables 4.6, 5.1, 6.2)\n"
        "  build    kd-tree build (one thread) and BVH build (median of the frames'\n"
        "           builds at each --threads count) time and memory against Embree's\n"
        "           BVH (high quality, one thread)\n"
        "Each row: frames/s (median of the timed frames after warm-up), rays/s, N and\n"
        "I per 2x2 packet, the ratio to Embree's best coherent variant at the same\n"
        "thread count, and the share of rays whose hit agrees with Embree's.\n",
};

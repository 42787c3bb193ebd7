/* rtt bench: the papers' tables on one scene, raced against Embree on the
 * same rays.  The work is in bench/; this file parses options, prints the
 * report and writes the optional Markdown and TSV files. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "cli.h"

static const char bench_help[] =
    "usage: rtt bench SCENE [--json] [--size N] [--frames N] [--threads N[,N..]] [--quick]\n"
    "                 [--views FILE [--view NAME]] [--only KINDS] [--no-embree] [--max-depth N]\n"
    "                 [--markdown FILE] [--tsv FILE] [--images DIR] [--progress]\n"
    "\n"
    "Measures the thesis' tables on SCENE (scene .json, mesh, Quake III .bsp or .kdt):\n"
    "  primary  the traversal kernels alone on the camera's primary rays: mono, 2x2\n"
    "           packets, omni, frustum at tiles 4/8/16/32 with leaf culling on and off,\n"
    "           MFT, cone and MFT cone at the same tiles (Tables 4.1 - 4.5); Embree's\n"
    "           rtcIntersect1/4/8/16 on the very same rays, native ISA and SSE4.2,\n"
    "           robust and default scene flags\n"
    "  shadow   hard-shadow rays through our occlusion kernels and rtcOccluded1/16\n"
    "  render   full frames per traversal, and per shadow method (none, hard,\n"
    "           multi:4/16/32, cone:16, pyramid:16, edgewidth; methods the renderer\n"
    "           refuses are listed as skipped) (Tables 4.6, 5.1, 6.2)\n"
    "  build    kd-tree build time and memory (one thread) against Embree's BVH\n"
    "Each row: frames/s (median of the timed frames after warm-up), rays/s, N and\n"
    "I per 2x2 packet, the ratio to Embree's best coherent variant at the same\n"
    "thread count, and the share of rays whose hit agrees with Embree's.\n"
    "\n"
    "  --json            the report as JSON on stdout (default: a text table)\n"
    "  --size N          render N x N (the benchmarks use 512 and 1024; default: the scene's)\n"
    "  --frames N        timed frames per row, median reported (default 5)\n"
    "  --warmup N        untimed frames before them (default 1)\n"
    "  --max-depth N     the kd-tree's depth bound, 1 to 64 (default round(2 + log2 N), at least 8)\n"
    "  --threads LIST    thread counts, each row runs at each (default 1,2)\n"
    "  --quick           one frame, no warm-up, tile 8 only, one Embree variant, one\n"
    "                    thread unless --threads is given (a smoke run)\n"
    "  --views FILE      apply a camera and light from FILE (bench/views.json); the\n"
    "  --view NAME       entry is NAME, default the scene file's base name\n"
    "  --only KINDS      comma list of primary, shadow, render, build (default all)\n"
    "  --no-embree       do not race Embree\n"
    "  --markdown FILE   also write the thesis' tables as Markdown\n"
    "  --tsv FILE        also write one line per row for plotting\n"
    "  --images DIR      write each full render as DIR/<method>_<shadows>_t<threads>.exr\n"
    "  --progress        name each row on stderr as it starts\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

typedef struct bench_args {
    const char *scene_path, *views, *view, *markdown, *tsv;
    bool json, progress, threads_given;
    uint32_t size;
    rtt_bench_config config;
} bench_args;

static bool parse_threads(const char *text, rtt_bench_config *config)
{
    char buffer[64];
    if (strlen(text) >= sizeof buffer) return false;
    strcpy(buffer, text);
    config->thread_count = 0;
    for (char *save = NULL, *item = strtok_r(buffer, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        if (config->thread_count == RTT_BENCH_MAX_THREADS) return false;
        if (!cli_parse_u32(item, 1, 1024, &config->threads[config->thread_count])) return false;
        config->thread_count++;
    }
    return config->thread_count > 0;
}

static bool parse_kinds(const char *text, rtt_bench_config *config)
{
    static const char *const names[RTT_BENCH_KIND_COUNT] = {"primary", "shadow", "render", "build"};
    char buffer[64];
    if (strlen(text) >= sizeof buffer) return false;
    strcpy(buffer, text);
    for (int k = 0; k < RTT_BENCH_KIND_COUNT; k++) config->kinds[k] = false;
    int named = 0;
    for (char *save = NULL, *item = strtok_r(buffer, ",", &save); item; item = strtok_r(NULL, ",", &save), named++) {
        int found = -1;
        for (int k = 0; k < RTT_BENCH_KIND_COUNT; k++)
            if (strcmp(item, names[k]) == 0) found = k;
        if (found < 0) return false;
        config->kinds[found] = true;
    }
    return named > 0;
}

/* Returns -1 when the arguments are fine, else the exit code. */
static int parse_args(int argc, char **argv, bench_args *a)
{
    memset(a, 0, sizeof *a);
    rtt_bench_config_default(&a->config);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (cli_is_help(arg)) {
            fputs(bench_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(arg, "--json") == 0) a->json = true;
        else if (strcmp(arg, "--quick") == 0) a->config.quick = true;
        else if (strcmp(arg, "--no-embree") == 0) a->config.embree = false;
        else if (strcmp(arg, "--progress") == 0) a->progress = true;
        else if (arg[0] != '-' || arg[1] == '\0') {
            if (a->scene_path) return cli_usage_error("bench", "more than one SCENE given (\"%s\")", arg);
            a->scene_path = arg;
        } else if (i + 1 >= argc) {
            return cli_usage_error("bench", "%s needs a value", arg);
        } else {
            const char *value = argv[++i];
            if (strcmp(arg, "--size") == 0) {
                if (!cli_parse_u32(value, 8, 16384, &a->size))
                    return cli_usage_error("bench", "--size %s: expected a whole number from 8 to 16384 (512 or 1024)",
                                           value);
            } else if (strcmp(arg, "--frames") == 0) {
                if (!cli_parse_u32(value, 1, 64, &a->config.frames))
                    return cli_usage_error("bench", "--frames %s: expected a whole number from 1 to 64", value);
            } else if (strcmp(arg, "--max-depth") == 0) {
                if (!cli_parse_u32(value, 1, 64, &a->config.max_tree_depth))
                    return cli_usage_error("bench", "--max-depth %s: expected a whole number from 1 to 64", value);
            } else if (strcmp(arg, "--warmup") == 0) {
                if (!cli_parse_u32(value, 0, 64, &a->config.warmup))
                    return cli_usage_error("bench", "--warmup %s: expected a whole number from 0 to 64", value);
            } else if (strcmp(arg, "--threads") == 0) {
                if (!parse_threads(value, &a->config))
                    return cli_usage_error("bench", "--threads %s: expected up to %u whole numbers from 1 to 1024, "
                                           "comma-separated", value, RTT_BENCH_MAX_THREADS);
                a->threads_given = true;
            } else if (strcmp(arg, "--only") == 0) {
                if (!parse_kinds(value, &a->config))
                    return cli_usage_error("bench", "--only %s: expected a comma list of primary, shadow, render, build",
                                           value);
            } else if (strcmp(arg, "--views") == 0) {
                a->views = value;
            } else if (strcmp(arg, "--view") == 0) {
                a->view = value;
            } else if (strcmp(arg, "--markdown") == 0) {
                a->markdown = value;
            } else if (strcmp(arg, "--tsv") == 0) {
                a->tsv = value;
            } else if (strcmp(arg, "--images") == 0) {
                a->config.image_dir = value;
            } else {
                return cli_usage_error("bench", "unknown option \"%s\"", arg);
            }
        }
    }
    if (!a->scene_path) return cli_usage_error("bench", "no SCENE given");
    if (a->view && !a->views) return cli_usage_error("bench", "--view needs --views FILE");
    if (a->config.quick && !a->threads_given) {
        a->config.threads[0] = 1;
        a->config.thread_count = 1;
    }
    a->config.width = a->config.height = a->size;
    return -1;
}

static void print_progress(void *context, const char *row)
{
    (void)context;
    fprintf(stderr, "bench: %s\n", row);
}

static bool write_text(const char *path, char *text, rtt_error *err)
{
    if (!text) return rtt_error_set(err, "%s: out of memory formatting the report", path);
    bool ok = cli_write_file_atomic(path, text, strlen(text), err);
    free(text);
    return ok;
}

int cmd_bench(int argc, char **argv)
{
    bench_args args;
    int status = parse_args(argc, argv, &args);
    if (status >= 0) return status;
    if (args.progress) args.config.progress = print_progress;

    rtt_error err = {{0}};
    rtt_scene *scene = cli_load_scene(args.scene_path, 0, &err);
    if (!scene) return cli_fail(&err);
    char view[64] = "";
    if (args.views && !rtt_bench_apply_view(scene, args.views, args.view, view, &err)) {
        rtt_scene_free(scene);
        return cli_fail(&err);
    }
    rtt_bench_report report;
    bool ok = rtt_bench_run(scene, &args.config, &report, &err);
    rtt_scene_free(scene);
    if (!ok) return cli_fail(&err);
    snprintf(report.view, sizeof report.view, "%s", view);
    if (args.markdown) ok = write_text(args.markdown, rtt_bench_report_markdown(&report), &err);
    if (ok && args.tsv) ok = write_text(args.tsv, rtt_bench_report_tsv(&report), &err);
    char *text = ok ? (args.json ? rtt_bench_report_json(&report) : rtt_bench_report_table(&report)) : NULL;
    if (ok && !text) ok = rtt_error_set(&err, "rtt bench: out of memory formatting the report");
    if (text) {
        fputs(text, stdout);
        if (text[0] && text[strlen(text) - 1] != '\n') fputc('\n', stdout);
        free(text);
    }
    rtt_bench_report_free(&report);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

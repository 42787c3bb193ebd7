/* rtt conform: hit-by-hit agreement of the engines on one scene, or the
 * numerical-extremes suite (--extremes).  The work is in conformance/;
 * this file parses options, prints the report and picks the exit code. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "conform.h"
#include "extremes.h"

static const char conform_help[] =
    "usage: rtt conform SCENE [--rays primary|shadow|random|extreme|all] [--engines E,E,..]\n"
    "                         [--max-rays N] [--seed N] [--json]\n"
    "       rtt conform --extremes [--engines E,E,..] [--meshes DIR] [--max-rays N] [--json]\n"
    "\n"
    "Traces the same rays through each engine and compares every hit with the\n"
    "reference's: agree, tie (a neighbour hit at the same point: both triangles'\n"
    "planes crossed at the same t), boundary (a hit within tolerance of tnear or\n"
    "tfar), t-mismatch, and hit/miss disagreements split into grazing (the hit lies\n"
    "on an edge, or one engine slipped past an edge to a farther hit) and other.\n"
    "Fails when any engine has a t-mismatch, a non-grazing hit/miss or an occluded()\n"
    "disagreement, or more grazing hit/miss than 0.05% (optimized) or 1% (embree) of\n"
    "the primary, shadow and random rays.  On the extreme set, and in the --extremes\n"
    "checks that aim at vertices and edges or run along planes, grazing hit/miss is\n"
    "reported, not bounded (the rays graze by design); watertightness is checked\n"
    "apart.  Rules: conformance/README.md.\n"
    "\n"
    "  --rays SET       primary, shadow, random, extreme, a comma list, or all (default)\n"
    "  --engines LIST   optimized (every traversal mode, tile 8), optimized/MODE,\n"
    "                   embree, reference (default: optimized,embree)\n"
    "  --max-rays N     rays per set (default 65536; primary renders smaller to fit)\n"
    "  --seed N         seed of the random and extreme sets\n"
    "  --json           the report as JSON on stdout\n"
    "  --extremes       scaled and translated scenes, degenerate triangles, a deep tree,\n"
    "                   NaN/Inf input, watertightness from inside closed meshes\n"
    "  --meshes DIR     benchmark meshes for watertightness (default\n"
    "                   ${RTT_DATA_DIR:-~/.cache/rtt-data}/meshes; skipped when absent)\n"
    "\n"
    "Exit status: 0 conformant, 1 a threshold exceeded or bad input, 2 bad usage.\n";

static bool parse_sets(const char *text, bool sets[RTT_CONFORM_RAY_SET_COUNT])
{
    char buffer[128];
    if (strlen(text) >= sizeof buffer) return false;
    strcpy(buffer, text);
    for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++) sets[i] = false;
    char *save = NULL;
    int named = 0;
    for (char *item = strtok_r(buffer, ",", &save); item; item = strtok_r(NULL, ",", &save), named++) {
        if (strcmp(item, "all") == 0) {
            for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++) sets[i] = true;
            continue;
        }
        int s = rtt_conform_ray_set_parse(item);
        if (s < 0) return false;
        sets[s] = true;
    }
    return named > 0;
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

static int run_extremes(const char *engines, const char *meshes, size_t max_rays, bool json)
{
    rtt_extremes_config config;
    rtt_extremes_config_default(&config);
    if (engines) config.engines = engines;
    if (meshes) config.mesh_dir = meshes;
    if (max_rays) config.max_rays = max_rays;
    rtt_extremes_report report;
    rtt_error err = {{0}};
    if (!rtt_extremes_run(&config, &report, &err)) return cli_fail(&err);
    int rc = print_and_free(json ? rtt_extremes_report_json(&report) : rtt_extremes_report_table(&report));
    bool pass = report.pass;
    rtt_extremes_report_free(&report);
    return rc != RTT_EXIT_OK ? rc : pass ? RTT_EXIT_OK : RTT_EXIT_BAD_INPUT;
}

int cmd_conform(int argc, char **argv)
{
    rtt_conform_config config;
    rtt_conform_config_default(&config);
    const char *scene_path = NULL, *meshes = NULL;
    bool json = false, extremes = false;
    uint32_t max_rays = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (cli_is_help(arg)) {
            fputs(conform_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(arg, "--json") == 0) {
            json = true;
            continue;
        }
        if (strcmp(arg, "--extremes") == 0) {
            extremes = true;
            continue;
        }
        if (arg[0] != '-' || arg[1] == '\0') {
            if (scene_path) return cli_usage_error("conform", "more than one SCENE given");
            scene_path = arg;
            continue;
        }
        if (i + 1 >= argc) return cli_usage_error("conform", "%s needs a value", arg);
        const char *value = argv[++i];
        if (strcmp(arg, "--rays") == 0) {
            if (!parse_sets(value, config.sets))
                return cli_usage_error("conform", "--rays %s: expected primary, shadow, random, extreme or all", value);
        } else if (strcmp(arg, "--engines") == 0) {
            rtt_error err = {{0}};
            if (!rtt_conform_engines_valid(value, &err)) return cli_usage_error("conform", "%s", err.message);
            config.engines = value;
        } else if (strcmp(arg, "--max-rays") == 0) {
            if (!cli_parse_u32(value, 16, 100000000u, &max_rays))
                return cli_usage_error("conform", "--max-rays %s: expected a whole number from 16 to 100000000", value);
            config.max_rays = max_rays;
        } else if (strcmp(arg, "--seed") == 0) {
            uint32_t seed;
            if (!cli_parse_u32(value, 0, UINT32_MAX, &seed))
                return cli_usage_error("conform", "--seed %s: expected a whole number", value);
            config.seed = seed;
        } else if (strcmp(arg, "--meshes") == 0) {
            meshes = value;
        } else {
            return cli_usage_error("conform", "unknown option %s", arg);
        }
    }
    if (extremes) {
        if (scene_path) return cli_usage_error("conform", "--extremes builds its own scenes: give no SCENE");
        return run_extremes(config.engines, meshes, max_rays, json);
    }
    if (!scene_path) return cli_usage_error("conform", "no SCENE given");

    rtt_error err = {{0}};
    rtt_scene *scene = cli_load_scene(scene_path, 0, &err);
    if (!scene) return cli_fail(&err);
    rtt_conform_report report;
    bool ran = rtt_conform_run(scene, &config, &report, &err);
    rtt_scene_free(scene);
    if (!ran) return cli_fail(&err);
    int rc = print_and_free(json ? rtt_conform_report_json(&report) : rtt_conform_report_table(&report));
    bool pass = report.pass;
    rtt_conform_report_free(&report);
    return rc != RTT_EXIT_OK ? rc : pass ? RTT_EXIT_OK : RTT_EXIT_BAD_INPUT;
}

/* rtt render: load a scene, render it with the chosen engine, write images. */
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"

#define MAX_OUTPUTS 4

static const char render_help[] =
    "usage: rtt render SCENE [-o out.exr|out.png]... [options]\n"
    "\n"
    "Renders SCENE (scene .json, mesh file, Quake III .bsp or baked .kdt).\n"
    "\n"
    "  -o FILE               output image, .exr (float, with AOVs) or .png (sRGB);\n"
    "                        may be given more than once (default render.png)\n"
    "  --engine E            optimized (default), reference, or embree (the\n"
    "                        reference renderer tracing through Embree)\n"
    "  --traversal T         optimized kernel: mono, packet, omni, frustum, mft\n"
    "                        (default), cone, mft-cone\n"
    "  --tile N              frustum tile side: 4, 8 (default), 16, 32\n"
    "  --leaf-culling on|off packet/leaf culling (default on)\n"
    "  --shadows S           none, hard (default), multi:N, cone:N, pyramid:N,\n"
    "                        edgewidth[:R]   (N = 1..256 samples)\n"
    "  --edge-leak-fix       edgewidth: entry and exit polygons must share a vertex\n"
    "  --threads N           worker threads (default: one per core)\n"
    "  --width W --height H  image size (default: the scene's)\n"
    "  --max-bounces N       reflection/refraction depth (default: the scene's)\n"
    "  --max-depth N         kd-tree depth bound, 1 to 64 (reference and optimized;\n"
    "                        default round(2 + log2 N), at least 8)\n"
    "  --bezier-level N      Quake III patch tessellation (default 4)\n"
    "  --aov LIST            extra EXR channels: depth,prim,normal\n"
    "  --stats               print rays, N and I per 2x2 packet, stage times\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

typedef struct {
    const char *scene_path;
    const char *outputs[MAX_OUTPUTS];
    int output_count;
    const char *engine;
    uint32_t bezier_level;
    rtt_render_options render;
} render_args;

static bool has_image_extension(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && (strcasecmp(dot, ".exr") == 0 || strcasecmp(dot, ".png") == 0);
}

static bool parse_aovs(const char *list, uint32_t *aovs)
{
    char buffer[128];
    if (strlen(list) >= sizeof buffer) return false;
    strcpy(buffer, list);
    *aovs = 0;
    for (char *save = NULL, *name = strtok_r(buffer, ",", &save); name; name = strtok_r(NULL, ",", &save)) {
        if (strcmp(name, "depth") == 0) *aovs |= RTT_AOV_DEPTH;
        else if (strcmp(name, "prim") == 0) *aovs |= RTT_AOV_PRIM;
        else if (strcmp(name, "normal") == 0) *aovs |= RTT_AOV_NORMAL;
        else return false;
    }
    return *aovs != 0;
}

static bool takes_a_value(const char *option)
{
    static const char *const valued[] = {"-o", "--engine", "--traversal", "--tile", "--leaf-culling", "--shadows",
                                         "--threads", "--width", "--height", "--max-bounces", "--max-depth", "--bezier-level",
                                         "--aov"};
    for (size_t i = 0; i < sizeof valued / sizeof valued[0]; i++)
        if (strcmp(option, valued[i]) == 0) return true;
    return false;
}

/* Returns -1 when the arguments are fine, else the exit code. */
static int parse_args(int argc, char **argv, render_args *args)
{
    memset(args, 0, sizeof *args);
    args->engine = "optimized";
    rtt_render_options_default(&args->render);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        bool takes_value = true;
        if (cli_is_help(arg)) {
            fputs(render_help, stdout);
            return RTT_EXIT_OK;
        } else if (strcmp(arg, "--stats") == 0) {
            args->render.stats = true;
            takes_value = false;
        } else if (strcmp(arg, "--edge-leak-fix") == 0) {
            args->render.edge_leak_fix = true;
            takes_value = false;
        } else if (arg[0] != '-') {
            if (args->scene_path) return cli_usage_error("render", "more than one SCENE given (\"%s\")", arg);
            args->scene_path = arg;
            takes_value = false;
        } else if (!takes_a_value(arg)) {
            return cli_usage_error("render", "unknown option \"%s\"", arg);
        } else if (!value) {
            return cli_usage_error("render", "%s needs a value", arg);
        } else if (strcmp(arg, "-o") == 0) {
            if (args->output_count == MAX_OUTPUTS) return cli_usage_error("render", "at most %d outputs", MAX_OUTPUTS);
            if (!has_image_extension(value))
                return cli_usage_error("render", "-o %s: unknown image format (use .exr or .png)", value);
            args->outputs[args->output_count++] = value;
        } else if (strcmp(arg, "--engine") == 0) {
            if (strcmp(value, "reference") && strcmp(value, "optimized") && strcmp(value, "embree"))
                return cli_usage_error("render", "--engine %s: expected reference, optimized or embree", value);
            args->engine = value;
        } else if (strcmp(arg, "--traversal") == 0) {
            if (strlen(value) >= sizeof args->render.engine.traversal)
                return cli_usage_error("render", "--traversal %s: no kernel has so long a name", value);
            strcpy(args->render.engine.traversal, value);
            args->render.engine.given |= RTT_OPTION_TRAVERSAL;
        } else if (strcmp(arg, "--tile") == 0) {
            uint32_t tile;
            if (!cli_parse_u32(value, 4, 32, &tile) || (tile != 4 && tile != 8 && tile != 16 && tile != 32))
                return cli_usage_error("render", "--tile %s: expected 4, 8, 16 or 32", value);
            args->render.engine.tile = tile;
        } else if (strcmp(arg, "--leaf-culling") == 0) {
            if (strcmp(value, "on") && strcmp(value, "off"))
                return cli_usage_error("render", "--leaf-culling %s: expected on or off", value);
            args->render.engine.leaf_culling = strcmp(value, "on") == 0;
        } else if (strcmp(arg, "--shadows") == 0) {
            rtt_error err = {0};
            if (!rtt_shadow_method_parse(value, &args->render, &err))
                return cli_usage_error("render", "--shadows %s: %s", value, err.message);
        } else if (strcmp(arg, "--threads") == 0) {
            if (!cli_parse_u32(value, 1, 1024, &args->render.threads))
                return cli_usage_error("render", "--threads %s: expected a whole number from 1 to 1024", value);
        } else if (strcmp(arg, "--width") == 0) {
            if (!cli_parse_u32(value, 1, 16384, &args->render.width))
                return cli_usage_error("render", "--width %s: expected a whole number from 1 to 16384", value);
        } else if (strcmp(arg, "--height") == 0) {
            if (!cli_parse_u32(value, 1, 16384, &args->render.height))
                return cli_usage_error("render", "--height %s: expected a whole number from 1 to 16384", value);
        } else if (strcmp(arg, "--max-bounces") == 0) {
            if (!cli_parse_u32(value, 0, RTT_MAX_BOUNCES, &args->render.max_bounces))
                return cli_usage_error("render", "--max-bounces %s: expected a whole number from 0 to %u", value,
                                       RTT_MAX_BOUNCES);
        } else if (strcmp(arg, "--max-depth") == 0) {
            if (!cli_parse_u32(value, 1, 64, &args->render.engine.max_tree_depth))
                return cli_usage_error("render", "--max-depth %s: expected a whole number from 1 to 64", value);
        } else if (strcmp(arg, "--bezier-level") == 0) {
            if (!cli_parse_u32(value, 1, 64, &args->bezier_level))
                return cli_usage_error("render", "--bezier-level %s: expected a whole number from 1 to 64", value);
        } else if (strcmp(arg, "--aov") == 0) {
            if (!parse_aovs(value, &args->render.aovs))
                return cli_usage_error("render", "--aov %s: expected a list of depth, prim, normal", value);
        } else {
            return cli_usage_error("render", "unknown option \"%s\"", arg);
        }
        if (takes_value) i++;
    }
    if (!args->scene_path) return cli_usage_error("render", "no SCENE given");
    if (args->output_count == 0) args->outputs[args->output_count++] = "render.png";
    rtt_error err = {0};
    if (!rtt_render_options_check(args->engine, &args->render, &err)) return cli_usage_error("render", "%s", err.message);
    return -1;
}

/* Progress on a terminal only: a line rewritten in place on stderr. */
static void print_progress(void *context, uint32_t done, uint32_t total)
{
    (void)context;
    if (total >= 16 && (done % (total / 16) == 0 || done == total))
        fprintf(stderr, "\rrendering: %3u%%%s", (unsigned)(100.0 * done / total), done == total ? "\n" : "");
}

static void print_stats(const rtt_render_stats *s, const char *engine, const render_args *args)
{
    double packets = s->packets ? (double)s->packets : 1.0;
    uint64_t rays = s->primary_rays + s->shadow_rays + s->secondary_rays;
    printf("engine %s, traversal %s, tile %u, leaf culling %s\n", engine,
           args->render.engine.traversal[0] ? args->render.engine.traversal : "default", args->render.engine.tile,
           args->render.engine.leaf_culling ? "on" : "off");
    printf("rays: %llu primary, %llu shadow, %llu secondary; %.3g rays/s\n", (unsigned long long)s->primary_rays,
           (unsigned long long)s->shadow_rays, (unsigned long long)s->secondary_rays,
           s->seconds_total > 0 ? rays / s->seconds_total : 0.0);
    printf("2x2 packets: %llu, N (traversal steps per packet) %.2f, I (intersection tests per packet) %.2f\n",
           (unsigned long long)s->packets, s->traversal_steps / packets, s->intersection_tests / packets);
    printf("time: total %.4f s wall (%.2f fps)\n", s->seconds_total, s->seconds_total > 0 ? 1.0 / s->seconds_total : 0.0);
    /* the stage timers add up CPU time over the threads: their shares are of
     * that sum, not of the wall time */
    const double stages[4] = {s->seconds_primary_traversal, s->seconds_primary_intersection, s->seconds_shading,
                              s->seconds_secondary};
    const char *const names[4] = {"primary traversal   ", "primary intersection", "shading             ",
                                  "secondary           "};
    double sum = stages[0] + stages[1] + stages[2] + stages[3];
    const uint32_t threads = args->render.threads ? args->render.threads : (uint32_t)sysconf(_SC_NPROCESSORS_ONLN);
    printf("stages (CPU seconds over %u thread%s, share of their sum):\n", threads, threads == 1 ? "" : "s");
    for (int i = 0; i < 4; i++) printf("  %s %.4f s  %5.1f%%\n", names[i], stages[i], sum > 0 ? 100 * stages[i] / sum : 0.0);
}

static bool render_with_engine(const rtt_scene *scene, render_args *args, rtt_image *image, rtt_render_stats *stats,
                               rtt_error *err)
{
    rtt_engine *engine = rtt_engine_create(args->engine, scene, &args->render.engine, err);
    if (!engine) return false;
    bool ok = rtt_render(engine, &args->render, image, stats, err);
    rtt_engine_destroy(engine);
    return ok;
}

int cmd_render(int argc, char **argv)
{
    render_args args;
    int status = parse_args(argc, argv, &args);
    if (status >= 0) return status;

    rtt_error err = {0};
    rtt_scene *scene = cli_load_scene(args.scene_path, args.bezier_level, &err);
    if (!scene) return cli_fail(&err);
    uint32_t width = args.render.width ? args.render.width : scene->width;
    uint32_t height = args.render.height ? args.render.height : scene->height;
    args.render.width = width;
    args.render.height = height;
    if (isatty(STDERR_FILENO)) args.render.progress = print_progress;

    rtt_image *image = rtt_image_create(width, height, args.render.aovs, &err);
    rtt_render_stats stats;
    memset(&stats, 0, sizeof stats);
    bool ok = image && render_with_engine(scene, &args, image, &stats, &err);
    for (int i = 0; ok && i < args.output_count; i++) ok = rtt_image_write(image, args.outputs[i], &err);
    if (ok && args.render.stats) print_stats(&stats, args.engine, &args);
    rtt_image_free(image);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

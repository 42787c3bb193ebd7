/* rtt render: load a scene, render it with the chosen engine, write images. */
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "camera_options.h"
#include "cli.h"
#include "options.h"
#include "rtt/atomic_file.h"
#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"

#define MAX_OUTPUTS 4

typedef struct render_args {
    const char *scene_path;
    const char *outputs[MAX_OUTPUTS];
    uint32_t output_count;
    const char *engine;
    uint32_t bezier_level;
    rtt_render_options render;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
    cli_camera_args camera;
} render_args;

static bool has_extension(const char *path, const char *extension)
{
    const char *dot = strrchr(path, '.');
    return dot && strcasecmp(dot, extension) == 0;
}

static bool parse_output(const char *value, void *field, rtt_error *why)
{
    if (!has_extension(value, ".exr") && !has_extension(value, ".png"))
        return rtt_error_set(why, "unknown image format (use .exr or .png)");
    *(const char **)field = value;
    return true;
}

static bool parse_shadows(const char *value, void *field, rtt_error *why)
{
    return rtt_shadow_method_parse(value, field, why);
}

/* --aov's names, bit k of rtt_aov for name k */
static const char *const aov_names[] = {"depth", "prim", "normal", NULL};
_Static_assert(RTT_AOV_DEPTH == 1 << 0 && RTT_AOV_PRIM == 1 << 1 && RTT_AOV_NORMAL == 1 << 2, "aov_names' bits");

/* the help lines below state these bounds */
_Static_assert(RTT_MAX_BOUNCES == 64, "--max-bounces help: 0 to 64");
_Static_assert(RTT_MAX_SHADOW_SAMPLES == 256, "--shadows help: N = 1..256");

static const cli_option render_options[] = {
    {.name = "--output", .short_name = 'o', .value_name = "FILE",
     .help = "output image: .exr (float, with AOVs) or .png (sRGB); up to 4 of them (default render.png)",
     .kind = CLI_CUSTOM, CLI_FIELD(render_args, outputs), .parse = parse_output, .repeat_max = MAX_OUTPUTS,
     .count_offset = offsetof(render_args, output_count)},
    CLI_OPTION_ENGINE(render_args, engine),
    CLI_OPTIONS_KD_ENGINE(render_args, render.engine),
    {.name = "--shadows", .value_name = "METHOD",
     .help = "none, hard (default), multi:N, cone:N, pyramid:N (N = 1..256 samples), edgewidth[:R]",
     .kind = CLI_CUSTOM, CLI_FIELD(render_args, render), .parse = parse_shadows},
    {.name = "--edge-leak-fix", .help = "with --shadows edgewidth: entry and exit polygons must share a vertex",
     .kind = CLI_FLAG, CLI_FIELD(render_args, render.edge_leak_fix)},
    CLI_OPTION_RENDER_THREADS(render_args, render),
    CLI_OPTION_RENDER_SIZE(render_args, render),
    CLI_OPTION_MAX_BOUNCES(render_args, render),
    CLI_OPTION_BEZIER_LEVEL(render_args, bezier_level),
    CLI_OPTIONS_CAMERA(render_args, camera),
    {.name = "--aov", .value_name = "LIST", .help = "extra EXR channels, a comma list of depth, prim, normal",
     .kind = CLI_CHOICE_LIST, CLI_FIELD(render_args, render.aovs), .choices = aov_names},
    {.name = "--stats", .help = "print the engine, kernel and instruction set used, rays, N and I per 2x2 packet, "
                                "stage times",
     .kind = CLI_FLAG, CLI_FIELD(render_args, render.stats)},
    CLI_OPTION_MAX_MEMORY(render_args, max_memory),
};

/* What the parsed options ask that the engine, the scene file or the
 * outputs cannot honour. */
static int check_applicable(const cli_parsed *parsed, render_args *args)
{
    int rc = cli_check_engine_options(parsed, args->engine, &args->render.engine);
    if (rc != CLI_CONTINUE) return rc;
    rtt_error err = {{0}};
    if (!rtt_render_options_check(args->engine, &args->render, &err))
        return cli_refuse(parsed, cli_given(parsed, "--shadows") ? "--shadows" : NULL, "%s", err.message);
    if (args->render.edge_leak_fix && args->render.shadows != RTT_SHADOWS_EDGEWIDTH)
        return cli_refuse(parsed, "--edge-leak-fix", "applies to --shadows edgewidth only (shadows are %s)",
                          rtt_shadow_method_name(args->render.shadows));
    if (args->render.aovs) {
        uint32_t exr = 0;
        for (uint32_t i = 0; i < args->output_count; i++) exr += has_extension(args->outputs[i], ".exr");
        if (exr == 0 && args->output_count > 1)
            return cli_refuse(parsed, "--aov", "no output is EXR and PNG has no AOV channels; add an .exr");
        if (exr == 0)
            return cli_refuse(parsed, "--aov", "PNG output %s%s has no AOV channels; write an .exr", args->outputs[0],
                              cli_given(parsed, "--output") ? "" : " (the default)");
    }
    int rc_scene = cli_check_scene_options(parsed, args->scene_path, args->engine);
    return rc_scene != CLI_CONTINUE ? rc_scene : cli_camera_check(parsed, &args->camera, args->scene_path);
}

static void render_defaults(void *opaque)
{
    render_args *args = opaque;
    args->engine = "optimized";
    rtt_render_options_default(&args->render);
}

/* Progress on a terminal only: a line rewritten in place on stderr. */
static void print_progress(void *context, uint32_t done, uint32_t total)
{
    (void)context;
    if (total >= 16 && (done % (total / 16) == 0 || done == total))
        fprintf(stderr, "\rrendering: %3u%%%s", (unsigned)(100.0 * done / total), done == total ? "\n" : "");
}

/* The first accel the class has kernels for: what "the engine's default"
 * stands for. */
static rtt_accel default_accel(const rtt_engine_class *cls)
{
    for (int a = RTT_ACCEL_DEFAULT + 1; cls->kernel && a < RTT_ACCEL_COUNT; a++)
        if (cls->kernel((rtt_accel)a, 0)) return (rtt_accel)a;
    return RTT_ACCEL_DEFAULT;
}

/* What the render really used, for --stats: the engine, its acceleration
 * structure, its kernel and instruction set, and tile and leaf culling only
 * for an engine that reads them. */
static void describe_engine(rtt_engine *engine, const char *name, const rtt_engine_options *opt, char *out,
                            size_t size)
{
    const rtt_engine_class *cls = rtt_engine_find(name);
    const char *kernel = rtt_engine_kernel_name(engine);
    rtt_tree_info tree;
    size_t used = (size_t)snprintf(out, size, "engine %s", name);
    bool own_tree = !(cls->uses & RTT_OPTION_ACCEL) && rtt_engine_tree_info(engine, &tree);
    if (cls->uses & RTT_OPTION_ACCEL)
        used += (size_t)snprintf(out + used, size - used, ", accel %s",
                                 rtt_accel_name(opt->accel != RTT_ACCEL_DEFAULT ? opt->accel : default_accel(cls)));
    else if (own_tree)
        used += (size_t)snprintf(out + used, size - used, ", accel kd (its own)");
    if (kernel[0]) {
        used += (size_t)snprintf(out + used, size - used, ", kernel %s", kernel);
        const char *isa = strrchr(kernel, '/');
        const char *asked = rtt_isa_name(rtt_isa_resolve(opt->isa));
        if ((opt->given & RTT_OPTION_ISA) && isa && strcmp(isa + 1, asked) != 0)
            used += (size_t)snprintf(out + used, size - used, " (asked for %s: the kernel has no %s build)", asked,
                                     asked);
    } else {
        used += (size_t)snprintf(out + used, size - used, "%s", own_tree || (cls->uses & RTT_OPTION_ACCEL)
                                                                    ? ", no kernel choice"
                                                                    : ", its own acceleration structure and kernels");
    }
    if (cls->uses & RTT_OPTION_TILE)
        used += (size_t)snprintf(out + used, size - used, ", tile %u", opt->tile ? opt->tile : 8u);
    if (cls->uses & RTT_OPTION_LEAF_CULLING)
        snprintf(out + used, size - used, ", leaf culling %s", opt->leaf_culling ? "on" : "off");
}

static void print_stats(const rtt_render_stats *s, const char *engine_used, const render_args *args)
{
    double packets = s->packets ? (double)s->packets : 1.0;
    uint64_t rays = s->primary_rays + s->shadow_rays + s->secondary_rays;
    printf("%s\n", engine_used);
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
                               char *engine_used, size_t engine_used_size, rtt_error *err)
{
    args->render.engine.threads = args->render.threads; /* --threads bounds the build too */
    rtt_engine *engine = rtt_engine_create(args->engine, scene, &args->render.engine, err);
    if (!engine) return false;
    bool ok = rtt_render(engine, &args->render, image, stats, err);
    describe_engine(engine, args->engine, &args->render.engine, engine_used, engine_used_size);
    rtt_engine_destroy(engine);
    return ok;
}

static int render(void *opaque, const cli_parsed *parsed)
{
    render_args *args = opaque;
    if (args->output_count == 0) args->outputs[args->output_count++] = "render.png";
    int status = check_applicable(parsed, args);
    if (status != CLI_CONTINUE) return status;

    rtt_error err = {0};
    const char *inputs[] = {args->scene_path};
    rtt_scene *scene = cli_check_outputs(args->outputs, args->output_count, inputs, 1, &err)
                           ? cli_load_scene(args->scene_path, args->bezier_level, args->max_memory, &err)
                           : NULL;
    status = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (status != CLI_CONTINUE) {
        rtt_scene_free(scene);
        return status;
    }
    uint32_t width = args->render.width ? args->render.width : scene->width;
    uint32_t height = args->render.height ? args->render.height : scene->height;
    args->render.width = width;
    args->render.height = height;
    if (isatty(STDERR_FILENO)) args->render.progress = print_progress;

    rtt_image *image = rtt_image_create(width, height, args->render.aovs, &err);
    rtt_render_stats stats;
    memset(&stats, 0, sizeof stats);
    char engine_used[256] = "";
    bool ok = image && render_with_engine(scene, args, image, &stats, engine_used, sizeof engine_used, &err);
    rtt_atomic_files_hold(); /* all the outputs or none */
    for (uint32_t i = 0; ok && i < args->output_count; i++) ok = rtt_image_write(image, args->outputs[i], &err);
    ok = rtt_atomic_files_release(ok, &err) && ok;
    if (ok && args->render.stats) print_stats(&stats, engine_used, args);
    rtt_image_free(image);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command render_command = {
    .name = "render", .summary = "render a scene to EXR or PNG", .run = render,
    CLI_ARGS(render_args, render_defaults), CLI_ROWS(render_options), CLI_SCENE_OPERAND(render_args),
    .engine_offset = offsetof(render_args, render.engine),
    .synopsis = "SCENE [-o out.exr|out.png]... [options]",
    .description = "Renders SCENE (scene .json, mesh file, Quake III .bsp or baked .kdt).  An option\n"
                   "the chosen engine, scene file or output does not use is refused, not ignored.\n",
    .environment = "RTT_ISA=auto|sse4|avx2|avx512 picks the instruction set when --isa is not\n"
                   "given.\n",
};

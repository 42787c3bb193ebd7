/* rtt render: load a scene, render it with the chosen engine, write images. */
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "camera_options.h"
#include "cli.h"
#include "dist/dist.h"
#include "frame_outputs.h"
#include "options.h"
#include "rtt/atomic_file.h"
#include "progress.h"
#include "rtt/engine.h"
#include "rtt/image.h"
#include "rtt/interleaved.h"
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
    const char *camera_path;         /* --camera-path: a views file */
    uint32_t path_frames;            /* --path-frames: 0, one frame per view */
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
_Static_assert(RTT_MAX_SPP == 256, "--spp help: 1 to 256");
_Static_assert(RTT_INTERLEAVED_MIN_SAMPLES == 4 && RTT_INTERLEAVED_MAX_SAMPLES == 32 &&
                   RTT_INTERLEAVED_DEFAULT_SAMPLES == 16,
               "--shadows help: interleaved N = 4..32, default 16");

static const cli_option render_options[] = {
    {.name = "--output", .short_name = 'o', .value_name = "FILE",
     .help = "output image: .exr (float, with AOVs) or .png (sRGB); up to 4 of them (default render.png)",
     .kind = CLI_CUSTOM, CLI_FIELD(render_args, outputs), .parse = parse_output, .repeat_max = MAX_OUTPUTS,
     .count_offset = offsetof(render_args, output_count)},
    CLI_OPTION_ENGINE(render_args, engine),
    CLI_OPTIONS_KD_ENGINE(render_args, render.engine),
    {.name = "--shadows", .value_name = "METHOD",
     .help = "none, hard (default), multi:N, cone:N, pyramid:N (N = 1..256 samples), edgewidth[:R] (sphere and point "
             "lights; refused with quad lights), interleaved[:N][:nofilter|:refine] (N = 4..32, default 16: the pixel's "
             "4x4 interleaved sample set, then the 4x4 discontinuity filter; :refine adds a second pass that "
             "retraces the pixels the filter moved past their samples' noise with all 16 sets, 16N rays; the "
             "reference and embree engines), "
             "frusta[:N][:nofilter|:refine] (interleaved's samples and filter, each pixel's samples traced as one of 16 "
             "multi-frusta; the optimized engine with --accel bvh), pgrid (hard "
             "shadows through a perspective grid per light; the optimized engine), pgrid:N (N = 1..256: "
             "multi:N's samples, and image, through a 3D perspective grid per light, each point's N rays "
             "as packets; the optimized engine, any --accel)",
     .kind = CLI_CUSTOM, CLI_FIELD(render_args, render), .parse = parse_shadows},
    {.name = "--spp", .value_name = "N",
     .help = "anti-aliasing: N samples per pixel, 1 (default: the pixel centre) to 256, stratified "
             "(Hammersley, rotated per pixel), averaged by a box filter over the pixel",
     .kind = CLI_U32, CLI_FIELD(render_args, render.spp), .lo = 1, .hi = RTT_MAX_SPP},
    {.name = "--edge-leak-fix", .help = "with --shadows edgewidth: entry and exit polygons must share a vertex",
     .kind = CLI_FLAG, CLI_FIELD(render_args, render.edge_leak_fix)},
    CLI_OPTION_RENDER_THREADS(render_args, render),
    CLI_OPTION_RENDER_SIZE(render_args, render),
    CLI_OPTION_MAX_BOUNCES(render_args, render),
    CLI_OPTION_BEZIER_LEVEL(render_args, bezier_level),
    CLI_OPTIONS_CAMERA(render_args, camera),
    {.name = "--camera-path", .value_name = "FILE",
     .help = "render a sequence: one frame per view of a views file, in file order (or --path-frames); "
             "each output names its frames with a number, as in frame_%04d.png",
     .kind = CLI_STRING, CLI_FIELD(render_args, camera_path)},
    {.name = "--path-frames", .value_name = "N",
     .help = "with --camera-path: N frames (1 to 1000000) through the views as key frames, eye, look-at, up "
             "and fov interpolated linearly",
     .kind = CLI_U32, CLI_FIELD(render_args, path_frames), .lo = 1, .hi = RTT_MAX_PATH_FRAMES},
    {.name = "--aov", .value_name = "LIST", .help = "extra EXR channels, a comma list of depth, prim, normal",
     .kind = CLI_CHOICE_LIST, CLI_FIELD(render_args, render.aovs), .choices = aov_names},
    {.name = "--stats", .help = "print the engine, kernel and instruction set used, rays, N and I per 2x2 packet, "
                                "the renderer's stage times, and the wall times of load, build, render and write; frames; under "
                                "mpirun the tiles or frames of each rank",
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
    if (args->path_frames && !args->camera_path)
        return cli_refuse(parsed, "--path-frames", "applies to --camera-path only");
    static const char *const one_camera[] = {"--eye", "--look-at", "--up", "--view"};
    for (size_t i = 0; args->camera_path && i < sizeof one_camera / sizeof one_camera[0]; i++)
        if (cli_given(parsed, one_camera[i]))
            return cli_refuse(parsed, one_camera[i], "does not go with --camera-path, whose cameras it would replace");
    for (uint32_t i = 0; args->camera_path && i < args->output_count; i++) {
        rtt_error why = {{0}};
        if (!cli_frame_pattern_check(args->outputs[i], &why))
            return cli_refuse(parsed, "--output", "with --camera-path, %s", why.message);
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

/* Wall seconds of the stages --stats reports. */
typedef struct stage_times {
    double load, build, render, write;
} stage_times;

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

static void print_stats(const rtt_render_stats *s, const char *engine_used, const render_args *args,
                        const stage_times *times)
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
    printf("stages (wall): load %.4f s, build %.4f s, render %.4f s, write %.4f s\n", times->load, times->build,
           times->render, times->write);
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

/* Under MPI, for --stats: the share of the work each rank did. */
static void print_rank_shares(const rtt_dist *dist)
{
    const bool frames = rtt_dist_frames_of_rank(dist, 0) > 0; /* whole frames: rank 0 renders some too */
    printf("%s per rank:", frames ? "frames" : "tiles");
    for (uint32_t r = 0; r < rtt_dist_size(dist); r++)
        printf(" %u", frames ? rtt_dist_frames_of_rank(dist, r) : rtt_dist_tiles_of_rank(dist, r));
    printf(" (%u ranks; rays and stages above are summed over them)\n", rtt_dist_size(dist));
}

/* --camera-path's cameras, on every rank (a file only one node lacks is a
 * rank's failure like any other). */
static bool load_camera_path(const char *file, uint32_t frames, rtt_camera_path *path, rtt_error *err)
{
    rtt_view_list views = {0};
    bool ok = rtt_views_load(file, &views, err) && rtt_camera_path_make(&views, frames, file, path, err);
    rtt_views_free(&views);
    return ok;
}

/* Under MPI every rank builds its engine, and all go on only when all could
 * (rtt_dist_agree); the ranks share the frames' tiles, or the frames. */
static bool render_with_engine(rtt_dist *dist, const rtt_scene *scene, render_args *args, rtt_image *image,
                               const rtt_dist_frames *frames, rtt_render_stats *stats, char *engine_used,
                               size_t engine_used_size, stage_times *times, rtt_error *err)
{
    args->render.engine.threads = args->render.threads; /* --threads bounds the build too */
    cli_progress *progress = cli_progress_start("building the acceleration structure");
    rtt_engine *engine = rtt_engine_create(args->engine, scene, &args->render.engine, err);
    times->build = cli_progress_finish(progress);
    if (!rtt_dist_agree(dist, engine != NULL, err)) {
        rtt_engine_destroy(engine);
        return false;
    }
    progress = rtt_dist_rank(dist) == 0 ? cli_progress_start("rendering") : NULL; /* rank 0 speaks for the job */
    args->render.progress = progress ? cli_progress_update : NULL;
    args->render.progress_context = progress;
    bool ok = rtt_dist_render_frames(dist, engine, &args->render, image, frames, stats, err);
    times->render = cli_progress_finish(progress);
    args->render.progress = NULL;
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
    rtt_dist *dist = NULL; /* the MPI job when mpirun started us, else NULL: this process alone */
    if (!rtt_dist_open(&dist, &err)) return cli_fail(&err);
    const bool writer = rtt_dist_rank(dist) == 0; /* rank 0 writes and prints for the job */
    const char *inputs[] = {args->scene_path};
    stage_times times = {0};
    rtt_scene *scene = cli_check_outputs(args->outputs, args->output_count, inputs, 1, &err)
                           ? cli_load_scene_timed(args->scene_path, args->bezier_level, args->max_memory, &times.load,
                                                  &err)
                           : NULL;
    /* cli_camera_apply prints its own refusal; the other ranks must still hear of it */
    const int camera_status = scene ? cli_camera_apply(parsed, &args->camera, scene) : CLI_CONTINUE;
    cli_camera_free(&args->camera);
    if (camera_status != CLI_CONTINUE) rtt_error_set(&err, "the camera options do not fit %s", args->scene_path);
    rtt_camera_path path = {0};
    const bool framed = scene && camera_status == CLI_CONTINUE &&
                        (!args->camera_path || load_camera_path(args->camera_path, args->path_frames, &path, &err));
    rtt_image *image = NULL;
    if (framed) {
        args->render.width = args->render.width ? args->render.width : scene->width;
        args->render.height = args->render.height ? args->render.height : scene->height;
        image = rtt_image_create(args->render.width, args->render.height, args->render.aovs, &err);
    }
    rtt_render_stats stats;
    memset(&stats, 0, sizeof stats);
    char engine_used[256] = "";
    cli_frames outputs = {.scene = scene, .path = args->camera_path ? &path : NULL,
                          .fov_given = cli_given(parsed, "--fov"), .fov = args->camera.fov,
                          .outputs = args->outputs, .output_count = args->output_count};
    rtt_dist_frames frames = {.count = args->camera_path ? path.count : 1, .prepare = cli_frames_prepare,
                              .write = cli_frames_write, .context = &outputs};
    /* interleaved:N filters and composes the whole image after its tiles, from
     * planes the ranks do not exchange */
    if (image && rtt_dist_size(dist) > 1 &&
        (args->render.shadows == RTT_SHADOWS_INTERLEAVED || args->render.shadows == RTT_SHADOWS_FRUSTA)) {
        rtt_image_free(image);
        image = NULL;
        rtt_error_set(&err, "interleaved shadows filter across tiles: they render in one process, not under mpirun");
    }
    bool ok = rtt_dist_agree(dist, image != NULL, &err) &&
              render_with_engine(dist, scene, args, image, &frames, &stats, engine_used, sizeof engine_used, &times,
                                 &err);
    times.write = outputs.write_seconds;
    times.render -= times.write; /* the frames are written as they finish */
    if (ok && writer && args->render.stats) print_stats(&stats, engine_used, args, &times);
    if (ok && writer && args->render.stats && frames.count > 1)
        printf("frames: %u in %.3f s (%.3g frames/s)\n", frames.count, stats.seconds_total,
               stats.seconds_total > 0 ? frames.count / stats.seconds_total : 0.0);
    if (ok && writer && args->render.stats && rtt_dist_size(dist) > 1) print_rank_shares(dist);
    rtt_camera_path_free(&path);
    rtt_image_free(image);
    rtt_scene_free(scene);
    /* rank 0 names the failing rank, before MPI_Finalize lets any rank exit */
    status = ok                               ? RTT_EXIT_OK
             : camera_status != CLI_CONTINUE ? camera_status
             : writer                        ? cli_fail(&err)
                                             : RTT_EXIT_BAD_INPUT;
    rtt_dist_close(dist);
    return status;
}

const cli_command render_command = {
    .name = "render", .summary = "render a scene to EXR or PNG", .run = render,
    CLI_ARGS(render_args, render_defaults), CLI_ROWS(render_options), CLI_SCENE_OPERAND(render_args),
    .engine_offset = offsetof(render_args, render.engine),
    .synopsis = "SCENE [-o out.exr|out.png]... [--camera-path FILE [--path-frames N]] [options]",
    .description = "Renders SCENE (scene .json, mesh file, Quake III .bsp or baked .kdt).  An option\n"
                   "the chosen engine, scene file or output does not use is refused, not ignored.\n"
                   "Transparent materials let light through in proportion to their transparency\n"
                   "with hard, multi:N, cone:N and pyramid:N shadows; edgewidth treats them as\n"
                   "opaque on sphere lights.  Textures that cannot be read draw in their\n"
                   "material's colour, with one warning.\n"
                   "With --camera-path, a sequence: each -o holds one frame number (frame_%04d.png,\n"
                   "frames from 0).  Started by mpirun, the ranks share each frame's tiles (or, with\n"
                   "more frames than ranks, the frames); rank 0 writes the same bytes one process\n"
                   "would.\n",
    .environment = "RTT_ISA=auto|sse4|avx2|avx512 picks the instruction set when --isa is not\n"
                   "given.  RTT_TEXTURE_PATH=DIR[:DIR...] is where Quake III maps find their\n"
                   "textures (loose files and .pk3 archives; default: the map's directory, its\n"
                   "parent and the parent's pk3/).  RTT_PROGRESS_AFTER=SECONDS: progress lines\n"
                   "for stages longer than this (default 2).\n",
};

/* rtt view: the SDL2 window (viewer/), a thin driver like the others: the
 * options, the checks of rtt render, the scene, then rtt_viewer_run. */
#include <stdio.h>
#include <string.h>

#include "camera_options.h"
#include "cli.h"
#include "options.h"
#include "rtt/engine.h"
#ifdef RTT_HAVE_VIEWER
#include "viewer.h"
#endif

typedef struct view_settings {
    rtt_render_options render;
    const char *shadows_text;   /* --shadows as typed, for the overlay */
} view_settings;

typedef struct view_args {
    const char *scene_path;
    const char *engine;
    uint32_t bezier_level;
    view_settings settings;
    const char *script, *screenshot;
    cli_camera_args camera;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
} view_args;

static bool parse_view_shadows(const char *value, void *field, rtt_error *why)
{
    view_settings *s = field;
    if (!rtt_shadow_method_parse(value, &s->render, why)) return false;
    s->shadows_text = value;
    return true;
}

static bool parse_image_path(const char *value, void *field, rtt_error *why)
{
    const char *dot = strrchr(value, '.');
    if (!dot || (strcmp(dot, ".png") != 0 && strcmp(dot, ".exr") != 0))
        return rtt_error_set(why, "unknown image format (use .exr or .png)");
    *(const char **)field = value;
    return true;
}

static const cli_option view_options[] = {
    CLI_OPTION_ENGINE(view_args, engine),
    CLI_OPTIONS_KD_ENGINE(view_args, settings.render.engine),
    {.name = "--shadows", .value_name = "METHOD",
     .help = "the shadow method to start with (as rtt render; the G key cycles them)",
     .kind = CLI_CUSTOM, CLI_FIELD(view_args, settings), .parse = parse_view_shadows},
    {.name = "--spp", .value_name = "N",
     .help = "the samples per pixel a resting picture converges to, 1 to 256 (default 16; moving: 1)",
     .kind = CLI_U32, CLI_FIELD(view_args, settings.render.spp), .lo = 1, .hi = RTT_MAX_SPP},
    CLI_OPTION_RENDER_THREADS(view_args, settings.render),
    CLI_OPTION_RENDER_SIZE(view_args, settings.render),
    CLI_OPTION_MAX_BOUNCES(view_args, settings.render),
    CLI_OPTION_BEZIER_LEVEL(view_args, bezier_level),
    CLI_OPTIONS_CAMERA(view_args, camera),
    {.name = "--script", .value_name = "FILE",
     .help = "play a script of camera moves and key presses, then exit (viewer/README.md has the commands)",
     .kind = CLI_STRING, CLI_FIELD(view_args, script)},
    {.name = "--screenshot", .value_name = "FILE",
     .help = "write the last picture to FILE (.png or .exr) when the viewer exits",
     .kind = CLI_CUSTOM, CLI_FIELD(view_args, screenshot), .parse = parse_image_path},
    CLI_OPTION_MAX_MEMORY(view_args, max_memory),
};

static void view_defaults(void *opaque)
{
    view_args *args = opaque;
    args->engine = "optimized";
    rtt_render_options_default(&args->settings.render);
}

static int view(void *opaque, const cli_parsed *parsed)
{
    view_args *args = opaque;
    int rc = cli_check_engine_options(parsed, args->engine, &args->settings.render.engine);
    if (rc != CLI_CONTINUE) return rc;
    rtt_error err = {{0}};
    if (!rtt_render_options_check(args->engine, &args->settings.render, &err))
        return cli_refuse(parsed, cli_given(parsed, "--shadows") ? "--shadows" : NULL, "%s", err.message);
    rc = cli_check_scene_options(parsed, args->scene_path, args->engine);
    if (rc != CLI_CONTINUE) return rc;
#ifdef RTT_HAVE_VIEWER
    rc = cli_camera_check(parsed, &args->camera, args->scene_path);
    if (rc != CLI_CONTINUE) return rc;
    rtt_scene *scene = cli_load_scene(args->scene_path, args->bezier_level, args->max_memory, &err);
    rc = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (rc != CLI_CONTINUE) {
        rtt_scene_free(scene);
        return rc;
    }
    args->settings.render.engine.threads = args->settings.render.threads; /* --threads bounds the build too */
    const rtt_viewer_options opt = {
        .engine = args->engine,
        .shadows_text = args->settings.shadows_text,
        .render = args->settings.render,
        .script_path = args->script,
        .screenshot_path = args->screenshot,
    };
    bool ok = rtt_viewer_run(scene, &opt, &err);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
#else
    rtt_error_set(&err, "view: this rtt was built without the viewer (SDL2 was not found when it was configured; "
                        "install libsdl2-dev and rebuild)");
    return cli_fail(&err);
#endif
}

const cli_command view_command = {
    .name = "view", .summary = "fly through a scene in a window (SDL2), or play a script headless", .run = view,
    CLI_ARGS(view_args, view_defaults), CLI_ROWS(view_options), CLI_SCENE_OPERAND(view_args),
    .engine_offset = offsetof(view_args, settings.render.engine),
    .synopsis = "SCENE [render options] [--script FILE] [--screenshot OUT]",
    .description =
        "Opens a window on SCENE and renders it continuously with the chosen engine on every\n"
        "core; when the camera and the settings rest, the picture converges (1, 2, 4, ...\n"
        "samples per pixel up to --spp), then nothing is rendered.  Keys:\n"
        "  W/A/S/D or the arrows  move          mouse with a button held  look around\n"
        "  E or R / Q or F        up / down     + or ] / - or [           faster / slower\n"
        "  Home                   reset camera  T / G / I                 next traversal /\n"
        "  P or F12               screenshot    shadow method / instruction set\n"
        "  C                      print camera  (Shift: previous)         Esc  quit\n"
        "A screenshot writes rtt-view-NNNN.png and .exr in the current directory and prints\n"
        "the camera as a views.json entry.  The window title shows fps, Mrays/s, the kernel\n"
        "and instruction set, the shadow method and the resolution.\n",
    .environment = "RTT_ISA picks the instruction set when --isa is not given; DISPLAY (or\n"
                   "xvfb-run) the X server.\n",
};

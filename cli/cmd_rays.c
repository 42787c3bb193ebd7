/* rtt rays: writes a rays.bin of one of the conformance suite's ray kinds,
 * for `rtt trace` and outside programs. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera_options.h"
#include "cli.h"
#include "conform.h"
#include "options.h"

typedef struct rays_args {
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
    const char *scene_path, *out_path;
    int kind; /* -1: not given */
    uint32_t count, seed, bezier_level;
    cli_camera_args camera;
} rays_args;

static bool parse_kind(const char *value, void *field, rtt_error *why)
{
    for (size_t k = 0; rtt_conform_kind_name(k); k++)
        if (strcmp(value, rtt_conform_kind_name(k)) == 0) {
            *(int *)field = (int)k;
            return true;
        }
    char names[256] = "";
    for (size_t k = 0, used = 0; rtt_conform_kind_name(k) && used < sizeof names; k++)
        used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", k ? ", " : "", rtt_conform_kind_name(k));
    return rtt_error_set(why, "expected one of %s", names);
}

static void help_kinds(char *out, size_t size)
{
    size_t used = 0;
    for (size_t k = 0; rtt_conform_kind_name(k) && used < size; k++)
        used += (size_t)snprintf(out + used, size - used, " %s (%s);", rtt_conform_kind_name(k),
                                 rtt_conform_kind_summary(k));
}

static const cli_option rays_options[] = {
    {.name = "--kind", .value_name = "KIND", .help = "the kind of rays (required):", .kind = CLI_CUSTOM,
     CLI_FIELD(rays_args, kind), .parse = parse_kind, .help_more = help_kinds},
    {.name = "--count", .short_name = 'n', .value_name = "N",
     .help = "at most N rays, 1 to 100000000 (default 65536; primary renders fewer pixels to fit, inside "
             "has one per vertex and edge)",
     .kind = CLI_U32, CLI_FIELD(rays_args, count), .lo = 1, .hi = 100000000u},
    {.name = "--output", .short_name = 'o', .value_name = "FILE", .help = "the rays.bin to write (required)",
     .kind = CLI_STRING, CLI_FIELD(rays_args, out_path)},
    {.name = "--seed", .value_name = "S", .help = "seed of the random kinds (default 1)",
     .kind = CLI_U32, CLI_FIELD(rays_args, seed), .lo = 0, .hi = UINT32_MAX},
    CLI_OPTION_BEZIER_LEVEL(rays_args, bezier_level),
    CLI_OPTION_MAX_MEMORY(rays_args, max_memory),
    CLI_OPTIONS_CAMERA(rays_args, camera),
};

static void rays_defaults(void *opaque)
{
    rays_args *args = opaque;
    args->kind = -1;
    args->count = 65536;
    args->seed = 1;
}

static int rays(void *opaque, const cli_parsed *parsed)
{
    rays_args *args = opaque;
    if (args->kind < 0) return cli_refuse(parsed, NULL, "no --kind given");
    if (!args->out_path) return cli_refuse(parsed, NULL, "no output given (-o rays.bin)");
    int rc = cli_check_scene_options(parsed, args->scene_path, NULL);
    if (rc == CLI_CONTINUE) rc = cli_camera_check(parsed, &args->camera, args->scene_path);
    if (rc != CLI_CONTINUE) return rc;

    rtt_error err = {{0}};
    const char *inputs[] = {args->scene_path};
    rtt_scene *scene = cli_check_outputs(&args->out_path, 1, inputs, 1, &err)
                           ? cli_load_scene(args->scene_path, args->bezier_level, args->max_memory, &err)
                           : NULL;
    rc = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (rc != CLI_CONTINUE) {
        rtt_scene_free(scene);
        return rc;
    }
    rtt_engine *reference = NULL;
    if (strcmp(rtt_conform_kind_name((size_t)args->kind), "shadow") == 0) {
        rtt_engine_options opt;
        rtt_engine_options_default(&opt);
        reference = rtt_engine_create("reference", scene, &opt, &err);
    }
    rtt_ray *list = NULL;
    size_t count = 0;
    bool ok = (reference || strcmp(rtt_conform_kind_name((size_t)args->kind), "shadow") != 0) &&
              rtt_conform_make_kind(scene, (size_t)args->kind, reference, args->count, args->seed, &list, &count, &err);
    ok = ok && cli_write_file_atomic(args->out_path, list, count * sizeof *list, &err);
    if (ok) printf("%zu rays of kind %s written to %s\n", count, rtt_conform_kind_name((size_t)args->kind), args->out_path);
    free(list);
    rtt_engine_destroy(reference);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command rays_command = {
    .name = "rays", .summary = "write rays.bin of a conformance ray kind, seeded", .run = rays,
    CLI_ARGS(rays_args, rays_defaults), CLI_ROWS(rays_options), CLI_SCENE_OPERAND(rays_args),
    .synopsis = "SCENE --kind KIND -n N -o rays.bin [--seed S] [options]",
    .description = "Writes rays of one kind the conformance suite traces (the suite's own\n"
                   "generators) as rays.bin: 32-byte records, origin[3], direction[3], tnear,\n"
                   "tfar, little-endian float32, the input of `rtt trace`.  The same scene, kind,\n"
                   "count and seed give the same file.  Primary rays come from the scene's camera\n"
                   "(or the camera options').\n",
};

/* rtt triangles: the scene's triangles in global order, 9 little-endian
 * float32 each, so outside programs can check any engine's hits. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "options.h"

typedef struct triangles_args {
    const char *scene_path, *out_path;
    uint32_t bezier_level;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
} triangles_args;

static const cli_option triangles_options[] = {
    {.name = "--output", .short_name = 'o', .value_name = "FILE", .help = "the file to write (required)",
     .kind = CLI_STRING, CLI_FIELD(triangles_args, out_path)},
    CLI_OPTION_BEZIER_LEVEL(triangles_args, bezier_level),
    CLI_OPTION_MAX_MEMORY(triangles_args, max_memory),
};

static int triangles(void *opaque, const cli_parsed *parsed)
{
    const triangles_args *args = opaque;
    if (!args->out_path) return cli_refuse(parsed, NULL, "no output given (-o tris.bin)");
    int rc = cli_check_scene_options(parsed, args->scene_path, NULL);
    if (rc != CLI_CONTINUE) return rc;

    rtt_error err = {0};
    const char *inputs[] = {args->scene_path};
    if (!cli_check_outputs(&args->out_path, 1, inputs, 1, &err)) return cli_fail(&err);
    rtt_scene *scene = cli_load_scene(args->scene_path, args->bezier_level, args->max_memory, &err);
    if (!scene) return cli_fail(&err);
    size_t size = (size_t)scene->triangle_count * 9 * sizeof(float);
    float *xyz = malloc(size ? size : 1);
    bool ok = xyz != NULL;
    if (!ok) rtt_error_set(&err, "%s: out of memory", args->scene_path);
    for (uint32_t i = 0; ok && i < scene->triangle_count; i++) {
        rtt_vec3 corners[3];
        rtt_scene_triangle(scene, i, corners);
        memcpy(&xyz[(size_t)i * 9], corners, sizeof corners);
    }
    ok = ok && cli_write_file_atomic(args->out_path, xyz, size, &err);
    free(xyz);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command triangles_command = {
    .name = "triangles", .summary = "write the triangles in global order, 9 float32 each", .run = triangles,
    CLI_ARGS(triangles_args, NULL), CLI_ROWS(triangles_options), CLI_SCENE_OPERAND(triangles_args),
    .synopsis = "SCENE -o tris.bin [options]",
    .description = "Writes the triangles of SCENE in the global order (meshes in file order,\n"
                   "faces in file order, polygons fan-triangulated) as 9 little-endian float32\n"
                   "each (x0 y0 z0 x1 y1 z1 x2 y2 z2).  Degenerate triangles keep their place.\n",
};

/* rtt triangles: the scene's triangles in global order, 9 little-endian
 * float32 each, so outside programs can check any engine's hits. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char triangles_help[] =
    "usage: rtt triangles SCENE -o tris.bin [--bezier-level N]\n"
    "\n"
    "Writes the triangles of SCENE in the global order (meshes in file order,\n"
    "faces in file order, polygons fan-triangulated) as 9 little-endian float32\n"
    "each (x0 y0 z0 x1 y1 z1 x2 y2 z2).  Degenerate triangles keep their place.\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

int cmd_triangles(int argc, char **argv)
{
    const char *scene_path = NULL, *out_path = NULL;
    uint32_t bezier_level = 0;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(triangles_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(argv[i], "-o") == 0 || strcmp(argv[i], "--bezier-level") == 0) {
            if (i + 1 >= argc) return cli_usage_error("triangles", "%s needs a value", argv[i]);
            if (argv[i][1] == 'o') out_path = argv[++i];
            else if (!cli_parse_u32(argv[++i], 1, 64, &bezier_level))
                return cli_usage_error("triangles", "--bezier-level %s: expected 1 to 64", argv[i]);
        } else if (argv[i][0] == '-') {
            return cli_usage_error("triangles", "unknown option \"%s\"", argv[i]);
        } else if (scene_path) {
            return cli_usage_error("triangles", "more than one SCENE given");
        } else {
            scene_path = argv[i];
        }
    }
    if (!scene_path) return cli_usage_error("triangles", "no SCENE given");
    if (!out_path) return cli_usage_error("triangles", "no output given (-o tris.bin)");

    rtt_error err = {0};
    rtt_scene *scene = cli_load_scene(scene_path, bezier_level, &err);
    if (!scene) return cli_fail(&err);
    size_t size = (size_t)scene->triangle_count * 9 * sizeof(float);
    float *xyz = malloc(size ? size : 1);
    bool ok = xyz != NULL;
    if (!ok) rtt_error_set(&err, "%s: out of memory", scene_path);
    for (uint32_t i = 0; ok && i < scene->triangle_count; i++) {
        rtt_vec3 corners[3];
        rtt_scene_triangle(scene, i, corners);
        memcpy(&xyz[(size_t)i * 9], corners, sizeof corners);
    }
    ok = ok && cli_write_file_atomic(out_path, xyz, size, &err);
    free(xyz);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

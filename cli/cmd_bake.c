/* rtt bake: build the optimized kd-tree offline and save it with the scene
 * as a .kdt ("RTTest offline", Thesis 3.2), which `rtt render` and every
 * other command load without rebuilding. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "rtt/engine.h"
#include "rtt/optimized.h"

static const char bake_help[] =
    "usage: rtt bake SCENE -o scene.kdt [--max-depth N] [--bezier-level N]\n"
    "\n"
    "Builds the optimized engine's SAH kd-tree (perfect splits, C_trav = 1,\n"
    "C_isect = 5) for SCENE and writes it, with the whole scene (geometry,\n"
    "materials, lights, camera), as a versioned, checksummed .kdt.  The output\n"
    "is written to a temporary and renamed, so an existing file is replaced only\n"
    "by a complete one.\n"
    "\n"
    "  -o FILE           the .kdt to write (required)\n"
    "  --max-depth N     tree depth bound, 1 to 64 (default round(2 + log2 N), at least 8)\n"
    "  --bezier-level N  Quake III patch tessellation (default 4)\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

int cmd_bake(int argc, char **argv)
{
    const char *scene_path = NULL, *out_path = NULL;
    uint32_t bezier_level = 0;
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(bake_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(argv[i], "-o") == 0 || strcmp(argv[i], "--max-depth") == 0 ||
            strcmp(argv[i], "--bezier-level") == 0) {
            if (i + 1 >= argc) return cli_usage_error("bake", "%s needs a value", argv[i]);
            const char *option = argv[i], *value = argv[++i];
            if (strcmp(option, "-o") == 0) out_path = value;
            else if (strcmp(option, "--max-depth") == 0 && !cli_parse_u32(value, 1, 64, &opt.max_tree_depth))
                return cli_usage_error("bake", "--max-depth %s: expected 1 to 64", value);
            else if (strcmp(option, "--bezier-level") == 0 && !cli_parse_u32(value, 1, 64, &bezier_level))
                return cli_usage_error("bake", "--bezier-level %s: expected 1 to 64", value);
        } else if (argv[i][0] == '-') {
            return cli_usage_error("bake", "unknown option \"%s\"", argv[i]);
        } else if (scene_path) {
            return cli_usage_error("bake", "more than one SCENE given");
        } else {
            scene_path = argv[i];
        }
    }
    if (!scene_path) return cli_usage_error("bake", "no SCENE given");
    if (!out_path) return cli_usage_error("bake", "no output given (-o scene.kdt)");
    const char *dot = strrchr(out_path, '.');
    if (!dot || strcasecmp(dot, ".kdt") != 0)
        return cli_usage_error("bake", "-o %s: the output must end in .kdt", out_path);

    rtt_error err = {0};
    rtt_scene *scene = cli_load_scene(scene_path, bezier_level, &err);
    if (!scene) return cli_fail(&err);
    bool ok = rtt_optimized_bake(scene, &opt, out_path, &err);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

/* rtt info: what a scene holds and what the engines' kd-trees look like. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "rtt/engine.h"

static const char info_help[] =
    "usage: rtt info SCENE|scene.kdt [--engine optimized|reference|both] [--max-depth N]\n"
    "\n"
    "Prints triangles (and degenerate ones), vertices, meshes, materials, lights,\n"
    "bounds, and for each engine's kd-tree: build time (the optimized builder uses\n"
    "every core), depth against its bound, nodes, leaves, SAH cost, references and\n"
    "duplication against the reference cap, and memory.\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 bad usage.\n";

static const char *const material_type_names[] = {"diffuse", "specular", "reflective", "transparent",
                                                  "transparent_reflective"};

static void print_scene(const rtt_scene *s)
{
    uint32_t closed = 0;
    for (uint32_t i = 0; i < s->mesh_count; i++) closed += s->meshes[i].closed;
    printf("scene %s\n", s->path);
    printf("  triangles   %u (%u degenerate)\n", s->triangle_count, s->degenerate_count);
    printf("  vertices    %u%s\n", s->vertex_count, s->normals ? " with normals" : "");
    printf("  meshes      %u (%u closed)\n", s->mesh_count, closed);
    printf("  bounds      (%g, %g, %g) .. (%g, %g, %g)\n", s->bounds.lo.x, s->bounds.lo.y, s->bounds.lo.z,
           s->bounds.hi.x, s->bounds.hi.y, s->bounds.hi.z);
    printf("  image       %ux%u, max bounces %u\n", s->width, s->height, s->max_bounces);
    printf("  materials   %u:", s->material_count);
    for (uint32_t i = 0; i < s->material_count; i++)
        printf(" %s(%s)", s->materials[i].name[0] ? s->materials[i].name : "-",
               material_type_names[s->materials[i].type]);
    printf("\n  lights      %u:", s->light_count);
    for (uint32_t i = 0; i < s->light_count; i++)
        printf(" %s", s->lights[i].type == RTT_LIGHT_SPHERE ? "sphere" : "point");
    printf("\n");
}

static bool print_tree(const char *engine_name, const rtt_scene *scene, const rtt_engine_options *opt,
                       rtt_error *err)
{
    rtt_engine *engine = rtt_engine_create(engine_name, scene, opt, err);
    if (!engine) return false;
    rtt_tree_info t;
    if (rtt_engine_tree_info(engine, &t)) {
        double triangles = scene->triangle_count ? scene->triangle_count : 1;
        printf("%s kd-tree%s\n", engine_name, scene->baked && strcmp(engine_name, "optimized") == 0 ? " (baked)" : "");
        printf("  build       %.3f s\n", t.build_seconds);
        printf("  depth       %u (maximum %u)\n", t.depth, t.max_depth);
        printf("  nodes       %u, leaves %u (%u empty)\n", t.node_count, t.leaf_count, t.empty_leaf_count);
        printf("  SAH cost    %.3f\n", t.sah_cost);
        printf("  references  %llu, duplication %.2f (cap %llu)\n", (unsigned long long)t.references,
               t.references / triangles, (unsigned long long)t.reference_cap);
        printf("  memory      %.2f MiB\n", t.memory_bytes / (1024.0 * 1024.0));
    }
    rtt_engine_destroy(engine);
    return true;
}

int cmd_info(int argc, char **argv)
{
    const char *scene_path = NULL, *which = "both";
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(info_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(argv[i], "--engine") == 0 || strcmp(argv[i], "--max-depth") == 0) {
            if (i + 1 >= argc) return cli_usage_error("info", "%s needs a value", argv[i]);
            const char *value = argv[++i];
            if (argv[i - 1][2] == 'e') {
                if (strcmp(value, "optimized") && strcmp(value, "reference") && strcmp(value, "both"))
                    return cli_usage_error("info", "--engine %s: expected optimized, reference or both", value);
                which = value;
            } else if (!cli_parse_u32(value, 1, 64, &opt.max_tree_depth)) {
                return cli_usage_error("info", "--max-depth %s: expected 1 to 64", value);
            }
        } else if (argv[i][0] == '-') {
            return cli_usage_error("info", "unknown option \"%s\"", argv[i]);
        } else if (scene_path) {
            return cli_usage_error("info", "more than one SCENE given");
        } else {
            scene_path = argv[i];
        }
    }
    if (!scene_path) return cli_usage_error("info", "no SCENE given");

    rtt_error err = {0};
    rtt_scene *scene = cli_load_scene(scene_path, 0, &err);
    if (!scene) return cli_fail(&err);
    print_scene(scene);
    bool ok = true;
    if (strcmp(which, "reference") != 0) ok = print_tree("optimized", scene, &opt, &err);
    if (ok && strcmp(which, "optimized") != 0) ok = print_tree("reference", scene, &opt, &err);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

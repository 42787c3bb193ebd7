/* rtt info: what a scene holds and what the engines' kd-trees look like. */
#include <stdio.h>
#include <string.h>

#include "camera_options.h"
#include "cli.h"
#include "options.h"
#include "rtt/engine.h"

typedef enum info_engines { INFO_BOTH, INFO_OPTIMIZED, INFO_REFERENCE } info_engines;
static const char *const info_engine_choices[] = {"both", "optimized", "reference", NULL};

typedef struct info_args {
    const char *scene_path;
    int engines; /* info_engines */
    rtt_engine_options engine;
    uint64_t max_memory; /* the scene's memory budget in bytes; 0: the machine's */
    cli_camera_args camera;
} info_args;

static const cli_option info_options[] = {
    {.name = "--engine", .value_name = "NAME",
     .help = "whose kd-tree to describe: both (default), optimized or reference",
     .kind = CLI_CHOICE, CLI_FIELD(info_args, engines), .choices = info_engine_choices},
    CLI_OPTIONS_KD_TREE(info_args, engine),
    CLI_OPTION_BUILD_THREADS(info_args, engine),
    CLI_OPTION_MAX_MEMORY(info_args, max_memory),
    CLI_OPTIONS_CAMERA(info_args, camera),
};

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
    printf("\n");
    cli_print_camera_and_lights(s);
}

static bool print_tree(const char *engine_name, const rtt_scene *scene, const rtt_engine_options *opt,
                       rtt_error *err)
{
    rtt_engine *engine = rtt_engine_create(engine_name, scene, opt, err);
    if (!engine) return false;
    rtt_tree_info t;
    if (rtt_engine_tree_info(engine, &t)) {
        double triangles = scene->triangle_count ? scene->triangle_count : 1;
        const rtt_engine_class *cls = rtt_engine_find(engine_name);
        printf("%s kd-tree%s\n", engine_name, scene->baked && cls && cls->adopts_baked_tree ? " (baked)" : "");
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

/* The engine options and the scene file must suit every engine described. */
static int check_applicable(const cli_parsed *parsed, info_args *args, const char *const engines[2])
{
    for (int i = 0; i < 2 && engines[i]; i++) {
        int rc = cli_check_engine_options(parsed, engines[i], &args->engine);
        if (rc == CLI_CONTINUE) rc = cli_check_scene_options(parsed, args->scene_path, engines[i]);
        if (rc != CLI_CONTINUE) return rc;
    }
    return cli_camera_check(parsed, &args->camera, args->scene_path);
}

static void info_defaults(void *args)
{
    rtt_engine_options_default(&((info_args *)args)->engine);
}

static int info(void *opaque, const cli_parsed *parsed)
{
    info_args *args = opaque;
    const char *engines[2] = {args->engines == INFO_REFERENCE ? "reference" : "optimized",
                              args->engines == INFO_BOTH ? "reference" : NULL};
    int rc = check_applicable(parsed, args, engines);
    if (rc != CLI_CONTINUE) return rc;

    rtt_error err = {0};
    rtt_scene *scene = cli_load_scene(args->scene_path, 0, args->max_memory, &err);
    rc = scene ? cli_camera_apply(parsed, &args->camera, scene) : cli_fail(&err);
    cli_camera_free(&args->camera);
    if (rc != CLI_CONTINUE) {
        rtt_scene_free(scene);
        return rc;
    }
    print_scene(scene);
    bool ok = true;
    for (int i = 0; ok && i < 2 && engines[i]; i++) ok = print_tree(engines[i], scene, &args->engine, &err);
    rtt_scene_free(scene);
    return ok ? RTT_EXIT_OK : cli_fail(&err);
}

const cli_command info_command = {
    .name = "info", .summary = "triangles, bounds, tree depth, leaves, SAH cost, duplication", .run = info,
    CLI_ARGS(info_args, info_defaults), CLI_ROWS(info_options), CLI_SCENE_OPERAND(info_args),
    .engine_offset = offsetof(info_args, engine),
    .synopsis = "SCENE|scene.kdt [options]",
    .description = "Prints triangles (and degenerate ones), vertices, meshes, materials, bounds,\n"
                   "the camera and the lights a render with the same camera options uses, and\n"
                   "for each engine's kd-tree: build time (the optimized builder uses every\n"
                   "core), depth against its bound, nodes, leaves, SAH cost, references and\n"
                   "duplication against the reference cap, and memory.\n",
};

/* The reference engine: the rtt_engine vtable over the reference kd-tree
 * (kd_build_reference.c, Thesis 2.2.1) and its recursive traversal
 * (traverse_recursive.c, Thesis Listing 2.1).  It always builds its own tree;
 * a scene's baked tree (scene->baked) belongs to the optimized engine. */
#include <stdlib.h>

#include "kd_reference.h"
#include "rtt/reference.h"

typedef struct reference_engine {
    rtt_engine base; /* first, so an rtt_engine * is a reference_engine * */
    rtt_kd_tree tree;
} reference_engine;

static void reference_intersect(rtt_engine *engine, const rtt_ray *rays, rtt_hit *hits, size_t n)
{
    const reference_engine *self = (const reference_engine *)engine;
    for (size_t i = 0; i < n; i++) rtt_kd_reference_intersect(&self->tree, &rays[i], &hits[i]);
}

static void reference_occluded(rtt_engine *engine, const rtt_ray *rays, uint8_t *occluded, size_t n)
{
    const reference_engine *self = (const reference_engine *)engine;
    for (size_t i = 0; i < n; i++) occluded[i] = rtt_kd_reference_occluded(&self->tree, &rays[i]) ? 1 : 0;
}

static void reference_destroy(rtt_engine *engine)
{
    reference_engine *self = (reference_engine *)engine;
    rtt_kd_reference_free(&self->tree);
    free(self);
}

static bool reference_tree_info(rtt_engine *engine, rtt_tree_info *info)
{
    *info = ((const reference_engine *)engine)->tree.info;
    info->memory_bytes += sizeof(reference_engine);
    return true;
}

static const char *reference_isect_name(rtt_engine *engine)
{
    (void)engine;
    return "watertight"; /* isect_watertight.c */
}

static const rtt_engine_vtable reference_vtable = {
    .name = "reference",
    .intersect = reference_intersect,
    .occluded = reference_occluded,
    .render = rtt_reference_render_engine,
    .destroy = reference_destroy,
    .tree_info = reference_tree_info,
    .isect_name = reference_isect_name,
};

const rtt_engine_class rtt_reference_engine_class = {
    .name = "reference",
    .summary = "scalar oracle: recursive kd traversal, watertight test, Whitted shading",
    .uses = RTT_OPTION_MAX_DEPTH,
    .shadow_methods = RTT_REFERENCE_SHADOW_METHODS,
    .create = rtt_reference_engine_create,
};

rtt_engine *rtt_reference_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err)
{
    if (!scene) {
        rtt_error_set(err, "reference engine: no scene given");
        return NULL;
    }
    reference_engine *self = calloc(1, sizeof *self);
    if (!self) {
        rtt_error_set(err, "%s: out of memory creating the reference engine", scene->path);
        return NULL;
    }
    rtt_kd_build_options build = {.max_depth = opt ? opt->max_tree_depth : 0};
    if (!rtt_kd_reference_build(scene, &build, &self->tree, err)) {
        free(self);
        return NULL;
    }
    self->base.vt = &reference_vtable;
    self->base.scene = scene;
    return &self->base;
}

/* The optimized engine behind the engine interface: the SAH kd-tree of
 * kd_build_sah.c (also under --accel pgrid, whose per-frame eye-ray grid
 * lives in the renderer: the tree serves every other ray and the engine's
 * ray streams), or the tree of a baked .kdt
 * adopted as is (scene->baked, validated by scene/kdt_file.c; its arrays
 * have kd_tree.h's layout, asserted below, so nothing is rebuilt or copied).
 *
 * Arbitrary ray streams are cut into 2x2 packets of consecutive rays, and
 * the packets into blocks of the size the chosen kernel reads (1 packet for
 * mono/packet/omni, tile*tile/4 for the frustum family).  Every kernel is
 * exact for any rays, so no kernel needs a fallback here: the packet kernel
 * splits packets of mixed direction signs itself (Listing 2.4), and the
 * frustum, MFT and cone kernels trace a block packet by packet, omni-
 * directionally, when its rays share no useful frustum or cone (origins
 * spread out, mixed signs on every axis, rays starting behind a cone's apex:
 * kd/block.h, kd_frustum_is_incoherent / kd_cone_build).  What that trades on
 * incoherent streams: the proxy is built and thrown away per block.
 *
 * The engine holds no mutable state after creation, so any number of
 * threads may trace through it at once (scratch lives on the stack). */
#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_build.h"
#include "bvh_kernels.h"
#include "engine_optimized.h"
#include "kd_build.h"
#include "kdt_format.h"
#include "kernels.h"
#include "pgrid_eye.h"
#include "rtt/optimized.h"

_Static_assert(sizeof(kd_node) == sizeof(kdt_node) && offsetof(kd_node, bits) == offsetof(kdt_node, bits),
               "kd_node and the .kdt node agree");
_Static_assert(sizeof(kd_leaf) == sizeof(kdt_leaf) && offsetof(kd_leaf, first) == offsetof(kdt_leaf, first) &&
                   offsetof(kd_leaf, count) == offsetof(kdt_leaf, count) &&
                   offsetof(kd_leaf, lo) == offsetof(kdt_leaf, lo) && offsetof(kd_leaf, hi) == offsetof(kdt_leaf, hi),
               "kd_leaf and the .kdt leaf agree");
_Static_assert(sizeof(kd_triangle) == sizeof(kdt_triangle) &&
                   offsetof(kd_triangle, n_u) == offsetof(kdt_triangle, n_u) &&
                   offsetof(kd_triangle, c_nv) == offsetof(kdt_triangle, c_nv) &&
                   offsetof(kd_triangle, k) == offsetof(kdt_triangle, k) &&
                   offsetof(kd_triangle, prim) == offsetof(kdt_triangle, prim) &&
                   offsetof(kd_triangle, pad) == offsetof(kdt_triangle, pad),
               "kd_triangle and the .kdt triangle record agree");
_Static_assert(KD_DEPTH_LIMIT == KDT_DEPTH_LIMIT, "the builder and the .kdt reader bound depth alike");

/* The triangle test when the options leave it to the engine: watertight.
 * It lets no ray out of a closed mesh, and on primary frames it costs what
 * bench/results/accuracy.md measures against the projected test (within
 * the 1.15x the production path may spend on it). */
#define RTT_OPTIMIZED_DEFAULT_ISECT RTT_ISECT_WATERTIGHT

typedef struct optimized_engine {
    rtt_engine base;
    kd_tree tree;
    bool owns_tree;           /* false when the arrays belong to scene->baked */
    kd_corners *corners;      /* the watertight test's corners (tree.corners), NULL for the projected test */
    rtt_engine_options opt;
    const kd_kernel *kernel;  /* the descriptor-table row the options name (kd; the kd default under pgrid) */
    bvh_tree bvh;             /* --accel bvh: the BVH and its kernel row instead */
    const bvh_kernel *bvh_kernel;
    const pgrid_kernel *pgrid; /* --accel pgrid: the eye rays' cell kernel; streams go through the kd-tree */
    uint8_t *degenerate;      /* per triangle, 1 = never hits; NULL when the scene has none */
    char kernel_label[48];    /* "mft/avx512" */
    /* --shadows pgrid's light grids between frames (optimized_engine_light_grids_lend) */
    pgrid_shadows light_grids;
    const rtt_scene *light_scene; /* the scene their half was prepared for; NULL: none yet */
    atomic_bool light_grids_lent;
} optimized_engine;

static void optimized_destroy(rtt_engine *base);
static void optimized_intersect(rtt_engine *base, const rtt_ray *rays, rtt_hit *hits, size_t n);
static void optimized_occluded(rtt_engine *base, const rtt_ray *rays, uint8_t *occluded, size_t n);
static bool optimized_tree_info(rtt_engine *base, rtt_tree_info *info);
static const char *optimized_kernel_name(rtt_engine *base);
static const char *optimized_isect_name(rtt_engine *base);

static const rtt_engine_vtable optimized_vtable = {
    .name = "optimized",
    .intersect = optimized_intersect,
    .occluded = optimized_occluded,
    .render = rtt_optimized_render,
    .destroy = optimized_destroy,
    .tree_info = optimized_tree_info,
    .kernel_name = optimized_kernel_name,
    .isect_name = optimized_isect_name,
};

/* "unknown <accel> traversal "x": expected a, b, ..." from a table's names */
static bool unknown_traversal(const rtt_engine_options *opt, const char *(*name_at)(uint32_t), rtt_error *err)
{
    char names[160] = "";
    const char *name;
    for (uint32_t i = 0; (name = name_at(i)); i++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "", name);
    return rtt_error_set(err, "unknown %s traversal \"%s\": expected %s",
                         rtt_accel_name(opt->accel == RTT_ACCEL_DEFAULT ? RTT_ACCEL_KD : opt->accel), opt->traversal,
                         names);
}

static bool optimized_check(const rtt_engine_options *opt, rtt_error *err)
{
    if (opt->accel == RTT_ACCEL_BVH)
        return bvh_kernel_find(opt->traversal, RTT_ISA_AVX512) ? true : unknown_traversal(opt, bvh_kernel_name_at, err);
    if (opt->accel == RTT_ACCEL_PGRID)
        return pgrid_kernel_find(opt->traversal, RTT_ISA_AVX512) ? true : unknown_traversal(opt, pgrid_kernel_name_at, err);
    if (opt->accel != RTT_ACCEL_DEFAULT && opt->accel != RTT_ACCEL_KD)
        return rtt_error_set(err, "engine \"optimized\" has no %s acceleration structure", rtt_accel_name(opt->accel));
    return kd_kernel_find(opt->traversal, RTT_ISA_AVX512) ? true : unknown_traversal(opt, kd_kernel_name_at, err);
}

static const char *optimized_kernel_at(rtt_accel accel, uint32_t i)
{
    if (accel == RTT_ACCEL_BVH) return bvh_kernel_name_at(i);
    if (accel == RTT_ACCEL_PGRID) return pgrid_kernel_name_at(i);
    return accel == RTT_ACCEL_DEFAULT || accel == RTT_ACCEL_KD ? kd_kernel_name_at(i) : NULL;
}

const rtt_engine_class rtt_optimized_engine_class = {
    .name = "optimized",
    .summary = "production path: SAH kd-tree (packet/frustum/MFT/cone kernels, every shadow method), BVH, "
               "perspective grids",
    .uses = RTT_OPTION_ACCEL | RTT_OPTION_TRAVERSAL | RTT_OPTION_TILE | RTT_OPTION_LEAF_CULLING |
            RTT_OPTION_MAX_DEPTH | RTT_OPTION_ISA | RTT_OPTION_ISECT,
    .shadow_methods = RTT_SHADOWS_ALL,
    .adopts_baked_tree = true,
    .create = rtt_optimized_engine_create,
    .check = optimized_check,
    .kernel = optimized_kernel_at,
};

static const char *optimized_kernel_name(rtt_engine *base)
{
    return ((optimized_engine *)base)->kernel_label;
}

static const char *optimized_isect_name(rtt_engine *base)
{
    const optimized_engine *e = (optimized_engine *)base;
    const bool watertight = e->bvh_kernel ? e->bvh.watertight : e->tree.corners != NULL;
    return rtt_isect_name(watertight ? RTT_ISECT_WATERTIGHT : RTT_ISECT_PROJECTED);
}

static optimized_engine *as_optimized(rtt_engine *engine)
{
    return engine && engine->vt == &optimized_vtable ? (optimized_engine *)engine : NULL;
}

const kd_tree *kd_engine_tree(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e && !e->bvh_kernel ? &e->tree : NULL;
}

const kd_kernel *kd_engine_kernel(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e && !e->bvh_kernel ? e->kernel : NULL;
}

const bvh_tree *bvh_engine_tree(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e && e->bvh_kernel ? &e->bvh : NULL;
}

const bvh_kernel *bvh_engine_kernel(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e ? e->bvh_kernel : NULL;
}

const uint8_t *optimized_engine_degenerate(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e ? e->degenerate : NULL;
}

const pgrid_kernel *pgrid_engine_kernel(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    return e ? e->pgrid : NULL;
}

pgrid_shadows *optimized_engine_light_grids_lend(rtt_engine *engine, const rtt_scene *scene, rtt_error *err,
                                                bool *failed)
{
    optimized_engine *e = as_optimized(engine);
    *failed = false;
    if (!e || atomic_exchange(&e->light_grids_lent, true)) return NULL;
    if (e->light_scene != scene) {
        if (e->light_scene) pgrid_shadows_free(&e->light_grids);
        e->light_scene = NULL;
        if (!pgrid_shadows_prepare(&e->light_grids, scene, e->degenerate, err)) { /* it freed what it made */
            atomic_store(&e->light_grids_lent, false);
            *failed = true;
            return NULL;
        }
        e->light_scene = scene;
    }
    return &e->light_grids;
}

void optimized_engine_light_grids_return(rtt_engine *engine)
{
    optimized_engine *e = as_optimized(engine);
    if (e) atomic_store(&e->light_grids_lent, false);
}

/* The triangles that never hit, for the structures that skip them (the
 * perspective grid); NULL when there are none. */
static bool flag_degenerate(optimized_engine *e, const rtt_scene *scene, rtt_error *err)
{
    if (scene->degenerate_count == 0) return true;
    e->degenerate = malloc(scene->triangle_count);
    if (!e->degenerate) return rtt_error_set(err, "%s: out of memory creating the optimized engine", scene->path);
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 corners[3];
        rtt_scene_triangle(scene, i, corners);
        e->degenerate[i] = rtt_triangle_is_degenerate(corners);
    }
    return true;
}

static void adopt_baked(kd_tree *tree, const rtt_baked_tree *baked)
{
    memset(tree, 0, sizeof *tree);
    tree->nodes = (kd_node *)baked->nodes;
    tree->leaves = (kd_leaf *)baked->leaves;
    tree->triangles = (kd_triangle *)baked->records;
    tree->node_count = baked->node_count;
    tree->leaf_count = baked->leaf_count;
    tree->triangle_count = baked->record_count;
    tree->bounds = baked->bounds;
    tree->info = baked->info;
}

/* The watertight test reads each record's triangle as the scene stores it:
 * one kd_corners per record, in the records' (leaf) order. */
static bool attach_corners(optimized_engine *e, const rtt_scene *scene, rtt_error *err)
{
    const uint32_t n = e->tree.triangle_count;
    e->corners = aligned_alloc(16, (size_t)(n ? n : 1) * sizeof *e->corners); /* 48-byte entries: a multiple of 16 */
    if (!e->corners) return rtt_error_set(err, "%s: out of memory for the watertight test", scene->path);
    for (uint32_t i = 0; i < n; i++) {
        rtt_vec3 p[3];
        const uint32_t prim = e->tree.triangles[i].prim;
        rtt_scene_triangle(scene, prim, p);
        e->corners[i] = (kd_corners){{p[0].x, p[0].y, p[0].z}, {p[1].x, p[1].y, p[1].z},
                                     {p[2].x, p[2].y, p[2].z}, prim, 0, 0};
    }
    e->tree.corners = e->corners;
    return true;
}

rtt_engine *rtt_optimized_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err)
{
    rtt_engine_options defaults;
    if (!opt) {
        rtt_engine_options_default(&defaults);
        opt = &defaults;
    }
    if (!rtt_engine_class_check(&rtt_optimized_engine_class, opt, err)) return NULL;
    optimized_engine *e = calloc(1, sizeof *e);
    if (!e) return rtt_error_set(err, "%s: out of memory creating the optimized engine", scene->path), NULL;
    e->base.vt = &optimized_vtable;
    e->base.scene = scene;
    e->opt = *opt;
    if (e->opt.tile == 0) e->opt.tile = 8;
    const rtt_isa isa = rtt_isa_resolve(opt->isa);
    const rtt_isect isect = opt->isect == RTT_ISECT_DEFAULT ? RTT_OPTIMIZED_DEFAULT_ISECT : opt->isect;
    if (opt->accel == RTT_ACCEL_BVH) {
        /* a baked .kdt holds a kd-tree: the BVH is built whatever the scene carries */
        e->bvh_kernel = bvh_kernel_find(opt->traversal, isa);
        snprintf(e->kernel_label, sizeof e->kernel_label, "%s/%s", e->bvh_kernel->name,
                 rtt_isa_name(e->bvh_kernel->isa));
        bvh_build_options build = {.leaf_size = 0, .max_depth = opt->max_tree_depth, .threads = opt->threads};
        if (!bvh_build_sah(scene, &build, &e->bvh, err)) {
            free(e);
            return NULL;
        }
        /* the solids bvh-mft's camera path culls back faces of (per scene, apart from the build) */
        if (!bvh_tree_mark_solids(&e->bvh, scene, err)) {
            bvh_tree_free(&e->bvh);
            free(e);
            return NULL;
        }
        /* the leaves carry both the records and the corners: the test is a flag */
        e->bvh.watertight = isect == RTT_ISECT_WATERTIGHT;
        return &e->base;
    }
    if (opt->accel == RTT_ACCEL_PGRID) {
        e->pgrid = pgrid_kernel_find(opt->traversal, isa);
        e->kernel = kd_kernel_find("", isa);
        snprintf(e->kernel_label, sizeof e->kernel_label, "%s/%s", e->pgrid->name, rtt_isa_name(e->pgrid->isa));
    } else {
        e->kernel = kd_kernel_find(opt->traversal, isa);
        snprintf(e->kernel_label, sizeof e->kernel_label, "%s/%s", e->kernel->name, rtt_isa_name(e->kernel->isa));
    }
    if (!flag_degenerate(e, scene, err)) {
        free(e);
        return NULL;
    }
    if (scene->baked) {
        /* the tree the file carries, whatever max_tree_depth asks: rebake to change it */
        adopt_baked(&e->tree, scene->baked);
        if (!kd_baked_tree_verify(scene, &e->tree, opt->threads, err)) {
            free(e->degenerate);
            free(e);
            return NULL;
        }
    } else {
        kd_build_options build = {.max_depth = opt->max_tree_depth, .threads = opt->threads};
        if (!kd_build_sah(scene, &build, &e->tree, err)) {
            free(e->degenerate);
            free(e);
            return NULL;
        }
        e->owns_tree = true;
    }
    if (isect == RTT_ISECT_WATERTIGHT && !attach_corners(e, scene, err)) {
        optimized_destroy(&e->base);
        return NULL;
    }
    return &e->base;
}

static void optimized_destroy(rtt_engine *base)
{
    optimized_engine *e = as_optimized(base);
    if (!e) return;
    free(e->corners);
    e->tree.corners = NULL;
    if (e->owns_tree) kd_tree_free(&e->tree);
    if (e->bvh_kernel) bvh_tree_free(&e->bvh);
    free(e->degenerate);
    if (e->light_scene) pgrid_shadows_free(&e->light_grids);
    free(e);
}

/* The rays in the blocks the kernel reads (consecutive rays, four to a
 * packet): closest hits into `hits`, or with hits NULL occlusion into
 * `occluded`.  Scratch on the stack: engines are shared between threads. */
static void trace_stream(const optimized_engine *e, const rtt_ray *rays, size_t n, rtt_hit *hits, uint8_t *occluded)
{
    const size_t block_rays = 4u * (size_t)kd_kernel_block_packets(e->kernel, e->opt.tile);
    _Alignas(16) ray_packet4 packets[KD_BLOCK_MAX_PACKETS];
    _Alignas(16) hit_packet4 out[KD_BLOCK_MAX_PACKETS];
    uint8_t masks[KD_BLOCK_MAX_PACKETS];
    for (size_t first = 0; first < n; first += block_rays) {
        const size_t count = n - first < block_rays ? n - first : block_rays;
        const uint32_t packet_count = (uint32_t)((count + 3) / 4);
        for (uint32_t p = 0; p < packet_count; p++) {
            ray_packet4_load(&packets[p], &rays[first + 4u * p], (uint32_t)(count - 4u * p < 4 ? count - 4u * p : 4));
            hit_packet4_clear(&out[p]);
            masks[p] = 0;
        }
        const kd_query query = {.packets = packets, .packet_count = packet_count, .hits = hits ? out : NULL,
                                .occluded = hits ? NULL : masks, .leaf_culling = e->opt.leaf_culling};
        e->kernel->trace(&e->tree, &query);
        for (size_t i = 0; i < count; i++) {
            if (hits && i % 4 == 0) hit_packet4_store(&out[i / 4], &hits[first + i], (uint32_t)(count - i));
            if (!hits) occluded[first + i] = (masks[i / 4] >> (i % 4)) & 1u;
        }
    }
}

static void trace_rays(const optimized_engine *e, const rtt_ray *rays, size_t n, rtt_hit *hits, uint8_t *occluded)
{
    if (e->bvh_kernel)
        e->bvh_kernel->trace(&e->bvh, &(bvh_query){.rays = rays, .count = n, .hits = hits, .occluded = occluded});
    else if (e->tree.triangle_count == 0 && hits)
        for (size_t i = 0; i < n; i++) hits[i] = (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS};
    else if (e->tree.triangle_count == 0)
        memset(occluded, 0, n);
    else
        trace_stream(e, rays, n, hits, occluded);
}

/* The power of two that makes a ray's subnormal direction components normal
 * (1 when it has none, or when the largest would overflow).  The kernels
 * step through split planes with 1 / dir, which overflows to infinity for a
 * subnormal component, and a ray creeping towards a plane along one would
 * then never cross it; scaled by a power of two the ray is the same ray, its
 * t scaled exactly. */
static float subnormal_rescale(const rtt_ray *r)
{
    float smallest = INFINITY, largest = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float a = fabsf(r->dir[k]);
        if (a > 0.0f && a < smallest) smallest = a;
        if (a > largest) largest = a;
    }
    if (!(smallest < FLT_MIN) || !isfinite(largest)) return 1.0f;
    float scale = 1.0f;
    while (smallest * scale < FLT_MIN) scale *= 2.0f;
    return largest * scale < 0x1p100f ? scale : 1.0f;
}

/* Rays with subnormal direction components are traced scaled
 * (subnormal_rescale) and their t scaled back; the others as they are.  A
 * hit whose t overflows when scaled back is no hit, as for the reference
 * (fuzz/regressions/kd_build/subnormal_direction_overflowing_t). */
static void trace_rescaled(const optimized_engine *e, const rtt_ray *rays, size_t n, rtt_hit *hits, uint8_t *occluded)
{
    size_t first = 0;
    while (first < n && subnormal_rescale(&rays[first]) == 1.0f) first++;
    if (first == n) {
        trace_rays(e, rays, n, hits, occluded);
        return;
    }
    rtt_ray *scaled = malloc(n * sizeof *scaled);
    float *scales = malloc(n * sizeof *scales);
    if (!scaled || !scales) { /* out of memory: the rays as they are */
        free(scaled);
        free(scales);
        trace_rays(e, rays, n, hits, occluded);
        return;
    }
    for (size_t i = 0; i < n; i++) {
        scaled[i] = rays[i];
        scales[i] = subnormal_rescale(&rays[i]);
        if (scales[i] == 1.0f) continue;
        for (int k = 0; k < 3; k++) scaled[i].dir[k] *= scales[i];
        scaled[i].tnear /= scales[i];
        /* a t past FLT_MAX is infinite where the ray is (never below its
         * tfar): the scaled ray stops where t * scale would overflow,
         * 2^128 / scale, exclusive (FLT_MAX itself still counts) */
        scaled[i].tfar = rays[i].tfar > FLT_MAX ? 0x1p127f / scales[i] * 2.0f : rays[i].tfar / scales[i];
    }
    trace_rays(e, scaled, n, hits, occluded);
    for (size_t i = 0; hits && i < n; i++)
        if (hits[i].prim != RTT_MISS) hits[i].t *= scales[i];
    free(scaled);
    free(scales);
}

static void optimized_intersect(rtt_engine *base, const rtt_ray *rays, rtt_hit *hits, size_t n)
{
    trace_rescaled((const optimized_engine *)base, rays, n, hits, NULL);
}

static void optimized_occluded(rtt_engine *base, const rtt_ray *rays, uint8_t *occluded, size_t n)
{
    trace_rescaled((const optimized_engine *)base, rays, n, NULL, occluded);
}

static bool optimized_tree_info(rtt_engine *base, rtt_tree_info *info)
{
    optimized_engine *e = (optimized_engine *)base;
    *info = e->bvh_kernel ? e->bvh.info : e->tree.info;
    return true;
}

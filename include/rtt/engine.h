/* The engine interface: the seam every check uses (DESIGN.md).
 *
 * An engine traces arbitrary streams of rays against one scene.  Three exist:
 * "reference" (reference/), "optimized" (optimized/) and "embree"
 * (conformance/, only when built with RTT_EMBREE).  The registry that maps a
 * name to its constructor lives in conformance/engine_registry.c because only
 * that layer may see all three.  */
#ifndef RTT_ENGINE_H
#define RTT_ENGINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/scene.h"

#define RTT_MISS 0xFFFFFFFFu

/* 32 bytes, little-endian on disk in rays.bin. A hit counts only for
 * tnear < t < tfar. */
typedef struct rtt_ray {
    float org[3], dir[3], tnear, tfar;
} rtt_ray;
_Static_assert(sizeof(rtt_ray) == 32, "rtt_ray is a 32-byte file record");

/* 16 bytes; prim = RTT_MISS and t = +inf on a miss.  u, v are the barycentric
 * coordinates of vertices 1 and 2. */
typedef struct rtt_hit {
    float t, u, v;
    uint32_t prim;
} rtt_hit;
_Static_assert(sizeof(rtt_hit) == 16, "rtt_hit is a 16-byte file record");

/* Traversal kernels of the optimized engine (Thesis chapters 2 and 4). */
typedef enum rtt_traversal {
    RTT_TRAVERSAL_MONO = 0,    /* Listing 2.2, one ray, explicit stack */
    RTT_TRAVERSAL_PACKET,      /* Listing 2.4, 2x2 packets, equal signs */
    RTT_TRAVERSAL_OMNI,        /* Listing 4.1, omni-directional 2x2 */
    RTT_TRAVERSAL_FRUSTUM,     /* Listing 4.2 + 4.1.4 culling */
    RTT_TRAVERSAL_MFT,         /* 4.1.5 multiple frustum traversal */
    RTT_TRAVERSAL_CONE,        /* Listings 4.3 - 4.5 */
    RTT_TRAVERSAL_MFT_CONE,    /* four cones per tile */
    RTT_TRAVERSAL_COUNT
} rtt_traversal;

typedef struct rtt_engine_options {
    rtt_traversal traversal;   /* optimized engine only */
    uint32_t tile;             /* frustum tile side: 4, 8, 16, 32 (default 8) */
    int leaf_culling;          /* packet/leaf culling on (1, default) or off (0) */
    uint32_t max_tree_depth;   /* 0 → rtt_kd_default_max_depth */
    uint32_t threads;          /* 0 → one per core */
} rtt_engine_options;

typedef struct rtt_engine rtt_engine;

/* Both kd-tree builders' depth bound when the options leave it at 0:
 * round(2 + log2 N), at least 8.  The thesis fixes a maximum depth, not its
 * value; pbrt's 8 + 1.3 log2 N let the SAH carve the CGAL meshes down to
 * 7-9 references per triangle (62 MB for bunny00), and a sweep of the bound
 * put the optimum of the mesh views at log2 N .. log2 N + 2, the Quake maps
 * indifferent (bench/results/tree-depth.md).  N counts the
 * triangles the builder keeps. */
uint32_t rtt_kd_default_max_depth(uint32_t triangles);

/* What `rtt info` reports of an engine's acceleration structure. */
typedef struct rtt_tree_info {
    uint32_t depth;               /* deepest leaf */
    uint32_t max_depth;           /* the bound the builder held */
    uint32_t node_count, leaf_count, empty_leaf_count;
    uint64_t references;          /* triangle references in leaves (duplication = references / triangles) */
    uint64_t reference_cap;       /* the builder's cap on duplicated references */
    double sah_cost;              /* expected cost of the tree (C_trav = 1, C_isect = 5) */
    double build_seconds;
    uint64_t memory_bytes;
} rtt_tree_info;

/* What an engine implements.  Engines embed `rtt_engine` as their first member. */
typedef struct rtt_engine_vtable {
    const char *name;
    void (*intersect)(rtt_engine *, const rtt_ray *rays, rtt_hit *hits, size_t n);
    void (*occluded)(rtt_engine *, const rtt_ray *rays, uint8_t *occluded, size_t n);
    void (*destroy)(rtt_engine *);
    /* optional (NULL when the engine has no kd-tree, e.g. Embree) */
    bool (*tree_info)(rtt_engine *, rtt_tree_info *);
} rtt_engine_vtable;

struct rtt_engine {
    const rtt_engine_vtable *vt;
    const rtt_scene *scene;
};

/* name: "reference", "optimized" or "embree".  opt may be NULL (defaults). */
rtt_engine *rtt_engine_create(const char *name, const rtt_scene *scene, const rtt_engine_options *opt,
                              rtt_error *err);
void rtt_engine_intersect(rtt_engine *engine, const rtt_ray *rays, rtt_hit *hits, size_t n);
void rtt_engine_occluded(rtt_engine *engine, const rtt_ray *rays, uint8_t *occluded, size_t n);
void rtt_engine_destroy(rtt_engine *engine);
/* False when the engine has no kd-tree to describe. */
bool rtt_engine_tree_info(rtt_engine *engine, rtt_tree_info *info);

/* Fills defaults: mono traversal, tile 8, leaf culling on. */
void rtt_engine_options_default(rtt_engine_options *opt);
const char *rtt_traversal_name(rtt_traversal t);
/* Returns -1 for an unknown name. */
int rtt_traversal_parse(const char *name);

#endif

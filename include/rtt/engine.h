/* The engine interface: the seam every check uses.
 *
 * An engine traces arbitrary streams of rays against one scene and renders
 * it.  Engines register themselves by name (rtt_engine_register); the
 * built-in ones are "reference" (reference/), "optimized" (optimized/) and,
 * in builds with Embree, "embree" (conformance/, the only layer that links
 * Embree).  rtt_builtin_engines_register() (include/rtt/rtt.h) registers the
 * first two.  The interface, the registry and the options check live in
 * engine/, a library below every engine. */
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

/* Acceleration structures.  Each has its own kernel descriptor table in the
 * engine that implements it; kernels are named there and nowhere else. */
typedef enum rtt_accel {
    RTT_ACCEL_DEFAULT = 0,   /* the engine's own choice */
    RTT_ACCEL_KD,            /* SAH kd-tree with perfect splits (the thesis) */
    RTT_ACCEL_BVH,           /* binned SAH BVH, two child boxes per 64-byte node (Benthin & Wald 2009) */
    RTT_ACCEL_PGRID,         /* per-frame perspective grids for eye rays (Hunt & Mark 2008) */
    RTT_ACCEL_COUNT
} rtt_accel;

/* Instruction sets the kernels are compiled for.  AUTO takes $RTT_ISA when
 * it is set (auto, sse4, avx2, avx512), else the widest the CPU has. */
typedef enum rtt_isa {
    RTT_ISA_AUTO = 0,
    RTT_ISA_SSE4,            /* SSE4.1: every x86-64 rtt runs on */
    RTT_ISA_AVX2,            /* AVX2 + FMA */
    RTT_ISA_AVX512,          /* AVX-512 F, BW, DQ, VL */
    RTT_ISA_COUNT
} rtt_isa;

/* Ray/triangle tests of the production path.  DEFAULT is the engine's
 * choice (the optimized engine's: watertight, bench/results/accuracy.md). */
typedef enum rtt_isect {
    RTT_ISECT_DEFAULT = 0,
    RTT_ISECT_WATERTIGHT,    /* Woop, Benthin & Wald 2013: no ray slips through a shared edge */
    RTT_ISECT_PROJECTED,     /* Wald's projected barycentric test: not watertight */
    RTT_ISECT_COUNT
} rtt_isect;

/* Bits of rtt_engine_options.given and of an engine's `uses`: which options
 * a caller set on purpose, and which an engine reads.  An option given to an
 * engine that does not read it is an error (rtt_engine_options_check), so a
 * setting is never silently ignored. */
enum {
    RTT_OPTION_ACCEL = 1u << 0,
    RTT_OPTION_TRAVERSAL = 1u << 1,
    RTT_OPTION_TILE = 1u << 2,
    RTT_OPTION_LEAF_CULLING = 1u << 3,
    RTT_OPTION_MAX_DEPTH = 1u << 4,
    RTT_OPTION_ISA = 1u << 5,
    RTT_OPTION_ISECT = 1u << 6,
};

#define RTT_TRAVERSAL_NAME_MAX 32u
#define RTT_TILE_MAX 32u /* the largest tile side rtt_engine_options.tile takes */

typedef struct rtt_engine_options {
    rtt_accel accel;
    char traversal[RTT_TRAVERSAL_NAME_MAX]; /* a kernel of the accel's table; "" → the engine's default */
    uint32_t tile;             /* block tile side: 4, 8, 16, 32 (0 → 8) */
    int leaf_culling;          /* packet/leaf culling on (1, default) or off (0) */
    uint32_t max_tree_depth;   /* 1..64; 0 → rtt_kd_default_max_depth */
    rtt_isa isa;
    rtt_isect isect;           /* the triangle test */
    uint32_t threads;          /* build threads; 0 → one per core */
    uint32_t given;            /* RTT_OPTION_* bits the caller set on purpose */
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
#define RTT_KD_DEPTH_LIMIT 64u

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

struct rtt_render_options;
struct rtt_render_stats;
struct rtt_image;

/* What an engine instance implements.  Engines embed `rtt_engine` as their
 * first member. */
typedef struct rtt_engine_vtable {
    const char *name;
    void (*intersect)(rtt_engine *, const rtt_ray *rays, rtt_hit *hits, size_t n);
    void (*occluded)(rtt_engine *, const rtt_ray *rays, uint8_t *occluded, size_t n);
    /* the whole image; options already checked by rtt_render */
    bool (*render)(rtt_engine *, const struct rtt_render_options *, struct rtt_image *,
                   struct rtt_render_stats *, rtt_error *);
    void (*destroy)(rtt_engine *);
    /* optional (NULL when the engine has no tree of its own to describe, e.g. Embree) */
    bool (*tree_info)(rtt_engine *, rtt_tree_info *);
    /* the kernel and instruction set the engine traces with, for reports
     * (NULL: the engine has none to name) */
    const char *(*kernel_name)(rtt_engine *);
    /* the ray/triangle test it traces with, "watertight" or "projected"
     * (rtt_isect_name); NULL: neither (e.g. Embree's own) */
    const char *(*isect_name)(rtt_engine *);
} rtt_engine_vtable;

struct rtt_engine {
    const rtt_engine_vtable *vt;
    const rtt_scene *scene;
};

/* An engine as the registry knows it, before any scene: its constructor,
 * the options it reads and the shadow methods its renderer draws. */
typedef struct rtt_engine_class {
    const char *name;
    const char *summary;                 /* one line for --help */
    uint32_t uses;                       /* RTT_OPTION_* bits it reads */
    uint32_t shadow_methods;             /* bit (1 << rtt_shadow_method) per method it renders */
    bool adopts_baked_tree;              /* a scene's baked .kdt tree is used as is: build options do not apply */
    rtt_engine *(*create)(const rtt_scene *, const rtt_engine_options *, rtt_error *);
    /* optional: engine-specific checks (kernel names, accel) beyond the
     * generic ones; called by rtt_engine_options_check */
    bool (*check)(const rtt_engine_options *, rtt_error *);
    /* optional: the i-th kernel name of the accel's table (i from 0), NULL
     * past the last; `rtt render --help` and the bench list them */
    const char *(*kernel)(rtt_accel accel, uint32_t i);
} rtt_engine_class;

/* Adds a class to the registry (at most 16; a second class of the same name
 * replaces the first).  Thread-safe; classes must outlive the process. */
bool rtt_engine_register(const rtt_engine_class *cls, rtt_error *err);
/* NULL when no engine of that name is registered. */
const rtt_engine_class *rtt_engine_find(const char *name);
/* The i-th registered class, NULL past the last. */
const rtt_engine_class *rtt_engine_class_at(uint32_t i);

/* Checks `opt` for engine `name`: known accel, a traversal of its table,
 * tile 0/4/8/16/32, depth 0..64, a known instruction set the CPU has, and no
 * option in `opt->given` that the engine does not read.  One line in err. */
bool rtt_engine_options_check(const char *name, const rtt_engine_options *opt, rtt_error *err);
/* The same for a class in hand (engine constructors called directly use it). */
bool rtt_engine_class_check(const rtt_engine_class *cls, const rtt_engine_options *opt, rtt_error *err);

/* Rays given in the scene's own coordinates (rays.bin, a user's rays) moved
 * into its stored ones (origin minus rtt_scene.origin, in double): what an
 * engine traces.  t, u, v and prim are the same in both. */
void rtt_rays_to_stored(const rtt_scene *scene, rtt_ray *rays, size_t n);
/* The reverse, for rays an engine's caller generated from the scene (the
 * conformance sets) and writes out for `rtt trace --rays`. */
void rtt_rays_from_stored(const rtt_scene *scene, rtt_ray *rays, size_t n);

/* name: a registered engine.  opt may be NULL (defaults).  Checks the
 * options (rtt_engine_options_check) before building anything. */
rtt_engine *rtt_engine_create(const char *name, const rtt_scene *scene, const rtt_engine_options *opt,
                              rtt_error *err);
void rtt_engine_intersect(rtt_engine *engine, const rtt_ray *rays, rtt_hit *hits, size_t n);
void rtt_engine_occluded(rtt_engine *engine, const rtt_ray *rays, uint8_t *occluded, size_t n);
void rtt_engine_destroy(rtt_engine *engine);
/* False when the engine has no tree to describe. */
bool rtt_engine_tree_info(rtt_engine *engine, rtt_tree_info *info);
/* "mft/avx512" style: the kernel and instruction set in use; "" when none. */
const char *rtt_engine_kernel_name(rtt_engine *engine);

/* "watertight" or "projected": the triangle test in use; "" when the engine
 * names none (Embree). */
const char *rtt_engine_isect_name(rtt_engine *engine);

/* Fills defaults: the engine's default accel and traversal, tile 8, leaf
 * culling on, ISA auto, nothing given. */
void rtt_engine_options_default(rtt_engine_options *opt);

/* Instruction sets by name ("auto", "sse4", "avx2", "avx512"). */
const char *rtt_isa_name(rtt_isa isa);
bool rtt_isa_parse(const char *name, rtt_isa *out);
/* Whether this CPU (and OS) can run code of that instruction set. */
bool rtt_isa_supported(rtt_isa isa);
/* The instruction set AUTO stands for here: $RTT_ISA when set and valid,
 * else the widest supported.  A concrete request is returned as is. */
rtt_isa rtt_isa_resolve(rtt_isa requested);
/* This CPU's L2 cache per core, in bytes, as the C library reports it; 0
 * when it does not know (kernels that size their working sets by it keep
 * their measured defaults then). */
size_t rtt_cpu_l2_bytes(void);
/* Triangle tests by name ("watertight", "projected"). */
const char *rtt_isect_name(rtt_isect isect);
bool rtt_isect_parse(const char *name, rtt_isect *out);
/* Accels by name ("kd"). */
const char *rtt_accel_name(rtt_accel accel);
bool rtt_accel_parse(const char *name, rtt_accel *out);

#endif

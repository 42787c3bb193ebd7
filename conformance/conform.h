/* The hit-by-hit conformance suite (docs/ARCHITECTURE.md "Conformance"): ray sets,
 * the comparison of one engine's hits against an oracle's, the tolerance on
 * t, and the report (a text table and JSON).  conformance/README.md states
 * every rule and threshold used here.  Library code: it never prints; the
 * report is returned as text for cli/ to print. */
#ifndef RTT_CONFORM_H
#define RTT_CONFORM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/scene.h"

typedef enum rtt_conform_ray_set {
    RTT_CONFORM_PRIMARY = 0, /* one ray per pixel of the scene's camera, in 8x8 tile order */
    RTT_CONFORM_SHADOW,      /* from the reference's primary hits to every light centre */
    RTT_CONFORM_RANDOM,      /* origins in and around the bounds, random directions, fixed seed */
    RTT_CONFORM_EXTREME,     /* axis-parallel, -0.0, vertex- and edge-aimed, on-surface, NaN/Inf */
    RTT_CONFORM_RAY_SET_COUNT
} rtt_conform_ray_set;

const char *rtt_conform_ray_set_name(rtt_conform_ray_set set);
/* -1 for an unknown name. */
int rtt_conform_ray_set_parse(const char *name);

/* Fills *rays (malloc'd, caller frees) with at most max_rays rays of the
 * set (max_rays 0 → the default of 65536; the primary set is then rendered
 * at a lower resolution of the same aspect).  The shadow set needs the
 * reference engine (its primary hits); the others ignore it. */
bool rtt_conform_make_rays(const rtt_scene *scene, rtt_conform_ray_set set, rtt_engine *reference,
                           size_t max_rays, uint64_t seed, rtt_ray **rays, size_t *count, rtt_error *err);

/* The ray kinds `rtt rays` writes (conform_ray_kinds.c): the sets above and
 * the extremes' patterns one at a time, by index (name and summary NULL past
 * the last).  rtt_conform_make_kind fills *rays (malloc'd) with at most n
 * rays of kind `kind`, from the suite's own generators; `reference` is needed
 * by the shadow kind only. */
const char *rtt_conform_kind_name(size_t kind);
const char *rtt_conform_kind_summary(size_t kind);
bool rtt_conform_make_kind(const rtt_scene *scene, size_t kind, rtt_engine *reference, size_t n, uint64_t seed,
                           rtt_ray **rays, size_t *count, rtt_error *err);

/* The categories one ray falls in when an engine's hit is compared with the
 * oracle's. */
typedef enum rtt_conform_category {
    RTT_CONFORM_AGREE = 0,     /* same prim and t within tolerance, or both miss */
    RTT_CONFORM_TIE,           /* different prims hit at the same point (same t, or one plane crossing) */
    RTT_CONFORM_BOUNDARY,      /* a hit within tolerance of tnear or tfar: unspecified */
    RTT_CONFORM_T_MISMATCH,    /* both hit, but not the same hit and not a tie */
    RTT_CONFORM_GRAZING,       /* hit/miss where the hit lies within tolerance of an edge */
    RTT_CONFORM_HITMISS_OTHER, /* any other hit/miss disagreement */
    RTT_CONFORM_CATEGORY_COUNT
} rtt_conform_category;

const char *rtt_conform_category_name(rtt_conform_category c);

/* The largest magnitude of any coordinate of the scene's bounds. */
float rtt_conform_scene_magnitude(const rtt_scene *scene);
/* Tolerance on t for a hit at t along ray r:
 *   1e-5 * (|t| + (max|org| + magnitude) / |dir|)  */
double rtt_conform_t_tolerance(const rtt_ray *r, double t, double magnitude);
/* Classifies the hit `test` against `oracle` for ray r. */
rtt_conform_category rtt_conform_classify(const rtt_scene *scene, double magnitude, const rtt_ray *r,
                                          const rtt_hit *test, const rtt_hit *oracle);

/* Thresholds a row must meet (conformance/README.md). */
#define RTT_CONFORM_GRAZING_SHARE_OPTIMIZED 0.0005 /* 0.05% of the rays */
#define RTT_CONFORM_GRAZING_SHARE_EMBREE 0.01      /* 1%, as Embree's own verify tool allows */

/* One engine pair on one ray set. */
typedef struct rtt_conform_row {
    char engine[40];                           /* "optimized/frustum", "embree", ... */
    char oracle[16];                           /* always "reference" */
    rtt_conform_ray_set set;
    uint64_t rays;
    uint64_t count[RTT_CONFORM_CATEGORY_COUNT];
    uint64_t occluded_mismatch;                /* occluded() disagrees where intersect() agreed */
    double grazing_limit;                      /* allowed share of grazing hit/miss */
    bool pass;
    char error[256];                           /* non-empty when the engine could not run */
} rtt_conform_row;

typedef struct rtt_conform_report {
    char scene[512];
    uint32_t triangles;
    double magnitude;
    rtt_conform_row *rows;
    size_t row_count, row_cap;
    bool pass;
} rtt_conform_report;

/* What to run.  engines: a comma-separated list of "optimized" (every
 * traversal mode, tile 8), "optimized/MODE", "embree", "reference" (the
 * reference against itself: a determinism check); NULL → "optimized" plus
 * "embree" when built with it. */
typedef struct rtt_conform_config {
    bool sets[RTT_CONFORM_RAY_SET_COUNT];
    const char *engines;
    size_t max_rays;
    uint64_t seed;
    rtt_isa isa;           /* given to each listed engine that reads an instruction-set choice;
                              RTT_ISA_AUTO (default): each engine's own ($RTT_ISA, else the widest) */
    rtt_isect isect;       /* likewise the triangle test; RTT_ISECT_DEFAULT: each engine's own */
} rtt_conform_config;

void rtt_conform_config_default(rtt_conform_config *config);
/* "optimized,embree" when built with Embree, else "optimized". */
const char *rtt_conform_default_engines(void);

/* One engine to run: a registry name, its options and the label reports use. */
typedef struct rtt_conform_engine_spec {
    char label[40];
    const char *name;
    rtt_engine_options opt;
} rtt_conform_engine_spec;

/* Expands an engine list (see rtt_conform_config) into at most cap specs.
 * Returns the count, or -1 with err on an unknown entry. */
/* Registers every engine of this build (reference, optimized, and embree
 * when built with it) by name; idempotent. */
bool rtt_conform_register_engines(rtt_error *err);

int rtt_conform_expand_engines(const char *list, rtt_conform_engine_spec *specs, int cap, rtt_error *err);
/* Gives instruction set `isa` and triangle test `isect` to each spec whose
 * engine reads them (AUTO and DEFAULT leave the specs as they are). */
void rtt_conform_specs_set_isa(rtt_conform_engine_spec *specs, int count, rtt_isa isa, rtt_isect isect);
/* Checks an engine list without running anything. */
bool rtt_conform_engines_valid(const char *engines, rtt_error *err);

/* Runs every engine on every selected set against the reference.  Fails
 * (false + err) only when the reference itself cannot run; an engine that
 * cannot be created gives a failing row with its message. */
bool rtt_conform_run(const rtt_scene *scene, const rtt_conform_config *config, rtt_conform_report *report,
                     rtt_error *err);
/* Compares precomputed hits (one row); used by rtt_conform_run and tests. */
void rtt_conform_compare(const rtt_scene *scene, const rtt_ray *rays, const rtt_hit *test, const uint8_t *test_occluded,
                         const rtt_hit *oracle, size_t n, rtt_conform_row *row);
/* Sets row->pass from its counts and grazing_limit. */
void rtt_conform_row_judge(rtt_conform_row *row);
void rtt_conform_report_free(rtt_conform_report *report);

/* The report as a text table or JSON; malloc'd, NULL when out of memory. */
char *rtt_conform_report_table(const rtt_conform_report *report);
char *rtt_conform_report_json(const rtt_conform_report *report);

#endif

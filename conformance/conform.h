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
    RTT_CONFORM_FILE,        /* the caller's rays (rtt_conform_config.file_rays), judged as the random set */
    RTT_CONFORM_RAY_SET_COUNT
} rtt_conform_ray_set;

const char *rtt_conform_ray_set_name(rtt_conform_ray_set set);
/* -1 for an unknown name, and for "file" (its rays come from the caller). */
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
 * rays of kind `kind`, from the suite's own generators, in the scene's own
 * coordinates (what rays.bin holds and rtt trace reads; the origins are
 * rounded to float once more on the way); `reference` is needed by the
 * shadow kind only. */
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
    RTT_CONFORM_UNSPECIFIED,   /* a ray outside Embree's range, not handed to it (embree rows only) */
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

/* The double-precision referee (conform_referee.c): a brute force over
 * every triangle with the watertight test in double.  `prim` is RTT_MISS
 * when nothing is hit in (tnear, tfar).  False (and a miss) for a ray it
 * cannot decide: a non-finite origin or direction, a NaN bound, an empty
 * interval, a zero direction. */
typedef struct rtt_conform_referee_hit {
    double t;
    uint32_t prim;
} rtt_conform_referee_hit;

bool rtt_conform_referee(const rtt_scene *scene, const rtt_ray *r, rtt_conform_referee_hit *out);
/* Whether the referee can decide r (the conditions above). */
bool rtt_conform_ray_decidable(const rtt_ray *r);
/* The referee's hit as an rtt_hit (t rounded to float, no barycentrics). */
rtt_hit rtt_conform_referee_as_hit(const rtt_conform_referee_hit *h);
/* Does the referee accept `h` as the answer to r?  The classifier against
 * the referee's hit gives agree, tie or boundary. */
bool rtt_conform_referee_accepts(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *h,
                                 const rtt_conform_referee_hit *referee);
/* Ray-triangle tests the referee may spend in one run of rtt_conform_run:
 * about 10 s of one core.  Disagreements beyond it are judged as if the
 * referee had sided with the oracle (counted as `unrefereed`). */
#define RTT_CONFORM_REFEREE_BUDGET 2000000000ull

/* Thresholds a row must meet (conformance/README.md). */
#define RTT_CONFORM_GRAZING_SHARE_OPTIMIZED 0.0005 /* 0.05% of the rays */
#define RTT_CONFORM_GRAZING_SHARE_EMBREE 0.01      /* 1%, as Embree's own verify tool allows */

/* What the referee said about a disagreement. */
typedef enum rtt_conform_verdict {
    RTT_VERDICT_NONE = 0,         /* not refereed: beyond the budget, or no referee (rtt_conform_compare) */
    RTT_VERDICT_ENGINE_WRONG,     /* the engine of the row disagrees with the referee (an error of the row) */
    RTT_VERDICT_REFERENCE_WRONG,  /* the reference disagrees, the engine agrees; on the embree row an error */
    RTT_VERDICT_EMBREE_WRONG,     /* Embree disagrees, the reference agrees: counted apart, never an error */
    RTT_VERDICT_BOTH_RIGHT,       /* the referee accepts both answers (a tie, a boundary hit) */
    RTT_VERDICT_UNDECIDABLE,      /* the referee cannot take the ray (it never can when an engine could) */
} rtt_conform_verdict;

const char *rtt_conform_verdict_name(rtt_conform_verdict v);

/* One disagreeing ray, as the report names it.  The ray's origin is in the
 * scene's own coordinates (as in --failing-rays and rays.bin). */
typedef struct rtt_conform_ray_note {
    uint32_t index;             /* in its ray set */
    int64_t file_index;         /* its record in the failing-rays file; -1 when not in it */
    rtt_ray ray;
    rtt_hit engine, oracle;     /* intersect() of each */
    uint8_t engine_occluded;    /* occluded() of the engine */
    bool occluded;              /* the disagreement is in occluded(), intersect() agreed */
    rtt_conform_category category; /* the engine's answer against the oracle's */
    /* the refused answer (the engine's, or the reference's when the verdict
     * is reference wrong) against the referee's hit: the category its error
     * counts in; RTT_CONFORM_CATEGORY_COUNT when not refereed */
    rtt_conform_category judged;
    rtt_conform_verdict verdict;
    rtt_conform_referee_hit referee;
} rtt_conform_ray_note;

#define RTT_CONFORM_NOTES 8 /* rays named per row and kind */

/* One engine pair on one ray set. */
typedef struct rtt_conform_row {
    char engine[40];                           /* "optimized/frustum", "embree", ... */
    bool engine_is_embree_row;                 /* the engine is Embree: the rtt side judged is the reference */
    char oracle[16];                           /* always "reference" */
    rtt_conform_ray_set set;
    uint64_t rays;
    uint64_t count[RTT_CONFORM_CATEGORY_COUNT];
    uint64_t occluded_mismatch;                /* occluded() disagrees where intersect() agreed */
    /* The errors of the row's own rtt side after the referee (the engine;
     * on the embree row the reference), per category, and its occluded()
     * errors: the thresholds apply to these.  Without a referee they equal
     * count[] and occluded_mismatch. */
    uint64_t errors[RTT_CONFORM_CATEGORY_COUNT];
    uint64_t occluded_errors;
    uint64_t refereed, unrefereed;             /* disagreements the referee decided / left (budget) */
    uint64_t embree_wrong, reference_wrong, both_right;
    rtt_conform_ray_note failing[RTT_CONFORM_NOTES]; /* the first errors of the row */
    size_t failing_count;
    rtt_conform_ray_note wrong_oracle[RTT_CONFORM_NOTES]; /* the first Embree-wrong or reference-wrong rays */
    size_t wrong_oracle_count;
    uint32_t *error_rays;                      /* every error's index in the set (rtt_conform_run only) */
    size_t error_ray_count, error_ray_cap;
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
    /* The errors of every failing row, each ray once, in the scene's own
     * coordinates: what --failing-rays writes (rtt trace --rays replays it). */
    rtt_ray *failing_rays;
    size_t failing_ray_count;
    uint64_t failing_rays_inexact;             /* of those, rays whose origin does not round-trip exactly */
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
    bool referee_every_ray;   /* the referee decides every ray, not only disagreements (within its budget) */
    const rtt_ray *file_rays; /* non-NULL: trace only these (the "file" set), in the scene's own coordinates */
    size_t file_ray_count;
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
/* The referee's state on one ray set of a run: its answers, asked lazily,
 * and the budget (ray-triangle tests) shared by every set of the run. */
typedef struct rtt_conform_referee_cache {
    rtt_conform_referee_hit *hits; /* per ray of the set, NULL until first asked */
    uint8_t *state;                /* per ray: 0 not asked, 1 decided, 2 undecidable */
    size_t n;
    uint64_t *budget;
} rtt_conform_referee_cache;
void rtt_conform_referee_cache_free(rtt_conform_referee_cache *cache);

/* How one row's disagreements are judged. */
typedef struct rtt_conform_judging {
    rtt_conform_referee_cache *referee; /* NULL: no referee, errors are the disagreements */
    bool engine_is_embree;              /* the engine of the row is Embree (its errors are "Embree wrong") */
    bool collect;                       /* keep every error's index (row->error_rays) */
    bool every_ray;                     /* the referee also decides rays engine and oracle agree on */
} rtt_conform_judging;

/* Compares precomputed hits of one row, judged as `judging` says. */
bool rtt_conform_compare_judged(const rtt_scene *scene, const rtt_ray *rays, const rtt_hit *test,
                                const uint8_t *test_occluded, const rtt_hit *oracle, size_t n, rtt_conform_row *row,
                                const rtt_conform_judging *judging);
/* Compares precomputed hits (one row) without a referee; used by the
 * extremes and tests. */
void rtt_conform_compare(const rtt_scene *scene, const rtt_ray *rays, const rtt_hit *test, const uint8_t *test_occluded,
                         const rtt_hit *oracle, size_t n, rtt_conform_row *row);
/* Sets row->pass from its counts and grazing_limit. */
void rtt_conform_row_judge(rtt_conform_row *row);
void rtt_conform_report_free(rtt_conform_report *report);
/* Frees a row's error list (rows of rtt_conform_compare_judged with collect). */
void rtt_conform_row_free(rtt_conform_row *row);

/* The report as a text table or JSON; malloc'd, NULL when out of memory. */
char *rtt_conform_report_table(const rtt_conform_report *report);
char *rtt_conform_report_json(const rtt_conform_report *report);

#endif

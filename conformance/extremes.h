/* The numerical-extremes suite (`rtt conform --extremes`): scenes built in
 * code that stress precision and robustness, run through every engine.
 * Each result is one check on one engine; a check is either asserted (it
 * decides pass/fail) or measured and reported only.  conformance/README.md
 * lists what holds per engine. */
#ifndef RTT_EXTREMES_H
#define RTT_EXTREMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "conform.h"
#include "rtt/error.h"

typedef struct rtt_extreme_result {
    char check[48];          /* "scale 1e-20", "watertight sphere", ... */
    char engine[40];
    uint64_t rays;           /* rays traced (0 for checks without rays) */
    uint64_t failures;       /* what the check counts as wrong: escapes, hits on invalid rays, ... */
    bool has_counts;         /* row holds a hit-by-hit comparison */
    rtt_conform_row row;
    bool asserted;           /* counts towards pass/fail */
    bool pass;
    char note[200];          /* what was measured, in words */
} rtt_extreme_result;

typedef struct rtt_extremes_report {
    rtt_extreme_result *items;
    size_t count, cap;
    bool pass;
} rtt_extremes_report;

typedef struct rtt_extremes_config {
    const char *engines;     /* as rtt_conform_config; NULL → default */
    const char *mesh_dir;    /* closed benchmark meshes; NULL → ${RTT_DATA_DIR:-~/.cache/rtt-data}/meshes */
    size_t max_rays;         /* per check (default 8192); watertight meshes sample their vertices to fit */
    double embree_escape_limit; /* share of escaping rays allowed from Embree (default 0.02) */
    rtt_isa isa;             /* as rtt_conform_config */
    rtt_isect isect;         /* as rtt_conform_config */
} rtt_extremes_config;

void rtt_extremes_config_default(rtt_extremes_config *config);
/* Runs every check; false only when a scene cannot be built. */
bool rtt_extremes_run(const rtt_extremes_config *config, rtt_extremes_report *report, rtt_error *err);
void rtt_extremes_report_free(rtt_extremes_report *report);
char *rtt_extremes_report_table(const rtt_extremes_report *report);
char *rtt_extremes_report_json(const rtt_extremes_report *report);

/* Scenes of the suite, exposed for tests: 9 floats per triangle, malloc'd.
 * A closed UV sphere of radius r around c (shared vertices bit-identical). */
float *rtt_extremes_sphere(uint32_t segments, uint32_t rings, float radius, const float centre[3], uint32_t *count);
/* Rays from `inside` to every vertex and every edge midpoint of the scene's
 * triangles (each edge once per triangle), at most max (evenly sampled).
 * `inside` and the rays are in the scene's stored coordinates
 * (rtt_scene_point_to_stored; rtt_ext_inside_point gives such a point). */
rtt_ray *rtt_extremes_watertight_rays(const rtt_scene *scene, const float inside[3], size_t max, size_t *count);

#endif

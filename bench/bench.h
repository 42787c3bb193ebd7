/* rtt bench: the thesis' tables on one scene, raced against Embree on the
 * same rays in the same process (Thesis Tables 3.1, 4.1 - 4.6, 5.1,
 * 6.2).  Library code: it never prints; reports come back as text (table,
 * Markdown, JSON, TSV) for cli/ to print or write.
 *
 * Five kinds of row, each measured as the median of `frames` timed frames
 * after `warmup` untimed ones, with the thread count of the row:
 *
 *   primary  the traversal kernels alone on the camera's primary rays,
 *            pre-formed into tile blocks of 2x2 packets exactly as
 *            render_optimized.c forms them; the Embree peer traces the very
 *            same rays (rtcIntersect1, and rtcIntersect4/8/16 over 2x2, 4x2
 *            and 4x4 pixel blocks with the coherent context flag).  Both
 *            sides reset their hit records inside the timed frame and run
 *            through the same tile scheduler (rtt_tiles_run).
 *   shadow   hard-shadow rays (primary hit to the light's centre) through
 *            our occlusion kernels and rtcOccluded1/rtcOccluded16.
 *   render   full frames of the optimized renderer (rtt_optimized_render):
 *            every traversal, and every shadow method the renderer has.
 *   build    kd-tree build (one thread) and BVH build (the frames' median
 *            at each thread count) time and memory against Embree's BVH
 *            build (high quality, one thread) per Embree variant.
 *   soft     soft shadows: each primary hit's 16 interleaved samples of the
 *            first light (which must have area): our frusta:16 kernel
 *            (rays made on demand), our bvh-packet and Embree's
 *            rtcOccluded16 (coherent flag) with one pixel's 16 rays per
 *            packet (bench_frusta.c); then multi:8's rays (8 samples per
 *            hit): Embree's rtcOccluded8 one pixel per packet, pgrid:8 (the
 *            3D light grid, its build row beside it) and Table 5's
 *            uniform-grid step counts (bench_pgrid.c, bench_grid3d.c).
 *   The BVH kernels (bvh-mono, bvh-packet) race on the same primary and
 *   shadow rays, 16x16 tiles of 4x4 pixel blocks (bench_bvh.c).
 *
 * N and I (traversal steps and intersection tests per 2x2 packet) come from
 * one extra counting frame, never from a timed one. */
#ifndef RTT_BENCH_H
#define RTT_BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/error.h"
#include "rtt/scene.h"

#define RTT_BENCH_MAX_THREADS 4u
#define RTT_BENCH_MAX_LIGHT_RES 8u     /* --pgrid-light-res entries */
#define RTT_BENCH_LIGHT_RES_MOST 2048u /* the light grids' most cells per face side (PGRID_LIGHT_RES_MAX) */

typedef enum rtt_bench_kind {
    RTT_BENCH_PRIMARY = 0,
    RTT_BENCH_SHADOW,
    RTT_BENCH_RENDER,
    RTT_BENCH_BUILD,
    RTT_BENCH_SOFT,
    RTT_BENCH_KIND_COUNT
} rtt_bench_kind;

typedef struct rtt_bench_config {
    uint32_t width, height;                 /* 0 → the scene's */
    uint32_t frames;                        /* timed frames per row (median), default 5 */
    uint32_t warmup;                        /* untimed frames first, default 1 */
    uint32_t threads[RTT_BENCH_MAX_THREADS];/* each row runs at each of these */
    uint32_t thread_count;                  /* default 2: {1, 2} */
    bool kinds[RTT_BENCH_KIND_COUNT];       /* which sections run (default all) */
    bool embree;                            /* race the peer (default when built with it) */
    bool quick;                             /* one frame, no warm-up, one tile per family */
    uint32_t max_tree_depth;                /* the kd-tree's depth bound, 0 → the builder's default */
    rtt_accel accel;                        /* our rows: RTT_ACCEL_DEFAULT (default) every structure's,
                                               else only that one's (kd, pgrid) */
    uint32_t pgrid_cell;                    /* the eye grid's cell side in pixels, 0 → its default */
    uint32_t pgrid_light_res[RTT_BENCH_MAX_LIGHT_RES]; /* the light grids' cells per face side, a row per entry */
    uint32_t pgrid_light_res_count;         /* 0: one row, the scene's rule (pgrid_light_res_rule) */
    rtt_isa isa;                            /* the kernels' instruction set; RTT_ISA_AUTO (default):
                                               $RTT_ISA when set, else the widest the CPU has */
    rtt_isect isect;                        /* the kernels' triangle test; RTT_ISECT_DEFAULT: the engine's */
    bool compare_isects;                    /* kernel rows once per triangle test, in the same run */
    const char *image_dir;                  /* write each render row's image here (EXR), or NULL */
    /* Called before each row from the running thread (the CLI prints it). */
    void (*progress)(void *context, const char *row);
    void *progress_context;
} rtt_bench_config;

typedef struct rtt_bench_row {
    rtt_bench_kind kind;
    char engine[12];           /* "rtt", "embree" or "llvmpipe" */
    char method[48];           /* "mft 16x16", "packet 2x2", "rtcIntersect16", "edgewidth" */
    char family[16];           /* "mft", "frustum", "packet", ... / "embree" */
    char variant[32];          /* embree: "native robust" ...; rtt: "cull on" / "cull off" */
    char shadows[24];          /* render rows: the shadow method */
    char isect[12];            /* rtt rows: "watertight" or "projected"; "" for Embree */
    uint32_t tile;             /* 0 when the method has none */
    int leaf_culling;          /* -1 when not applicable */
    uint32_t lanes;            /* embree: rays per call (1, 4, 8, 16) */
    uint32_t threads, width, height;
    uint32_t frames;           /* timed frames behind the median */
    double seconds;            /* median frame time (build: build time) */
    double seconds_min;
    double fps, rays_per_second;
    uint64_t rays;             /* rays per frame */
    double n, i;               /* per 2x2 packet; negative when not counted */
    uint64_t memory_bytes;     /* build rows */
    double vs_embree;          /* fps / Embree's best coherent fps for the same kind,
                                  size and threads; 0 when there is none */
    double agree;              /* share of rays whose prim (or occlusion) equals
                                  Embree's (robust variant); negative when unchecked */
    char image[256];           /* render rows with image_dir: the file written */
    char error[240];           /* non-empty: the row did not run, and why */
} rtt_bench_row;

typedef struct rtt_bench_report {
    char scene[512];
    char view[64];                 /* the views.json entry applied, or "" */
    uint32_t triangles, width, height;
    uint32_t frames, warmup;
    rtt_tree_info tree;            /* our kd-tree (built on one thread) */
    bool have_tree;
    char embree_note[200];         /* "not built", or the flags used */
    rtt_bench_row *rows;
    size_t row_count, row_cap;
} rtt_bench_report;

void rtt_bench_config_default(rtt_bench_config *config);

/* Applies a view of a views file (bench/views.json, read by rtt_views_load)
 * to the scene as the benchmarks define it: its camera, its light (replacing
 * the scene's lights by one; a view without one keeps the scene's), and its
 * image size when it names one.  False + err when out of memory. */
struct rtt_view;
bool rtt_bench_apply_view(rtt_scene *scene, const struct rtt_view *view, rtt_error *err);

/* Runs every row the config asks for.  False only when the optimized
 * engine cannot be built or memory runs out; a row that cannot run (a
 * shadow method the renderer refuses, Embree missing) carries its error. */
bool rtt_bench_run(const rtt_scene *scene, const rtt_bench_config *config, rtt_bench_report *report,
                   rtt_error *err);
void rtt_bench_report_free(rtt_bench_report *report);

/* The report as text; malloc'd, NULL when out of memory.
 *   table:    a plain text table per kind
 *   markdown: the thesis' tables (4.1-4.6, 5.1, 6.2) with Embree ratios
 *   json:     every row and field
 *   tsv:      one line per row for plotting (scene, kind, method, tile,
 *             threads, size, fps, rays/s, vs_embree), no header */
char *rtt_bench_report_table(const rtt_bench_report *report);
char *rtt_bench_report_markdown(const rtt_bench_report *report);
char *rtt_bench_report_json(const rtt_bench_report *report);
char *rtt_bench_report_tsv(const rtt_bench_report *report);

#endif

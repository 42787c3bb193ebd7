/* rtt_bench_run: which rows run, in which order (bench.h).
 *
 * Order keeps the expensive set-up shared: one kd-tree build (one thread),
 * one Embree build per variant, the primary rays made once, the tile blocks
 * made once per tile size and every kernel and thread count run on them
 * before the next size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/render.h"

#include "bvh_build.h"
#include "engine_optimized.h"
#include "pgrid_soft.h"

#define EMBREE_VARIANTS 4

typedef struct bench_state {
    const rtt_scene *scene;
    const rtt_bench_config *config;
    rtt_bench_report *report;
    rtt_engine *engine;
    const kd_tree *tree;
    /* the trees the kernel rows trace: the engine's, and with compare_isects
     * the same tree with the other triangle test (corners dropped) */
    kd_tree projected_view;
    const kd_tree *isect_trees[2];
    uint32_t isect_tree_count;
    rtt_engine *bvh_engine;     /* the optimized engine with --accel bvh (one-thread build) */
    const bvh_tree *bvh;
    bench_embree *peers[EMBREE_VARIANTS];
    uint32_t width, height;
    uint32_t warmup, frames;
    uint32_t *result;           /* per pixel, the row being checked */
    uint32_t *oracle;           /* per pixel, Embree's (first variant, rtcIntersect1/rtcOccluded1) */
    bool have_oracle;
    rtt_error *err;             /* a failure that ends the run (an image not written) */
} bench_state;

void rtt_bench_config_default(rtt_bench_config *config)
{
    memset(config, 0, sizeof *config);
    config->frames = 5;
    config->warmup = 1;
    config->threads[0] = 1;
    config->threads[1] = 2;
    config->thread_count = 2;
    for (int k = 0; k < RTT_BENCH_KIND_COUNT; k++) config->kinds[k] = true;
    config->embree = bench_embree_available();
}

bool bench_report_push(rtt_bench_report *report, const rtt_bench_row *row)
{
    if (report->row_count == report->row_cap) {
        size_t cap = report->row_cap ? 2 * report->row_cap : 64;
        rtt_bench_row *grown = realloc(report->rows, cap * sizeof *grown);
        if (!grown) return false;
        report->rows = grown;
        report->row_cap = cap;
    }
    report->rows[report->row_count++] = *row;
    return true;
}

void rtt_bench_report_free(rtt_bench_report *report)
{
    free(report->rows);
    memset(report, 0, sizeof *report);
}

/* Shadow and soft rows trace occlusion; primary rows closest hits. */
static bool is_occlusion(rtt_bench_kind kind) { return kind == RTT_BENCH_SHADOW || kind == RTT_BENCH_SOFT; }

static void progress(const bench_state *s, const rtt_bench_row *row)
{
    if (!s->config->progress) return;
    char line[200];
    snprintf(line, sizeof line, "%s %s %s%s%s%s%s, %u thread%s, %ux%u",
             row->kind == RTT_BENCH_PRIMARY ? "primary" : row->kind == RTT_BENCH_SHADOW ? "shadow"
             : row->kind == RTT_BENCH_RENDER ? "render" : row->kind == RTT_BENCH_BUILD ? "build" : "soft",
             row->engine, row->method, row->variant[0] ? " " : "", row->variant, row->shadows[0] ? " shadows " : "",
             row->shadows, row->threads,
             row->threads == 1 ? "" : "s", row->width, row->height);
    s->config->progress(s->config->progress_context, line);
}

/* Copies "prefix message" into row->error, cut to fit. */
static void row_error(rtt_bench_row *row, const char *prefix, const char *message)
{
    size_t room = sizeof row->error - 1, used = 0;
    for (const char *part[2] = {prefix, message}, **p = part; p < part + 2; p++)
        for (const char *c = *p; *c && used < room; c++) row->error[used++] = *c;
    row->error[used] = '\0';
}

static rtt_bench_row row_start(const bench_state *s, rtt_bench_kind kind, const char *engine, uint32_t threads)
{
    rtt_bench_row row;
    memset(&row, 0, sizeof row);
    row.kind = kind;
    snprintf(row.engine, sizeof row.engine, "%s", engine);
    row.threads = threads;
    row.width = s->width;
    row.height = s->height;
    row.leaf_culling = -1;
    row.n = row.i = -1.0;
    row.agree = -1.0;
    return row;
}

/* A pgrid row and the build row of its per-frame grid, for `threads`. */
static void pgrid_rows_start(const bench_state *s, rtt_bench_kind kind, uint32_t threads, const char *method,
                             const char *build_method, uint64_t rays, rtt_bench_row *row, rtt_bench_row *build)
{
    *row = row_start(s, kind, "rtt", threads);
    *build = row_start(s, RTT_BENCH_BUILD, "rtt", threads);
    snprintf(row->method, sizeof row->method, "%s", method);
    snprintf(build->method, sizeof build->method, "%s", build_method);
    snprintf(row->family, sizeof row->family, "pgrid");
    snprintf(build->family, sizeof build->family, "build");
    row->rays = rays;
    build->rays = s->scene->triangle_count;
}

/* Share of active pixels where the row's result equals the oracle's. */
static double agreement(const bench_state *s, const bench_rays *rays)
{
    uint64_t same = 0, active = 0;
    size_t pixels = (size_t)rays->width * rays->height;
    for (size_t i = 0; i < pixels; i++) {
        if (!bench_ray_active(&rays->rays[i])) continue;
        active++;
        same += s->result[i] == s->oracle[i];
    }
    return active ? (double)same / (double)active : 1.0;
}

/* ---- our kernels and the peer on one ray set (primary or shadow) ---- */

typedef struct kernel_method {
    const char *family;  /* the kernel's name in the descriptor table */
    uint32_t tile;       /* block tile; 0 = independent 2x2 packets (scheduled in 8x8 tiles) */
    int leaf_culling;
} kernel_method;

static void method_label(const kernel_method *m, char *out, size_t size)
{
    if (m->tile == 0) snprintf(out, size, "%s%s", m->family, strcmp(m->family, "mono") == 0 ? "" : " 2x2");
    else snprintf(out, size, "%s %ux%u", m->family, m->tile, m->tile);
}

static bool run_kernel_rows(bench_state *s, rtt_bench_kind kind, const bench_rays *rays,
                            const kernel_method *methods, size_t method_count)
{
    static const uint32_t block_tiles[] = {8, 4, 16, 32};
    for (size_t bt = 0; bt < sizeof block_tiles / sizeof block_tiles[0]; bt++) {
        bool used = false;
        for (size_t m = 0; m < method_count; m++) used |= (methods[m].tile ? methods[m].tile : 8u) == block_tiles[bt];
        if (!used) continue;
        bench_blocks blocks;
        if (!bench_blocks_make(rays, block_tiles[bt], &blocks)) return false;
        for (size_t m = 0; m < method_count; m++) {
            if ((methods[m].tile ? methods[m].tile : 8u) != block_tiles[bt]) continue;
            /* each thread count, and at each the triangle tests one after the other */
            for (uint32_t run = 0; run < s->config->thread_count * s->isect_tree_count; run++) {
                const uint32_t t = run / s->isect_tree_count;
                const kd_tree *tree = s->isect_trees[run % s->isect_tree_count];
                const char *isect = tree->corners ? "watertight" : "projected";
                rtt_bench_row row = row_start(s, kind, "rtt", s->config->threads[t]);
                method_label(&methods[m], row.method, sizeof row.method);
                snprintf(row.family, sizeof row.family, "%s", methods[m].family);
                snprintf(row.isect, sizeof row.isect, "%s", isect);
                snprintf(row.variant, sizeof row.variant, "cull %s%s%s", methods[m].leaf_culling ? "on" : "off",
                         s->isect_tree_count > 1 ? " " : "", s->isect_tree_count > 1 ? isect : "");
                row.tile = methods[m].tile;
                row.leaf_culling = methods[m].leaf_culling;
                row.rays = rays->active;
                progress(s, &row);
                bench_trace_spec spec = {is_occlusion(kind), row.threads, s->warmup, s->frames, t == 0,
                                         s->config->isa};
                bool check = t == 0 && s->have_oracle;
                if (!bench_kernel_row(tree, &blocks, s->width, s->height, methods[m].family,
                                      methods[m].leaf_culling, &spec, &row, check ? s->result : NULL)) {
                    bench_blocks_free(&blocks);
                    return false;
                }
                if (check && !row.error[0]) row.agree = agreement(s, rays);
                if (!bench_report_push(s->report, &row)) {
                    bench_blocks_free(&blocks);
                    return false;
                }
            }
        }
        bench_blocks_free(&blocks);
    }
    return true;
}

static bool run_peer_rows(bench_state *s, rtt_bench_kind kind, const bench_rays *rays, const uint32_t *lanes,
                          size_t lane_count)
{
    static const char *const names[] = {"rtcIntersect", "rtcOccluded"};
    s->have_oracle = false;
    for (int v = 0; v < EMBREE_VARIANTS; v++) {
        if (!s->peers[v]) continue;
        for (size_t l = 0; l < lane_count; l++)
            for (uint32_t t = 0; t < s->config->thread_count; t++) {
                rtt_bench_row row = row_start(s, kind, "embree", s->config->threads[t]);
                snprintf(row.method, sizeof row.method, "%s%u", names[is_occlusion(kind)], lanes[l]);
                snprintf(row.family, sizeof row.family, "embree");
                snprintf(row.variant, sizeof row.variant, "%s", bench_embree_variant(s->peers[v]));
                row.lanes = lanes[l];
                row.rays = rays->active;
                progress(s, &row);
                bench_trace_spec spec = {is_occlusion(kind), row.threads, s->warmup, s->frames, false,
                                         RTT_ISA_AUTO};
                /* The first Embree result becomes the oracle the others are checked against. */
                bool make_oracle = !s->have_oracle && t == 0;
                uint32_t *out = t == 0 ? (make_oracle ? s->oracle : s->result) : NULL;
                rtt_error err = {{0}};
                if (!bench_embree_row(s->peers[v], rays, lanes[l], &spec, &row, out, &err))
                    row_error(&row, "", err.message);
                if (out && !row.error[0]) {
                    row.agree = make_oracle ? 1.0 : agreement(s, rays);
                    s->have_oracle = true;
                }
                if (!bench_report_push(s->report, &row)) return false;
            }
    }
    return true;
}

/* The BVH kernels on the same rays (bench_bvh.c): one row per kernel and
 * thread count, checked against Embree's answers on the first. */
static bool run_bvh_rows(bench_state *s, rtt_bench_kind kind, const bench_rays *rays)
{
    /* hard-shadow rays head to the first light: bvh-mft bounds them from there */
    const rtt_vec3 light = s->scene->light_count ? s->scene->lights[0].position : rtt_v3(0, 0, 0);
    const float toward[3] = {light.x, light.y, light.z};
    const char *name;
    for (uint32_t k = 0; (name = bvh_kernel_name_at(k)); k++)
        for (uint32_t t = 0; t < s->config->thread_count; t++) {
            rtt_bench_row row = row_start(s, kind, "rtt", s->config->threads[t]);
            snprintf(row.method, sizeof row.method, "%s", name);
            snprintf(row.family, sizeof row.family, "%s", name);
            snprintf(row.variant, sizeof row.variant, "bvh");
            snprintf(row.isect, sizeof row.isect, "%s", s->bvh->watertight ? "watertight" : "projected");
            row.rays = rays->active;
            progress(s, &row);
            bench_trace_spec spec = {is_occlusion(kind), row.threads, s->warmup, s->frames, t == 0,
                                     s->config->isa};
            bool check = t == 0 && s->have_oracle;
            if (!bench_bvh_row(s->bvh, rays, name, kind == RTT_BENCH_SHADOW && s->scene->light_count ? toward : NULL,
                               &spec, &row, NULL, check ? s->result : NULL))
                return false;
            if (check && !row.error[0]) row.agree = agreement(s, rays);
            if (!bench_report_push(s->report, &row)) return false;
        }
    return true;
}

/* "tris 3575K" or "tris 3575K/725K": Table 1's triangles reached (and
 * passed on after the frusta's culling). */
static void table1_variant(rtt_bench_row *row, const bvh_counters *c, bool culled)
{
    char text[64];
    if (culled)
        snprintf(text, sizeof text, "bvh tris %lluK/%lluK", (unsigned long long)(c->triangles / 1000),
                 (unsigned long long)(c->isect_tests / 1000));
    else
        snprintf(text, sizeof text, "bvh tris %lluK", (unsigned long long)(c->triangles / 1000));
    memcpy(row->variant, text, sizeof row->variant - 1);
    row->variant[sizeof row->variant - 1] = '\0';
}

/* Soft shadows (bench_frusta.c, Benthin & Wald 2009 Table 1's S rows): each
 * primary hit's 16 interleaved samples of the first light.  Embree's
 * rtcOccluded16 with one pixel's 16 rays per packet (coherent flag), our
 * bvh-packet on the very same packets ("S-Packet") and frusta:16 (our
 * soft-shadow frusta, rays made on demand), each checked ray by ray against
 * Embree's answers.  N and I per 2x2 rays as the BVH rows; the variant
 * carries the triangles reached (and passed on after culling). */
/* Hunt & Mark 2008 section 5.3 (Tables 1 and 5): multi:8's rays (every
 * primary hit's 8 samples of the first light, as --shadows multi:8 and
 * pgrid:8 trace them), Embree's rtcOccluded8 with one pixel's 8 rays per
 * packet (coherent flag), then pgrid:8 (the 3D light grid, built every
 * frame: its build row gives the share) checked ray by ray against Embree,
 * then Table 5's count: the cells a uniform 3D grid of as many cells over
 * the scene's bounds visits per ray (a 3D-DDA) beside the 3D light grid's
 * (pgrid:8's n on its first thread count). */
#define BENCH_PGRID_SOFT_SAMPLES 8u
static bool run_pgrid_soft(bench_state *s, const bench_rays *multi)
{
    static const uint32_t lanes[] = {BENCH_PGRID_SOFT_SAMPLES};
    if (!run_peer_rows(s, RTT_BENCH_SOFT, multi, lanes, 1)) return false;
    for (uint32_t th = 0; th < s->config->thread_count; th++) {
        char method[32], build_method[32];
        snprintf(method, sizeof method, "pgrid:%u", BENCH_PGRID_SOFT_SAMPLES);
        snprintf(build_method, sizeof build_method, "pgrid:%u light", BENCH_PGRID_SOFT_SAMPLES);
        rtt_bench_row row, build;
        pgrid_rows_start(s, RTT_BENCH_SOFT, s->config->threads[th], method, build_method, multi->active, &row, &build);
        snprintf(row.isect, sizeof row.isect, "watertight");
        progress(s, &row);
        bench_trace_spec spec = {true, row.threads, s->warmup, s->frames, th == 0, s->config->isa};
        const bool check = th == 0 && s->have_oracle;
        if (!bench_pgrid_soft_row(s->scene, optimized_engine_degenerate(s->engine), multi, BENCH_PGRID_SOFT_SAMPLES,
                                  &spec, &row, &build, check ? s->result : NULL))
            return false;
        if (check && !row.error[0]) row.agree = agreement(s, multi);
        if (!bench_report_push(s->report, &row) || !bench_report_push(s->report, &build)) return false;
    }
    /* as many cells as the six faces' grid, and as one face's (the paper's 54^3 against 200x200x4) */
    const uint64_t face = (uint64_t)PGRID_SOFT_SLICES_DEFAULT * PGRID_SOFT_RES_DEFAULT * PGRID_SOFT_RES_DEFAULT;
    const uint64_t cells[2] = {PGRID_LIGHT_FACES * face, face};
    for (int c = 0; c < 2; c++) {
        rtt_bench_row row = row_start(s, RTT_BENCH_SOFT, "rtt", 1);
        uint32_t dims[3];
        row.n = bench_grid3d_steps_per_ray(s->scene, multi, cells[c], dims);
        snprintf(row.method, sizeof row.method, "uniform-grid:%u steps", BENCH_PGRID_SOFT_SAMPLES);
        snprintf(row.family, sizeof row.family, "grid3d");
        snprintf(row.variant, sizeof row.variant, "uniform %ux%ux%u", dims[0], dims[1], dims[2]);
        row.rays = multi->active;
        if (!bench_report_push(s->report, &row)) return false;
    }
    return true;
}

static bool runs_accel(const bench_state *s, rtt_accel accel)
{
    return s->config->accel == RTT_ACCEL_DEFAULT || s->config->accel == accel;
}

static bool run_soft(bench_state *s, const bench_rays *primary)
{
    const size_t pixels = (size_t)s->width * s->height;
    rtt_hit *hits = malloc(pixels * sizeof *hits);
    uint32_t *prim = malloc(pixels * sizeof *prim), *result = s->result, *oracle = s->oracle;
    float *t = malloc(pixels * sizeof *t);
    bool ok = hits && prim && t;
    bench_soft soft = {0};
    bench_rays multi = {0};
    rtt_error why = {{0}};
    bool made = false;
    if (ok) {
        rtt_engine_intersect(s->engine, primary->rays, hits, pixels);
        for (size_t i = 0; i < pixels; i++) prim[i] = hits[i].prim, t[i] = hits[i].t;
        made = bench_soft_make(s->scene, primary, prim, t, &soft, &why) &&
               bench_soft_multi_make(s->scene, primary, prim, t, BENCH_PGRID_SOFT_SAMPLES, &multi, &why);
    }
    free(hits), free(prim), free(t);
    if (ok && !made) { /* no light with area: one row says so */
        rtt_bench_row row = row_start(s, RTT_BENCH_SOFT, "rtt", s->config->threads[0]);
        snprintf(row.method, sizeof row.method, "frusta:%u", BENCH_SOFT_SAMPLES);
        row_error(&row, "", why.message);
        bench_soft_free(&soft);
        free(multi.rays);
        return bench_report_push(s->report, &row);
    }
    s->result = ok ? malloc(pixels * BENCH_SOFT_SAMPLES * sizeof *s->result) : NULL;
    s->oracle = ok ? malloc(pixels * BENCH_SOFT_SAMPLES * sizeof *s->oracle) : NULL;
    ok = ok && s->result && s->oracle;
    static const uint32_t lanes[] = {16};
    const bool bvh = runs_accel(s, RTT_ACCEL_BVH); /* frusta:16 and its racers; pgrid:8 and its racers below */
    ok = ok && (!bvh || run_peer_rows(s, RTT_BENCH_SOFT, &soft.rays, lanes, 1));
    for (uint32_t th = 0; ok && bvh && th < s->config->thread_count; th++)
        for (int packet = 0; ok && packet < 2; packet++) {
            rtt_bench_row row = row_start(s, RTT_BENCH_SOFT, "rtt", s->config->threads[th]);
            snprintf(row.method, sizeof row.method, packet ? "bvh-packet" : "frusta:%u", BENCH_SOFT_SAMPLES);
            snprintf(row.family, sizeof row.family, packet ? "bvh-packet" : "frusta");
            snprintf(row.variant, sizeof row.variant, "bvh");
            row.rays = soft.rays.active;
            progress(s, &row);
            bench_trace_spec spec = {true, row.threads, s->warmup, s->frames, th == 0, s->config->isa};
            const bool check = th == 0 && s->have_oracle;
            bvh_counters sum = {0};
            ok = packet ? bench_bvh_row(s->bvh, &soft.rays, "bvh-packet", NULL, &spec, &row, &sum,
                                        check ? s->result : NULL)
                        : bench_frusta_row(s->bvh, &soft, &spec, &row, &sum, check ? s->result : NULL);
            if (th == 0) table1_variant(&row, &sum, !packet);
            if (ok && check && !row.error[0]) row.agree = agreement(s, &soft.rays);
            ok = ok && bench_report_push(s->report, &row);
        }
    ok = ok && (!runs_accel(s, RTT_ACCEL_PGRID) || run_pgrid_soft(s, &multi));
    free(multi.rays);
    free(s->result), free(s->oracle);
    s->result = result, s->oracle = oracle;
    bench_soft_free(&soft);
    return ok;
}

/* The software Z-buffer anchor on the same view: its agree column is the
 * share of pixels whose prim equals the perspective grid's (`ours`). */
static bool run_llvmpipe(bench_state *s, const bench_rays *rays, const uint32_t *ours)
{
    if (!bench_llvmpipe_available()) return true;
    for (uint32_t t = 0; t < s->config->thread_count; t++) {
        rtt_bench_row row = row_start(s, RTT_BENCH_PRIMARY, "llvmpipe", s->config->threads[t]);
        snprintf(row.method, sizeof row.method, "z-buffer prim id");
        snprintf(row.family, sizeof row.family, "llvmpipe");
        row.rays = rays->active;
        progress(s, &row);
        bench_trace_spec spec = {false, row.threads, s->warmup, s->frames, false, RTT_ISA_AUTO};
        rtt_error err = {{0}};
        if (!bench_llvmpipe_row(s->scene, s->width, s->height, &spec, &row, t == 0 ? s->result : NULL, &err))
            row_error(&row, "", err.message);
        if (t == 0 && !row.error[0]) {
            uint64_t same = 0, pixels = (uint64_t)s->width * s->height;
            for (uint64_t i = 0; i < pixels; i++) same += s->result[i] == ours[i];
            row.agree = pixels ? (double)same / (double)pixels : 1.0;
        }
        if (!bench_report_push(s->report, &row)) return false;
    }
    return true;
}

/* Hunt & Mark's Table 1, primary: the perspective grid per frame, its
 * build as a build row of the same method. */
static bool run_pgrid_rows(bench_state *s, const bench_rays *rays, uint32_t *ours)
{
    for (uint32_t t = 0; t < s->config->thread_count; t++) {
        rtt_bench_row row, build;
        pgrid_rows_start(s, RTT_BENCH_PRIMARY, s->config->threads[t], "pgrid", "pgrid", rays->active, &row, &build);
        progress(s, &row);
        bench_trace_spec spec = {false, row.threads, s->warmup, s->frames, false, s->config->isa};
        bool check = t == 0 && s->have_oracle;
        if (!bench_pgrid_row(s->scene, optimized_engine_degenerate(s->engine), s->width, s->height,
                             s->config->pgrid_cell, &spec, &row,
                             &build, check ? s->result : NULL))
            return false;
        if (check && !row.error[0]) row.agree = agreement(s, rays);
        if (!bench_report_push(s->report, &row) || !bench_report_push(s->report, &build)) return false;
        if (t == 0 && !row.error[0]) memcpy(ours, s->result, (size_t)s->width * s->height * sizeof *s->result);
    }
    return true;
}

static bool run_pgrid_primary(bench_state *s, const bench_rays *rays)
{
    uint32_t *ours = malloc((size_t)s->width * s->height * sizeof *ours);
    if (ours) memset(ours, 0xFF, (size_t)s->width * s->height * sizeof *ours); /* RTT_MISS until the row runs */
    bool ok = ours && run_pgrid_rows(s, rays, ours) && run_llvmpipe(s, rays, ours);
    free(ours);
    return ok;
}

static bool run_primary(bench_state *s, const bench_rays *rays)
{
    static const uint32_t lanes[] = {1, 4, 8, 16}, quick_lanes[] = {1, 16};
    if (!run_peer_rows(s, RTT_BENCH_PRIMARY, rays, s->config->quick ? quick_lanes : lanes, s->config->quick ? 2 : 4))
        return false;
    if (runs_accel(s, RTT_ACCEL_PGRID) && !run_pgrid_primary(s, rays)) return false;

    /* --accel bvh: the BVH rows only (they follow the kd rows otherwise) */
    if (!runs_accel(s, RTT_ACCEL_KD)) return !runs_accel(s, RTT_ACCEL_BVH) || run_bvh_rows(s, RTT_BENCH_PRIMARY, rays);
    kernel_method methods[32];
    size_t n = 0;
    methods[n++] = (kernel_method){"mono", 0, 1};
    methods[n++] = (kernel_method){"packet", 0, 1};
    methods[n++] = (kernel_method){"omni", 0, 1};
    static const uint32_t tiles[] = {4, 8, 16, 32};
    for (size_t k = 0; k < 4; k++) {
        uint32_t tile = tiles[k];
        if (s->config->quick && tile != 8) continue;
        methods[n++] = (kernel_method){"frustum", tile, 1};
        methods[n++] = (kernel_method){"frustum", tile, 0};
        methods[n++] = (kernel_method){"mft", tile, 1};
        methods[n++] = (kernel_method){"cone", tile, 1};
        methods[n++] = (kernel_method){"mft-cone", tile, 1};
    }
    return run_kernel_rows(s, RTT_BENCH_PRIMARY, rays, methods, n) && run_bvh_rows(s, RTT_BENCH_PRIMARY, rays);
}

/* --shadows pgrid's light grid on the shadow rays (bench_pgrid_shadow_row). */
static bool run_pgrid_shadow_rows(bench_state *s, const bench_rays *rays, const uint32_t *origin_prim)
{
    const uint32_t sizes = s->config->pgrid_light_res_count ? s->config->pgrid_light_res_count : 1;
    for (uint32_t k = 0; k < sizes * s->config->thread_count; k++) {
        const uint32_t t = k % s->config->thread_count, res = s->config->pgrid_light_res_count
                                                                 ? s->config->pgrid_light_res[k / s->config->thread_count]
                                                                 : 0;
        rtt_bench_row row, build;
        pgrid_rows_start(s, RTT_BENCH_SHADOW, s->config->threads[t], "pgrid", "pgrid light", rays->active, &row, &build);
        progress(s, &row);
        bench_trace_spec spec = {true, row.threads, s->warmup, s->frames, false, s->config->isa};
        bool check = k == 0 && s->have_oracle;
        if (!bench_pgrid_shadow_row(s->scene, optimized_engine_degenerate(s->engine), rays, origin_prim, res, &spec, &row,
                                    &build,
                                    check ? s->result : NULL))
            return false;
        if (check && !row.error[0]) row.agree = agreement(s, rays);
        if (!bench_report_push(s->report, &row) || !bench_report_push(s->report, &build)) return false;
    }
    return true;
}

static bool run_shadow(bench_state *s, const bench_rays *primary)
{
    size_t pixels = (size_t)s->width * s->height;
    rtt_hit *hits = malloc(pixels * sizeof *hits);
    uint32_t *prim = malloc(pixels * sizeof *prim);
    float *t = malloc(pixels * sizeof *t);
    bool ok = hits && prim && t;
    bench_rays shadow = {0};
    if (ok) {
        rtt_engine_intersect(s->engine, primary->rays, hits, pixels);
        for (size_t i = 0; i < pixels; i++) prim[i] = hits[i].prim, t[i] = hits[i].t;
        ok = bench_rays_shadow(s->scene, primary, prim, t, &shadow);
    }
    free(hits), free(t);
    static const uint32_t lanes[] = {1, 16};
    ok = ok && run_peer_rows(s, RTT_BENCH_SHADOW, &shadow, lanes, 2);
    kernel_method methods[] = {
        {"mono", 0, 1},          {"packet", 0, 1},
        {"omni", 0, 1},          {"frustum", 8, 1},
        {"mft", 8, 1},            {"mft", 16, 1},
        {"cone", 8, 1},
    };
    ok = ok && run_kernel_rows(s, RTT_BENCH_SHADOW, &shadow, methods, sizeof methods / sizeof methods[0]);
    ok = ok && run_bvh_rows(s, RTT_BENCH_SHADOW, &shadow);
    if (runs_accel(s, RTT_ACCEL_PGRID)) ok = ok && run_pgrid_shadow_rows(s, &shadow, prim);
    free(prim);
    bench_rays_free(&shadow);
    return ok;
}

/* ---- full renders ---- */

typedef struct render_frame {
    rtt_engine *engine;
    rtt_render_options options;
    rtt_image *image;
    bool failed;
    rtt_error err;
} render_frame;

static void render_once(void *context)
{
    render_frame *f = context;
    if (!f->failed && !rtt_optimized_render(f->engine, &f->options, f->image, NULL, &f->err)) f->failed = true;
}

static void image_name(const rtt_bench_row *row, char *out, size_t size, const char *dir)
{
    char label[96];
    snprintf(label, sizeof label, "%s_%s_t%u", row->method, row->shadows, row->threads);
    for (char *c = label; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_')) *c = '_';
    snprintf(out, size, "%s/%s.exr", dir, label);
}

static bool render_row(bench_state *s, const kernel_method *m, const char *shadows, uint32_t threads)
{
    rtt_bench_row row = row_start(s, RTT_BENCH_RENDER, "rtt", threads);
    method_label(m, row.method, sizeof row.method);
    snprintf(row.family, sizeof row.family, "%s", m->family);
    snprintf(row.shadows, sizeof row.shadows, "%s", shadows);
    row.tile = m->tile;
    row.leaf_culling = m->leaf_culling;
    progress(s, &row);
    render_frame f = {.engine = s->engine};
    rtt_render_options_default(&f.options);
    f.options.width = s->width;
    f.options.height = s->height;
    f.options.threads = threads;
    snprintf(f.options.engine.traversal, sizeof f.options.engine.traversal, "%s", m->family);
    f.options.engine.tile = m->tile ? m->tile : 8u;
    f.options.engine.leaf_culling = m->leaf_culling;
    f.options.engine.isa = s->config->isa;
    f.options.engine.isect = s->config->isect;
    if (!rtt_shadow_method_parse(shadows, &f.options, &f.err)) {
        row_error(&row, "", f.err.message);
        return bench_report_push(s->report, &row);
    }
    f.image = rtt_image_create(s->width, s->height, 0, &f.err);
    if (!f.image) return false;
    rtt_render_stats stats;
    memset(&stats, 0, sizeof stats);
    if (!rtt_optimized_render(s->engine, &f.options, f.image, &stats, &f.err)) {
        row_error(&row, "skipped: ", f.err.message);
    } else {
        row.rays = stats.primary_rays + stats.shadow_rays + stats.secondary_rays;
        if (stats.packets) {
            row.n = (double)stats.traversal_steps / (double)stats.packets;
            row.i = (double)stats.intersection_tests / (double)stats.packets;
        }
        if (s->config->image_dir) {
            image_name(&row, row.image, sizeof row.image, s->config->image_dir);
            rtt_error err = {{0}};
            if (!rtt_image_write(f.image, row.image, &err)) { /* an output lost is a failed run, not a row */
                rtt_image_free(f.image);
                *s->err = err;
                return false;
            }
        }
        bench_time_frames(render_once, &f, s->warmup, s->frames, &row);
        if (f.failed) row_error(&row, "", f.err.message);
    }
    rtt_image_free(f.image);
    return bench_report_push(s->report, &row);
}

static bool run_renders(bench_state *s)
{
    const rtt_bench_config *c = s->config;
    const uint32_t most = c->threads[c->thread_count - 1];
    kernel_method traversals[] = {
        {"mono", 0, 1},        {"packet", 0, 1},
        {"omni", 0, 1},        {"frustum", 8, 1},
        {"frustum", 16, 1}, {"mft", 8, 1},
        {"mft", 16, 1},         {"mft", 32, 1},
        {"cone", 8, 1},        {"mft-cone", 16, 1},
    };
    for (size_t m = 0; m < sizeof traversals / sizeof traversals[0]; m++) {
        /* --quick: every family once, at tile 8 */
        if (c->quick && traversals[m].tile > 8 && strcmp(traversals[m].family, "mft-cone")) continue;
        if (c->quick && traversals[m].tile > 8) traversals[m].tile = 8;
        for (uint32_t t = 0; t < c->thread_count; t++)
            if (!render_row(s, &traversals[m], "hard", c->threads[t])) return false;
    }
    /* Tables 4.6 and 5.1 (shadow methods, on the fastest thread count) and
     * 6.2 (edge width at every thread count), all under MFT. */
    const kernel_method mft = {"mft", c->quick ? 8u : 16u, 1};
    static const char *const shadows[] = {"none", "multi:4", "multi:16", "multi:32", "cone:16", "pyramid:16",
                                          "edgewidth"};
    for (size_t k = 0; k < sizeof shadows / sizeof shadows[0]; k++) {
        if (strcmp(shadows[k], "edgewidth") == 0) {
            for (uint32_t t = 0; t < c->thread_count; t++)
                if (!render_row(s, &mft, shadows[k], c->threads[t])) return false;
        } else if (!render_row(s, &mft, shadows[k], c->quick ? c->threads[0] : most)) {
            return false;
        }
    }
    return true;
}

/* ---- builds ---- */

/* One timed BVH build (bench_time_frames' frame), freed at once. */
typedef struct bvh_build_frame {
    const rtt_scene *scene;
    bvh_build_options options;
    bool ok;
} bvh_build_frame;

static void bvh_build_run(void *context)
{
    bvh_build_frame *f = context;
    bvh_tree tree;
    rtt_error err = {{0}};
    if (bvh_build_sah(f->scene, &f->options, &tree, &err)) bvh_tree_free(&tree);
    else f->ok = false;
}

static bool run_builds(bench_state *s)
{
    rtt_bench_row row = row_start(s, RTT_BENCH_BUILD, "rtt", 1);
    snprintf(row.method, sizeof row.method, "kd-tree SAH");
    snprintf(row.family, sizeof row.family, "build");
    row.seconds = row.seconds_min = s->report->tree.build_seconds;
    row.memory_bytes = s->report->tree.memory_bytes;
    row.frames = 1;
    row.rays = s->scene->triangle_count;
    if (!bench_report_push(s->report, &row)) return false;
    rtt_tree_info bvh_info;
    const bool have_bvh_info = rtt_engine_tree_info(s->bvh_engine, &bvh_info);
    for (uint32_t t = 0; t < s->config->thread_count; t++) { /* one BVH build row per thread count */
        rtt_bench_row bvh_row = row_start(s, RTT_BENCH_BUILD, "rtt", s->config->threads[t]);
        snprintf(bvh_row.method, sizeof bvh_row.method, "BVH binned SAH");
        snprintf(bvh_row.family, sizeof bvh_row.family, "build");
        bvh_row.rays = s->scene->triangle_count;
        progress(s, &bvh_row);
        bvh_build_frame frame = {s->scene, {.threads = s->config->threads[t]}, true};
        bench_time_frames(bvh_build_run, &frame, s->warmup, s->frames, &bvh_row);
        bvh_row.fps = bvh_row.rays_per_second = 0.0; /* a build row reports seconds */
        if (!frame.ok) row_error(&bvh_row, "", "out of memory building the BVH");
        if (have_bvh_info) bvh_row.memory_bytes = bvh_info.memory_bytes;
        if (!bench_report_push(s->report, &bvh_row)) return false;
    }
    static const bool natives[EMBREE_VARIANTS] = {true, true, false, false};
    static const bool robusts[EMBREE_VARIANTS] = {true, false, true, false};
    if (!s->config->embree) {
        snprintf(s->report->embree_note, sizeof s->report->embree_note, "Embree not raced (%s)",
                 bench_embree_available() ? "--no-embree" : "built without Embree");
        return true;
    }
    snprintf(s->report->embree_note, sizeof s->report->embree_note,
             "Embree 3, RTC_BUILD_QUALITY_HIGH, one build thread; ISA native or sse4.2; scene flag ROBUST or NONE; "
             "coherent context flag for 4/8/16-wide calls");
    for (int v = 0; v < EMBREE_VARIANTS; v++) {
        if (s->config->quick && v > 0) break;
        rtt_bench_row b = row_start(s, RTT_BENCH_BUILD, "embree", 1);
        snprintf(b.method, sizeof b.method, "BVH high quality");
        snprintf(b.family, sizeof b.family, "build");
        b.rays = s->scene->triangle_count;
        rtt_error err = {{0}};
        progress(s, &b);
        s->peers[v] = bench_embree_create(s->scene, natives[v], robusts[v], &b, &err);
        if (s->peers[v]) snprintf(b.variant, sizeof b.variant, "%s", bench_embree_variant(s->peers[v]));
        else row_error(&b, "", err.message);
        if (!bench_report_push(s->report, &b)) return false;
    }
    return true;
}

/* vs_embree: a row's fps over the best coherent Embree fps of its kind,
 * size and thread count (render rows: over the primary race's best). */
static void compute_ratios(rtt_bench_report *report)
{
    for (size_t i = 0; i < report->row_count; i++) {
        rtt_bench_row *r = &report->rows[i];
        if (r->error[0] || r->kind == RTT_BENCH_BUILD || r->kind == RTT_BENCH_RENDER) continue;
        double best = 0.0;
        for (size_t j = 0; j < report->row_count; j++) {
            const rtt_bench_row *e = &report->rows[j];
            if (strcmp(e->engine, "embree") || e->error[0] || e->kind != r->kind || e->lanes < 4) continue;
            if (e->threads != r->threads || e->width != r->width || e->height != r->height) continue;
            if (e->fps > best) best = e->fps;
        }
        r->vs_embree = best > 0 ? r->fps / best : 0.0;
    }
}

bool rtt_bench_run(const rtt_scene *scene, const rtt_bench_config *config, rtt_bench_report *report, rtt_error *err)
{
    memset(report, 0, sizeof *report);
    snprintf(report->scene, sizeof report->scene, "%s", scene->path);
    rtt_error failure = {{0}};
    bench_state s = {.scene = scene, .config = config, .report = report, .err = &failure};
    s.width = config->width ? config->width : scene->width;
    s.height = config->height ? config->height : scene->height;
    s.warmup = config->quick ? 0 : config->warmup;
    s.frames = config->quick ? 1 : config->frames;
    report->triangles = scene->triangle_count;
    report->width = s.width;
    report->height = s.height;
    report->frames = s.frames;
    report->warmup = s.warmup;
    if (config->thread_count == 0 || config->thread_count > RTT_BENCH_MAX_THREADS)
        return rtt_error_set(err, "rtt bench: between 1 and %u thread counts", RTT_BENCH_MAX_THREADS);

    rtt_engine_options options;
    rtt_engine_options_default(&options);
    options.threads = 1; /* the build row is a one-core build */
    options.max_tree_depth = config->max_tree_depth;
    options.isa = config->isa;
    options.isect = config->isect;
    s.engine = rtt_optimized_engine_create(scene, &options, err);
    if (!s.engine) return false;
    s.tree = kd_engine_tree(s.engine);
    s.isect_trees[s.isect_tree_count++] = s.tree;
    if (config->compare_isects && s.tree->corners) {
        s.projected_view = *s.tree;
        s.projected_view.corners = NULL; /* the same tree and records, Wald's projected test */
        s.isect_trees[s.isect_tree_count++] = &s.projected_view;
    }
    report->have_tree = rtt_engine_tree_info(s.engine, &report->tree);
    options.accel = RTT_ACCEL_BVH;
    options.max_tree_depth = 0; /* the kd-tree's bound is not the BVH's */
    s.bvh_engine = rtt_optimized_engine_create(scene, &options, err);
    if (!s.bvh_engine) {
        rtt_engine_destroy(s.engine);
        return false;
    }
    s.bvh = bvh_engine_tree(s.bvh_engine);

    size_t pixels = (size_t)s.width * s.height;
    s.result = malloc(pixels * sizeof *s.result);
    s.oracle = malloc(pixels * sizeof *s.oracle);
    bench_rays primary = {0};
    bool ok = s.result && s.oracle && bench_rays_primary(scene, s.width, s.height, &primary);
    ok = ok && run_builds(&s);
    if (ok && config->kinds[RTT_BENCH_PRIMARY]) ok = run_primary(&s, &primary);
    if (ok && config->kinds[RTT_BENCH_SHADOW]) ok = run_shadow(&s, &primary);
    if (ok && config->kinds[RTT_BENCH_SOFT]) ok = run_soft(&s, &primary);
    for (int v = 0; v < EMBREE_VARIANTS; v++) bench_embree_destroy(s.peers[v]), s.peers[v] = NULL;
    if (ok && config->kinds[RTT_BENCH_RENDER]) ok = run_renders(&s);
    if (ok && !config->kinds[RTT_BENCH_BUILD]) {
        size_t kept = 0;
        for (size_t i = 0; i < report->row_count; i++)
            if (report->rows[i].kind != RTT_BENCH_BUILD) report->rows[kept++] = report->rows[i];
        report->row_count = kept;
    }
    if (ok) compute_ratios(report);
    bench_rays_free(&primary);
    free(s.result), free(s.oracle);
    rtt_engine_destroy(s.engine);
    rtt_engine_destroy(s.bvh_engine);
    if (!ok) {
        rtt_bench_report_free(report);
        if (failure.message[0]) {
            *err = failure;
            return false;
        }
        return rtt_error_set(err, "%s: out of memory in the benchmark", scene->path);
    }
    return true;
}

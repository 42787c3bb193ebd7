/* The perspective grid's eye rays in the primary race (Hunt & Mark 2008,
 * Table 1's primary columns): a frame is the grid's build plus every cell
 * traced and every pixel's hit resolved (t, u, v, prim into one rtt_hit per
 * pixel, what Embree's rows produce), on the thread counts of the other
 * rows.  The rays are the pixel formula, so unlike the other rows nothing
 * is loaded: that is the method.  The build's median is reported as a
 * build row of the same method, so the build share is build / frame. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "engine/clock.h"
#include "engine/threads.h"
#include "pgrid_eye.h"

typedef struct pgrid_frame {
    pgrid_eye grid;
    const pgrid_kernel *kernel;
    const rtt_scene *scene;
    const uint8_t *degenerate;
    rtt_camera_frame camera;
    uint32_t width, height, cell, threads;
    rtt_hit *hits;
    double *build_seconds;      /* per frame run, warm-up included */
    uint32_t runs;
    bool failed;
} pgrid_frame;

static void run_frame(void *context)
{
    pgrid_frame *f = context;
    rtt_error err;
    double build = 0.0;
    f->failed |= !pgrid_eye_trace_frame(&f->grid, f->kernel, f->scene, f->degenerate, &f->camera, f->width,
                                        f->height, f->cell, f->threads, f->hits, &build, &err);
    f->build_seconds[f->runs++] = build;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

bool bench_pgrid_row(const rtt_scene *scene, const uint8_t *degenerate, uint32_t width, uint32_t height,
                     uint32_t cell, const bench_trace_spec *spec, rtt_bench_row *row, rtt_bench_row *build_row, uint32_t *result)
{
    pgrid_frame f = {.kernel = pgrid_kernel_find("pgrid", rtt_isa_resolve(spec->isa)), .scene = scene,
                     .degenerate = degenerate, .camera = rtt_camera_frame_make(&scene->camera, width, height),
                     .width = width, .height = height, .cell = cell, .threads = spec->threads};
    /* 64-byte aligned: a row of four hits is one line, streamed (pgrid_eye_trace_frame) */
    f.hits = aligned_alloc(64, ((size_t)width * height * sizeof *f.hits + 63) & ~(size_t)63);
    f.build_seconds = calloc((size_t)spec->warmup + spec->frames, sizeof *f.build_seconds);
    if (!f.hits || !f.build_seconds) {
        free(f.hits);
        free(f.build_seconds);
        return false;
    }
    bench_time_frames(run_frame, &f, spec->warmup, spec->frames, row);
    /* the cell the frames ran with: --pgrid-cell's, or pgrid_eye_cell_rule's */
    snprintf(row->variant, sizeof row->variant, "%s/%s cell %u", f.kernel->name, rtt_isa_name(f.kernel->isa),
             f.grid.cell);
    row->tile = f.grid.cell;
    if (f.failed) snprintf(row->error, sizeof row->error, "out of memory building the perspective grid");
    double *timed = f.build_seconds + spec->warmup;
    qsort(timed, spec->frames, sizeof *timed, compare_double);
    build_row->seconds = timed[spec->frames / 2];
    build_row->seconds_min = timed[0];
    build_row->frames = spec->frames;
    build_row->memory_bytes = f.grid.triangle_count * sizeof(pgrid_triangle) + f.grid.ref_count * sizeof(uint32_t) +
                              ((size_t)pgrid_eye_cell_count(&f.grid) + 1) * sizeof(uint32_t);
    snprintf(build_row->variant, sizeof build_row->variant, "%s", row->variant);
    if (result)
        for (size_t i = 0; i < (size_t)width * height; i++) result[i] = f.hits[i].prim;
    pgrid_eye_free(&f.grid);
    free(f.hits);
    free(f.build_seconds);
    return true;
}

/* ---- hard shadows through the light grid (Table 1's shadow columns) ----
 * A frame is the light grid's build for the bench's light (light 0, whose
 * rays bench_rays_shadow makes; the scene's half, corners and culled
 * meshes, is built once, as the kd-tree) plus the shadow rays of every pixel,
 * batched per eye-ray cell (PGRID_EYE_CELL_DEFAULT pixels square, in
 * pixel order within; the batches made before the frames, as every racer's
 * rays are), each batch through the kernel on the thread pool. */

typedef struct pgrid_shadow_frame {
    pgrid_shadows grids;
    const pgrid_kernel *kernel;
    const rtt_scene *scene;
    uint32_t threads;
    bench_shadow_batches batches; /* made once before the frames, as every racer's rays */
    uint8_t *answers;             /* per ray of the batches */
    double *build_seconds;
    uint32_t runs, light_res;   /* light_res 0: pgrid_light_res_rule */
    _Atomic bool failed;
} pgrid_shadow_frame;

bool bench_shadow_batches_make(bench_shadow_batches *b, const bench_rays *rays, const uint32_t *origin_prim,
                               uint32_t side)
{
    memset(b, 0, sizeof *b);
    const uint32_t w = rays->width, h = rays->height;
    const size_t pixels = (size_t)w * h;
    b->cells = ((w + side - 1) / side) * ((h + side - 1) / side);
    b->rays = malloc(pixels * sizeof *b->rays);
    b->prim = malloc(pixels * sizeof *b->prim);
    b->pixel = malloc(pixels * sizeof *b->pixel);
    b->first = malloc(((size_t)b->cells + 1) * sizeof *b->first);
    if (!b->rays || !b->prim || !b->pixel || !b->first) return false;
    uint32_t n = 0, cell = 0;
    for (uint32_t y0 = 0; y0 < h; y0 += side)
        for (uint32_t x0 = 0; x0 < w; x0 += side) {
            const uint32_t x1 = x0 + side < w ? x0 + side : w, y1 = y0 + side < h ? y0 + side : h;
            b->first[cell++] = n;
            for (uint32_t y = y0; y < y1; y++)
                for (uint32_t x = x0; x < x1; x++) {
                    const uint32_t i = y * w + x;
                    if (!bench_ray_active(&rays->rays[i])) continue;
                    b->rays[n] = rays->rays[i];
                    b->prim[n] = origin_prim[i];
                    b->pixel[n++] = i;
                }
        }
    b->first[cell] = n;
    return true;
}

void bench_shadow_batches_free(bench_shadow_batches *b)
{
    free(b->rays), free(b->prim), free(b->pixel), free(b->first);
    memset(b, 0, sizeof *b);
}

/* What bench_shadow_batches_trace's tasks share. */
typedef struct shadow_batches_job {
    const bench_shadow_batches *batches;
    const pgrid_kernel *kernel;
    const pgrid_shadows *grids;
    uint8_t *answers;
    _Atomic bool failed;
} shadow_batches_job;

static void trace_shadow_batch(void *context, uint32_t thread, uint32_t cell)
{
    (void)thread;
    shadow_batches_job *job = context;
    const bench_shadow_batches *b = job->batches;
    const uint32_t first = b->first[cell];
    if (!job->kernel->shadow_occluded(job->grids, 0, b->rays + first, b->prim + first, b->first[cell + 1] - first,
                                      job->answers + first))
        job->failed = true;
}

bool bench_shadow_batches_trace(const bench_shadow_batches *b, const pgrid_kernel *kernel, const pgrid_shadows *grids,
                                uint8_t *answers, uint32_t threads)
{
    shadow_batches_job job = {.batches = b, .kernel = kernel, .grids = grids, .answers = answers};
    rtt_parallel_run(b->cells, threads, trace_shadow_batch, &job);
    return !job.failed;
}

static void run_shadow_frame(void *context)
{
    pgrid_shadow_frame *f = context;
    const uint64_t t0 = rtt_clock_ns();
    const rtt_vec3 at = f->scene->lights[0].position;
    const float position[3] = {at.x, at.y, at.z};
    /* rebuilt into the last frame's arrays, on the frame's threads */
    if (!pgrid_light_rebuild(&f->grids.lights[0], &f->grids, f->scene, position, f->light_res, f->threads)) {
        f->failed = true;
        return;
    }
    f->grids.light_count = 1;
    f->build_seconds[f->runs++] = 1e-9 * (double)(rtt_clock_ns() - t0);
    if (!bench_shadow_batches_trace(&f->batches, f->kernel, &f->grids, f->answers, f->threads)) f->failed = true;
}

bool bench_pgrid_shadow_row(const rtt_scene *scene, const uint8_t *degenerate, const bench_rays *rays,
                            const uint32_t *origin_prim, uint32_t light_res, const bench_trace_spec *spec,
                            rtt_bench_row *row, rtt_bench_row *build_row, uint32_t *result)
{
    const uint32_t threads = rtt_thread_count(spec->threads);
    pgrid_shadow_frame f = {.kernel = pgrid_kernel_find("pgrid", rtt_isa_resolve(spec->isa)), .scene = scene,
                            .threads = threads, .light_res = light_res};
    f.build_seconds = calloc((size_t)spec->warmup + spec->frames, sizeof *f.build_seconds);
    rtt_error err;
    bool ok = f.build_seconds && bench_shadow_batches_make(&f.batches, rays, origin_prim, PGRID_EYE_CELL_DEFAULT) &&
              (f.answers = malloc((size_t)f.batches.first[f.batches.cells] + 1)) != NULL &&
              pgrid_shadows_prepare(&f.grids, scene, degenerate, &err);
    if (ok) {
        f.grids.prints = f.kernel->light_prints;
        bench_time_frames(run_shadow_frame, &f, spec->warmup, spec->frames, row);
        snprintf(row->variant, sizeof row->variant, "%s/%s light %u", f.kernel->name, rtt_isa_name(f.kernel->isa),
                 f.grids.lights[0].res);
        if (f.failed) snprintf(row->error, sizeof row->error, "out of memory in the light grid");
        double *timed = f.build_seconds + spec->warmup;
        qsort(timed, spec->frames, sizeof *timed, compare_double);
        build_row->seconds = timed[spec->frames / 2];
        build_row->seconds_min = timed[0];
        build_row->frames = spec->frames;
        const pgrid_light *L = f.grids.light_count ? &f.grids.lights[0] : NULL;
        build_row->memory_bytes = (size_t)f.grids.corner_count * sizeof(kd_corners) +
                                  (L ? L->ref_count * sizeof(uint32_t) +
                                           ((size_t)PGRID_LIGHT_FACES * L->res * L->res) * 2 * sizeof(uint32_t)
                                     : 0);
        snprintf(build_row->variant, sizeof build_row->variant, "%s", row->variant);
        if (result) {
            for (size_t i = 0; i < (size_t)rays->width * rays->height; i++) result[i] = 0;
            for (uint32_t k = 0; k < f.batches.first[f.batches.cells]; k++) result[f.batches.pixel[k]] = f.answers[k];
        }
    }
    pgrid_shadows_free(&f.grids);
    bench_shadow_batches_free(&f.batches);
    free(f.answers);
    free(f.build_seconds);
    return ok;
}

/* ---- soft shadows through the 3D light grid (--shadows pgrid:N) ----
 * A frame is the 3D grid's build for light 0 (the triangles' corners are
 * made once, as the kd-tree) plus every pixel's N rays, gathered pixel by
 * pixel (a pixel's rays share their origin: one packet of the slice
 * traverser), a row of pixels per job on the thread pool. */

typedef struct pgrid_soft_frame {
    pgrid_soft grids;                  /* its one light: light 0's grid of this frame */
    const pgrid_kernel *kernel;
    const rtt_scene *scene;
    uint32_t width, height, threads;   /* in pixels */
    rtt_ray *packed;                   /* the active rays, pixel after pixel */
    uint32_t *place;                   /* per packed ray: its index in the layout */
    uint32_t *row_first;               /* per pixel row: its first packed ray (height + 1) */
    uint8_t *occluded;                 /* per packed ray */
    pgrid_soft_counts *counts;         /* per row, when counting */
    double *build_seconds;
    uint32_t runs;
    _Atomic bool failed;
} pgrid_soft_frame;

static void trace_soft_row(void *context, uint32_t thread, uint32_t y)
{
    (void)thread;
    pgrid_soft_frame *f = context;
    const uint32_t first = f->row_first[y], end = f->row_first[y + 1];
    f->kernel->soft_occluded(&f->grids, 0, f->packed + first, end - first, f->occluded + first,
                             f->counts ? &f->counts[y] : NULL);
}

static void run_soft_frame(void *context)
{
    pgrid_soft_frame *f = context;
    const uint64_t t0 = rtt_clock_ns();
    pgrid_soft_light_free(&f->grids.lights[0]);
    f->grids.light_count = 0;
    const rtt_light *light = &f->scene->lights[0];
    const float position[3] = {light->position.x, light->position.y, light->position.z};
    if (!pgrid_soft_light_build(&f->grids.lights[0], &f->grids, position, pgrid_soft_light_extent(light), 0, 0)) {
        f->failed = true;
        return;
    }
    if (f->build_seconds) f->build_seconds[f->runs++] = 1e-9 * (double)(rtt_clock_ns() - t0);
    f->grids.light_count = 1;
    rtt_parallel_run(f->height, f->threads, trace_soft_row, f);
}

bool bench_pgrid_soft_row(const rtt_scene *scene, const uint8_t *degenerate, const bench_rays *rays, uint32_t n,
                          const bench_trace_spec *spec, rtt_bench_row *row, rtt_bench_row *build_row, uint32_t *result)
{
    const uint32_t rows = n / 4u, width = rays->width / 4u, height = rays->height / rows;
    pgrid_soft_frame f = {.kernel = pgrid_kernel_find("pgrid", rtt_isa_resolve(spec->isa)), .scene = scene,
                          .width = width, .height = height, .threads = rtt_thread_count(spec->threads)};
    const size_t total = (size_t)rays->width * rays->height;
    f.packed = malloc((rays->active + 1) * sizeof *f.packed);
    f.place = malloc((rays->active + 1) * sizeof *f.place);
    f.occluded = malloc(rays->active + 1);
    f.row_first = malloc(((size_t)height + 1) * sizeof *f.row_first);
    f.build_seconds = calloc((size_t)spec->warmup + spec->frames, sizeof *f.build_seconds);
    rtt_error err;
    bool ok = f.packed && f.place && f.occluded && f.row_first && f.build_seconds &&
              pgrid_soft_prepare(&f.grids, scene, degenerate, &err);
    if (ok) { /* pixel (x, y)'s sample k is at (4x + k % 4, rows y + k / 4) */
        uint32_t m = 0;
        for (uint32_t y = 0; y < height; y++) {
            f.row_first[y] = m;
            for (uint32_t x = 0; x < width; x++)
                for (uint32_t k = 0; k < n; k++) {
                    const uint32_t at = (rows * y + k / 4u) * rays->width + 4u * x + k % 4u;
                    if (!bench_ray_active(&rays->rays[at])) continue;
                    f.packed[m] = rays->rays[at];
                    f.place[m++] = at;
                }
        }
        f.row_first[height] = m;
        snprintf(row->variant, sizeof row->variant, "%s/%s %ux%ux%u", f.kernel->name, rtt_isa_name(f.kernel->isa),
                 PGRID_SOFT_RES_DEFAULT, PGRID_SOFT_RES_DEFAULT, PGRID_SOFT_SLICES_DEFAULT);
        bench_time_frames(run_soft_frame, &f, spec->warmup, spec->frames, row);
        if (f.failed) snprintf(row->error, sizeof row->error, "out of memory in the 3D light grid");
        double *timed = f.build_seconds + spec->warmup;
        qsort(timed, spec->frames, sizeof *timed, compare_double);
        build_row->seconds = timed[spec->frames / 2];
        build_row->seconds_min = timed[0];
        build_row->frames = spec->frames;
        const pgrid_soft_light *L = &f.grids.lights[0];
        build_row->memory_bytes = (size_t)f.grids.tri_count * sizeof(pgrid_soft_tri) + L->ref_count * sizeof(uint32_t) +
                                  ((size_t)L->slices * PGRID_LIGHT_FACES * L->res * L->res + 1) * sizeof(uint32_t);
        snprintf(build_row->variant, sizeof build_row->variant, "%s", row->variant);
        if (spec->count && !f.failed) { /* one more frame, counting: Table 5's steps per ray */
            f.counts = calloc(height, sizeof *f.counts);
            f.build_seconds = (free(f.build_seconds), NULL);
            if (f.counts) {
                run_soft_frame(&f);
                pgrid_soft_counts sum = {0};
                for (uint32_t y = 0; y < height; y++)
                    sum.rays += f.counts[y].rays, sum.steps += f.counts[y].steps, sum.tests += f.counts[y].tests;
                row->n = sum.rays ? (double)sum.steps / (double)sum.rays : 0.0;
                row->i = sum.rays ? (double)sum.tests / (double)sum.rays : 0.0;
            }
            free(f.counts);
        }
        if (result) {
            for (size_t i = 0; i < total; i++) result[i] = 0;
            for (uint32_t j = 0; j < f.row_first[height]; j++) result[f.place[j]] = f.occluded[j];
        }
    }
    pgrid_soft_free(&f.grids);
    free(f.packed), free(f.place), free(f.occluded), free(f.row_first), free(f.build_seconds);
    return ok;
}

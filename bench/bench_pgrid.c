/* The perspective grid's eye rays in the primary race (Hunt & Mark 2008,
 * Table 1's primary columns): a frame is the grid's build plus every cell
 * traced and every pixel's hit resolved (t, u, v, prim into one rtt_hit per
 * pixel, what Embree's rows produce), on the thread counts of the other
 * rows.  The rays are the pixel formula, so unlike the other rows nothing
 * is loaded: that is the method.  The build's median is reported as a
 * build row of the same method, so the build share is build / frame. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
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
    f.hits = malloc((size_t)width * height * sizeof *f.hits);
    f.build_seconds = calloc((size_t)spec->warmup + spec->frames, sizeof *f.build_seconds);
    if (!f.hits || !f.build_seconds) {
        free(f.hits);
        free(f.build_seconds);
        return false;
    }
    snprintf(row->variant, sizeof row->variant, "%s/%s cell %u", f.kernel->name, rtt_isa_name(f.kernel->isa),
             cell ? cell : PGRID_EYE_CELL_DEFAULT);
    row->tile = cell ? cell : PGRID_EYE_CELL_DEFAULT;
    bench_time_frames(run_frame, &f, spec->warmup, spec->frames, row);
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

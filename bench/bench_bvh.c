/* Our BVH kernels alone on the bench's rays (the primary and hard-shadow
 * races against Embree, Benthin & Wald 2009 Table 1's P-Packet column): the
 * frame is cut into 16x16-pixel tiles, each tile's rays reordered into 4x4
 * pixel blocks (row-major blocks, row-major pixels inside a block) so that
 * a 16-wide packet is one 4x4 block, as Embree's rtcIntersect16 row gets
 * it (an 8-wide packet is a 4x2 half, a 4-wide one a row of four); the
 * tiles go to threads through rtt_tiles_run, one kernel call per tile.
 * A kernel that makes primary rays itself from the camera frame (bvh-mft's
 * trace_camera) gets each tile as a pixel rectangle instead and writes its
 * hits there row-major: the rays are made on demand, never loaded, as
 * Benthin & Wald's are.  Counters per thread on the extra counting frame only.  The soft rows'
 * frusta:16 kernel is timed here too, on the same tiles (bench_frusta_row). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "bvh_kernels.h"
#include "engine/threads.h"

#define BVH_BENCH_TILE 16u

typedef struct {
    bvh_counters counters;
    char pad[64 - sizeof(bvh_counters) % 64];
} bvh_thread_counters;

typedef struct bvh_job {
    const bvh_tree *tree;
    const bvh_kernel *kernel;
    const rtt_ray *rays;      /* tile order, BVH_BENCH_TILE^2 per tile */
    uint32_t *pixel;          /* the pixel of each, UINT32_MAX off the image */
    rtt_hit *hits;
    uint8_t *occluded;
    const float *toward;
    const bvh_camera_block *camera; /* the frame, for trace_camera; NULL: the rays */
    bvh_thread_counters *counters;
    uint32_t tiles_x, threads;
} bvh_job;

static void bvh_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    bvh_job *job = context;
    const size_t first = ((size_t)(y0 / BVH_BENCH_TILE) * job->tiles_x + x0 / BVH_BENCH_TILE) *
                         BVH_BENCH_TILE * BVH_BENCH_TILE;
    if (job->camera) {
        bvh_camera_block block = *job->camera;
        block.x0 = x0, block.y0 = y0, block.x1 = x1, block.y1 = y1;
        job->kernel->trace_camera(job->tree, &block, &job->hits[first],
                                  job->counters ? &job->counters[thread].counters : NULL);
        return;
    }
    bvh_query q = {.rays = &job->rays[first], .count = BVH_BENCH_TILE * BVH_BENCH_TILE,
                   .counters = job->counters ? &job->counters[thread].counters : NULL, .toward = job->toward};
    if (job->occluded) q.occluded = &job->occluded[first];
    else q.hits = &job->hits[first];
    job->kernel->trace(job->tree, &q);
}

/* One frame: the image's 16x16 tiles through `tile` on `threads` threads. */
typedef struct bvh_frame {
    rtt_tile_fn tile;
    void *job;
    uint32_t width, height, threads;
} bvh_frame;

static void bvh_frame_run(void *context)
{
    bvh_frame *f = context;
    rtt_tiles_run(f->width, f->height, BVH_BENCH_TILE, f->threads, f->tile, f->job, NULL, NULL);
}

/* The counting frame's totals over the threads. */
static void counters_sum(const bvh_thread_counters *counters, uint32_t threads, bvh_counters *sum)
{
    memset(sum, 0, sizeof *sum);
    for (uint32_t t = 0; t < threads; t++) {
        sum->packets += counters[t].counters.packets;
        sum->aabb_tests += counters[t].counters.aabb_tests;
        sum->triangles += counters[t].counters.triangles;
        sum->isect_tests += counters[t].counters.isect_tests;
    }
}

bool bench_bvh_row(const bvh_tree *tree, const bench_rays *rays, const char *kernel_name, const float *toward,
                   const bench_trace_spec *spec, rtt_bench_row *row, bvh_counters *total, uint32_t *result)
{
    const uint32_t w = rays->width, h = rays->height;
    const uint32_t tiles_x = (w + BVH_BENCH_TILE - 1) / BVH_BENCH_TILE, tiles_y = (h + BVH_BENCH_TILE - 1) / BVH_BENCH_TILE;
    const size_t slots = (size_t)tiles_x * tiles_y * BVH_BENCH_TILE * BVH_BENCH_TILE;
    bvh_job job = {.tree = tree, .kernel = bvh_kernel_find(kernel_name, rtt_isa_resolve(spec->isa)),
                   .tiles_x = tiles_x, .threads = spec->threads, .toward = spec->occlusion ? toward : NULL};
    if (!job.kernel) {
        snprintf(row->error, sizeof row->error, "no bvh kernel named %s", kernel_name);
        return true;
    }
    rtt_ray *ordered = malloc(slots * sizeof *ordered);
    job.pixel = malloc(slots * sizeof *job.pixel);
    /* 64-byte lines: a tile's rows (16 records) start on one, for bvh-mft's streamed stores */
    job.hits = spec->occlusion ? NULL : aligned_alloc(64, slots * sizeof *job.hits);
    job.occluded = spec->occlusion ? malloc(slots) : NULL;
    bvh_thread_counters *counters = spec->count ? calloc(spec->threads, sizeof *counters) : NULL;
    if (!ordered || !job.pixel || (!job.hits && !job.occluded) || (spec->count && !counters)) {
        free(ordered), free(job.pixel), free(job.hits), free(job.occluded), free(counters);
        return false;
    }
    const rtt_ray off_image = {{0, 0, 0}, {1, 0, 0}, INFINITY, -INFINITY};
    for (size_t i = 0; i < slots; i++) {
        const uint32_t tile = (uint32_t)(i / (BVH_BENCH_TILE * BVH_BENCH_TILE)), in = (uint32_t)(i % 256u);
        const uint32_t block = in / 16u, lane = in % 16u;
        const uint32_t x = (tile % tiles_x) * BVH_BENCH_TILE + (block % 4u) * 4u + lane % 4u;
        const uint32_t y = (tile / tiles_x) * BVH_BENCH_TILE + (block / 4u) * 4u + lane / 4u;
        const bool on = x < w && y < h;
        job.pixel[i] = on ? y * w + x : UINT32_MAX;
        ordered[i] = on ? rays->rays[(size_t)y * w + x] : off_image;
    }
    job.rays = ordered;
    const rtt_camera_frame *c = &rays->camera;
    const bvh_camera_block camera = {{c->eye.x, c->eye.y, c->eye.z}, {c->corner.x, c->corner.y, c->corner.z},
                                     {c->du.x, c->du.y, c->du.z}, {c->dv.x, c->dv.y, c->dv.z}, 0, 0, 0, 0,
                                     true /* a frame's hits, read after it: streamed */};
    if (!spec->occlusion && rays->from_camera && job.kernel->trace_camera) {
        job.camera = &camera;
        /* the tile's hits row-major (bvh_camera_block) */
        for (size_t i = 0; i < slots; i++) {
            const uint32_t tile = (uint32_t)(i / (BVH_BENCH_TILE * BVH_BENCH_TILE)), in = (uint32_t)(i % 256u);
            const uint32_t tx = (tile % tiles_x) * BVH_BENCH_TILE, ty = (tile / tiles_x) * BVH_BENCH_TILE;
            const uint32_t tw = w - tx < BVH_BENCH_TILE ? w - tx : BVH_BENCH_TILE;
            const uint32_t th = h - ty < BVH_BENCH_TILE ? h - ty : BVH_BENCH_TILE;
            job.pixel[i] = in < tw * th ? (ty + in / tw) * w + tx + in % tw : UINT32_MAX;
        }
    }
    bvh_frame frame = {bvh_tile, &job, w, h, spec->threads};
    bench_time_frames(bvh_frame_run, &frame, spec->warmup, spec->frames, row);
    row->n = row->i = -1.0;
    if (counters) {
        job.counters = counters;
        bvh_frame_run(&frame);
        bvh_counters sum;
        counters_sum(counters, spec->threads, &sum);
        if (total) *total = sum;
        /* per 2x2 packet of rays, as the kd rows count N and I */
        const double quads = (double)slots / 4.0;
        row->n = (double)sum.aabb_tests / quads;
        row->i = (double)sum.isect_tests / quads;
    }
    if (result)
        for (size_t i = 0; i < slots; i++) {
            if (job.pixel[i] == UINT32_MAX) continue;
            result[job.pixel[i]] = spec->occlusion ? job.occluded[i] : job.hits[i].prim;
        }
    free(ordered), free(job.pixel), free(job.hits), free(job.occluded), free(counters);
    return true;
}

/* ---- soft shadows: the frusta:16 row (bench_frusta.c makes its work) ---- */

typedef struct soft_job {
    const bvh_tree *tree;
    const bvh_shadow_kernel *kernel;
    const bench_soft *soft;
    const bvh_shadow_point *points;  /* per tile, its pixels with a hit in 4x4 block order */
    const uint32_t *first;           /* tile t's points: first[t] .. first[t + 1] */
    uint32_t *masks;                 /* one per point */
    bvh_thread_counters *counters;
    uint32_t tiles_x;
} soft_job;

static void soft_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)x1, (void)y1;
    soft_job *job = context;
    const uint32_t tile = (y0 / BVH_BENCH_TILE) * job->tiles_x + x0 / BVH_BENCH_TILE, first = job->first[tile];
    job->kernel->trace(job->tree, &(bvh_shadow_query){.points = &job->points[first],
                                                      .count = job->first[tile + 1] - first,
                                                      .sets = &job->soft->sets,
                                                      .epsilon = job->soft->epsilon,
                                                      .occluded = &job->masks[first],
                                                      .counters = job->counters ? &job->counters[thread].counters
                                                                                : NULL});
}

bool bench_frusta_row(const bvh_tree *tree, const bench_soft *soft, const bench_trace_spec *spec, rtt_bench_row *row,
                      bvh_counters *sum, uint32_t *result)
{
    const uint32_t w = soft->width, h = soft->height;
    const uint32_t tiles_x = (w + BVH_BENCH_TILE - 1) / BVH_BENCH_TILE, tiles_y = (h + BVH_BENCH_TILE - 1) / BVH_BENCH_TILE;
    const size_t tiles = (size_t)tiles_x * tiles_y, pixels = (size_t)w * h;
    soft_job job = {.tree = tree, .kernel = bvh_shadow_kernel_find(rtt_isa_resolve(spec->isa)), .soft = soft,
                    .tiles_x = tiles_x};
    bvh_shadow_point *points = malloc((pixels ? pixels : 1) * sizeof *points);
    uint32_t *first = malloc((tiles + 1) * sizeof *first), *pixel = malloc((pixels ? pixels : 1) * sizeof *pixel);
    uint32_t *masks = calloc(pixels ? pixels : 1, sizeof *masks);
    bvh_thread_counters *counters = sum && spec->count ? calloc(spec->threads, sizeof *counters) : NULL;
    if (!points || !first || !pixel || !masks || (sum && spec->count && !counters)) {
        free(points), free(first), free(pixel), free(masks), free(counters);
        return false;
    }
    uint32_t count = 0;
    for (size_t tile = 0; tile < tiles; tile++) { /* tiles row-major, 4x4 blocks row-major, pixels row-major */
        first[tile] = count;
        for (uint32_t in = 0; in < BVH_BENCH_TILE * BVH_BENCH_TILE; in++) {
            const uint32_t block = in / 16u, lane = in % 16u;
            const uint32_t x = (uint32_t)(tile % tiles_x) * BVH_BENCH_TILE + (block % 4u) * 4u + lane % 4u;
            const uint32_t y = (uint32_t)(tile / tiles_x) * BVH_BENCH_TILE + (block / 4u) * 4u + lane / 4u;
            if (x >= w || y >= h || !soft->has[(size_t)y * w + x]) continue;
            pixel[count] = y * w + x;
            points[count++] = soft->points[(size_t)y * w + x];
        }
    }
    first[tiles] = count;
    job.points = points, job.first = first, job.masks = masks;
    bvh_frame frame = {soft_tile, &job, w, h, spec->threads};
    bench_time_frames(bvh_frame_run, &frame, spec->warmup, spec->frames, row);
    row->n = row->i = -1.0;
    if (counters) {
        job.counters = counters;
        bvh_frame_run(&frame);
        counters_sum(counters, spec->threads, sum);
        /* per 2x2 rays of the rays' image, as the BVH rows count N and I on it */
        const double quads = (double)soft->rays.width * soft->rays.height / 4.0;
        row->n = quads > 0 ? (double)sum->aabb_tests / quads : 0.0;
        row->i = quads > 0 ? (double)sum->isect_tests / quads : 0.0;
    }
    if (result) /* each ray's bit, at its place in the rays' image (inactive rays: clear) */
        for (uint32_t i = 0; i < count; i++) {
            const uint32_t x = pixel[i] % w, y = pixel[i] / w;
            for (uint32_t k = 0; k < BENCH_SOFT_SAMPLES; k++)
                result[(size_t)(4u * y + k / 4u) * soft->rays.width + 4u * x + k % 4u] = masks[i] >> k & 1u;
        }
    free(points), free(first), free(pixel), free(masks), free(counters);
    return true;
}

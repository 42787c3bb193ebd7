/* Our traversal kernels alone on ready tile blocks (the primary-visibility
 * race against Embree): per tile, clear the hit records and call the kernel of
 * the traversal once on the tile's block, exactly as render_optimized.c
 * calls it for primary rays, but without ray generation and shading.  Tiles
 * go to threads through rtt_tiles_run, as in the renderer and as the Embree
 * peer's tiles do.  Counters are per thread (cache-line apart) and only on
 * the extra counting frame. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "engine/threads.h"
#include "kernels.h"
#include "rtt/image.h"

typedef struct {
    kd_counters counters;
    char pad[64 - sizeof(kd_counters) % 64];
} thread_counters;

typedef struct kernel_job {
    const kd_tree *tree;
    const bench_blocks *blocks;
    const kd_kernel *kernel;
    bool occlusion;
    int leaf_culling;
    hit_packet4 *hits;
    uint8_t *masks;
    thread_counters *counters; /* NULL on timed frames */
    uint32_t threads;
} kernel_job;

static void kernel_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)x1, (void)y1;
    kernel_job *job = context;
    const bench_blocks *b = job->blocks;
    size_t tile = (size_t)(y0 / b->tile) * b->tiles_x + x0 / b->tile;
    size_t first = tile * b->block_packets;
    kd_counters *counters = job->counters ? &job->counters[thread].counters : NULL;
    kd_query q = {.packets = &b->packets[first], .packet_count = b->block_packets, .leaf_culling = job->leaf_culling,
                  .counters = counters};
    if (job->occlusion) {
        q.occluded = &job->masks[first];
    } else {
        q.hits = &job->hits[first];
        for (uint32_t p = 0; p < b->block_packets; p++) hit_packet4_clear(&q.hits[p]);
    }
    job->kernel->trace(job->tree, &q);
}

typedef struct frame_context {
    kernel_job *job;
    uint32_t width, height;
} frame_context;

static void kernel_frame(void *context)
{
    frame_context *f = context;
    rtt_tiles_run(f->width, f->height, f->job->blocks->tile, f->job->threads, kernel_tile, f->job, NULL, NULL);
}

static void store_results(const kernel_job *job, uint32_t *result, size_t pixels)
{
    const bench_blocks *b = job->blocks;
    size_t packets = (size_t)b->tiles_x * b->tiles_y * b->block_packets;
    for (size_t i = 0; i < pixels; i++) result[i] = job->occlusion ? 0u : RTT_MISS;
    for (size_t p = 0; p < packets; p++) {
        rtt_hit hits[4] = {{0}};
        if (!job->occlusion) hit_packet4_store(&job->hits[p], hits, 4);
        for (uint32_t l = 0; l < 4; l++) {
            uint32_t pixel = b->pixel[4 * p + l];
            if (pixel == UINT32_MAX) continue;
            result[pixel] = job->occlusion ? (job->masks[p] >> l) & 1u : hits[l].prim;
        }
    }
}

bool bench_kernel_row(const kd_tree *tree, const bench_blocks *blocks, uint32_t width, uint32_t height,
                      const char *kernel_name, int leaf_culling, const bench_trace_spec *spec, rtt_bench_row *row,
                      uint32_t *result)
{
    size_t packets = (size_t)blocks->tiles_x * blocks->tiles_y * blocks->block_packets;
    kernel_job job = {
        .tree = tree,
        .blocks = blocks,
        .kernel = kd_kernel_find(kernel_name, rtt_isa_resolve(spec->isa)),
        .occlusion = spec->occlusion,
        .leaf_culling = leaf_culling,
        .threads = spec->threads,
    };
    if (!job.kernel) {
        snprintf(row->error, sizeof row->error, "no kd kernel named %s", kernel_name);
        return true;
    }
    job.hits = spec->occlusion ? NULL : aligned_alloc(64, ((packets * sizeof(hit_packet4) + 63) / 64) * 64);
    job.masks = spec->occlusion ? calloc(packets, 1) : NULL;
    job.counters = spec->count ? calloc(spec->threads, sizeof(thread_counters)) : NULL;
    if ((!job.hits && !job.masks) || (spec->count && !job.counters)) {
        free(job.hits), free(job.masks), free(job.counters);
        return false;
    }
    frame_context frame = {&job, width, height};
    thread_counters *counters = job.counters;
    job.counters = NULL;
    bench_time_frames(kernel_frame, &frame, spec->warmup, spec->frames, row);
    row->n = row->i = -1.0;
    if (counters) {
        job.counters = counters;
        kernel_frame(&frame);
        kd_counters sum = {0, 0, 0};
        for (uint32_t t = 0; t < spec->threads; t++) {
            sum.packets += job.counters[t].counters.packets;
            sum.steps += job.counters[t].counters.steps;
            sum.isects += job.counters[t].counters.isects;
        }
        if (sum.packets) {
            row->n = (double)sum.steps / (double)sum.packets;
            row->i = (double)sum.isects / (double)sum.packets;
        }
    }
    if (result) store_results(&job, result, (size_t)width * height);
    free(job.hits), free(job.masks), free(counters);
    return true;
}

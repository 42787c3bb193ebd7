/* The Embree 3 peer of the benchmarks, on exactly the rays our kernels
 * trace (bench_internal.h).
 *
 * Fairness, as the report states it:
 * - Same rays (the per-pixel rays of bench_frame.c), same tile scheduler
 *   (rtt_tiles_run, 16x16 tiles), same thread count, same process.
 * - Rays are stored ready in Embree's own layout before timing (as ours are
 *   stored as ray_packet4); inside a timed frame each side only resets its
 *   hit records (Embree: tfar and geomID per lane; ours: hit_packet4_clear).
 * - rtcIntersect1 over the pixels of a tile in row order; rtcIntersect4/8/16
 *   over 2x2, 4x2 and 4x4 pixel blocks with RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
 *   rtcOccluded1/16 likewise for hard shadows.
 * - Variants: Embree's native ISA choice (AVX-512/AVX2 where the CPU has
 *   them) or pinned to SSE4.2 like our kernels; RTC_SCENE_FLAG_ROBUST or no
 *   flag.  RTC_BUILD_QUALITY_HIGH always; the device is created with
 *   threads=1 so its build time compares with our one-thread build (the
 *   thread count of a device only affects builds, never rtcIntersect). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "engine/threads.h"
#include "embree_engine.h"

#ifdef RTT_HAVE_EMBREE
#include <embree3/rtcore.h>

#include "rtt/image.h"

_Static_assert(sizeof(struct RTCRayHit) == 80, "RTCRayHit is 20 four-byte slots (one instance level)");
_Static_assert(sizeof(struct RTCRayHit16) == 1280, "RTCRayHit16 is 20 slots of 16 lanes");

/* Slots of Embree's ray/hit layouts: field f of lane i of an N-wide
 * structure of arrays is slot f * N + i (N = 1 is RTCRayHit itself). */
enum { SLOT_ORG = 0, SLOT_TNEAR = 3, SLOT_DIR = 4, SLOT_TIME = 7, SLOT_TFAR = 8, SLOT_MASK = 9, SLOT_ID = 10,
       SLOT_FLAGS = 11, SLOT_PRIM = 17, SLOT_GEOM = 18, SLOT_INST = 19, SLOTS = 20 };

#define PEER_TILE 16u

struct bench_embree {
    RTCDevice device;
    RTCScene scene;
    char variant[32];
    _Atomic long long memory;  /* bytes Embree holds, from its memory monitor */
    char first_error[200];
};

static void record_error(void *user, enum RTCError code, const char *str)
{
    bench_embree *peer = user;
    if (peer->first_error[0] == '\0')
        snprintf(peer->first_error, sizeof peer->first_error, "embree error %d: %s", (int)code, str ? str : "?");
}

static bool monitor_memory(void *user, ssize_t bytes, bool post)
{
    bench_embree *peer = user;
    if (!post) peer->memory += bytes;
    return true;
}

bool bench_embree_available(void) { return true; }

const char *bench_embree_variant(const bench_embree *peer) { return peer->variant; }

void bench_embree_destroy(bench_embree *peer)
{
    if (!peer) return;
    if (peer->scene) rtcReleaseScene(peer->scene);
    if (peer->device) rtcReleaseDevice(peer->device);
    free(peer);
}

static bool attach_triangles(bench_embree *peer, const rtt_scene *scene)
{
    return rtt_embree_attach_triangles(peer->device, peer->scene, scene) && peer->first_error[0] == '\0';
}

bench_embree *bench_embree_create(const rtt_scene *scene, bool native, bool robust, rtt_bench_row *build_row,
                                  rtt_error *err)
{
    bench_embree *peer = calloc(1, sizeof *peer);
    if (!peer) {
        rtt_error_set(err, "%s: out of memory creating the Embree peer", scene->path);
        return NULL;
    }
    snprintf(peer->variant, sizeof peer->variant, "%s %s", native ? "native" : "sse4.2", robust ? "robust" : "default");
    const char *config = native ? "threads=1,verbose=0" : "isa=sse4.2,threads=1,verbose=0";
    peer->device = rtcNewDevice(config);
    if (!peer->device) {
        rtt_error_set(err, "%s: embree: rtcNewDevice(\"%s\") failed", scene->path, config);
        free(peer);
        return NULL;
    }
    rtcSetDeviceErrorFunction(peer->device, record_error, peer);
    rtcSetDeviceMemoryMonitorFunction(peer->device, monitor_memory, peer);
    double start = rtt_clock_seconds();
    peer->scene = rtcNewScene(peer->device);
    if (peer->scene) {
        rtcSetSceneFlags(peer->scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
        rtcSetSceneBuildQuality(peer->scene, RTC_BUILD_QUALITY_HIGH);
        if (scene->triangle_count == 0 || attach_triangles(peer, scene)) rtcCommitScene(peer->scene);
    }
    double seconds = rtt_clock_seconds() - start;
    if (!peer->scene || peer->first_error[0]) {
        rtt_error_set(err, "%s: %s", scene->path, peer->first_error[0] ? peer->first_error : "embree: no scene");
        bench_embree_destroy(peer);
        return NULL;
    }
    if (build_row) {
        build_row->seconds = build_row->seconds_min = seconds;
        build_row->frames = 1;
        build_row->memory_bytes = peer->memory > 0 ? (uint64_t)peer->memory : 0;
    }
    return peer;
}

/* The rays in Embree's layout, per 16x16 tile, in blocks of `lanes`. */
typedef struct peer_rays {
    uint32_t lanes, block_w, block_h, blocks_per_tile, tiles_x, tiles_y;
    float *slots;         /* blocks * SLOTS * lanes, 64-byte aligned */
    int *valid;           /* blocks * lanes: -1 active, 0 not */
    uint32_t *pixel;      /* blocks * lanes, UINT32_MAX when inactive */
    float *tfar;          /* blocks * lanes: the pristine tfar */
} peer_rays;

static void peer_rays_free(peer_rays *p)
{
    free(p->slots), free(p->valid), free(p->pixel), free(p->tfar);
    memset(p, 0, sizeof *p);
}

static void fill_lane(float *block, uint32_t lanes, uint32_t i, const rtt_ray *r)
{
    for (int a = 0; a < 3; a++) {
        block[(SLOT_ORG + a) * lanes + i] = r->org[a];
        block[(SLOT_DIR + a) * lanes + i] = r->dir[a];
    }
    block[SLOT_TNEAR * lanes + i] = r->tnear < 0.0f ? 0.0f : r->tnear;
    block[SLOT_TIME * lanes + i] = 0.0f;
    block[SLOT_TFAR * lanes + i] = r->tfar;
    uint32_t *words = (uint32_t *)block;
    words[SLOT_MASK * lanes + i] = 0xFFFFFFFFu;
    words[SLOT_ID * lanes + i] = 0;
    words[SLOT_FLAGS * lanes + i] = 0;
    words[SLOT_GEOM * lanes + i] = RTC_INVALID_GEOMETRY_ID;
    words[SLOT_INST * lanes + i] = RTC_INVALID_GEOMETRY_ID;
}

static bool peer_rays_make(const bench_rays *rays, uint32_t lanes, peer_rays *p)
{
    memset(p, 0, sizeof *p);
    p->lanes = lanes;
    p->block_w = lanes == 1 ? 1 : lanes == 4 ? 2 : 4;
    p->block_h = lanes / p->block_w;
    p->blocks_per_tile = PEER_TILE * PEER_TILE / lanes;
    p->tiles_x = (rays->width + PEER_TILE - 1) / PEER_TILE;
    p->tiles_y = (rays->height + PEER_TILE - 1) / PEER_TILE;
    size_t blocks = (size_t)p->tiles_x * p->tiles_y * p->blocks_per_tile, total = blocks * lanes;
    p->slots = aligned_alloc(64, ((total * SLOTS * sizeof(float) + 63) / 64) * 64);
    p->valid = aligned_alloc(64, ((total * sizeof(int) + 63) / 64) * 64);
    p->pixel = malloc(total * sizeof *p->pixel);
    p->tfar = malloc(total * sizeof *p->tfar);
    if (!p->slots || !p->valid || !p->pixel || !p->tfar) {
        peer_rays_free(p);
        return false;
    }
    const rtt_ray inactive = {{0, 0, 0}, {1, 0, 0}, 0.0f, -1.0f};
    const uint32_t blocks_x = PEER_TILE / p->block_w;
    for (size_t b = 0; b < blocks; b++) {
        size_t tile = b / p->blocks_per_tile;
        uint32_t within = (uint32_t)(b % p->blocks_per_tile);
        uint32_t bx = (uint32_t)(tile % p->tiles_x) * PEER_TILE + (within % blocks_x) * p->block_w;
        uint32_t by = (uint32_t)(tile / p->tiles_x) * PEER_TILE + (within / blocks_x) * p->block_h;
        float *block = &p->slots[b * SLOTS * lanes];
        for (uint32_t i = 0; i < lanes; i++) {
            uint32_t px = bx + i % p->block_w, py = by + i / p->block_w;
            size_t lane = b * lanes + i;
            const rtt_ray *r = &inactive;
            p->pixel[lane] = UINT32_MAX;
            if (px < rays->width && py < rays->height && bench_ray_active(&rays->rays[(size_t)py * rays->width + px])) {
                p->pixel[lane] = py * rays->width + px;
                r = &rays->rays[p->pixel[lane]];
            }
            p->valid[lane] = p->pixel[lane] == UINT32_MAX ? 0 : -1;
            p->tfar[lane] = r->tfar;
            fill_lane(block, lanes, i, r);
        }
    }
    return true;
}

typedef struct peer_job {
    bench_embree *peer;
    peer_rays *rays;
    bool occlusion;
    uint32_t width, height, threads;
} peer_job;

static void trace_block(const peer_job *job, struct RTCIntersectContext *context, size_t b)
{
    const peer_rays *p = job->rays;
    const uint32_t lanes = p->lanes;
    float *block = &p->slots[b * SLOTS * lanes];
    const int *valid = &p->valid[b * lanes];
    uint32_t *words = (uint32_t *)block;
    for (uint32_t i = 0; i < lanes; i++) {
        block[SLOT_TFAR * lanes + i] = p->tfar[b * lanes + i];
        words[SLOT_GEOM * lanes + i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCScene scene = job->peer->scene;
    if (job->occlusion) {
        switch (lanes) {
        case 1: if (valid[0]) rtcOccluded1(scene, context, (struct RTCRay *)block); break;
        case 4: rtcOccluded4(valid, scene, context, (struct RTCRay4 *)block); break;
        case 8: rtcOccluded8(valid, scene, context, (struct RTCRay8 *)block); break;
        default: rtcOccluded16(valid, scene, context, (struct RTCRay16 *)block); break;
        }
        return;
    }
    switch (lanes) {
    case 1: if (valid[0]) rtcIntersect1(scene, context, (struct RTCRayHit *)block); break;
    case 4: rtcIntersect4(valid, scene, context, (struct RTCRayHit4 *)block); break;
    case 8: rtcIntersect8(valid, scene, context, (struct RTCRayHit8 *)block); break;
    default: rtcIntersect16(valid, scene, context, (struct RTCRayHit16 *)block); break;
    }
}

static void peer_tile(void *context, uint32_t thread, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1)
{
    (void)thread, (void)x1, (void)y1;
    const peer_job *job = context;
    const peer_rays *p = job->rays;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = p->lanes > 1 ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    size_t tile = (size_t)(y0 / PEER_TILE) * p->tiles_x + x0 / PEER_TILE;
    for (uint32_t k = 0; k < p->blocks_per_tile; k++) trace_block(job, &ctx, tile * p->blocks_per_tile + k);
}

static void peer_frame(void *context)
{
    peer_job *job = context;
    rtt_tiles_run(job->width, job->height, PEER_TILE, job->threads, peer_tile, job, NULL, NULL);
}

static void store_results(const peer_job *job, uint32_t *result, size_t pixels)
{
    const peer_rays *p = job->rays;
    for (size_t i = 0; i < pixels; i++) result[i] = job->occlusion ? 0u : RTT_MISS;
    size_t lanes = (size_t)p->tiles_x * p->tiles_y * p->blocks_per_tile * p->lanes;
    for (size_t lane = 0; lane < lanes; lane++) {
        if (p->pixel[lane] == UINT32_MAX) continue;
        size_t b = lane / p->lanes, i = lane % p->lanes;
        const float *block = &p->slots[b * SLOTS * p->lanes];
        const uint32_t *words = (const uint32_t *)block;
        if (job->occlusion) result[p->pixel[lane]] = block[SLOT_TFAR * p->lanes + i] == -INFINITY;
        else if (words[SLOT_GEOM * p->lanes + i] != RTC_INVALID_GEOMETRY_ID)
            result[p->pixel[lane]] = words[SLOT_PRIM * p->lanes + i];
    }
}

bool bench_embree_row(bench_embree *peer, const bench_rays *rays, uint32_t lanes, const bench_trace_spec *spec,
                      rtt_bench_row *row, uint32_t *result, rtt_error *err)
{
    peer_rays p;
    if (!peer_rays_make(rays, lanes, &p)) return rtt_error_set(err, "out of memory laying out rays for Embree");
    peer_job job = {peer, &p, spec->occlusion, rays->width, rays->height, spec->threads};
    bench_time_frames(peer_frame, &job, spec->warmup, spec->frames, row);
    row->n = row->i = -1.0;
    if (result) store_results(&job, result, (size_t)rays->width * rays->height);
    peer_rays_free(&p);
    if (peer->first_error[0]) snprintf(row->error, sizeof row->error, "%.200s", peer->first_error);
    return true;
}

#else /* built without Embree: the peer reports itself missing */

struct bench_embree {
    int unused;
};

bool bench_embree_available(void) { return false; }
const char *bench_embree_variant(const bench_embree *peer) { return peer ? "none" : "none"; }
void bench_embree_destroy(bench_embree *peer) { (void)peer; }

bench_embree *bench_embree_create(const rtt_scene *scene, bool native, bool robust, rtt_bench_row *build_row,
                                  rtt_error *err)
{
    (void)native, (void)robust, (void)build_row;
    rtt_error_set(err, "%s: rtt was built without Embree (RTT_EMBREE=OFF)", scene->path);
    return NULL;
}

bool bench_embree_row(bench_embree *peer, const bench_rays *rays, uint32_t lanes, const bench_trace_spec *spec,
                      rtt_bench_row *row, uint32_t *result, rtt_error *err)
{
    (void)peer, (void)rays, (void)lanes, (void)spec, (void)row, (void)result;
    return rtt_error_set(err, "rtt was built without Embree (RTT_EMBREE=OFF)");
}

#endif

/* The rays of one benchmark frame and the tile blocks our kernels read
 * (bench_internal.h), plus the frame timer.  Rays are made once per row
 * set, outside any timed frame, so both racers read identical, ready rays. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_internal.h"
#include "rtt/shade.h"

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void bench_time_frames(bench_frame_fn fn, void *context, uint32_t warmup, uint32_t frames, rtt_bench_row *row)
{
    enum { MAX_FRAMES = 64 };
    double times[MAX_FRAMES];
    if (frames < 1) frames = 1;
    if (frames > MAX_FRAMES) frames = MAX_FRAMES;
    for (uint32_t f = 0; f < warmup; f++) fn(context);
    for (uint32_t f = 0; f < frames; f++) {
        double start = rtt_clock_seconds();
        fn(context);
        times[f] = rtt_clock_seconds() - start;
    }
    qsort(times, frames, sizeof times[0], compare_doubles);
    row->frames = frames;
    row->seconds = frames % 2 ? times[frames / 2] : 0.5 * (times[frames / 2 - 1] + times[frames / 2]);
    row->seconds_min = times[0];
    row->fps = row->seconds > 0 ? 1.0 / row->seconds : 0.0;
    row->rays_per_second = row->seconds > 0 ? (double)row->rays / row->seconds : 0.0;
}

static const rtt_ray inactive_ray = {{0, 0, 0}, {1, 0, 0}, INFINITY, -INFINITY};

bool bench_rays_primary(const rtt_scene *scene, uint32_t width, uint32_t height, bench_rays *out)
{
    memset(out, 0, sizeof *out);
    out->rays = malloc((size_t)width * height * sizeof *out->rays);
    if (!out->rays) return false;
    out->width = width;
    out->height = height;
    rtt_camera_frame frame = rtt_camera_frame_make(&scene->camera, width, height);
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) out->rays[(size_t)y * width + x] = rtt_camera_ray(&frame, x, y);
    out->active = (uint64_t)width * height;
    out->from_camera = true;
    out->camera = frame;
    return true;
}

bool bench_rays_shadow(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                       bench_rays *out)
{
    memset(out, 0, sizeof *out);
    size_t count = (size_t)primary->width * primary->height;
    out->rays = malloc(count * sizeof *out->rays);
    if (!out->rays) return false;
    out->width = primary->width;
    out->height = primary->height;
    const float epsilon = rtt_scene_ray_epsilon(scene);
    const rtt_vec3 light = scene->lights[0].position;
    for (size_t i = 0; i < count; i++) {
        const rtt_ray *r = &primary->rays[i];
        out->rays[i] = inactive_ray;
        if (prim[i] == RTT_MISS) continue;
        float p[3], to[3], lp[3] = {light.x, light.y, light.z}, d2 = 0.0f;
        for (int a = 0; a < 3; a++) {
            p[a] = r->org[a] + t[i] * r->dir[a];
            to[a] = lp[a] - p[a];
            d2 += to[a] * to[a];
        }
        float d = sqrtf(d2);
        if (!(d > 2.0f * epsilon)) continue;
        rtt_ray *s = &out->rays[i];
        for (int a = 0; a < 3; a++) {
            s->org[a] = p[a];
            s->dir[a] = to[a] / d;
        }
        s->tnear = epsilon;
        s->tfar = d - epsilon;
        out->active++;
    }
    return true;
}

void bench_rays_free(bench_rays *rays)
{
    free(rays->rays);
    memset(rays, 0, sizeof *rays);
}

bool bench_blocks_make(const bench_rays *rays, uint32_t tile, bench_blocks *out)
{
    memset(out, 0, sizeof *out);
    const uint32_t side = tile / 2u;
    out->tile = tile;
    out->tiles_x = (rays->width + tile - 1) / tile;
    out->tiles_y = (rays->height + tile - 1) / tile;
    out->block_packets = side * side;
    size_t packets = (size_t)out->tiles_x * out->tiles_y * out->block_packets;
    out->packets = aligned_alloc(64, ((packets * sizeof *out->packets + 63) / 64) * 64);
    out->pixel = malloc(packets * 4 * sizeof *out->pixel);
    if (!out->packets || !out->pixel) {
        bench_blocks_free(out);
        return false;
    }
    for (uint32_t ty = 0; ty < out->tiles_y; ty++)
        for (uint32_t tx = 0; tx < out->tiles_x; tx++) {
            size_t base = ((size_t)ty * out->tiles_x + tx) * out->block_packets;
            for (uint32_t q = 0; q < out->block_packets; q++) {
                uint32_t qx = tx * tile + 2u * (q % side), qy = ty * tile + 2u * (q / side);
                rtt_ray lanes[4];
                for (uint32_t l = 0; l < 4; l++) {
                    uint32_t px = qx + (l & 1u), py = qy + (l >> 1);
                    uint32_t pixel = UINT32_MAX;
                    lanes[l] = inactive_ray;
                    if (px < rays->width && py < rays->height) {
                        pixel = py * rays->width + px;
                        lanes[l] = rays->rays[pixel];
                        if (!bench_ray_active(&lanes[l])) pixel = UINT32_MAX;
                    }
                    out->pixel[4 * (base + q) + l] = pixel;
                }
                ray_packet4_load(&out->packets[base + q], lanes, 4);
            }
        }
    return true;
}

void bench_blocks_free(bench_blocks *blocks)
{
    free(blocks->packets);
    free(blocks->pixel);
    memset(blocks, 0, sizeof *blocks);
}

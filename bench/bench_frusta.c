/* The soft-shadow rows (kind "soft", Benthin & Wald 2009 Table 1's S-Frusta
 * and S-Packet): every primary hit's 16 samples of the first light (which
 * must have area) from the pixel's 4x4 interleaved set (rtt/interleaved.h),
 * as --shadows frusta:16 traces them.
 *
 *   frusta:16   our soft-shadow frusta kernel (bvh_shadow_kernel): 16x16
 *               tiles of 4x4 pixel blocks, one frustum per pixel, the rays
 *               generated on demand;
 *   the rays    the same samples as explicit rays, laid out as an image 4x
 *               wider and higher: pixel (x, y)'s sample k at (4x + k % 4,
 *               4y + k / 4), so a 4x4 block of that image is one pixel's 16
 *               rays.  Embree's rtcOccluded16 over 4x4 blocks (coherent
 *               flag) then traces one pixel's rays per packet, and our own
 *               bvh-packet over 4x4 blocks (bench_bvh.c) the same packets
 *               ("S-Packet").
 *
 * The frusta:16 row itself is bench_bvh.c's (bench_frusta_row), beside the
 * BVH rows it shares its tiles and counters with.  A ray is built with the optimized renderer's operations (shader_proxy.c's
 * shadow_segment on rtt_light_frame_point), so each side answers the same
 * rays and the agree column compares them ray by ray. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "bvh_kernels.h"
#include "rtt/interleaved.h"
#include "rtt/shade.h"

static const rtt_ray inactive = {{0, 0, 0}, {1, 0, 0}, INFINITY, -INFINITY};

/* The shader proxy's shadow segment from p to target (shader_proxy.c's
 * shadow_segment); false (and the inactive ray) when none fits. */
static bool segment_ray(rtt_vec3 p, rtt_vec3 target, float epsilon, rtt_ray *ray)
{
    *ray = inactive;
    const rtt_vec3 to = rtt_v3_sub(target, p);
    const float d = rtt_v3_length(to);
    if (!(d > 2.0f * epsilon)) return false;
    const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / d);
    *ray = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, epsilon, d - epsilon};
    return true;
}

/* Pixel i's primary hit point (false on a miss). */
static bool hit_point(const bench_rays *primary, const uint32_t *prim, const float *t, size_t i, rtt_vec3 *p)
{
    const rtt_ray *r = &primary->rays[i];
    *p = rtt_v3(0, 0, 0);
    if (prim[i] == RTT_MISS) return false;
    *p = rtt_v3(r->org[0] + t[i] * r->dir[0], r->org[1] + t[i] * r->dir[1], r->org[2] + t[i] * r->dir[2]);
    return true;
}

bool bench_soft_make(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                     bench_soft *out, rtt_error *err)
{
    memset(out, 0, sizeof *out);
    if (scene->light_count == 0 || !rtt_light_has_area(&scene->lights[0]))
        return rtt_error_set(err, "soft rows need the first light to have area (a sphere or quad light)");
    const rtt_light *light = &scene->lights[0];
    const uint32_t w = primary->width, h = primary->height, n = BENCH_SOFT_SAMPLES;
    const size_t pixels = (size_t)w * h;
    out->width = w, out->height = h;
    out->epsilon = rtt_scene_ray_epsilon(scene);
    out->sets.samples = n;
    float xy[BVH_SHADOW_MAX_SAMPLES][2];
    for (uint32_t set = 0; set < RTT_INTERLEAVED_SETS; set++) {
        rtt_interleaved_coords(light, set, n, xy);
        for (uint32_t k = 0; k < n; k++) out->sets.x[set][k] = xy[k][0], out->sets.y[set][k] = xy[k][1];
        rtt_interleaved_bounds(light, set, n, out->sets.lo[set], out->sets.hi[set]);
    }
    out->points = malloc(pixels * sizeof *out->points);
    out->has = calloc(pixels, 1);
    out->rays.rays = malloc(pixels * n * sizeof *out->rays.rays);
    if (!out->points || !out->has || !out->rays.rays) {
        bench_soft_free(out);
        return rtt_error_set(err, "out of memory for the soft-shadow rays");
    }
    out->rays.width = 4u * w, out->rays.height = 4u * h;
    for (size_t i = 0; i < pixels; i++) {
        const uint32_t x = (uint32_t)(i % w), y = (uint32_t)(i / w);
        rtt_vec3 p;
        out->has[i] = hit_point(primary, prim, t, i, &p);
        const rtt_light_frame fr = rtt_light_sample_frame(light, p);
        bvh_shadow_point *pt = &out->points[i];
        *pt = (bvh_shadow_point){{p.x, p.y, p.z}, {fr.base.x, fr.base.y, fr.base.z}, {fr.du.x, fr.du.y, fr.du.z},
                                 {fr.dv.x, fr.dv.y, fr.dv.z}, rtt_interleaved_set(x, y)};
        for (uint32_t k = 0; k < n; k++) {
            rtt_ray *ray = &out->rays.rays[(size_t)(4u * y + k / 4u) * out->rays.width + 4u * x + k % 4u];
            *ray = inactive;
            if (out->has[i] &&
                segment_ray(p, rtt_light_frame_point(&fr, out->sets.x[pt->set][k], out->sets.y[pt->set][k]),
                            out->epsilon, ray))
                out->rays.active++;
        }
    }
    return true;
}

void bench_soft_free(bench_soft *soft)
{
    free(soft->points), free(soft->has), free(soft->rays.rays);
    memset(soft, 0, sizeof *soft);
}

bool bench_soft_multi_make(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                           uint32_t n, bench_rays *out, rtt_error *err)
{
    memset(out, 0, sizeof *out);
    if (scene->light_count == 0 || !rtt_light_has_area(&scene->lights[0]))
        return rtt_error_set(err, "soft rows need the first light to have area (a sphere or quad light)");
    if (n == 0 || n % 4u)
        return rtt_error_set(err, "multi:%u soft rows: the sample count must be a multiple of 4", n);
    const rtt_light *light = &scene->lights[0];
    const uint32_t w = primary->width, h = primary->height, rows = n / 4u;
    const float epsilon = rtt_scene_ray_epsilon(scene);
    out->width = 4u * w, out->height = rows * h;
    out->rays = malloc((size_t)out->width * out->height * sizeof *out->rays);
    if (!out->rays) return rtt_error_set(err, "out of memory for the soft-shadow rays");
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const uint32_t x = (uint32_t)(i % w), y = (uint32_t)(i / w);
        rtt_vec3 p;
        const bool has = hit_point(primary, prim, t, i, &p);
        for (uint32_t k = 0; k < n; k++) {
            rtt_ray *ray = &out->rays[(size_t)(rows * y + k / 4u) * out->width + 4u * x + k % 4u];
            *ray = inactive;
            if (has && segment_ray(p, rtt_light_sample(light, p, k, n, (uint32_t)i), epsilon, ray)) out->active++;
        }
    }
    return true;
}

/* Interleaved sample sets, the 4x4 discontinuity filter and the shadow
 * planes of rtt/interleaved.h (Benthin and Wald 2009, section 4.5).  The
 * light frames the samples map through live with the other light sampling
 * in shade.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/interleaved.h"
#include "rtt/shade.h"

/* XOR of the 4-bit digits of i. */
static uint32_t nibble_xor(uint32_t i)
{
    i ^= i >> 16;
    i ^= i >> 8;
    i ^= i >> 4;
    return i & 15u;
}

void rtt_interleaved_sample(uint32_t set, uint32_t i, uint32_t n, float out[2])
{
    /* point k of the Hammersley set of 16n: the i-th index whose digits XOR to `set` */
    const uint32_t k = RTT_INTERLEAVED_SETS * i + ((set & 15u) ^ nibble_xor(i));
    rtt_hammersley(k, RTT_INTERLEAVED_SETS * (n ? n : 1u), out);
}

void rtt_interleaved_coords(const rtt_light *light, uint32_t set, uint32_t n, float (*xy)[2])
{
    for (uint32_t i = 0; i < n; i++) {
        float s[2];
        rtt_interleaved_sample(set, i, n, s);
        rtt_light_sample_coords(light, s, xy[i]);
    }
}

void rtt_interleaved_bounds(const rtt_light *light, uint32_t set, uint32_t n, float lo[2], float hi[2])
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        float s[2], c[2];
        rtt_interleaved_sample(set, i, n, s);
        rtt_light_sample_coords(light, s, c);
        for (int k = 0; k < 2; k++) {
            lo[k] = fminf(lo[k], c[k]);
            hi[k] = fmaxf(hi[k], c[k]);
        }
    }
}

/* ---- the discontinuity filter ---- */

void rtt_discontinuity_thresholds_default(rtt_discontinuity_thresholds *t)
{
    t->depth_relative = RTT_DISCONTINUITY_DEPTH_RELATIVE;
    t->normal_cos = RTT_DISCONTINUITY_NORMAL_COS;
}

static bool same_surface(const float *depth, const float *normals, size_t p, size_t q,
                         const rtt_discontinuity_thresholds *t)
{
    if (!isfinite(depth[q]) || !(fabsf(depth[q] - depth[p]) <= t->depth_relative * depth[p])) return false;
    const float *a = &normals[3 * p], *b = &normals[3 * q];
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= t->normal_cos;
}

/* Weight of offset d (-2..2) along one axis: a 4-pixel box centred on the
 * pixel covers the pixels at +-2 by half. */
static float box_weight(int d) { return d == -2 || d == 2 ? 0.5f : 1.0f; }

void rtt_discontinuity_filter(const float *visibility, const float *depth, const float *normals, uint32_t width,
                              uint32_t height, const rtt_discontinuity_thresholds *t, float *out)
{
    rtt_discontinuity_thresholds defaults;
    if (!t) {
        rtt_discontinuity_thresholds_default(&defaults);
        t = &defaults;
    }
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            const size_t p = (size_t)y * width + x;
            if (isnan(visibility[p]) || !isfinite(depth[p])) {
                out[p] = visibility[p];
                continue;
            }
            float sum = 0.0f, weight = 0.0f;
            for (int dy = -2; dy <= 2; dy++) {
                const int64_t qy = (int64_t)y + dy;
                if (qy < 0 || qy >= (int64_t)height) continue;
                for (int dx = -2; dx <= 2; dx++) {
                    const int64_t qx = (int64_t)x + dx;
                    if (qx < 0 || qx >= (int64_t)width) continue;
                    const size_t q = (size_t)qy * width + (size_t)qx;
                    if (q != p && (isnan(visibility[q]) || !same_surface(depth, normals, p, q, t))) continue;
                    const float w = box_weight(dx) * box_weight(dy);
                    sum += w * visibility[q];
                    weight += w;
                }
            }
            out[p] = sum / weight;
        }
    }
}

/* ---- shadow planes ---- */

uint64_t rtt_shadow_planes_bytes(uint32_t width, uint32_t height, uint32_t lights)
{
    const uint64_t pixels = (uint64_t)width * height, per_pixel = 10u * sizeof(float) + (uint64_t)lights * 16u;
    if (pixels && per_pixel > (UINT64_MAX - lights) / pixels) return UINT64_MAX; /* saturates */
    return pixels * per_pixel + lights;
}

bool rtt_shadow_planes_init(rtt_shadow_planes *planes, uint32_t width, uint32_t height, const rtt_light *lights,
                            uint32_t count)
{
    memset(planes, 0, sizeof *planes);
    if (rtt_shadow_planes_bytes(width, height, count) > RTT_SHADOW_PLANES_MAX_BYTES) return false;
    const size_t pixels = (size_t)width * height, per_light = count ? count : 1u;
    if (width && pixels / width != height) return false;
    if (pixels > SIZE_MAX / sizeof(float) / 3u / per_light) return false;
    planes->width = width;
    planes->height = height;
    planes->lights = count;
    planes->rest = calloc(3 * pixels + 1, sizeof(float));
    planes->normal = calloc(3 * pixels + 1, sizeof(float));
    planes->point = calloc(3 * pixels + 1, sizeof(float));
    planes->depth = malloc((pixels + 1) * sizeof(float));
    planes->visibility = malloc((pixels * per_light + 1) * sizeof(float));
    planes->contribution = calloc(3 * pixels * per_light + 1, sizeof(float));
    planes->soft = calloc(per_light, sizeof(bool));
    if (!planes->rest || !planes->normal || !planes->point || !planes->depth || !planes->visibility ||
        !planes->contribution || !planes->soft) {
        rtt_shadow_planes_free(planes);
        return false;
    }
    for (size_t i = 0; i < pixels; i++) planes->depth[i] = INFINITY;
    for (size_t i = 0; i < pixels * count; i++) planes->visibility[i] = NAN;
    for (uint32_t l = 0; l < count; l++) planes->soft[l] = rtt_light_has_area(&lights[l]);
    return true;
}

bool rtt_shadow_planes_create(rtt_shadow_planes *planes, const rtt_scene *scene, uint32_t width, uint32_t height,
                              rtt_error *err)
{
    memset(planes, 0, sizeof *planes);
    const uint64_t bytes = rtt_shadow_planes_bytes(width, height, scene->light_count);
    if (bytes > RTT_SHADOW_PLANES_MAX_BYTES)
        return rtt_error_set(err,
                             "%s: interleaved shadows keep %.1f GiB of planes for %ux%u pixels and %u lights, more "
                             "than %llu GiB: render smaller or with fewer lights",
                             scene->path, (double)bytes / (double)(1u << 30), width, height, scene->light_count,
                             (unsigned long long)(RTT_SHADOW_PLANES_MAX_BYTES >> 30));
    if (!rtt_shadow_planes_init(planes, width, height, scene->lights, scene->light_count))
        return rtt_error_set(err, "%s: out of memory for the %ux%u shadow planes", scene->path, width, height);
    return true;
}

void rtt_shadow_planes_free(rtt_shadow_planes *planes)
{
    free(planes->rest);
    free(planes->normal);
    free(planes->point);
    free(planes->depth);
    free(planes->visibility);
    free(planes->contribution);
    free(planes->soft);
    memset(planes, 0, sizeof *planes);
}

bool rtt_refine_needed(float visibility, float filtered, uint32_t samples)
{
    const float spread = sqrtf(filtered * (1.0f - filtered) / (float)samples);
    return fabsf(filtered - visibility) > spread + RTT_REFINE_MARGIN;
}

/* The soft lights' planes filtered into `filtered` (pixels * lights), the
 * others copied. */
static void filter_planes(const rtt_shadow_planes *planes, const rtt_discontinuity_thresholds *t, float *filtered)
{
    const size_t pixels = (size_t)planes->width * planes->height;
    for (uint32_t l = 0; l < planes->lights; l++) {
        if (planes->soft[l])
            rtt_discontinuity_filter(&planes->visibility[pixels * l], planes->depth, planes->normal, planes->width,
                                     planes->height, t, &filtered[pixels * l]);
        else
            memcpy(&filtered[pixels * l], &planes->visibility[pixels * l], pixels * sizeof(float));
    }
}

/* rgb = rest + every light's contribution times vis (NaN: left out). */
static void compose(const rtt_shadow_planes *planes, const float *vis, float *rgb)
{
    const size_t pixels = (size_t)planes->width * planes->height;
    for (size_t p = 0; p < pixels; p++) {
        rtt_vec3 colour = rtt_v3(planes->rest[3 * p], planes->rest[3 * p + 1], planes->rest[3 * p + 2]);
        for (uint32_t l = 0; l < planes->lights; l++) {
            float v = vis[pixels * l + p];
            if (isnan(v)) continue;
            const float *c = &planes->contribution[3 * (pixels * l + p)];
            colour = rtt_v3_madd(colour, rtt_v3(c[0], c[1], c[2]), v);
        }
        rgb[3 * p + 0] = colour.x;
        rgb[3 * p + 1] = colour.y;
        rgb[3 * p + 2] = colour.z;
    }
}

bool rtt_shadow_planes_resolve(const rtt_shadow_planes *planes, bool filter, const rtt_discontinuity_thresholds *t,
                               float *rgb)
{
    const size_t pixels = (size_t)planes->width * planes->height;
    float *filtered = NULL;
    if (filter && planes->lights && !(filtered = malloc(pixels * planes->lights * sizeof(float)))) return false;
    if (filtered) filter_planes(planes, t, filtered);
    compose(planes, filtered ? filtered : planes->visibility, rgb);
    free(filtered);
    return true;
}

bool rtt_shadow_planes_resolve_refined(const rtt_shadow_planes *planes, uint32_t samples,
                                       const rtt_discontinuity_thresholds *t, rtt_refine_fn refine, void *context,
                                       float *rgb, uint64_t *refined)
{
    const size_t pixels = (size_t)planes->width * planes->height;
    if (refined) *refined = 0;
    if (!planes->lights) {
        compose(planes, planes->visibility, rgb);
        return true;
    }
    const size_t room = pixels ? pixels : 1;
    float *filtered = malloc(room * planes->lights * sizeof(float)), *vis = malloc(room * sizeof(float));
    uint32_t *list = malloc(room * sizeof(uint32_t)); /* pixels < 2^32: the planes' cap */
    bool ok = filtered && vis && list;
    if (ok) filter_planes(planes, t, filtered);
    for (uint32_t l = 0; ok && l < planes->lights; l++) {
        if (!planes->soft[l]) continue;
        const float *own = &planes->visibility[pixels * l];
        float *out = &filtered[pixels * l];
        size_t count = 0;
        for (size_t p = 0; p < pixels; p++) /* a pixel with a visibility has a hit */
            if (!isnan(own[p]) && isfinite(planes->depth[p]) && rtt_refine_needed(own[p], out[p], samples))
                list[count++] = (uint32_t)p;
        if (!count) continue;
        ok = refine(context, l, list, count, vis);
        for (size_t i = 0; ok && i < count; i++) out[list[i]] = vis[i];
        if (refined) *refined += count;
    }
    if (ok) compose(planes, filtered, rgb);
    free(filtered);
    free(list);
    free(vis);
    return ok;
}

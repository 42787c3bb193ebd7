/* The shader proxy's multi-frusta shadow passes (sp_frusta.h).
 *
 * Both order their work in 4x4 pixel blocks before the kernel sees it: the
 * proxy gathers a tile's shading points light by light in quad order (2x2
 * packets, row-major), where 16 consecutive points are an 8x2 strip; sorted
 * by (light, 4x4 block, place in the block) 16 consecutive points are one
 * block, so on AVX-512 one kernel pass holds a block (soft shadows: one
 * frustum per pixel, the pixel's N samples) or 16 blocks (hard shadows: one
 * frustum per block, the 16 pixels' rays to the light).  The answers go back
 * to the proxy's order; nothing else changes, so the image is the one the
 * ray-by-ray methods draw (interleaved:N for frusta:N, hard for hard). */
#include <stdlib.h>
#include <string.h>

#include "sp_frusta.h"

bvh_shadow_sets *sp_frusta_sets_create(const rtt_scene *scene, uint32_t n)
{
    const uint32_t lights = scene->light_count ? scene->light_count : 1;
    bvh_shadow_sets *sets = calloc(lights, sizeof *sets);
    if (!sets || n > BVH_SHADOW_MAX_SAMPLES) {
        free(sets);
        return NULL;
    }
    float xy[BVH_SHADOW_MAX_SAMPLES][2];
    for (uint32_t l = 0; l < scene->light_count; l++) {
        bvh_shadow_sets *s = &sets[l];
        s->samples = n;
        for (uint32_t set = 0; set < RTT_INTERLEAVED_SETS; set++) {
            rtt_interleaved_coords(&scene->lights[l], set, n, xy);
            for (uint32_t k = 0; k < n; k++) s->x[set][k] = xy[k][0], s->y[set][k] = xy[k][1];
            rtt_interleaved_bounds(&scene->lights[l], set, n, s->lo[set], s->hi[set]);
        }
    }
    return sets;
}

bool sp_frusta_soft(const sp_shading *sh, const rtt_light *light)
{
    return sh->shadows == RTT_SHADOWS_FRUSTA && sh->frusta_sets && !sh->transparent_shadows &&
           rtt_light_has_area(light);
}

bool sp_frusta_begin(sp_scratch *s, size_t points)
{
    s->frusta_count = 0;
    return SP_RESERVE(s, frusta_points, points, bvh_shadow_point) && SP_RESERVE(s, frusta_light, points, uint32_t) &&
           SP_RESERVE(s, frusta_pixel, points, uint32_t) && SP_RESERVE(s, frusta_mask, points, uint32_t);
}

/* Shading point p's frustum of set `set` towards the light of frame `frame` (as seen from p). */
static bvh_shadow_point shadow_point(const rtt_light_frame *frame, rtt_vec3 p, uint32_t set)
{
    return (bvh_shadow_point){.org = {p.x, p.y, p.z},
                              .base = {frame->base.x, frame->base.y, frame->base.z},
                              .du = {frame->du.x, frame->du.y, frame->du.z},
                              .dv = {frame->dv.x, frame->dv.y, frame->dv.z},
                              .set = set};
}

uint32_t sp_frusta_push_point(sp_scratch *s, const sp_shading *sh, uint32_t light, rtt_vec3 p, uint32_t pixel)
{
    const uint32_t i = s->frusta_count++;
    const rtt_light_frame frame = rtt_light_sample_frame(&sh->scene->lights[light], p);
    SP_ARRAY(s->frusta_points, bvh_shadow_point)[i] =
        shadow_point(&frame, p, rtt_interleaved_set(pixel % sh->width, pixel / sh->width));
    SP_ARRAY(s->frusta_light, uint32_t)[i] = light;
    SP_ARRAY(s->frusta_pixel, uint32_t)[i] = pixel;
    SP_ARRAY(s->frusta_mask, uint32_t)[i] = 0;
    return i;
}

uint32_t sp_frusta_clear_samples(const sp_scratch *s, uint32_t point, uint32_t n)
{
    const uint32_t mask = SP_ARRAY(s->frusta_mask, uint32_t)[point];
    return n - (uint32_t)__builtin_popcount(mask);
}

/* Pixels refined a kernel call at a time: 16 frusta each. */
#define REFINE_CHUNK 256u

bool sp_frusta_refine(const sp_shading *sh, const sp_tracer *tr, uint32_t light, const float *point,
                      const uint32_t *pixel, size_t count, float *vis, uint64_t *rays)
{
    enum { SETS = RTT_INTERLEAVED_SETS };
    const size_t room = count < REFINE_CHUNK ? count : REFINE_CHUNK;
    bvh_shadow_point *points = malloc((room ? room : 1) * SETS * sizeof *points);
    uint32_t *occluded = malloc((room ? room : 1) * SETS * sizeof *occluded);
    if (!points || !occluded) {
        free(points);
        free(occluded);
        return false;
    }
    const rtt_light *L = &sh->scene->lights[light];
    const uint32_t all = SETS * sh->shadow_samples;
    for (size_t first = 0; first < count; first += REFINE_CHUNK) {
        const size_t m = count - first < REFINE_CHUNK ? count - first : REFINE_CHUNK;
        for (size_t i = 0; i < m; i++) {
            const float *at = &point[3 * (size_t)pixel[first + i]];
            const rtt_vec3 p = rtt_v3(at[0], at[1], at[2]);
            const rtt_light_frame frame = rtt_light_sample_frame(L, p);
            for (uint32_t set = 0; set < SETS; set++) points[i * SETS + set] = shadow_point(&frame, p, set);
        }
        tr->bvh_shadows->trace(tr->bvh, &(bvh_shadow_query){.points = points,
                                                            .count = m * SETS,
                                                            .sets = &sh->frusta_sets[light],
                                                            .epsilon = sh->epsilon,
                                                            .occluded = occluded});
        for (size_t i = 0; i < m; i++) {
            uint32_t blocked = 0;
            for (uint32_t set = 0; set < SETS; set++) blocked += (uint32_t)__builtin_popcount(occluded[i * SETS + set]);
            vis[first + i] = (float)(all - blocked) / (float)all; /* the reference's sum of 0s and 1s over 16 N */
        }
    }
    *rays += (uint64_t)all * count;
    free(points);
    free(occluded);
    return true;
}

/* ---- the 4x4 block order ---- */

typedef struct block_order {
    uint64_t key;                   /* light, 4x4 block, place in the block */
    uint32_t index;                 /* in the proxy's order */
} block_order;

static int block_order_compare(const void *a, const void *b)
{
    const block_order *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

static uint64_t block_key(uint32_t light, uint32_t pixel, uint32_t width)
{
    const uint32_t px = pixel % width, py = pixel / width, blocks_x = (width + 3u) / 4u;
    const uint64_t block = (uint64_t)(py / 4u) * blocks_x + px / 4u;
    return (uint64_t)light << 40 | block << 4 | (py & 3u) << 2 | (px & 3u);
}

/* The `count` items (lights and pixels given) in block order, into
 * s->frusta_order; false when out of memory. */
static bool order_blocks(sp_scratch *s, const uint32_t *light, const uint32_t *pixel, uint32_t count, uint32_t width)
{
    if (!SP_RESERVE(s, frusta_order, count, block_order)) return false;
    block_order *order = SP_ARRAY(s->frusta_order, block_order);
    for (uint32_t i = 0; i < count; i++) order[i] = (block_order){block_key(light[i], pixel[i], width), i};
    qsort(order, count, sizeof *order, block_order_compare);
    return true;
}

/* Sorted items [first, end) all of light `light` through the kernel. */
typedef void (*light_run_fn)(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t light, uint32_t first,
                             uint32_t end);

/* The `count` sorted items one light's run at a time, then each answer back
 * to its item's place: answer i (of `answer` bytes) to out[order[i]]. */
static void trace_light_runs(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t count, light_run_fn fn,
                             size_t answer, void *out)
{
    const uint32_t *light = SP_ARRAY(s->frusta_light, uint32_t);
    const block_order *order = SP_ARRAY(s->frusta_order, block_order);
    for (uint32_t first = 0, end; first < count; first = end) {
        const uint32_t l = light[order[first].index];
        for (end = first + 1; end < count && light[order[end].index] == l;) end++;
        fn(sh, tr, s, l, first, end);
    }
    for (uint32_t i = 0; i < count; i++)
        memcpy((char *)out + order[i].index * answer, (const char *)s->frusta_answer.data + i * answer, answer);
}

/* The `count` items of s->frusta_light and frusta_pixel in block order
 * (s->frusta_order), `items` (of `size` bytes each) copied in that order to
 * s->frusta_sorted, and room for `count` answers of `answer` bytes in
 * s->frusta_answer; false when out of memory. */
static bool sort_items(sp_scratch *s, uint32_t width, uint32_t count, const void *items, size_t size, size_t answer)
{
    if (!order_blocks(s, SP_ARRAY(s->frusta_light, uint32_t), SP_ARRAY(s->frusta_pixel, uint32_t), count, width) ||
        !sp_reserve(s, &s->frusta_sorted, count, size, 16) || !sp_reserve(s, &s->frusta_answer, count, answer, 16))
        return false;
    const block_order *order = SP_ARRAY(s->frusta_order, block_order);
    for (uint32_t i = 0; i < count; i++)
        memcpy((char *)s->frusta_sorted.data + i * size, (const char *)items + order[i].index * size, size);
    return true;
}

static void trace_points_run(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t light, uint32_t first,
                             uint32_t end)
{
    tr->bvh_shadows->trace(tr->bvh, &(bvh_shadow_query){.points = SP_ARRAY(s->frusta_sorted, bvh_shadow_point) + first,
                                                        .count = end - first,
                                                        .sets = &sh->frusta_sets[light],
                                                        .epsilon = sh->epsilon,
                                                        .occluded = SP_ARRAY(s->frusta_answer, uint32_t) + first});
}

void sp_frusta_trace_points(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s)
{
    const uint32_t count = s->frusta_count;
    if (s->failed || !count ||
        !sort_items(s, sh->width, count, s->frusta_points.data, sizeof(bvh_shadow_point), sizeof(uint32_t)))
        return;
    trace_light_runs(sh, tr, s, count, trace_points_run, sizeof(uint32_t), s->frusta_mask.data);
}

/* ---- hard shadows through bvh-mft ---- */

bool sp_frusta_hard(const sp_shading *sh, const sp_tracer *tr)
{
    return sh->shadows == RTT_SHADOWS_HARD && tr->bvh && tr->bvh_kernel && strcmp(tr->bvh_kernel->name, "bvh-mft") == 0;
}

bool sp_frusta_reserve_rays(sp_scratch *s, size_t rays)
{
    return SP_RESERVE(s, frusta_light, rays, uint32_t) && SP_RESERVE(s, frusta_pixel, rays, uint32_t);
}

void sp_frusta_note_ray(sp_scratch *s, uint32_t ray, uint32_t light, uint32_t pixel)
{
    SP_ARRAY(s->frusta_light, uint32_t)[ray] = light;
    SP_ARRAY(s->frusta_pixel, uint32_t)[ray] = pixel;
}

static void trace_rays_run(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t light, uint32_t first,
                           uint32_t end)
{
    const rtt_vec3 at = sh->scene->lights[light].position;
    const float toward[3] = {at.x, at.y, at.z};
    tr->bvh_kernel->trace(tr->bvh, &(bvh_query){.rays = SP_ARRAY(s->frusta_sorted, rtt_ray) + first,
                                                .count = end - first,
                                                .occluded = SP_ARRAY(s->frusta_answer, uint8_t) + first,
                                                .toward = toward});
}

void sp_frusta_trace_rays(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t rays)
{
    if (s->failed || !rays || !sort_items(s, sh->width, rays, s->shadow_rays.data, sizeof(rtt_ray), sizeof(uint8_t)))
        return;
    uint8_t *clear = SP_ARRAY(s->shadow_clear, uint8_t);
    trace_light_runs(sh, tr, s, rays, trace_rays_run, sizeof(uint8_t), clear);
    for (uint32_t i = 0; i < rays; i++) clear[i] = !clear[i]; /* occluded to clear */
}

/* Thesis 4.2.1 and Figure 3.2: the shader proxy.  A tile's rays are shaded
 * level by level (level 0 the primary rays, level d the rays of bounce d):
 *
 *   1. surfaces of the level's hits (shading normal facing the ray,
 *      entering = geometric normal against the ray), and per light the
 *      unoccluded contribution (rtt_shade_light);
 *   2. the shadow rays of every contribution that is not exactly zero, in
 *      2x2 packets through the occlusion kernel of the chosen traversal;
 *   3. local colour = ambient + sum contribution * vis, weights wr/wt, and
 *      the reflected/refracted rays appended to the next level, which is
 *      traced as omni-directional 2x2 packets (Listing 4.1: secondary rays
 *      are too incoherent for frusta, 4.1.3);
 *   4. colours combined bottom-up: (1 - wr - wt) local + wr refl + wt refr.
 *
 * Every formula, constant and operation order is the reference's
 * (reference/render_whitted.c), per ray with the scalar functions of
 * shade.h; what the proxy changes is only how rays are traced (packets,
 * blocks) and that a pixel's rays are processed breadth-first.  Trades:
 * memory for the level arrays (a tile's shading trees) against tracing
 * secondary and shadow rays as packets.
 *
 * Shadow methods: hard and multi:N trace their rays in 2x2 packets through
 * the occlusion kernel of the chosen traversal; cone:N and pyramid:N trace
 * the very same sample rays, each shading point's N samples of a light as
 * one block under one cone or pyramid (shadow_cone.c), so visibility per
 * sample and the images equal multi:N's; edgewidth[:R] traces one ray per
 * point and sphere light from the light's centre (edge_width.c) and uses
 * 1 - its occlusion, point lights keeping the hard shadow ray. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "edge_width.h"
#include "frustum.h"
#include "shader_proxy.h"
#include "shadow_cone.h"

#include "kernels.h"

#define SP_SHADOW_CHUNK 8192u /* shadow rays traced per batch */

typedef struct sp_light_request {
    rtt_vec3 contribution;
    uint32_t first, rays, auto_clear;
    uint32_t edge;                  /* edgewidth: index of its ray in edge_rays, or NO_EDGE_RAY */
    bool active;                    /* contribution not exactly zero */
} sp_light_request;

#define NO_EDGE_RAY UINT32_MAX

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static bool grow(void **array, uint32_t *capacity, uint32_t needed, size_t size, size_t align)
{
    if (needed <= *capacity) return true;
    uint32_t cap = *capacity ? *capacity : 64u;
    while (cap < needed) cap *= 2u;
    void *fresh = NULL;
    if (posix_memalign(&fresh, align, (size_t)cap * size) != 0) return false;
    if (*array && *capacity) memcpy(fresh, *array, (size_t)*capacity * size);
    free(*array);
    *array = fresh;
    *capacity = cap;
    return true;
}

bool sp_scratch_init(sp_scratch *s, uint32_t level_count, bool timing)
{
    memset(s, 0, sizeof *s);
    s->levels = calloc(level_count, sizeof *s->levels);
    s->level_count = level_count;
    s->timing = timing;
    return s->levels != NULL;
}

void sp_scratch_free(sp_scratch *s)
{
    if (s->levels)
        for (uint32_t i = 0; i < s->level_count; i++) free(s->levels[i].nodes);
    free(s->levels);
    free(s->packets);
    free(s->hits);
    free(s->occluded);
    free(s->shadow_rays);
    free(s->shadow_clear);
    free(s->surfaces);
    free(s->requests);
    free(s->group_first);
    free(s->edge_rays);
    free(s->edge_order);
    free(s->edge_light);
    free(s->edge_occlusion);
    memset(s, 0, sizeof *s);
}

int32_t sp_level_push(sp_scratch *s, uint32_t level, const rtt_ray *ray, uint32_t pixel)
{
    sp_level *l = &s->levels[level];
    if (!grow((void **)&l->nodes, &l->capacity, l->count + 1, sizeof(sp_node), 16)) {
        s->failed = true;
        return -1;
    }
    sp_node *n = &l->nodes[l->count];
    n->ray = *ray;
    n->pixel = pixel;
    n->reflected = n->refracted = -1;
    n->wr = n->wt = 0.0f;
    return (int32_t)l->count++;
}

/* A kernel over packet_count packets, cut into the blocks it reads. */
static void trace_blocks(const sp_tracer *tr, const kd_kernel *kernel, kd_query q)
{
    const uint32_t total = q.packet_count, block = kernel->block == KD_BLOCK_TILE ? tr->block_packets : total;
    const ray_packet4 *packets = q.packets;
    hit_packet4 *hits = q.hits;
    uint8_t *occluded = q.occluded;
    for (uint32_t first = 0; first < total; first += block) {
        q.packets = packets + first;
        q.packet_count = total - first < block ? total - first : block;
        q.hits = hits ? hits + first : NULL;
        q.occluded = occluded ? occluded + first : NULL;
        kernel->trace(tr->tree, &q);
    }
}

void sp_trace_packets(const sp_tracer *tr, const kd_kernel *kernel, const ray_packet4 *packets, hit_packet4 *hits,
                      uint32_t packet_count, kd_counters *counters, uint64_t *isect_ns)
{
    for (uint32_t p = 0; p < packet_count; p++) hit_packet4_clear(&hits[p]);
    trace_blocks(tr, kernel,
                 (kd_query){.packets = packets, .packet_count = packet_count, .hits = hits,
                            .leaf_culling = tr->leaf_culling, .counters = counters, .isect_ns = isect_ns});
}

void sp_trace_packets_occluded(const sp_tracer *tr, const kd_kernel *kernel, const ray_packet4 *packets,
                               uint8_t *occluded, uint32_t packet_count)
{
    trace_blocks(tr, kernel,
                 (kd_query){.packets = packets, .packet_count = packet_count, .occluded = occluded,
                            .leaf_culling = tr->leaf_culling});
}

bool sp_ensure_packets(sp_scratch *s, uint32_t packets)
{
    if (!grow((void **)&s->packets, &s->packet_capacity, packets, sizeof(ray_packet4), 16) ||
        !grow((void **)&s->hits, &s->hit_capacity, packets, sizeof(hit_packet4), 16) ||
        !grow((void **)&s->occluded, &s->occluded_capacity, packets, 1, 16)) {
        s->failed = true;
        return false;
    }
    return true;
}

/* Traces nodes' rays (closest hit) as omni 2x2 packets. */
static void trace_level(const sp_tracer *tr, sp_scratch *s, sp_level *level)
{
    uint32_t packets = (level->count + 3) / 4;
    if (!sp_ensure_packets(s, packets)) return;
    for (uint32_t p = 0; p < packets; p++) {
        rtt_ray rays[4];
        uint32_t n = level->count - 4 * p < 4 ? level->count - 4 * p : 4;
        for (uint32_t l = 0; l < n; l++) rays[l] = level->nodes[4 * p + l].ray;
        ray_packet4_load(&s->packets[p], rays, n);
    }
    sp_trace_packets(tr, tr->secondary, s->packets, s->hits, packets, NULL, NULL);
    for (uint32_t p = 0; p < packets; p++) {
        rtt_hit hits[4];
        float t[4], u[4], v[4];
        uint32_t prim[4];
        _mm_storeu_ps(t, s->hits[p].t), _mm_storeu_ps(u, s->hits[p].u), _mm_storeu_ps(v, s->hits[p].v);
        _mm_storeu_si128((__m128i *)prim, s->hits[p].prim);
        uint32_t n = level->count - 4 * p < 4 ? level->count - 4 * p : 4;
        for (uint32_t l = 0; l < n; l++) {
            hits[l] = (rtt_hit){t[l], u[l], v[l], prim[l]};
            if (prim[l] == RTT_MISS) hits[l].t = INFINITY;
            level->nodes[4 * p + l].hit = hits[l];
        }
    }
}

/* Shadow rays of the reference's segment_clear(p, target). */
static void shadow_segment(const sp_shading *sh, sp_scratch *s, rtt_vec3 p, rtt_vec3 target, sp_light_request *q)
{
    rtt_vec3 to_target = rtt_v3_sub(target, p);
    float distance = rtt_v3_length(to_target);
    if (!(distance > 2.0f * sh->epsilon)) {
        q->auto_clear++;
        return;
    }
    rtt_vec3 dir = rtt_v3_scale(to_target, 1.0f / distance);
    uint32_t i = q->first + q->rays++;
    s->shadow_rays[i] = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, sh->epsilon, distance - sh->epsilon};
}

/* Methods that trace rtt_light_sample's N samples on sphere lights. */
static bool is_sampled(rtt_shadow_method m)
{
    return m == RTT_SHADOWS_MULTI || m == RTT_SHADOWS_CONE || m == RTT_SHADOWS_PYRAMID;
}

static bool is_grouped(rtt_shadow_method m) { return m == RTT_SHADOWS_CONE || m == RTT_SHADOWS_PYRAMID; }

/* Edge width needs a light with extent; point lights keep hard shadows. */
static bool uses_edge_width(const sp_shading *sh, const rtt_light *light)
{
    return sh->shadows == RTT_SHADOWS_EDGEWIDTH && light->type == RTT_LIGHT_SPHERE && light->radius > 0.0f;
}

static uint32_t samples_per_light(const sp_shading *sh, const rtt_light *light)
{
    if (sh->shadows == RTT_SHADOWS_NONE) return 0;
    if (is_sampled(sh->shadows) && light->type == RTT_LIGHT_SPHERE) return sh->shadow_samples;
    return 1;
}

/* The edge-width ray of one request, or none when nothing fits between. */
static void edge_ray(const sp_shading *sh, sp_scratch *s, rtt_vec3 p, uint32_t light, sp_light_request *q,
                     uint32_t *edges)
{
    q->edge = NO_EDGE_RAY;
    if (!rtt_edge_width_ray(sh->scene->lights[light].position, p, sh->epsilon, &s->edge_rays[*edges])) {
        q->auto_clear++;
        return;
    }
    s->edge_light[*edges] = light;
    q->edge = (*edges)++;
}

/* Step 1 for nodes [first, end): surfaces, contributions, shadow rays (and
 * for cone/pyramid their groups, for edgewidth the edge rays).  Returns
 * the number of shadow rays. */
static uint32_t gather_shadows(const sp_shading *sh, sp_scratch *s, const sp_level *level, uint32_t first,
                               uint32_t end, uint32_t *groups, uint32_t *edges)
{
    const rtt_scene *scene = sh->scene;
    uint32_t rays = 0;
    *groups = *edges = 0;
    for (uint32_t i = first; i < end; i++) {
        const sp_node *node = &level->nodes[i];
        sp_light_request *req = &s->requests[(size_t)(i - first) * scene->light_count];
        if (node->hit.prim == RTT_MISS) continue;
        rtt_surface *surf = &s->surfaces[i - first];
        *surf = rtt_surface_at(scene, &node->ray, &node->hit);
        rtt_vec3 to_viewer = rtt_v3_scale(surf->dir, -1.0f);
        for (uint32_t l = 0; l < scene->light_count; l++) {
            const rtt_light *light = &scene->lights[l];
            sp_light_request *q = &req[l];
            q->active = false;
            q->first = rays, q->rays = 0, q->auto_clear = 0;
            q->edge = NO_EDGE_RAY;
            rtt_vec3 to_light = rtt_v3_sub(light->position, surf->point);
            float distance = rtt_v3_length(to_light);
            if (!(distance > 0.0f)) continue;
            q->contribution = rtt_shade_light(surf->material, surf->normal, to_viewer,
                                              rtt_v3_scale(to_light, 1.0f / distance), light, distance);
            if (q->contribution.x == 0.0f && q->contribution.y == 0.0f && q->contribution.z == 0.0f) continue;
            q->active = true;
            uint32_t n = samples_per_light(sh, light);
            if (is_sampled(sh->shadows) && light->type == RTT_LIGHT_SPHERE) {
                for (uint32_t k = 0; k < n; k++)
                    shadow_segment(sh, s, surf->point, rtt_light_sample(light, surf->point, k, n, node->pixel), q);
            } else if (uses_edge_width(sh, light)) {
                edge_ray(sh, s, surf->point, l, q, edges);
            } else if (n) {
                shadow_segment(sh, s, surf->point, light->position, q);
            }
            if (is_grouped(sh->shadows) && q->rays) s->group_first[(*groups)++] = q->first;
            rays += q->rays;
        }
    }
    if (is_grouped(sh->shadows)) s->group_first[*groups] = rays;
    return rays;
}

/* Step 2: the shadow rays as 2x2 packets through the occlusion kernels. */
static void trace_shadows(const sp_tracer *tr, sp_scratch *s, uint32_t rays)
{
    uint32_t packets = (rays + 3) / 4;
    if (!packets || !sp_ensure_packets(s, packets)) return;
    for (uint32_t p = 0; p < packets; p++) {
        uint32_t n = rays - 4 * p < 4 ? rays - 4 * p : 4;
        ray_packet4_load(&s->packets[p], &s->shadow_rays[4 * p], n);
    }
    sp_trace_packets_occluded(tr, tr->kernel, s->packets, s->occluded, packets);
    for (uint32_t i = 0; i < rays; i++) s->shadow_clear[i] = !(s->occluded[i / 4] >> (i % 4) & 1u);
}

/* Step 2 for cone:N and pyramid:N: each group (one point, one light) as one
 * block under its proxy. */
static void trace_shadow_groups(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t rays,
                                uint32_t groups)
{
    uint32_t packets = sc_group_packets(s->group_first, groups);
    if (!packets || !sp_ensure_packets(s, packets)) return;
    sc_trace_groups(tr->tree, sh->shadows == RTT_SHADOWS_CONE ? NULL : tr->pyramid, s->shadow_rays, s->group_first, groups, s->packets, s->occluded,
                    s->shadow_clear, tr->leaf_culling, NULL);
    for (uint32_t i = 0; i < rays; i++) s->shadow_clear[i] = !s->shadow_clear[i];
}

/* Step 2 for edgewidth: the edge rays, each light's together so that a
 * packet's rays share their origin (a counting sort by light). */
static void trace_edge_rays(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t edges)
{
    if (!edges) return;
    const uint32_t lights = sh->scene->light_count;
    uint32_t next = 0;
    for (uint32_t l = 0; l < lights; l++)
        for (uint32_t i = 0; i < edges; i++)
            if (s->edge_light[i] == l) s->edge_order[next++] = i;
    ew_occlusion_stream(tr->tree, &sh->edge_model, s->edge_rays, s->edge_order, edges, s->edge_occlusion, NULL);
}

/* Step 3 for nodes [first, end) of level d. */
static void resolve_locals(const sp_shading *sh, sp_scratch *s, uint32_t d, uint32_t first, uint32_t end)
{
    const rtt_scene *scene = sh->scene;
    for (uint32_t i = first; i < end; i++) {
        sp_node *node = &s->levels[d].nodes[i];
        if (node->hit.prim == RTT_MISS) {
            node->colour = scene->background;
            continue;
        }
        const rtt_surface *surf = &s->surfaces[i - first];
        const sp_light_request *req = &s->requests[(size_t)(i - first) * scene->light_count];
        const rtt_material *m = surf->material;
        rtt_vec3 colour = rtt_v3_scale(m->diffuse, scene->ambient);
        for (uint32_t l = 0; l < scene->light_count; l++) {
            const sp_light_request *q = &req[l];
            if (!q->active) continue;
            float vis = 1.0f;
            uint32_t n = samples_per_light(sh, &scene->lights[l]);
            if (q->edge != NO_EDGE_RAY) {
                vis = 1.0f - s->edge_occlusion[q->edge];
            } else if (n) {
                uint32_t clear = q->auto_clear;
                for (uint32_t k = 0; k < q->rays; k++) clear += s->shadow_clear[q->first + k];
                vis = n == 1 && !(is_sampled(sh->shadows) && scene->lights[l].type == RTT_LIGHT_SPHERE)
                          ? (clear ? 1.0f : 0.0f)
                          : (float)clear / (float)n;
            }
            colour = rtt_v3_madd(colour, q->contribution, vis);
        }
        float wr, wt;
        rtt_shade_weights(m, d, sh->max_bounces, &wr, &wt);
        node->colour = rtt_v3_scale(colour, 1.0f - wr - wt);
        node->wr = wr, node->wt = wt;
        if (d + 1 >= s->level_count) continue;
        rtt_vec3 dirs[2];
        int count = 0;
        if (wr > 0.0f) dirs[count++] = rtt_v3_reflect(surf->dir, surf->normal);
        if (wt > 0.0f) {
            const float ior = m->ior;
            const float eta_from = surf->entering ? 1.0f : ior, eta_to = surf->entering ? ior : 1.0f;
            dirs[count++] = rtt_refract(surf->dir, surf->normal, eta_from, eta_to);
        }
        for (int c = 0; c < count; c++) {
            rtt_vec3 dir = rtt_v3_normalize(dirs[c]);
            rtt_ray ray = {{surf->point.x, surf->point.y, surf->point.z}, {dir.x, dir.y, dir.z}, sh->epsilon,
                           INFINITY};
            uint32_t pixel = node->pixel;
            int32_t child = sp_level_push(s, d + 1, &ray, pixel);
            node = &s->levels[d].nodes[i]; /* the push never moves level d, but stay obvious */
            if (c == 0 && wr > 0.0f)
                node->reflected = child;
            else
                node->refracted = child;
            s->stats.secondary_rays++;
        }
    }
}

static void shade_level(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t d)
{
    const rtt_scene *scene = sh->scene;
    sp_level *level = &s->levels[d];
    uint32_t per_node = 0;
    for (uint32_t l = 0; l < scene->light_count; l++) per_node += samples_per_light(sh, &scene->lights[l]) + 1;
    uint32_t chunk = per_node ? SP_SHADOW_CHUNK / per_node : SP_SHADOW_CHUNK;
    if (chunk == 0) chunk = 1;
    uint32_t lights = scene->light_count ? scene->light_count : 1, rays_cap = chunk * per_node + 4;
    if (!grow((void **)&s->surfaces, &s->surface_capacity, chunk, sizeof(rtt_surface), 16) ||
        !grow((void **)&s->requests, &s->request_capacity, chunk * lights, sizeof(sp_light_request), 16) ||
        !grow((void **)&s->shadow_rays, &s->shadow_capacity, rays_cap, sizeof(rtt_ray), 16) ||
        !grow((void **)&s->shadow_clear, &s->clear_capacity, rays_cap, 1, 16)) {
        s->failed = true;
        return;
    }
    if ((is_grouped(sh->shadows) &&
         !grow((void **)&s->group_first, &s->group_capacity, chunk * lights + 1, sizeof(uint32_t), 16)) ||
        (sh->shadows == RTT_SHADOWS_EDGEWIDTH &&
         (!grow((void **)&s->edge_rays, &s->edge_ray_capacity, chunk * lights, sizeof(rtt_ray), 16) ||
          !grow((void **)&s->edge_order, &s->edge_order_capacity, chunk * lights, sizeof(uint32_t), 16) ||
          !grow((void **)&s->edge_light, &s->edge_light_capacity, chunk * lights, sizeof(uint32_t), 16) ||
          !grow((void **)&s->edge_occlusion, &s->edge_occlusion_capacity, chunk * lights, sizeof(float), 16)))) {
        s->failed = true;
        return;
    }
    for (uint32_t first = 0; first < level->count; first += chunk) {
        uint32_t end = level->count - first < chunk ? level->count : first + chunk;
        uint64_t t0 = s->timing ? now_ns() : 0;
        uint32_t groups, edges;
        uint32_t rays = gather_shadows(sh, s, level, first, end, &groups, &edges);
        uint64_t t1 = s->timing ? now_ns() : 0;
        if (is_grouped(sh->shadows))
            trace_shadow_groups(sh, tr, s, rays, groups);
        else
            trace_shadows(tr, s, rays);
        trace_edge_rays(sh, tr, s, edges);
        uint64_t t2 = s->timing ? now_ns() : 0;
        s->stats.shadow_rays += rays + edges;
        resolve_locals(sh, s, d, first, end);
        level = &s->levels[d];
        if (s->failed) return;
        if (s->timing) {
            s->stats.ns_shading += (t1 - t0) + (now_ns() - t2);
            s->stats.ns_secondary += t2 - t1;
        }
    }
}

/* Step 4: colour = (1 - wr - wt) local + wr reflected + wt refracted. */
static void combine(sp_scratch *s, uint32_t levels)
{
    for (uint32_t d = levels - 1; d-- > 0;) {
        sp_level *level = &s->levels[d];
        const sp_level *below = &s->levels[d + 1];
        for (uint32_t i = 0; i < level->count; i++) {
            sp_node *n = &level->nodes[i];
            if (n->reflected >= 0) n->colour = rtt_v3_madd(n->colour, below->nodes[n->reflected].colour, n->wr);
            if (n->refracted >= 0) n->colour = rtt_v3_madd(n->colour, below->nodes[n->refracted].colour, n->wt);
        }
    }
}

void sp_shade_tree(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s)
{
    for (uint32_t d = 1; d < s->level_count; d++) s->levels[d].count = 0;
    uint32_t used = 0;
    for (uint32_t d = 0; d < s->level_count && !s->failed; d++) {
        if (s->levels[d].count == 0) break;
        if (d > 0) {
            uint64_t t0 = s->timing ? now_ns() : 0;
            trace_level(tr, s, &s->levels[d]);
            if (s->timing) s->stats.ns_secondary += now_ns() - t0;
        }
        shade_level(sh, tr, s, d);
        used = d + 1;
    }
    if (!s->failed && used > 1) {
        uint64_t t0 = s->timing ? now_ns() : 0;
        combine(s, used);
        if (s->timing) s->stats.ns_shading += now_ns() - t0;
    }
}

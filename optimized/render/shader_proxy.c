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
 * one block under one cone or pyramid (kd/shadows/shadow_cone.c), so
 * visibility per sample and the images equal multi:N's; edgewidth[:R]
 * traces one ray per point and sphere light from the light's centre
 * (kd/shadows/edge_width.c) and uses 1 - its occlusion, point lights
 * keeping the hard shadow ray (edge widths treat transparent occluders as
 * opaque); interleaved:N traces the N samples of the pixel's interleaved set
 * (rtt/interleaved.h) in 2x2 packets like multi:N and, at the primary hits,
 * leaves the light terms to the renderer's rtt_shadow_planes instead of
 * adding them (the filter needs the whole image); pgrid traces hard's rays
 * (one to each light's centre) through the frame's light grids
 * (../pgrid/pgrid_light.h), each light's rays of the batch together;
 * pgrid:N traces multi:N's rays (point lights: hard's) through the frame's
 * 3D light grids (../pgrid/pgrid_soft.h), a point's N rays as packets.
 * multi, cone, pyramid, pgrid:N and interleaved sample sphere and quad
 * lights alike.
 *
 * Transparent shadows (scenes with a transparent material): after any of
 * those methods, the shadow rays found occluded are traced again, as omni
 * packets of closest hits, surface after surface (tnear moved to each hit)
 * while they cross transparent surfaces, each keeping the product of the
 * transparencies, as the reference does ray by ray. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "sp_frusta.h"
#include "sp_scratch.h"

#define SP_SHADOW_CHUNK 8192u /* shadow rays traced per batch */

typedef struct sp_light_request {
    rtt_vec3 contribution;
    uint32_t first, rays, auto_clear;
    uint32_t frustum;               /* frusta:N: its point in sp_frusta.c's batch, or NO_FRUSTUM */
    uint32_t edge;                  /* edgewidth: index of its ray in edge_rays, or NO_EDGE_RAY */
    bool active;                    /* contribution not exactly zero */
} sp_light_request;

#define NO_EDGE_RAY UINT32_MAX
#define NO_FRUSTUM UINT32_MAX

/* Traces level d's rays (closest hit) as omni 2x2 packets. */
static void trace_level(const sp_tracer *tr, sp_scratch *s, uint32_t d)
{
    const sp_level *level = &s->levels[d];
    const sp_node *nodes = sp_level_nodes(s, d);
    uint32_t packets = (level->count + 3) / 4;
    if (!sp_ensure_packets(s, packets)) return;
    ray_packet4 *out = SP_ARRAY(s->packets, ray_packet4);
    for (uint32_t p = 0; p < packets; p++) {
        rtt_ray rays[4];
        uint32_t n = level->count - 4 * p < 4 ? level->count - 4 * p : 4;
        for (uint32_t l = 0; l < n; l++) rays[l] = nodes[4 * p + l].ray;
        ray_packet4_load(&out[p], rays, n);
    }
    sp_trace_packets(tr, tr->secondary, out, SP_ARRAY(s->hits, hit_packet4), packets, NULL, NULL);
    sp_store_hits(s, d, NULL, packets);
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
    SP_ARRAY(s->shadow_rays, rtt_ray)[i] =
        (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, sh->epsilon, distance - sh->epsilon};
}

/* Methods that trace rtt_light_sample's N samples on sphere and quad lights. */
static bool is_sampled(rtt_shadow_method m)
{
    return m == RTT_SHADOWS_MULTI || m == RTT_SHADOWS_CONE || m == RTT_SHADOWS_PYRAMID || m == RTT_SHADOWS_PGRID_SOFT;
}

/* Does this light get N sample rays (else one to its centre)?  As the
 * reference: multi and its proxies sample every sphere and quad light,
 * interleaved those with area. */
static bool samples_light(const sp_shading *sh, const rtt_light *light)
{
    if (is_sampled(sh->shadows)) return light->type != RTT_LIGHT_POINT;
    return (sh->shadows == RTT_SHADOWS_INTERLEAVED || sh->shadows == RTT_SHADOWS_FRUSTA) && rtt_light_has_area(light);
}

/* Sample k of n of `light` for the shading point p of pixel `pixel`. */
static rtt_vec3 sample_point(const sp_shading *sh, const rtt_light *light, const rtt_light_frame *frame, rtt_vec3 p,
                             uint32_t k, uint32_t n, uint32_t pixel)
{
    if (sh->shadows != RTT_SHADOWS_INTERLEAVED && sh->shadows != RTT_SHADOWS_FRUSTA)
        return rtt_light_sample(light, p, k, n, pixel);
    float s[2], xy[2];
    rtt_interleaved_sample(rtt_interleaved_set(pixel % sh->width, pixel / sh->width), k, n, s);
    rtt_light_sample_coords(light, s, xy);
    return rtt_light_frame_point(frame, xy[0], xy[1]);
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
    if (samples_light(sh, light)) return sh->shadow_samples;
    return 1;
}

/* The edge-width ray of one request, or none when nothing fits between. */
static void edge_ray(const sp_shading *sh, sp_scratch *s, rtt_vec3 p, uint32_t light, sp_light_request *q,
                     uint32_t *edges)
{
    q->edge = NO_EDGE_RAY;
    rtt_ray *ray = &SP_ARRAY(s->edge_rays, rtt_ray)[*edges];
    if (!rtt_edge_width_ray(sh->scene->lights[light].position, p, sh->epsilon, ray)) {
        q->auto_clear++;
        return;
    }
    SP_ARRAY(s->edge_light, uint32_t)[*edges] = light;
    q->edge = (*edges)++;
}

/* Step 1 for nodes [first, end): surfaces, contributions, shadow rays (and
 * for cone/pyramid their groups, for edgewidth the edge rays).  Returns
 * the number of shadow rays.  The rays go light by light (all the nodes'
 * rays to light 0, then to light 1, ...): neighbouring pixels' rays to one
 * light share a packet and a block, as coherent as the primary rays; node by
 * node, a packet would hold rays to up to four lights in different places
 * and the frustum kernels could bound nothing (20x slower on a map lit by
 * 64 lights).  A request's rays stay contiguous either way. */
static uint32_t gather_shadows(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t d, uint32_t first,
                               uint32_t end, uint32_t *groups, uint32_t *edges)
{
    const rtt_scene *scene = sh->scene;
    const sp_node *nodes = sp_level_nodes(s, d);
    uint32_t *group_first = SP_ARRAY(s->group_first, uint32_t);
    uint32_t rays = 0;
    const bool hard_frusta = sp_frusta_hard(sh, tr);
    *groups = *edges = 0;
    s->frusta_count = 0;
    for (uint32_t i = first; i < end; i++) {
        const sp_node *node = &nodes[i];
        if (node->hit.prim == RTT_MISS) continue;
        SP_ARRAY(s->surfaces, rtt_surface)[i - first] = rtt_surface_at(scene, &node->ray, &node->hit);
    }
    for (uint32_t l = 0; l < scene->light_count; l++) {
        const rtt_light *light = &scene->lights[l];
        for (uint32_t i = first; i < end; i++) {
            const sp_node *node = &nodes[i];
            sp_light_request *req = &SP_ARRAY(s->requests, sp_light_request)[(size_t)(i - first) * scene->light_count];
            if (node->hit.prim == RTT_MISS) continue;
            const rtt_surface *surf = &SP_ARRAY(s->surfaces, rtt_surface)[i - first];
            sp_light_request *q = &req[l];
            q->active = false;
            q->first = rays, q->rays = 0, q->auto_clear = 0;
            q->edge = NO_EDGE_RAY;
            q->frustum = NO_FRUSTUM;
            rtt_vec3 to_light = rtt_v3_sub(light->position, surf->point);
            float distance = rtt_v3_length(to_light);
            if (!(distance > 0.0f)) continue;
            q->contribution = rtt_shade_light(surf, rtt_v3_scale(to_light, 1.0f / distance), light, distance);
            if (q->contribution.x == 0.0f && q->contribution.y == 0.0f && q->contribution.z == 0.0f) continue;
            q->active = true;
            uint32_t n = samples_per_light(sh, light);
            if (sp_frusta_soft(sh, light)) { /* frusta:N: the point, its rays made in the kernel */
                q->frustum = sp_frusta_push_point(s, sh, l, surf->point, node->pixel);
            } else if (samples_light(sh, light)) {
                const rtt_light_frame frame = rtt_light_sample_frame(light, surf->point);
                for (uint32_t k = 0; k < n; k++)
                    shadow_segment(sh, s, surf->point, sample_point(sh, light, &frame, surf->point, k, n, node->pixel),
                                   q);
            } else if (uses_edge_width(sh, light)) {
                edge_ray(sh, s, surf->point, l, q, edges);
            } else if (n) {
                shadow_segment(sh, s, surf->point, light->position, q);
                if (q->rays && hard_frusta) sp_frusta_note_ray(s, q->first, l, node->pixel);
            }
            if (is_grouped(sh->shadows) && q->rays) group_first[(*groups)++] = q->first;
            rays += q->rays;
        }
    }
    if (is_grouped(sh->shadows)) group_first[*groups] = rays;
    return rays;
}

/* Step 2: the shadow rays as 2x2 packets through the occlusion kernels. */
static void trace_shadows(const sp_tracer *tr, sp_scratch *s, uint32_t rays)
{
    uint32_t packets = (rays + 3) / 4;
    if (!packets || !sp_ensure_packets(s, packets)) return;
    ray_packet4 *out = SP_ARRAY(s->packets, ray_packet4);
    const rtt_ray *shadow_rays = SP_ARRAY(s->shadow_rays, rtt_ray);
    uint8_t *occluded = SP_ARRAY(s->occluded, uint8_t), *clear = SP_ARRAY(s->shadow_clear, uint8_t);
    for (uint32_t p = 0; p < packets; p++) {
        uint32_t n = rays - 4 * p < 4 ? rays - 4 * p : 4;
        ray_packet4_load(&out[p], &shadow_rays[4 * p], n);
    }
    sp_trace_packets_occluded(tr, tr->kernel, out, occluded, packets);
    for (uint32_t i = 0; i < rays; i++) clear[i] = !(occluded[i / 4] >> (i % 4) & 1u);
}

/* Step 2 for pgrid and pgrid:N: each light's rays (contiguous:
 * gather_shadows goes light by light) through that light's grid. */
static void trace_light_grids(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t d, uint32_t first,
                              uint32_t end)
{
    const uint32_t lights = sh->scene->light_count;
    const sp_node *nodes = sp_level_nodes(s, d);
    const sp_light_request *requests = SP_ARRAY(s->requests, sp_light_request);
    const rtt_ray *shadow_rays = SP_ARRAY(s->shadow_rays, rtt_ray);
    uint8_t *clear = SP_ARRAY(s->shadow_clear, uint8_t);
    /* per ray: the triangle it starts on (hard: one ray per node and light; pgrid:N needs none) */
    uint32_t *prim = tr->soft_grids ? NULL : malloc(((size_t)(end - first) + 1) * sizeof *prim);
    if (!prim && !tr->soft_grids) {
        s->failed = true;
        return;
    }
    uint32_t from = 0;
    for (uint32_t l = 0; l < lights; l++) {
        uint32_t to = from;
        for (uint32_t i = first; i < end; i++) {
            const sp_light_request *q = &requests[(size_t)(i - first) * lights + l];
            if (nodes[i].hit.prim == RTT_MISS) continue;
            for (uint32_t k = 0; prim && k < q->rays; k++) prim[q->first + k - from] = nodes[i].hit.prim;
            if (q->first + q->rays > to) to = q->first + q->rays;
        }
        if (to == from) continue;
        if (tr->soft_grids)
            tr->soft_grid_occluded(tr->soft_grids, l, &shadow_rays[from], to - from, &clear[from], NULL);
        else if (!tr->light_grid_occluded(tr->light_grids, l, &shadow_rays[from], prim, to - from, &clear[from])) {
            free(prim);
            s->failed = true;
            return;
        }
        for (uint32_t i = from; i < to; i++) clear[i] = !clear[i];
        from = to;
    }
    free(prim);
}

/* Step 2 for cone:N and pyramid:N: each group (one point, one light) as one
 * block under its proxy. */
static void trace_shadow_groups(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t rays,
                                uint32_t groups)
{
    const uint32_t *group_first = SP_ARRAY(s->group_first, uint32_t);
    uint32_t packets = sc_group_packets(group_first, groups);
    if (!packets || !sp_ensure_packets(s, packets)) return;
    uint8_t *clear = SP_ARRAY(s->shadow_clear, uint8_t);
    tr->shadows->trace_groups(tr->tree, sh->shadows == RTT_SHADOWS_CONE ? NULL : tr->pyramid,
                              SP_ARRAY(s->shadow_rays, rtt_ray), group_first, groups,
                              SP_ARRAY(s->packets, ray_packet4), SP_ARRAY(s->occluded, uint8_t), clear,
                              tr->leaf_culling, NULL);
    for (uint32_t i = 0; i < rays; i++) clear[i] = !clear[i];
}

/* Step 2 for edgewidth: the edge rays, each light's together so that a
 * packet's rays share their origin (a counting sort by light). */
static void trace_edge_rays(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t edges)
{
    if (!edges) return;
    const uint32_t lights = sh->scene->light_count;
    const uint32_t *edge_light = SP_ARRAY(s->edge_light, uint32_t);
    uint32_t *order = SP_ARRAY(s->edge_order, uint32_t), next = 0;
    for (uint32_t l = 0; l < lights; l++)
        for (uint32_t i = 0; i < edges; i++)
            if (edge_light[i] == l) order[next++] = i;
    tr->shadows->edge_width_stream(tr->tree, &sh->edge_model, SP_ARRAY(s->edge_rays, rtt_ray), order, edges,
                                   SP_ARRAY(s->edge_occlusion, float), NULL);
}

/* Step 2 for transparent shadows: each occluded ray's transmission, the
 * product of the transparencies of the surfaces it crosses, nearest first
 * (the reference's segment_transmission); clear rays keep 1. */
static void trace_transparent_shadows(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t rays)
{
    if (!SP_RESERVE(s, shadow_transmission, (size_t)rays + 1, float) ||
        !SP_RESERVE(s, shadow_pending, (size_t)rays + 1, uint32_t))
        return;
    float *transmission = SP_ARRAY(s->shadow_transmission, float);
    uint32_t *pending = SP_ARRAY(s->shadow_pending, uint32_t), count = 0;
    rtt_ray *shadow_rays = SP_ARRAY(s->shadow_rays, rtt_ray);
    const uint8_t *clear = SP_ARRAY(s->shadow_clear, uint8_t);
    for (uint32_t i = 0; i < rays; i++) {
        transmission[i] = 1.0f;
        if (!clear[i]) pending[count++] = i;
    }
    for (uint32_t layer = 0; layer < RTT_SHADOW_MAX_LAYERS && count; layer++) {
        uint32_t packets = (count + 3) / 4;
        if (!sp_ensure_packets(s, packets)) return;
        ray_packet4 *out = SP_ARRAY(s->packets, ray_packet4);
        for (uint32_t p = 0; p < packets; p++) {
            rtt_ray lane[4];
            uint32_t n = count - 4 * p < 4 ? count - 4 * p : 4;
            for (uint32_t l = 0; l < n; l++) lane[l] = shadow_rays[pending[4 * p + l]];
            ray_packet4_load(&out[p], lane, n);
        }
        hit_packet4 *hits = SP_ARRAY(s->hits, hit_packet4);
        sp_trace_packets(tr, tr->secondary, out, hits, packets, NULL, NULL);
        uint32_t next = 0;
        for (uint32_t p = 0; p < packets; p++) {
            rtt_hit hit[4];
            uint32_t n = count - 4 * p < 4 ? count - 4 * p : 4;
            hit_packet4_store(&hits[p], hit, n);
            for (uint32_t l = 0; l < n; l++) {
                uint32_t i = pending[4 * p + l];
                if (hit[l].prim == RTT_MISS) continue; /* past the last surface: lit through them */
                transmission[i] *= rtt_shadow_transmission(sh->scene, hit[l].prim);
                if (transmission[i] == 0.0f) continue;
                shadow_rays[i].tnear = hit[l].t;
                pending[next++] = i;
            }
        }
        count = next;
    }
    for (uint32_t k = 0; k < count; k++) transmission[pending[k]] = 0.0f; /* more surfaces than the bound */
}

/* Step 3 for nodes [first, end) of level d. */
static void resolve_locals(const sp_shading *sh, sp_scratch *s, uint32_t d, uint32_t first, uint32_t end)
{
    const rtt_scene *scene = sh->scene;
    const uint8_t *shadow_clear = SP_ARRAY(s->shadow_clear, uint8_t);
    const float *transmission = sh->transparent_shadows ? SP_ARRAY(s->shadow_transmission, float) : NULL;
    const float *edge_occlusion = SP_ARRAY(s->edge_occlusion, float);
    for (uint32_t i = first; i < end; i++) {
        sp_node *node = &sp_level_nodes(s, d)[i];
        if (node->hit.prim == RTT_MISS) {
            node->colour = scene->background;
            continue;
        }
        const rtt_surface *surf = &SP_ARRAY(s->surfaces, rtt_surface)[i - first];
        const sp_light_request *req =
            &SP_ARRAY(s->requests, sp_light_request)[(size_t)(i - first) * scene->light_count];
        const rtt_material *m = surf->material;
        float wr, wt;
        rtt_shade_weights(m, d, sh->max_bounces, &wr, &wt);
        rtt_shadow_planes *planes = d == 0 ? sh->planes : NULL;
        if (planes) { /* the shadow rays' origin, for the refining pass (as the reference's local_colour) */
            planes->point[3 * (size_t)node->pixel + 0] = surf->point.x;
            planes->point[3 * (size_t)node->pixel + 1] = surf->point.y;
            planes->point[3 * (size_t)node->pixel + 2] = surf->point.z;
        }
        rtt_vec3 colour = rtt_v3_scale(surf->diffuse, scene->ambient);
        for (uint32_t l = 0; l < scene->light_count; l++) {
            const sp_light_request *q = &req[l];
            if (!q->active) continue;
            float vis = 1.0f;
            uint32_t n = samples_per_light(sh, &scene->lights[l]);
            if (q->frustum != NO_FRUSTUM) {
                vis = (float)sp_frusta_clear_samples(s, q->frustum, n) / (float)n;
            } else if (q->edge != NO_EDGE_RAY) {
                vis = 1.0f - edge_occlusion[q->edge];
            } else if (n && transmission) {
                float clear = (float)q->auto_clear;
                for (uint32_t k = 0; k < q->rays; k++) clear += transmission[q->first + k];
                vis = n == 1 && !samples_light(sh, &scene->lights[l]) ? clear : clear / (float)n;
            } else if (n) {
                uint32_t clear = q->auto_clear;
                for (uint32_t k = 0; k < q->rays; k++) clear += shadow_clear[q->first + k];
                vis = n == 1 && !samples_light(sh, &scene->lights[l]) ? (clear ? 1.0f : 0.0f)
                                                                        : (float)clear / (float)n;
            }
            if (planes) { /* as the reference's local_colour */
                const size_t at = (size_t)planes->width * planes->height * l + node->pixel;
                planes->visibility[at] = vis;
                rtt_vec3 c = rtt_v3_scale(q->contribution, 1.0f - wr - wt);
                planes->contribution[3 * at + 0] = c.x;
                planes->contribution[3 * at + 1] = c.y;
                planes->contribution[3 * at + 2] = c.z;
            } else {
                colour = rtt_v3_madd(colour, q->contribution, vis);
            }
        }
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
            node = &sp_level_nodes(s, d)[i]; /* the push never moves level d, but stay obvious */
            if (c == 0 && wr > 0.0f)
                node->reflected = child;
            else
                node->refracted = child;
            s->stats.secondary_rays++;
        }
    }
}

/* Room for a chunk of `chunk` nodes of level d: surfaces and light
 * requests per node, shadow rays, and what the shadow method needs. */
static bool reserve_chunk(const sp_shading *sh, sp_scratch *s, uint32_t chunk, uint32_t per_node)
{
    const size_t lights = sh->scene->light_count ? sh->scene->light_count : 1, rays = (size_t)chunk * per_node + 4;
    const size_t requests = chunk * lights;
    if (!SP_RESERVE(s, surfaces, chunk, rtt_surface) || !SP_RESERVE(s, requests, requests, sp_light_request) ||
        !SP_RESERVE(s, shadow_rays, rays, rtt_ray) || !SP_RESERVE(s, shadow_clear, rays, uint8_t))
        return false;
    if (is_grouped(sh->shadows) && !SP_RESERVE(s, group_first, requests + 1, uint32_t)) return false;
    if (sh->shadows == RTT_SHADOWS_FRUSTA && !sp_frusta_begin(s, requests)) return false;
    if (sh->shadows == RTT_SHADOWS_HARD && !sp_frusta_reserve_rays(s, rays)) return false;
    if (sh->shadows == RTT_SHADOWS_EDGEWIDTH &&
        (!SP_RESERVE(s, edge_rays, requests, rtt_ray) || !SP_RESERVE(s, edge_order, requests, uint32_t) ||
         !SP_RESERVE(s, edge_light, requests, uint32_t) || !SP_RESERVE(s, edge_occlusion, requests, float)))
        return false;
    return true;
}

static void shade_level(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t d)
{
    const rtt_scene *scene = sh->scene;
    uint32_t per_node = 0;
    for (uint32_t l = 0; l < scene->light_count; l++) per_node += samples_per_light(sh, &scene->lights[l]) + 1;
    uint32_t chunk = per_node ? SP_SHADOW_CHUNK / per_node : SP_SHADOW_CHUNK;
    if (chunk == 0) chunk = 1;
    if (!reserve_chunk(sh, s, chunk, per_node)) return;
    for (uint32_t first = 0; first < s->levels[d].count; first += chunk) {
        uint32_t end = s->levels[d].count - first < chunk ? s->levels[d].count : first + chunk;
        uint64_t t0 = s->timing ? rtt_clock_ns() : 0;
        uint32_t groups, edges;
        uint32_t rays = gather_shadows(sh, tr, s, d, first, end, &groups, &edges);
        uint64_t t1 = s->timing ? rtt_clock_ns() : 0;
        if (is_grouped(sh->shadows))
            trace_shadow_groups(sh, tr, s, rays, groups);
        else if (sh->shadows == RTT_SHADOWS_PGRID || sh->shadows == RTT_SHADOWS_PGRID_SOFT)
            trace_light_grids(sh, tr, s, d, first, end);
        else if (sp_frusta_hard(sh, tr))
            sp_frusta_trace_rays(sh, tr, s, rays);
        else
            trace_shadows(tr, s, rays);
        sp_frusta_trace_points(sh, tr, s);
        trace_edge_rays(sh, tr, s, edges);
        if (sh->transparent_shadows && rays) trace_transparent_shadows(sh, tr, s, rays);
        uint64_t t2 = s->timing ? rtt_clock_ns() : 0;
        s->stats.shadow_rays += rays + edges + s->frusta_count * sh->shadow_samples;
        resolve_locals(sh, s, d, first, end);
        if (s->failed) return;
        if (s->timing) {
            s->stats.ns_shading += (t1 - t0) + (rtt_clock_ns() - t2);
            s->stats.ns_secondary += t2 - t1;
        }
    }
}

/* Step 4: colour = (1 - wr - wt) local + wr reflected + wt refracted. */
static void combine(sp_scratch *s, uint32_t levels)
{
    for (uint32_t d = levels - 1; d-- > 0;) {
        sp_node *nodes = sp_level_nodes(s, d);
        const sp_node *below = sp_level_nodes(s, d + 1);
        for (uint32_t i = 0; i < s->levels[d].count; i++) {
            sp_node *n = &nodes[i];
            if (n->reflected >= 0) n->colour = rtt_v3_madd(n->colour, below[n->reflected].colour, n->wr);
            if (n->refracted >= 0) n->colour = rtt_v3_madd(n->colour, below[n->refracted].colour, n->wt);
        }
    }
}

void sp_tile_shade(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s)
{
    for (uint32_t d = 1; d < s->level_count; d++) s->levels[d].count = 0;
    uint32_t used = 0;
    for (uint32_t d = 0; d < s->level_count && !s->failed; d++) {
        if (s->levels[d].count == 0) break;
        if (d > 0) {
            uint64_t t0 = s->timing ? rtt_clock_ns() : 0;
            trace_level(tr, s, d);
            if (s->timing) s->stats.ns_secondary += rtt_clock_ns() - t0;
        }
        shade_level(sh, tr, s, d);
        used = d + 1;
    }
    if (!s->failed && used > 1) {
        uint64_t t0 = s->timing ? rtt_clock_ns() : 0;
        combine(s, used);
        if (s->timing) s->stats.ns_shading += rtt_clock_ns() - t0;
    }
}

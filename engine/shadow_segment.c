/* Shadow segments through any engine (rtt/render.h): the reference
 * renderer's shadow rays, and the refining pass of interleaved shadows
 * (rtt/interleaved.h) that both renderers run after their tiles. */
#include <math.h>

#include "rtt/interleaved.h"
#include "rtt/render.h"
#include "rtt/shade.h"

float rtt_engine_segment_transmission(rtt_engine *engine, const rtt_scene *scene, rtt_vec3 p, rtt_vec3 target,
                                      float epsilon, bool transparent, uint64_t *rays)
{
    rtt_vec3 to_target = rtt_v3_sub(target, p);
    float distance = rtt_v3_length(to_target);
    if (!(distance > 2.0f * epsilon)) return 1.0f; /* nothing fits between */
    rtt_vec3 dir = rtt_v3_scale(to_target, 1.0f / distance);
    rtt_ray ray = {{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, epsilon, distance - epsilon};
    uint8_t occluded = 0;
    rtt_engine_occluded(engine, &ray, &occluded, 1);
    ++*rays;
    if (!occluded) return 1.0f;
    if (!transparent) return 0.0f;
    float transmission = 1.0f;
    for (uint32_t layer = 0; layer < RTT_SHADOW_MAX_LAYERS; layer++) {
        rtt_hit hit;
        rtt_engine_intersect(engine, &ray, &hit, 1);
        if (hit.prim == RTT_MISS) return transmission;
        transmission *= rtt_shadow_transmission(scene, hit.prim);
        if (transmission == 0.0f) return 0.0f;
        ray.tnear = hit.t; /* past this surface: hits count only beyond tnear */
    }
    return 0.0f;
}

/* The refined visibility of one point. */
static float refined_visibility(rtt_engine *engine, const rtt_scene *scene, const rtt_light *light, rtt_vec3 p,
                                uint32_t n, float epsilon, bool transparent, uint64_t *rays)
{
    const rtt_light_frame frame = rtt_light_sample_frame(light, p);
    float clear = 0.0f;
    for (uint32_t set = 0; set < RTT_INTERLEAVED_SETS; set++)
        for (uint32_t i = 0; i < n; i++) {
            float s[2], xy[2];
            rtt_interleaved_sample(set, i, n, s);
            rtt_light_sample_coords(light, s, xy);
            const rtt_vec3 target = rtt_light_frame_point(&frame, xy[0], xy[1]);
            clear += rtt_engine_segment_transmission(engine, scene, p, target, epsilon, transparent, rays);
        }
    return clear / (float)(RTT_INTERLEAVED_SETS * n);
}

void rtt_engine_refined_visibilities(rtt_engine *engine, const rtt_scene *scene, const rtt_shadow_planes *planes,
                                     uint32_t light, const uint32_t *pixel, size_t count, uint32_t n, float epsilon,
                                     bool transparent, float *vis, uint64_t *rays)
{
    for (size_t i = 0; i < count; i++) {
        const float *p = &planes->point[3 * (size_t)pixel[i]];
        vis[i] = refined_visibility(engine, scene, &scene->lights[light], rtt_v3(p[0], p[1], p[2]), n, epsilon,
                                    transparent, rays);
    }
}

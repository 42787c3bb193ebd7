/* The shader proxy's multi-frusta shadow passes (sp_frusta.c), private to
 * the proxy's files:
 *
 *   frusta:N   each shading point's N interleaved samples of a light with
 *              area as one frustum (bvh_shadow_kernel, optimized/bvh/
 *              shadow_frusta.c): the proxy pushes the points instead of
 *              rays, they are traced in 4x4 pixel blocks, and each point's
 *              occluded samples come back as a bit mask;
 *   hard       with --accel bvh --traversal bvh-mft, the hard shadow rays of
 *              each light, ordered in 4x4 pixel blocks, through bvh-mft with
 *              the light as their common end point (bvh_query.toward): 16
 *              hit points' rays make one frustum from the light. */
#ifndef RTT_OPTIMIZED_SP_FRUSTA_H
#define RTT_OPTIMIZED_SP_FRUSTA_H

#include "sp_scratch.h"

/* The sets' domain coordinates of every light of the scene for n samples
 * (one bvh_shadow_sets per light, the same for every point of a frame);
 * NULL when out of memory.  free() releases it. */
bvh_shadow_sets *sp_frusta_sets_create(const rtt_scene *scene, uint32_t n);

/* frusta:N: does this light's visibility come from the frusta kernel?
 * (lights with area, and not in scenes with transparent shadows, whose
 * transmission needs each occluded ray's closest hits: those trace
 * interleaved's rays). */
bool sp_frusta_soft(const sp_shading *sh, const rtt_light *light);
/* Room for `points` pushes; starts a batch. */
bool sp_frusta_begin(sp_scratch *s, size_t points);
/* A shading point p (of pixel `pixel`) and light `light`: returns its index. */
uint32_t sp_frusta_push_point(sp_scratch *s, const sp_shading *sh, uint32_t light, rtt_vec3 p, uint32_t pixel);
/* Traces the batch's points; then sp_frusta_clear_samples. */
void sp_frusta_trace_points(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s);
/* The samples of point `point` that reach the light (of n). */
uint32_t sp_frusta_clear_samples(const sp_scratch *s, uint32_t point, uint32_t n);

/* The refining pass of frusta:N:refine (rtt/interleaved.h) for lights
 * sp_frusta_soft takes: each of the `count` pixels' 16 sets as 16 frusta
 * from its shading point (point: 3 floats per pixel, the shadow planes'),
 * traced together (one kernel pass on AVX-512); vis[i] the clear share of
 * the 16 N samples.  *rays grows by 16 N a pixel.  False when out of
 * memory. */
bool sp_frusta_refine(const sp_shading *sh, const sp_tracer *tr, uint32_t light, const float *point,
                      const uint32_t *pixel, size_t count, float *vis, uint64_t *rays);

/* Hard shadows through bvh-mft: does this render trace them so? */
bool sp_frusta_hard(const sp_shading *sh, const sp_tracer *tr);
/* Room for `rays` notes; the light and pixel of shadow ray `ray`. */
bool sp_frusta_reserve_rays(sp_scratch *s, size_t rays);
void sp_frusta_note_ray(sp_scratch *s, uint32_t ray, uint32_t light, uint32_t pixel);
/* Traces shadow rays 0..rays-1 (all noted) into s->shadow_clear. */
void sp_frusta_trace_rays(const sp_shading *sh, const sp_tracer *tr, sp_scratch *s, uint32_t rays);

#endif

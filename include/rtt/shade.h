/* The shading model both renderers implement, so their images agree.
 *
 * Primary rays: one per pixel through the pixel centre, normalized
 * directions (t is a distance).  At a hit, the shading normal is the
 * interpolated vertex normal (or the geometric normal), turned to face the
 * incoming ray.  The local colour is
 *
 *   local = diffuse * ambient
 *         + sum over lights of  vis * E(d) * (diffuse * max(0, n.l)
 *                                             + specular * max(0, r.v)^shininess)
 *
 * with E(d) = colour * intensity / (c + l d + q d^2) (times the emitter's
 * cosine for quad lights, rtt/scene.h), l and d towards and from the
 * light's centre for every light type, the specular term only
 * for types SPECULAR, REFLECTIVE and TRANSPARENT_REFLECTIVE, and vis in [0,1]
 * the light's visibility from the chosen shadow method.  Then
 *
 *   colour = (1 - wr - wt) * local + wr * trace(reflected) + wt * trace(refracted)
 *
 * with wr = reflection (types REFLECTIVE, TRANSPARENT_REFLECTIVE), wt =
 * transparency (TRANSPARENT, TRANSPARENT_REFLECTIVE), clamped so that
 * wr + wt <= 1.  Total internal reflection sends the refracted ray along the
 * reflected direction.  At depth max_bounces, wr = wt = 0.  A miss returns the
 * background colour.  Secondary and shadow rays start at the hit point with
 * tnear = rtt_scene_ray_epsilon(); shadow rays end at tfar = d - epsilon.  */
#ifndef RTT_SHADE_H
#define RTT_SHADE_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/scene.h"

/* Precomputed camera: dir(x, y) = normalize(corner + x*du + y*dv) for pixel
 * coordinates x, y (pixel centres at +0.5; y grows downwards). */
typedef struct rtt_camera_frame {
    rtt_vec3 eye, corner, du, dv;
} rtt_camera_frame;

rtt_camera_frame rtt_camera_frame_make(const rtt_camera *camera, uint32_t width, uint32_t height);
/* The primary ray of pixel (px, py): through its centre, tnear 0, tfar inf. */
rtt_ray rtt_camera_ray(const rtt_camera_frame *frame, uint32_t px, uint32_t py);

/* Sample i of n on area light `light` as seen from point p, from a
 * Hammersley pattern scrambled per pixel (Cranley-Patterson rotation seeded
 * by `pixel`) to (su, sv) in [0,1)^2: on a sphere light a point on the disk
 * of the light's radius, centred on the light and facing p; on a quad light
 * the quad's point at (su - 1/2, sv - 1/2) (rtt/interleaved.h's frame).  For
 * a light without area (rtt_light_has_area), the centre. */
rtt_vec3 rtt_light_sample(const rtt_light *light, rtt_vec3 p, uint32_t i, uint32_t n, uint32_t pixel);
/* A sphere light with radius > 0 or a quad light with edge_u x edge_v != 0:
 * a light whose soft-shadow methods trace more than its centre. */
bool rtt_light_has_area(const rtt_light *light);
/* Point i of n of the 2D Hammersley set in [0,1)^2. */
void rtt_hammersley(uint32_t i, uint32_t n, float out[2]);

/* E(d) of the formula above, per channel. */
rtt_vec3 rtt_light_irradiance(const rtt_light *light, float distance);

/* The unoccluded contribution of one light to a surface point (without the
 * ambient term and before multiplying by vis): E(d) * (diffuse * max(0,n.l)
 * + specular term).  n faces the viewer, to_light and to_viewer are unit. */
rtt_vec3 rtt_shade_light(const rtt_material *m, rtt_vec3 n, rtt_vec3 to_viewer, rtt_vec3 to_light,
                         const rtt_light *light, float distance);

/* Weights of the reflected and refracted rays for material m at bounce
 * `depth` (0 for primary hits). */
void rtt_shade_weights(const rtt_material *m, uint32_t depth, uint32_t max_bounces, float *wr, float *wt);

/* Direction of the refracted ray for unit incident dir d and unit normal n
 * facing against d (dot(d, n) < 0) when going from a medium of index
 * eta_from into eta_to; the reflected direction on total internal
 * reflection.  `entering` tells the caller which side the ray was on: a hit
 * whose geometric normal faces the ray enters the object. */
rtt_vec3 rtt_refract(rtt_vec3 d, rtt_vec3 n, float eta_from, float eta_to);

/* The surface a hit shows the shader: the hit point, the incoming ray's unit
 * direction, the shading normal turned to face the ray, whether the ray
 * enters the object (the geometric normal faces it) and the material.  Both
 * renderers shade from it, so they see exactly the same surface. */
typedef struct rtt_surface {
    rtt_vec3 point, dir, normal;
    bool entering;
    const rtt_material *material;
} rtt_surface;

rtt_surface rtt_surface_at(const rtt_scene *scene, const rtt_ray *ray, const rtt_hit *hit);

/* Interpolated shading normal of triangle prim at barycentrics (u, v),
 * normalized, not yet turned towards the ray; geometric when the scene has
 * no vertex normals. */
rtt_vec3 rtt_scene_shading_normal(const rtt_scene *scene, uint32_t prim, float u, float v);
rtt_vec3 rtt_scene_geometric_normal(const rtt_scene *scene, uint32_t prim);

#endif

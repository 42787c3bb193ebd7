/* The shading model both renderers implement, so their images agree.
 *
 * Primary rays: one per pixel through the pixel centre, normalized
 * directions (t is a distance).  At a hit, the shading normal is the
 * interpolated vertex normal (or the geometric normal), perturbed by the
 * material's normal map when it has one, turned to face the incoming ray;
 * diffuse is the material's colour, or its diffuse map's bilinear sample at
 * the interpolated texture coordinates (Thesis 4.2.1, steps 3 and 4).  The
 * local colour is
 *
 *   local = diffuse * ambient
 *         + sum over lights of  vis * E(d) * (diffuse * max(0, n.l)
 *                                             + specular * max(0, r.v)^shininess)
 *
 * with E(d) = colour * intensity / (c + l r + q r^2), r = d / D, D the light's
 * attenuation_distance (rtt/scene.h; 1 by default) (times the emitter's
 * cosine for quad lights, rtt/scene.h), l and d towards and from the
 * light's centre for every light type, the specular term only
 * for types SPECULAR, REFLECTIVE and TRANSPARENT_REFLECTIVE, and vis in [0,1]
 * the light's visibility from the chosen shadow method.  A shadow ray that
 * meets transparent surfaces (types TRANSPARENT, TRANSPARENT_REFLECTIVE)
 * passes through them: it carries the product of their `transparency` (each
 * clamped to [0, 1]) up to the first opaque surface (0) or the light, over at
 * most RTT_SHADOW_MAX_LAYERS surfaces (more count as opaque); the shadow
 * methods average that over their rays where they average clear rays.  Then
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
/* The same through the point `offset` (each in [0, 1)) of the pixel. */
rtt_ray rtt_camera_ray_at(const rtt_camera_frame *frame, uint32_t px, uint32_t py, const float offset[2]);

/* Anti-aliasing: subpixel sample i of n of pixel `pixel` (py * width + px),
 * an offset in [0, 1)^2 into the pixel.  n = 1: the centre (0.5, 0.5), the
 * one-ray-per-pixel image.  n > 1: the Hammersley set (i / n, radical inverse
 * of i in base 2), stratified and low-discrepancy (for n a power of two a
 * (0, m, 2)-net: one sample in every elementary interval of area 1/n),
 * toroidally shifted by a rotation hashed from the pixel (Cranley-Patterson),
 * so that neighbouring pixels do not repeat one pattern and edges show noise
 * rather than a structured alias.  Deterministic: the same for any thread
 * count and in both renderers.  The pixel's colour is the plain mean of its n
 * samples: a box filter over the pixel, the estimate of the pixel's area
 * integral that stratification converges fastest for, and one that keeps
 * every sample inside its own pixel, so tiles stay independent and the image
 * does not depend on how tiles go to threads (a wider tent or Gaussian filter
 * would spread samples over neighbouring tiles). */
void rtt_pixel_sample(uint32_t i, uint32_t n, uint32_t pixel, float out[2]);

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

#define RTT_SHADOW_MAX_LAYERS 16u

/* E(d) of the formula above, per channel. */
rtt_vec3 rtt_light_irradiance(const rtt_light *light, float distance);

struct rtt_surface;
/* The unoccluded contribution of one light to a surface point (without the
 * ambient term and before multiplying by vis): E(d) * (diffuse * max(0,n.l)
 * + specular term), with the surface's diffuse colour and normal (which
 * faces the viewer); to_light is unit. */
rtt_vec3 rtt_shade_light(const struct rtt_surface *s, rtt_vec3 to_light, const rtt_light *light, float distance);

/* Does any material let shadow rays through (types TRANSPARENT,
 * TRANSPARENT_REFLECTIVE with transparency > 0)?  Scenes without pay nothing. */
bool rtt_scene_has_transparent_shadows(const rtt_scene *scene);
/* The factor a shadow ray keeps passing the surface of triangle prim:
 * its material's clamped transparency when transparent, else 0. */
float rtt_shadow_transmission(const rtt_scene *scene, uint32_t prim);

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
 * enters the object (the geometric normal faces it), the diffuse colour
 * and the material.  Both
 * renderers shade from it, so they see exactly the same surface. */
typedef struct rtt_surface {
    rtt_vec3 point, dir, normal;
    rtt_vec3 diffuse; /* the material's colour, or its diffuse map at the hit */
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

/* The shading model of include/rtt/shade.h: camera rays, light samples,
 * light frames (rtt/interleaved.h), the local illumination of one light,
 * secondary-ray weights, refraction and surface normals.  Both renderers call these same functions, so their
 * images differ only where the engines return different hits. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "rtt/interleaved.h"
#include "rtt/shade.h"

#define SHADE_PI 3.14159265358979f

rtt_camera_frame rtt_camera_frame_make(const rtt_camera *camera, uint32_t width, uint32_t height)
{
    rtt_vec3 forward = rtt_v3_normalize(rtt_v3_sub(camera->look_at, camera->eye));
    rtt_vec3 right = rtt_v3_cross(forward, camera->up);
    if (!(rtt_v3_length(right) > 1e-6f)) /* up parallel to the view: any perpendicular will do */
        right = rtt_v3_cross(forward, fabsf(forward.y) < 0.9f ? rtt_v3(0, 1, 0) : rtt_v3(1, 0, 0));
    right = rtt_v3_normalize(right);
    rtt_vec3 up = rtt_v3_cross(right, forward);
    float half_h = tanf(0.5f * camera->fov_deg * SHADE_PI / 180.0f);
    float half_w = half_h * (float)width / (float)(height ? height : 1);
    rtt_camera_frame f;
    f.eye = camera->eye;
    f.corner = rtt_v3_add(forward, rtt_v3_sub(rtt_v3_scale(up, half_h), rtt_v3_scale(right, half_w)));
    f.du = rtt_v3_scale(right, 2.0f * half_w / (float)(width ? width : 1));
    f.dv = rtt_v3_scale(up, -2.0f * half_h / (float)(height ? height : 1));
    return f;
}

rtt_ray rtt_camera_ray_at(const rtt_camera_frame *frame, uint32_t px, uint32_t py, const float offset[2])
{
    rtt_vec3 d = rtt_v3_add(frame->corner, rtt_v3_add(rtt_v3_scale(frame->du, (float)px + offset[0]),
                                                      rtt_v3_scale(frame->dv, (float)py + offset[1])));
    d = rtt_v3_normalize(d);
    return (rtt_ray){{frame->eye.x, frame->eye.y, frame->eye.z}, {d.x, d.y, d.z}, 0.0f, INFINITY};
}

rtt_ray rtt_camera_ray(const rtt_camera_frame *frame, uint32_t px, uint32_t py)
{
    static const float centre[2] = {0.5f, 0.5f};
    return rtt_camera_ray_at(frame, px, py, centre);
}

static float radical_inverse_base2(uint32_t bits)
{
    bits = (bits << 16) | (bits >> 16);
    bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
    bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
    bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
    bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
    return (float)(bits >> 8) * (1.0f / 16777216.0f);
}

void rtt_hammersley(uint32_t i, uint32_t n, float out[2])
{
    out[0] = (float)i / (float)(n ? n : 1);
    out[1] = radical_inverse_base2(i);
}

/* A 32-bit integer hash (the "lowbias32" finalizer): decorrelates the
 * per-pixel rotations of neighbouring pixels. */
static uint32_t hash_u32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

static float wrap_unit(float x) { return x >= 1.0f ? x - 1.0f : x; }

void rtt_pixel_sample(uint32_t i, uint32_t n, uint32_t pixel, float out[2])
{
    if (n <= 1) {
        out[0] = out[1] = 0.5f;
        return;
    }
    float h[2];
    rtt_hammersley(i, n, h);
    /* the light samples rotate by hash(2 pixel + 1): an even seed keeps the
     * two patterns of a pixel apart */
    uint32_t seed = hash_u32(pixel * 2u);
    out[0] = wrap_unit(h[0] + (float)(seed >> 8) * (1.0f / 16777216.0f));
    out[1] = wrap_unit(h[1] + (float)(hash_u32(seed) >> 8) * (1.0f / 16777216.0f));
}

/* Two unit vectors u, v orthogonal to each other and to the direction from
 * the centre of `light` towards p: the plane of the disc a sphere light shows p. */
static void facing_basis(const rtt_light *light, rtt_vec3 p, rtt_vec3 *u, rtt_vec3 *v)
{
    rtt_vec3 w = rtt_v3_normalize(rtt_v3_sub(p, light->position));
    if (!(rtt_v3_length(w) > 0.0f)) w = rtt_v3(0, 1, 0);
    rtt_vec3 a = fabsf(w.x) < 0.9f ? rtt_v3(1, 0, 0) : rtt_v3(0, 1, 0);
    *u = rtt_v3_normalize(rtt_v3_cross(a, w));
    *v = rtt_v3_cross(w, *u);
}

bool rtt_light_has_area(const rtt_light *light)
{
    if (light->type == RTT_LIGHT_SPHERE) return light->radius > 0.0f;
    if (light->type == RTT_LIGHT_QUAD) {
        float area = rtt_v3_length(rtt_v3_cross(light->edge_u, light->edge_v));
        return area > 0.0f && isfinite(area);
    }
    return false;
}

rtt_vec3 rtt_light_sample(const rtt_light *light, rtt_vec3 p, uint32_t i, uint32_t n, uint32_t pixel)
{
    if (!rtt_light_has_area(light)) return light->position;
    float h[2];
    rtt_hammersley(i, n, h);
    /* Cranley-Patterson rotation seeded by the pixel */
    uint32_t seed = hash_u32(pixel * 2u + 1u);
    float su = wrap_unit(h[0] + (float)(seed >> 8) * (1.0f / 16777216.0f));
    float sv = wrap_unit(h[1] + (float)(hash_u32(seed) >> 8) * (1.0f / 16777216.0f));
    if (light->type == RTT_LIGHT_QUAD) {
        rtt_light_frame frame = rtt_light_sample_frame(light, p);
        return rtt_light_frame_point(&frame, su - 0.5f, sv - 0.5f);
    }
    /* uniform on the disk of the light's radius, facing p */
    float r = light->radius * sqrtf(su), phi = 2.0f * SHADE_PI * sv;
    rtt_vec3 u, v;
    facing_basis(light, p, &u, &v);
    return rtt_v3_add(light->position,
                      rtt_v3_add(rtt_v3_scale(u, r * cosf(phi)), rtt_v3_scale(v, r * sinf(phi))));
}

void rtt_light_sample_coords(const rtt_light *light, const float s[2], float out[2])
{
    if (light->type == RTT_LIGHT_QUAD) {
        out[0] = s[0] - 0.5f;
        out[1] = s[1] - 0.5f;
    } else if (light->type == RTT_LIGHT_SPHERE) {
        float r = sqrtf(s[0]), phi = 2.0f * SHADE_PI * s[1];
        out[0] = r * cosf(phi);
        out[1] = r * sinf(phi);
    } else {
        out[0] = out[1] = 0.0f;
    }
}

rtt_light_frame rtt_light_sample_frame(const rtt_light *light, rtt_vec3 p)
{
    rtt_light_frame f = {light->position, rtt_v3(0, 0, 0), rtt_v3(0, 0, 0)};
    if (!rtt_light_has_area(light)) return f;
    if (light->type == RTT_LIGHT_QUAD) {
        f.du = light->edge_u;
        f.dv = light->edge_v;
    } else {
        rtt_vec3 u, v;
        facing_basis(light, p, &u, &v);
        f.du = rtt_v3_scale(u, light->radius);
        f.dv = rtt_v3_scale(v, light->radius);
    }
    return f;
}

rtt_vec3 rtt_light_frame_point(const rtt_light_frame *frame, float x, float y)
{
    return rtt_v3_madd(rtt_v3_madd(frame->base, frame->du, x), frame->dv, y);
}

rtt_vec3 rtt_light_irradiance(const rtt_light *light, float distance)
{
    /* d in units of the light's own length: a pure number near 1 at any scale */
    const float r = light->attenuation_distance > 0.0f ? distance / light->attenuation_distance : distance;
    float falloff = light->attenuation[0] + light->attenuation[1] * r + light->attenuation[2] * r * r;
    if (!(falloff > 0.0f)) return rtt_v3(0.0f, 0.0f, 0.0f);
    return rtt_v3_scale(light->color, light->intensity / falloff);
}

static bool has_specular(rtt_material_type type)
{
    return type == RTT_MATERIAL_SPECULAR || type == RTT_MATERIAL_REFLECTIVE ||
           type == RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
}

rtt_vec3 rtt_shade_light(const rtt_surface *s, rtt_vec3 to_light, const rtt_light *light, float distance)
{
    const rtt_material *m = s->material;
    rtt_vec3 n = s->normal, to_viewer = rtt_v3_scale(s->dir, -1.0f);
    float n_dot_l = rtt_v3_dot(n, to_light);
    if (!(n_dot_l > 0.0f)) return rtt_v3(0.0f, 0.0f, 0.0f); /* the light is behind the surface */
    rtt_vec3 e = rtt_light_irradiance(light, distance);
    if (light->type == RTT_LIGHT_QUAD) { /* one-sided Lambertian emitter */
        float cos_emit = -rtt_v3_dot(rtt_v3_normalize(rtt_v3_cross(light->edge_u, light->edge_v)), to_light);
        if (!(cos_emit > 0.0f)) return rtt_v3(0.0f, 0.0f, 0.0f); /* behind the quad's plane */
        e = rtt_v3_scale(e, cos_emit);
    }
    rtt_vec3 response = rtt_v3_scale(s->diffuse, n_dot_l);
    if (has_specular(m->type) && m->specular > 0.0f) {
        rtt_vec3 r = rtt_v3_reflect(rtt_v3_scale(to_light, -1.0f), n);
        float r_dot_v = rtt_v3_dot(r, to_viewer);
        if (r_dot_v > 0.0f) {
            float sp = m->specular * powf(r_dot_v, m->shininess);
            response = rtt_v3_add(response, rtt_v3(sp, sp, sp));
        }
    }
    return rtt_v3_mul(e, response);
}

static bool is_transparent(const rtt_material *m)
{
    return (m->type == RTT_MATERIAL_TRANSPARENT || m->type == RTT_MATERIAL_TRANSPARENT_REFLECTIVE) &&
           m->transparency > 0.0f;
}

bool rtt_scene_has_transparent_shadows(const rtt_scene *scene)
{
    for (uint32_t i = 0; i < scene->material_count; i++)
        if (is_transparent(&scene->materials[i])) return true;
    return false;
}

float rtt_shadow_transmission(const rtt_scene *scene, uint32_t prim)
{
    const rtt_material *m = &scene->materials[scene->triangle_material[prim]];
    return is_transparent(m) ? fminf(m->transparency, 1.0f) : 0.0f;
}

void rtt_shade_weights(const rtt_material *m, uint32_t depth, uint32_t max_bounces, float *wr, float *wt)
{
    float r = 0.0f, t = 0.0f;
    if (depth < max_bounces) {
        if (m->type == RTT_MATERIAL_REFLECTIVE || m->type == RTT_MATERIAL_TRANSPARENT_REFLECTIVE)
            r = fminf(fmaxf(m->reflection, 0.0f), 1.0f);
        if (m->type == RTT_MATERIAL_TRANSPARENT || m->type == RTT_MATERIAL_TRANSPARENT_REFLECTIVE)
            t = fminf(fmaxf(m->transparency, 0.0f), 1.0f);
        if (r + t > 1.0f) { /* keep their ratio, sum to one */
            float s = 1.0f / (r + t);
            r *= s;
            t *= s;
        }
    }
    *wr = r;
    *wt = t;
}

rtt_vec3 rtt_refract(rtt_vec3 d, rtt_vec3 n, float eta_from, float eta_to)
{
    float eta = eta_from / eta_to;
    float cos_i = -rtt_v3_dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
    if (k < 0.0f) return rtt_v3_reflect(d, n); /* total internal reflection */
    return rtt_v3_normalize(rtt_v3_add(rtt_v3_scale(d, eta), rtt_v3_scale(n, eta * cos_i - sqrtf(k))));
}

rtt_vec3 rtt_scene_geometric_normal(const rtt_scene *scene, uint32_t prim)
{
    /* In double: the cross product of the edges grows as the square of the
     * scene's scale, so in float it overflows beyond 1e19 and loses its
     * digits (subnormal, then zero) below 1e-19; the normal must not. */
    rtt_vec3 tri[3];
    rtt_scene_triangle(scene, prim, tri);
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)rtt_v3_get(tri[1], a) - rtt_v3_get(tri[0], a);
        e2[a] = (double)rtt_v3_get(tri[2], a) - rtt_v3_get(tri[0], a);
    }
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0) || !isfinite(len)) return rtt_v3(0.0f, 0.0f, 0.0f);
    return rtt_v3((float)(n[0] / len), (float)(n[1] / len), (float)(n[2] / len));
}

rtt_vec3 rtt_scene_shading_normal(const rtt_scene *scene, uint32_t prim, float u, float v)
{
    if (!scene->normals) return rtt_scene_geometric_normal(scene, prim);
    const rtt_triangle *t = &scene->triangles[prim];
    rtt_vec3 n = rtt_v3_add(rtt_v3_scale(scene->normals[t->v[0]], 1.0f - u - v),
                            rtt_v3_add(rtt_v3_scale(scene->normals[t->v[1]], u), rtt_v3_scale(scene->normals[t->v[2]], v)));
    float len = rtt_v3_length(n);
    return len > 0.0f && isfinite(len) ? rtt_v3_scale(n, 1.0f / len) : rtt_scene_geometric_normal(scene, prim);
}

/* Texture coordinates of triangle prim's corners. */
static void corner_texcoords(const rtt_scene *scene, uint32_t prim, float uv[3][2])
{
    const rtt_triangle *t = &scene->triangles[prim];
    for (int k = 0; k < 3; k++) {
        uv[k][0] = scene->texcoords[2 * (size_t)t->v[k]];
        uv[k][1] = scene->texcoords[2 * (size_t)t->v[k] + 1];
    }
}

/* Normal map in tangent space: the tangent and bitangent are the
 * directions of growing u and v on the triangle (from its positions and
 * texture coordinates), made orthonormal to the interpolated normal n; the
 * map's texel (2c - 1) gives the normal in that frame.  A triangle whose
 * texture coordinates are degenerate keeps n. */
static rtt_vec3 perturb_normal(const rtt_scene *scene, uint32_t prim, const float uv[3][2], const float st[2],
                               rtt_vec3 n, const rtt_texture *map)
{
    rtt_vec3 p[3];
    rtt_scene_triangle(scene, prim, p);
    rtt_vec3 e1 = rtt_v3_sub(p[1], p[0]), e2 = rtt_v3_sub(p[2], p[0]);
    float du1 = uv[1][0] - uv[0][0], dv1 = uv[1][1] - uv[0][1];
    float du2 = uv[2][0] - uv[0][0], dv2 = uv[2][1] - uv[0][1];
    float det = du1 * dv2 - du2 * dv1;
    if (!(fabsf(det) > 1e-20f) || !isfinite(det)) return n;
    rtt_vec3 tangent = rtt_v3_scale(rtt_v3_sub(rtt_v3_scale(e1, dv2), rtt_v3_scale(e2, dv1)), 1.0f / det);
    rtt_vec3 bitangent = rtt_v3_scale(rtt_v3_sub(rtt_v3_scale(e2, du1), rtt_v3_scale(e1, du2)), 1.0f / det);
    tangent = rtt_v3_sub(tangent, rtt_v3_scale(n, rtt_v3_dot(n, tangent)));
    float length = rtt_v3_length(tangent);
    if (!(length > 0.0f) || !isfinite(length)) return n;
    tangent = rtt_v3_scale(tangent, 1.0f / length);
    rtt_vec3 b = rtt_v3_cross(n, tangent);
    if (rtt_v3_dot(b, bitangent) < 0.0f) b = rtt_v3_scale(b, -1.0f); /* mirrored texture coordinates */
    rtt_vec3 c = rtt_texture_sample(map, st[0], st[1], false);
    rtt_vec3 m = rtt_v3(2.0f * c.x - 1.0f, 2.0f * c.y - 1.0f, 2.0f * c.z - 1.0f);
    rtt_vec3 out = rtt_v3_add(rtt_v3_add(rtt_v3_scale(tangent, m.x), rtt_v3_scale(b, m.y)), rtt_v3_scale(n, m.z));
    float out_length = rtt_v3_length(out);
    return out_length > 0.0f && isfinite(out_length) ? rtt_v3_scale(out, 1.0f / out_length) : n;
}

rtt_surface rtt_surface_at(const rtt_scene *scene, const rtt_ray *ray, const rtt_hit *hit)
{
    rtt_surface s;
    rtt_vec3 org = rtt_v3(ray->org[0], ray->org[1], ray->org[2]);
    rtt_vec3 dir = rtt_v3(ray->dir[0], ray->dir[1], ray->dir[2]);
    s.point = rtt_v3_madd(org, dir, hit->t);
    s.dir = rtt_v3_normalize(dir);
    s.material = &scene->materials[scene->triangle_material[hit->prim]];
    s.normal = rtt_scene_shading_normal(scene, hit->prim, hit->u, hit->v);
    s.diffuse = s.material->diffuse;
    if ((s.material->diffuse_map || s.material->normal_map) && scene->texcoords) {
        float uv[3][2], st[2];
        corner_texcoords(scene, hit->prim, uv);
        const float w0 = 1.0f - hit->u - hit->v;
        for (int a = 0; a < 2; a++) st[a] = w0 * uv[0][a] + hit->u * uv[1][a] + hit->v * uv[2][a];
        if (s.material->diffuse_map)
            s.diffuse = rtt_texture_sample(&scene->textures[s.material->diffuse_map - 1], st[0], st[1], true);
        if (s.material->normal_map)
            s.normal = perturb_normal(scene, hit->prim, uv, st, s.normal, &scene->textures[s.material->normal_map - 1]);
    }
    if (rtt_v3_dot(s.normal, s.dir) > 0.0f) s.normal = rtt_v3_scale(s.normal, -1.0f);
    s.entering = rtt_v3_dot(rtt_scene_geometric_normal(scene, hit->prim), s.dir) < 0.0f;
    return s;
}

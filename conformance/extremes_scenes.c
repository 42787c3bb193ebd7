/* The scenes of the extremes suite, built in code, and the ray patterns
 * aimed at them: the patterns of Embree's verify tool (rays at vertices and
 * edges, from inside closed meshes) and of pbrt's tests (axis-parallel rays
 * with signed zeros, origins on surfaces).  Everything is deterministic. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "conform_random.h"
#include "extremes_internal.h"
#include "rtt/reference.h"

static rtt_ray make_ray(rtt_vec3 org, rtt_vec3 dir)
{
    return (rtt_ray){{org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, 0.0f, INFINITY};
}

/* ---- scenes ----------------------------------------------------------- */

static void put_triangle(float *out, rtt_vec3 a, rtt_vec3 b, rtt_vec3 c)
{
    const rtt_vec3 corners[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
        out[3 * k + 0] = corners[k].x;
        out[3 * k + 1] = corners[k].y;
        out[3 * k + 2] = corners[k].z;
    }
}

float *rtt_extremes_sphere(uint32_t segments, uint32_t rings, float radius, const float centre[3], uint32_t *count)
{
    *count = 0;
    if (segments < 3 || rings < 2) return NULL;
    uint32_t vertex_count = 2 + (rings - 1) * segments, triangle_count = 2 * segments * (rings - 1);
    rtt_vec3 *v = malloc(vertex_count * sizeof *v);
    float *out = malloc((size_t)triangle_count * 9 * sizeof *out);
    if (!v || !out) {
        free(v);
        free(out);
        return NULL;
    }
    /* Positions are computed once, so shared corners are bit-identical. */
    v[0] = rtt_v3(centre[0], centre[1], (float)((double)centre[2] + radius));
    v[1] = rtt_v3(centre[0], centre[1], (float)((double)centre[2] - radius));
    for (uint32_t i = 1; i < rings; i++) {
        double theta = M_PI * i / rings;
        for (uint32_t j = 0; j < segments; j++) {
            double phi = 2.0 * M_PI * j / segments;
            v[2 + (i - 1) * segments + j] = rtt_v3((float)(centre[0] + radius * sin(theta) * cos(phi)),
                                                   (float)(centre[1] + radius * sin(theta) * sin(phi)),
                                                   (float)(centre[2] + radius * cos(theta)));
        }
    }
#define RING(i, j) v[2 + ((i) - 1) * segments + ((j) % segments)]
    uint32_t t = 0;
    for (uint32_t j = 0; j < segments; j++) {
        put_triangle(&out[9 * t++], v[0], RING(1, j), RING(1, j + 1));
        put_triangle(&out[9 * t++], v[1], RING(rings - 1, j + 1), RING(rings - 1, j));
    }
    for (uint32_t i = 1; i + 1 < rings; i++)
        for (uint32_t j = 0; j < segments; j++) {
            put_triangle(&out[9 * t++], RING(i, j), RING(i + 1, j), RING(i + 1, j + 1));
            put_triangle(&out[9 * t++], RING(i, j), RING(i + 1, j + 1), RING(i, j + 1));
        }
#undef RING
    free(v);
    *count = t;
    return out;
}

/* Appends `extra` triangles' worth of room to a soup. */
static float *soup_grow(float *soup, uint32_t count, uint32_t extra)
{
    float *grown = realloc(soup, (size_t)(count + extra) * 9 * sizeof *grown);
    if (!grown) free(soup);
    return grown;
}

#define BASE_SOUP_RANDOM 200u
#define BASE_FLOOR_CELLS 8u

float *rtt_ext_base_soup(uint32_t *count)
{
    const float centre[3] = {0.25f, -0.125f, 0.5f};
    uint32_t n = 0;
    float *soup = rtt_extremes_sphere(24, 12, 1.0f, centre, &n);
    uint32_t extra = BASE_SOUP_RANDOM + 2 * BASE_FLOOR_CELLS * BASE_FLOOR_CELLS;
    if (!soup || !(soup = soup_grow(soup, n, extra))) return NULL;
    uint64_t state = 0xBA5E5EEDull;
    for (uint32_t i = 0; i < BASE_SOUP_RANDOM; i++) { /* small random triangles in [-2, 2]^3 */
        rtt_vec3 p = rtt_v3(4.0f * next_unit(&state) - 2.0f, 4.0f * next_unit(&state) - 2.0f,
                            4.0f * next_unit(&state) - 2.0f);
        rtt_vec3 a = rtt_v3_madd(p, random_direction(&state), 0.3f);
        rtt_vec3 b = rtt_v3_madd(p, random_direction(&state), 0.3f);
        put_triangle(&soup[9 * n++], p, a, b);
    }
    /* the floor z = -1.5: cells of 0.5, corners exactly representable */
    for (uint32_t i = 0; i < BASE_FLOOR_CELLS; i++)
        for (uint32_t j = 0; j < BASE_FLOOR_CELLS; j++) {
            float x0 = -2.0f + 0.5f * (float)i, y0 = -2.0f + 0.5f * (float)j, z = -1.5f;
            rtt_vec3 a = rtt_v3(x0, y0, z), b = rtt_v3(x0 + 0.5f, y0, z), c = rtt_v3(x0 + 0.5f, y0 + 0.5f, z),
                     d = rtt_v3(x0, y0 + 0.5f, z);
            put_triangle(&soup[9 * n++], a, b, c);
            put_triangle(&soup[9 * n++], a, c, d);
        }
    *count = n;
    return soup;
}

float *rtt_ext_degenerate_soup(uint32_t *count, uint32_t degenerate[], uint32_t degenerate_cap,
                               uint32_t *degenerate_count)
{
    const float centre[3] = {0.0f, 0.0f, 0.0f};
    uint32_t n = 0, d = 0;
    float *soup = rtt_extremes_sphere(12, 6, 0.5f, centre, &n);
    if (!soup || !(soup = soup_grow(soup, n, 64))) return NULL;
#define DEGENERATE(a, b, c)                                   \
    do {                                                      \
        if (d < degenerate_cap) degenerate[d++] = n;          \
        put_triangle(&soup[9 * n++], (a), (b), (c));          \
    } while (0)
    rtt_vec3 p = rtt_v3(1.0f, 0.5f, 0.25f), q = rtt_v3(1.75f, 0.5f, 0.25f);
    DEGENERATE(p, p, p);                                                  /* a point */
    DEGENERATE(p, q, p);                                                  /* two equal corners */
    DEGENERATE(rtt_v3(-1, 0.75f, 0), rtt_v3(1, 0.75f, 0), rtt_v3(0.25f, 0.75f, 0)); /* collinear on an axis */
    DEGENERATE(rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1), rtt_v3(0.5f, 0.5f, 0.5f)); /* collinear on the diagonal */
    DEGENERATE(rtt_v3(0, 0, 0.5f), rtt_v3(0, 0, 0.5f), rtt_v3(0, 0, -0.5f)); /* through the sphere's poles */
#undef DEGENERATE
    /* needles: length 2, width 1e-6 and 1e-12, across the sphere and the scene */
    put_triangle(&soup[9 * n++], rtt_v3(-1, -0.25f, 0.1f), rtt_v3(1, -0.25f, 0.1f), rtt_v3(0, -0.25f + 1e-6f, 0.1f));
    put_triangle(&soup[9 * n++], rtt_v3(-1, 0.3f, -0.7f), rtt_v3(1, 0.3f, 0.7f), rtt_v3(0, 0.3f + 1e-12f, 0.0f));
    put_triangle(&soup[9 * n++], rtt_v3(0.6f, -1, -1), rtt_v3(0.6f, 1, 1), rtt_v3(0.6f + 1e-7f, 0, 0));
    /* coplanar overlapping in z = 0.75: a triangle, its copy with corners
     * rotated, its mirror (reversed winding), and one half overlapping it */
    rtt_vec3 a = rtt_v3(-1, -1, 0.75f), b = rtt_v3(1, -1, 0.75f), c = rtt_v3(0, 1, 0.75f);
    put_triangle(&soup[9 * n++], a, b, c);
    put_triangle(&soup[9 * n++], b, c, a);
    put_triangle(&soup[9 * n++], a, c, b);
    put_triangle(&soup[9 * n++], rtt_v3(0, -1.5f, 0.75f), rtt_v3(1.5f, 0.5f, 0.75f), rtt_v3(-0.5f, 0.5f, 0.75f));
    /* coplanar overlapping on a tilted plane through the sphere */
    rtt_vec3 e = rtt_v3(-0.75f, -0.75f, -0.5f), f = rtt_v3(0.75f, -0.25f, 0.0f), g = rtt_v3(-0.25f, 0.75f, 0.5f);
    put_triangle(&soup[9 * n++], e, f, g);
    put_triangle(&soup[9 * n++], g, e, f);
    /* a T-junction: two triangles meeting the middle of a third's edge */
    rtt_vec3 t0 = rtt_v3(-1, 1.25f, -0.25f), t1 = rtt_v3(1, 1.25f, -0.25f), t2 = rtt_v3(0, 1.25f, -1.25f),
             tm = rtt_v3(0, 1.25f, -0.25f), t3 = rtt_v3(0, 1.25f, 0.75f);
    put_triangle(&soup[9 * n++], t0, t1, t2);
    put_triangle(&soup[9 * n++], t0, tm, t3);
    put_triangle(&soup[9 * n++], tm, t1, t3);
    *count = n;
    *degenerate_count = d;
    return soup;
}

float *rtt_ext_deep_soup(uint32_t count)
{
    float *soup = malloc((size_t)(count ? count : 1) * 9 * sizeof *soup);
    if (!soup) return NULL;
    double size = 1.0;
    for (uint32_t i = 0; i < count; i++, size *= 0.75) {
        float p = (float)size, s = (float)(0.5 * size), h = (float)(0.25 * size);
        put_triangle(&soup[9 * i], rtt_v3(p, p, p), rtt_v3(p + s, p, p + h), rtt_v3(p, p + s, p - h));
    }
    return soup;
}

void rtt_ext_transform(float *xyz9, uint32_t count, double scale, const double offset[3])
{
    for (size_t i = 0; i < (size_t)count * 9; i++) xyz9[i] = (float)((double)xyz9[i] * scale + offset[i % 3]);
}

/* ---- ray patterns ----------------------------------------------------- */

/* The bounds grown by a quarter of their extent on each side. */
static rtt_bounds around_bounds(const rtt_scene *s)
{
    rtt_bounds b = s->bounds;
    rtt_vec3 grow = rtt_v3_scale(rtt_v3_sub(b.hi, b.lo), 0.25f);
    return (rtt_bounds){rtt_v3_sub(b.lo, grow), rtt_v3_add(b.hi, grow)};
}

static rtt_vec3 random_point(uint64_t *state, rtt_bounds b)
{
    rtt_vec3 e = rtt_v3_sub(b.hi, b.lo);
    return rtt_v3(b.lo.x + e.x * next_unit(state), b.lo.y + e.y * next_unit(state), b.lo.z + e.z * next_unit(state));
}

/* Corner k (0..2) or the midpoint of edge k (3..5) of a random triangle. */
static rtt_vec3 random_target(const rtt_scene *s, uint64_t *state)
{
    rtt_vec3 t[3];
    rtt_scene_triangle(s, next_below(state, s->triangle_count), t);
    uint32_t k = next_below(state, 6);
    return k < 3 ? t[k] : rtt_v3_scale(rtt_v3_add(t[k - 3], t[(k - 2) % 3]), 0.5f);
}

static rtt_vec3 signed_zeros(uint32_t pattern) /* the four combinations for two axes, on all three */
{
    return rtt_v3(pattern & 1 ? -0.0f : 0.0f, pattern & 2 ? -0.0f : 0.0f, pattern & 4 ? -0.0f : 0.0f);
}

size_t rtt_ext_rays_axis_parallel(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out)
{
    if (!s->triangle_count) return 0;
    uint64_t state = seed;
    rtt_bounds around = around_bounds(s);
    size_t n;
    for (n = 0; n < max; n++) {
        rtt_vec3 target = random_target(s, &state), org = target, dir = signed_zeros((uint32_t)(n / 6));
        int axis = (int)(n % 3);
        bool up = (n / 3) % 2 == 0;
        rtt_v3_set(&org, axis, up ? rtt_v3_get(around.lo, axis) : rtt_v3_get(around.hi, axis));
        rtt_v3_set(&dir, axis, up ? 1.0f : -1.0f);
        out[n] = make_ray(org, dir);
    }
    return n;
}

size_t rtt_ext_rays_split_planes(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out)
{
    if (!s->triangle_count) return 0;
    uint64_t state = seed;
    size_t n;
    for (n = 0; n < max; n++) {
        rtt_vec3 org = rtt_v3(0.0f, 0.0f, 0.0f); /* set per axis below; GCC -O2 + TSan cannot see it */
        for (int a = 0; a < 3; a++) {
            rtt_vec3 t[3];
            rtt_scene_triangle(s, next_below(&state, s->triangle_count), t);
            rtt_v3_set(&org, a, rtt_v3_get(t[next_below(&state, 3)], a));
        }
        rtt_vec3 dir = random_direction(&state);
        if (n % 2) { /* axis-parallel, running inside the planes of the other two axes */
            dir = signed_zeros(next_below(&state, 8));
            rtt_v3_set(&dir, (int)next_below(&state, 3), next_below(&state, 2) ? 1.0f : -1.0f);
        }
        out[n] = make_ray(org, dir);
    }
    return n;
}

size_t rtt_ext_rays_on_surface(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out)
{
    if (!s->triangle_count) return 0;
    uint64_t state = seed;
    size_t n;
    for (n = 0; n < max; n++) {
        rtt_vec3 t[3], org;
        rtt_scene_triangle(s, next_below(&state, s->triangle_count), t);
        if (n % 4 == 3) {
            org = t[next_below(&state, 3)];
        } else {
            float a = next_unit(&state), b = next_unit(&state);
            if (a + b > 1.0f) {
                a = 1.0f - a;
                b = 1.0f - b;
            }
            org = rtt_v3_add(t[0], rtt_v3_add(rtt_v3_scale(rtt_v3_sub(t[1], t[0]), a),
                                              rtt_v3_scale(rtt_v3_sub(t[2], t[0]), b)));
        }
        out[n] = make_ray(org, random_direction(&state));
    }
    return n;
}

size_t rtt_ext_rays_vertex_aimed(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out)
{
    if (!s->triangle_count) return 0;
    uint64_t state = seed;
    rtt_bounds around = around_bounds(s);
    size_t n;
    for (n = 0; n < max; n++) {
        rtt_vec3 org = random_point(&state, around);
        out[n] = make_ray(org, rtt_v3_sub(random_target(s, &state), org)); /* t = 1 at the target */
    }
    return n;
}

size_t rtt_ext_rays_near_triangles(const rtt_scene *s, uint64_t seed, size_t max, rtt_ray *out)
{
    if (!s->triangle_count) return 0;
    uint64_t state = seed;
    size_t n;
    for (n = 0; n < max; n++) {
        rtt_vec3 t[3];
        rtt_scene_triangle(s, next_below(&state, s->triangle_count), t);
        float a = 0.05f + 0.45f * next_unit(&state), b = 0.05f + 0.45f * next_unit(&state);
        rtt_vec3 target = rtt_v3_add(t[0], rtt_v3_add(rtt_v3_scale(rtt_v3_sub(t[1], t[0]), a),
                                                      rtt_v3_scale(rtt_v3_sub(t[2], t[0]), b)));
        float size = rtt_v3_length(rtt_v3_sub(t[1], t[0])) + rtt_v3_length(rtt_v3_sub(t[2], t[0]));
        rtt_vec3 org = rtt_v3_madd(target, random_direction(&state), 2.0f * size);
        out[n] = make_ray(org, rtt_v3_sub(target, org));
    }
    return n;
}

size_t rtt_ext_invalid_pattern_count(void) { return 16; }

size_t rtt_ext_rays_invalid(rtt_vec3 c, size_t max, rtt_ray *out)
{
    const float nan = NAN, inf = INFINITY;
    const rtt_ray list[16] = {
        {{nan, c.y, c.z}, {0, 0, 1}, 0, inf},
        {{c.x, c.y, c.z}, {nan, nan, nan}, 0, inf},
        {{c.x, c.y, c.z}, {0, nan, 1}, 0, inf},
        {{c.x, c.y, c.z}, {0, 0, 0}, 0, inf},
        {{c.x, c.y, c.z}, {-0.0f, -0.0f, -0.0f}, 0, inf},
        {{inf, c.y, c.z}, {-1, 0, 0}, 0, inf},
        {{-inf, -inf, -inf}, {1, 1, 1}, 0, inf},
        {{c.x, c.y, c.z}, {inf, 0, 0}, 0, inf},
        {{c.x, c.y, c.z}, {inf, -inf, inf}, 0, inf},
        {{c.x, c.y, c.z}, {1, 0, 0}, nan, inf},
        {{c.x, c.y, c.z}, {1, 0, 0}, 0, nan},
        {{c.x, c.y, c.z}, {0, 1, 0}, 5, 1},
        {{c.x, c.y, c.z}, {0, 0, 1}, inf, inf},
        {{c.x, c.y, c.z}, {0, 0, -1}, -inf, -inf},
        {{c.x, c.y, c.z}, {0, -1, 0}, 0, 0},
        {{nan, nan, nan}, {nan, nan, nan}, nan, nan},
    };
    for (size_t i = 0; i < max; i++) out[i] = list[i % 16];
    return max;
}

/* ---- closed meshes ---------------------------------------------------- */

typedef struct edge_key {
    uint32_t a, b;
} edge_key;

static int edge_order(const void *x, const void *y)
{
    const edge_key *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

bool rtt_ext_mesh_closed(const rtt_scene *s)
{
    if (!s->triangle_count) return false;
    size_t n = (size_t)s->triangle_count * 3;
    edge_key *edges = malloc(n * sizeof *edges);
    if (!edges) return false;
    for (uint32_t i = 0; i < s->triangle_count; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = s->triangles[i].v[k], b = s->triangles[i].v[(k + 1) % 3];
            edges[3 * i + k] = a < b ? (edge_key){a, b} : (edge_key){b, a};
        }
    qsort(edges, n, sizeof *edges, edge_order);
    bool closed = true;
    for (size_t i = 0; i < n && closed;) {
        size_t j = i;
        while (j < n && edges[j].a == edges[i].a && edges[j].b == edges[i].b) j++;
        closed = j - i == 2 && edges[i].a != edges[i].b;
        i = j;
    }
    free(edges);
    return closed;
}

/* Crossings of the ray with every triangle (brute force). */
static uint32_t crossings(const rtt_scene *s, const rtt_ray *r)
{
    uint32_t hits = 0;
    for (uint32_t i = 0; i < s->triangle_count; i++) {
        rtt_vec3 t[3];
        float th, u, v;
        rtt_scene_triangle(s, i, t);
        hits += rtt_reference_intersect_triangle(r, t, &th, &u, &v);
    }
    return hits;
}

bool rtt_ext_inside_point(const rtt_scene *s, int skip, float inside[3])
{
    /* Directions no mesh is likely to have edges along. */
    const rtt_vec3 dirs[3] = {{0.5773f, 0.5812f, 0.5735f}, {-0.2341f, 0.9123f, -0.3361f}, {0.7071f, -0.1234f, -0.6963f}};
    rtt_vec3 lo = s->bounds.lo, e = rtt_v3_sub(s->bounds.hi, s->bounds.lo);
    for (int g = 0; g < 1 + 5 * 5 * 5; g++) {
        rtt_vec3 p = rtt_v3_madd(lo, e, 0.5f);
        if (g > 0) {
            int i = (g - 1) % 5, j = (g - 1) / 5 % 5, k = (g - 1) / 25;
            p = rtt_v3_add(lo, rtt_v3_mul(e, rtt_v3(0.1f + 0.2f * i, 0.1f + 0.2f * j, 0.1f + 0.2f * k)));
        }
        bool in = true;
        for (int d = 0; d < 3 && in; d++) {
            rtt_ray r = make_ray(p, dirs[d]);
            in = crossings(s, &r) % 2 == 1;
        }
        if (in && skip-- == 0) {
            inside[0] = p.x;
            inside[1] = p.y;
            inside[2] = p.z;
            return true;
        }
    }
    return false;
}

rtt_ray *rtt_extremes_watertight_rays(const rtt_scene *s, const float inside[3], size_t max, size_t *count)
{
    *count = 0;
    size_t candidates = (size_t)s->vertex_count + 3 * (size_t)s->triangle_count;
    size_t n = candidates < max ? candidates : max;
    rtt_ray *rays = malloc((n ? n : 1) * sizeof *rays);
    if (!rays) return NULL;
    rtt_vec3 org = rtt_v3(inside[0], inside[1], inside[2]);
    for (size_t i = 0; i < n; i++) {
        size_t c = n == candidates ? i : (size_t)((double)i * (double)candidates / (double)n);
        rtt_vec3 target;
        if (c < s->vertex_count) {
            target = s->vertices[c];
        } else {
            size_t e = c - s->vertex_count;
            rtt_vec3 t[3];
            rtt_scene_triangle(s, (uint32_t)(e / 3), t);
            target = rtt_v3_scale(rtt_v3_add(t[e % 3], t[(e + 1) % 3]), 0.5f);
        }
        rays[i] = make_ray(org, rtt_v3_sub(target, org));
    }
    *count = n;
    return rays;
}

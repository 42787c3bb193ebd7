/* The light grids' per-frame build (pgrid_light.h): corners once, then per
 * light every triangle's footprint on the six faces in double, counted and
 * placed by a counting sort (each cell's list in global triangle order). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "pgrid_light.h"

#define FOOTPRINT_NONE UINT16_MAX
#define NEAR_FACTOR 256.0
#define MU_MAX 1e-2

/* A triangle's cell rectangle on one face (inclusive; x0 = NONE: none). */
typedef struct footprint {
    uint16_t x0, y0, x1, y1;
} footprint;

/* Keeps the part of polygon p (n corners) with dot(plane, q) >= 0. */
static int clip_plane(const double (*p)[3], int n, const double plane[3], double (*out)[3])
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double *a = p[i], *b = p[(i + 1) % n];
        const double da = plane[0] * a[0] + plane[1] * a[1] + plane[2] * a[2];
        const double db = plane[0] * b[0] + plane[1] * b[1] + plane[2] * b[2];
        if (da >= 0.0) memcpy(out[m++], a, sizeof out[0]);
        if ((da >= 0.0) != (db >= 0.0)) {
            const double s = da / (da - db);
            for (int k = 0; k < 3; k++) out[m][k] = a[k] + s * (b[k] - a[k]);
            m++;
        }
    }
    return m;
}

/* The footprint of corners c (relative to the light) on `face`, its
 * pyramid and rectangle widened by mu. */
static footprint face_footprint(const double c[3][3], uint32_t face, double mu, uint32_t res)
{
    const uint32_t axis = face / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double sign = face % 2 ? -1.0 : 1.0, wide = 1.0 + mu;
    double poly[2][16][3];
    int n = 3;
    memcpy(poly[0], c, 3 * sizeof poly[0][0]);
    for (int k = 0; k < 4 && n > 0; k++) {
        double plane[3] = {0.0, 0.0, 0.0};
        plane[axis] = sign * wide;
        plane[k < 2 ? u : v] = k % 2 ? 1.0 : -1.0;
        n = clip_plane((const double(*)[3])poly[k % 2], n, plane, poly[(k + 1) % 2]);
    }
    footprint f = {FOOTPRINT_NONE, 0, 0, 0};
    if (n == 0) return f;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++) {
        const double *q = poly[0][i], major = sign * q[axis];
        if (!(major > 0.0)) return f; /* only at the apex: such triangles are near ones */
        const double s = q[u] / major, t = q[v] / major;
        lo[0] = fmin(lo[0], s), hi[0] = fmax(hi[0], s);
        lo[1] = fmin(lo[1], t), hi[1] = fmax(hi[1], t);
    }
    int32_t cell[4];
    for (int k = 0; k < 2; k++) {
        const double a = ((lo[k] - mu) + 1.0) * 0.5 * res, b = ((hi[k] + mu) + 1.0) * 0.5 * res;
        cell[k] = a < 0.0 ? 0 : a >= res ? (int32_t)res - 1 : (int32_t)a;
        cell[2 + k] = b < 0.0 ? 0 : b >= res ? (int32_t)res - 1 : (int32_t)b;
    }
    f = (footprint){(uint16_t)cell[0], (uint16_t)cell[1], (uint16_t)cell[2], (uint16_t)cell[3]};
    return f;
}

/* A lower bound of the distance from the origin to the triangle c: the
 * larger of the distances to its box and to its plane. */
static double distance_bound(const double c[3][3])
{
    double box = 0.0;
    for (int k = 0; k < 3; k++) {
        const double lo = fmin(c[0][k], fmin(c[1][k], c[2][k])), hi = fmax(c[0][k], fmax(c[1][k], c[2][k]));
        const double gap = lo > 0.0 ? lo : hi < 0.0 ? -hi : 0.0;
        box += gap * gap;
    }
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = c[1][k] - c[0][k], e2[k] = c[2][k] - c[0][k];
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double plane = len > 0.0 ? fabs(n[0] * c[0][0] + n[1] * c[0][1] + n[2] * c[0][2]) / len : 0.0;
    const double b = sqrt(box);
    return b > plane ? b : plane;
}

/* E: the largest coordinate magnitude of the scene's bounds and the light, times 2^-14. */
static double error_bound(const rtt_scene *scene, const float position[3])
{
    double m = 0.0;
    const float *lo = &scene->bounds.lo.x, *hi = &scene->bounds.hi.x;
    for (int k = 0; k < 3; k++) {
        m = fmax(m, fabs((double)position[k]));
        if (!rtt_bounds_is_empty(scene->bounds)) m = fmax(m, fmax(fabs((double)lo[k]), fabs((double)hi[k])));
    }
    return ldexp(m > 0.0 ? m : 1.0, -14);
}

void pgrid_light_free(pgrid_light *light)
{
    free(light->cell_first);
    free(light->cell_min);
    free(light->refs);
    free(light->near);
    memset(light, 0, sizeof *light);
}

bool pgrid_light_build(pgrid_light *light, const pgrid_shadows *grids, const rtt_scene *scene,
                       const float position[3], uint32_t res)
{
    memset(light, 0, sizeof *light);
    if (res == 0) res = PGRID_LIGHT_RES_DEFAULT;
    if (res > PGRID_LIGHT_RES_MAX) res = PGRID_LIGHT_RES_MAX;
    memcpy(light->position, position, sizeof light->position);
    light->res = res;
    const double E = error_bound(scene, position);
    light->reach = (float)(4.0 * E);
    const size_t cells = (size_t)PGRID_LIGHT_FACES * res * res, n = grids->corner_count;
    light->cell_first = calloc(cells + 1, sizeof *light->cell_first);
    light->cell_min = malloc(cells * sizeof *light->cell_min);
    light->near = malloc((n + 1) * sizeof *light->near);
    footprint *prints = malloc((n * PGRID_LIGHT_FACES + 1) * sizeof *prints);
    float *bound = malloc((n + 1) * sizeof *bound);
    bool ok = light->cell_first && light->cell_min && light->near && prints && bound;
    for (size_t c = 0; ok && c < cells; c++) light->cell_min[c] = INFINITY;
    for (uint32_t i = 0; ok && i < n; i++) {
        const kd_corners *k = &grids->corners[i];
        double c[3][3];
        for (int a = 0; a < 3; a++)
            c[0][a] = (double)k->a[a] - position[a], c[1][a] = (double)k->b[a] - position[a],
            c[2][a] = (double)k->c[a] - position[a];
        const double d = distance_bound(c);
        bound[i] = (float)(d * (1.0 - 1e-6));
        const double mu = 1e-5 + 4.0 * (2.0 * E / (d - 2.0 * E));
        footprint *f = &prints[(size_t)i * PGRID_LIGHT_FACES];
        if (!(d > NEAR_FACTOR * E) || !(mu <= MU_MAX)) {
            light->near[light->near_count++] = i;
            for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) f[face].x0 = FOOTPRINT_NONE;
            continue;
        }
        for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
            f[face] = face_footprint((const double(*)[3])c, face, mu, res);
            if (f[face].x0 == FOOTPRINT_NONE) continue;
            for (uint32_t y = f[face].y0; y <= f[face].y1; y++)
                for (uint32_t x = f[face].x0; x <= f[face].x1; x++) {
                    const size_t cell = ((size_t)face * res + y) * res + x;
                    light->cell_first[cell + 1]++;
                    if (bound[i] < light->cell_min[cell]) light->cell_min[cell] = bound[i];
                }
        }
    }
    if (ok) {
        for (size_t c = 0; c < cells; c++) light->cell_first[c + 1] += light->cell_first[c];
        light->ref_count = light->cell_first[cells];
        light->refs = malloc((light->ref_count + 1) * sizeof *light->refs);
        ok = light->refs != NULL;
    }
    if (ok) {
        uint32_t *fill = malloc((cells + 1) * sizeof *fill);
        ok = fill != NULL;
        if (ok) memcpy(fill, light->cell_first, cells * sizeof *fill);
        for (uint32_t i = 0; ok && i < n; i++)
            for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
                const footprint *f = &prints[(size_t)i * PGRID_LIGHT_FACES + face];
                if (f->x0 == FOOTPRINT_NONE) continue;
                for (uint32_t y = f->y0; y <= f->y1; y++)
                    for (uint32_t x = f->x0; x <= f->x1; x++) light->refs[fill[((size_t)face * res + y) * res + x]++] = i;
            }
        free(fill);
    }
    free(prints);
    free(bound);
    if (!ok) pgrid_light_free(light);
    return ok;
}

void pgrid_shadows_free(pgrid_shadows *grids)
{
    for (uint32_t l = 0; grids->lights && l < grids->light_count; l++) pgrid_light_free(&grids->lights[l]);
    free(grids->lights);
    free(grids->corners);
    memset(grids, 0, sizeof *grids);
}

bool pgrid_shadows_build(pgrid_shadows *grids, const rtt_scene *scene, const uint8_t *degenerate, uint32_t res,
                         rtt_error *err)
{
    const uint64_t t0 = rtt_clock_ns();
    memset(grids, 0, sizeof *grids);
    grids->corners = aligned_alloc(64, ((size_t)scene->triangle_count + 1) * sizeof *grids->corners + 64);
    grids->lights = calloc(scene->light_count + 1, sizeof *grids->lights);
    bool ok = grids->corners && grids->lights;
    for (uint32_t i = 0; ok && i < scene->triangle_count; i++) {
        if (degenerate && degenerate[i]) continue;
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, i, tri);
        kd_corners *k = &grids->corners[grids->corner_count++];
        memset(k, 0, sizeof *k);
        k->a[0] = tri[0].x, k->a[1] = tri[0].y, k->a[2] = tri[0].z;
        k->b[0] = tri[1].x, k->b[1] = tri[1].y, k->b[2] = tri[1].z;
        k->c[0] = tri[2].x, k->c[1] = tri[2].y, k->c[2] = tri[2].z;
        k->prim = i;
    }
    for (uint32_t l = 0; ok && l < scene->light_count; l++) {
        const rtt_vec3 p = scene->lights[l].position;
        const float position[3] = {p.x, p.y, p.z};
        ok = pgrid_light_build(&grids->lights[l], grids, scene, position, res);
        if (ok) grids->light_count = l + 1;
    }
    grids->build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    if (!ok) pgrid_shadows_free(grids);
    return ok || rtt_error_set(err, "%s: out of memory building the light grids", scene->path);
}

/* The soft-shadow light grids' per-frame build (pgrid_soft.h): the scene's
 * triangles' corners, then per light the slice bounds, the near list and a
 * counting sort of every triangle's cells (each cell's list in triangle
 * order).  Baseline code, in double where it bounds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "pgrid_soft.h"

/* A polygon clipped against faces' planes: at most 3 + 5 corners. */
enum { POLY_MAX = 12 };

typedef struct poly {
    double q[POLY_MAX][3];
    int n;
} poly;

/* Keeps the part of `p` where n . q + offset >= 0 (Sutherland-Hodgman). */
static void clip_plane(poly *p, const double n[3], double offset)
{
    poly out = {.n = 0};
    for (int i = 0; i < p->n; i++) {
        const double *a = p->q[i], *b = p->q[(i + 1) % p->n];
        const double da = n[0] * a[0] + n[1] * a[1] + n[2] * a[2] + offset;
        const double db = n[0] * b[0] + n[1] * b[1] + n[2] * b[2] + offset;
        if (da >= 0.0 && out.n < POLY_MAX) memcpy(out.q[out.n++], a, sizeof out.q[0]);
        if ((da >= 0.0) != (db >= 0.0) && out.n < POLY_MAX) {
            const double s = da / (da - db);
            for (int k = 0; k < 3; k++) out.q[out.n][k] = a[k] + s * (b[k] - a[k]);
            out.n++;
        }
    }
    *p = out;
}

/* The cell range [lo, hi] of face coordinates [u0, u1] on res cells. */
static void cell_range(double u0, double u1, uint32_t res, uint32_t *lo, uint32_t *hi)
{
    const double half = 0.5 * (double)res;
    double a = floor((u0 + 1.0) * half), b = floor((u1 + 1.0) * half);
    if (a < 0.0) a = 0.0;
    if (b > (double)res - 1.0) b = (double)res - 1.0;
    *lo = (uint32_t)a, *hi = (uint32_t)(b < a ? a : b);
}

/* Triangle t's cell rectangle on face f ([x0, x1] x [y0, y1]); false when
 * its clipped footprint there is empty. */
static bool face_rect(const pgrid_soft_light *L, const double c[3][3], uint32_t f, uint32_t r[4])
{
    const uint32_t axis = f / 2, b = (axis + 1) % 3, cc = (axis + 2) % 3;
    const double s = (f & 1u) ? -1.0 : 1.0, w = 1.0 + 4.0 * L->slack / L->near;
    const double mu = 4.0 * L->slack / L->near + 1e-6;
    poly p = {.n = 3};
    memcpy(p.q, c, 3 * sizeof p.q[0]);
    double n[3] = {0, 0, 0};
    n[axis] = s;
    clip_plane(&p, n, -0.5 * L->near);
    for (int side = 0; side < 4 && p.n; side++) {
        double m[3] = {0, 0, 0};
        m[axis] = w * s;
        m[side < 2 ? b : cc] = (side & 1) ? 1.0 : -1.0;
        clip_plane(&p, m, 0.0);
    }
    if (p.n == 0) return false;
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (int i = 0; i < p.n; i++) {
        const double major = s * p.q[i][axis], u = p.q[i][b] / major, v = p.q[i][cc] / major;
        u0 = fmin(u0, u), u1 = fmax(u1, u), v0 = fmin(v0, v), v1 = fmax(v1, v);
    }
    cell_range(u0 - mu, u1 + mu, L->res, &r[0], &r[1]);
    cell_range(v0 - mu, v1 + mu, L->res, &r[2], &r[3]);
    return true;
}

/* Triangle `t` relative to the light, its slices [k0, k1] and whether it
 * goes to the near list. */
static bool triangle_place(const pgrid_soft_light *L, const pgrid_soft_tri *tri, double c[3][3], uint32_t *k0,
                           uint32_t *k1, double *least)
{
    double lo[3], hi[3], far = 0.0;
    for (int k = 0; k < 3; k++) {
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) {
            c[k][a] = (double)tri->v[k][a] - L->position[a];
            d2 += c[k][a] * c[k][a];
            lo[a] = k ? fmin(lo[a], c[k][a]) : c[k][a], hi[a] = k ? fmax(hi[a], c[k][a]) : c[k][a];
        }
        far = fmax(far, sqrt(d2));
    }
    double gap_max = 0.0, gap2 = 0.0;
    for (int a = 0; a < 3; a++) {
        const double g = lo[a] > 0.0 ? lo[a] : hi[a] < 0.0 ? -hi[a] : 0.0;
        gap_max = fmax(gap_max, g), gap2 += g * g;
    }
    const double dlo = sqrt(gap2) - 2.0 * L->slack, dhi = far + 2.0 * L->slack;
    *least = dlo;
    uint32_t a = 0, b = L->slices - 1;
    while (a + 1 < L->slices && L->bound[a + 1] <= dlo) a++;
    while (b > a && L->bound[b] > dhi) b--;
    *k0 = a, *k1 = b;
    return gap_max < L->near + 2.0 * L->slack;
}

bool pgrid_soft_light_build(pgrid_soft_light *L, const pgrid_soft *g, const float position[3], float extent,
                            uint32_t res, uint32_t slices)
{
    memset(L, 0, sizeof *L);
    res = res ? res : PGRID_SOFT_RES_DEFAULT;
    slices = slices ? slices : PGRID_SOFT_SLICES_DEFAULT;
    if (res > PGRID_LIGHT_RES_MAX || slices > PGRID_SOFT_SLICES_MAX) return false;
    L->res = res, L->slices = slices;
    /* E from the largest coordinate of the triangles and the light; the scene's farthest corner */
    double m = 0.0, far = 0.0, gap = INFINITY;
    for (int a = 0; a < 3; a++) L->position[a] = position[a], m = fmax(m, fabs((double)position[a]));
    for (uint32_t t = 0; t < g->tri_count; t++) {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, tri_gap = 0.0;
        for (int k = 0; k < 3; k++) {
            double d2 = 0.0;
            for (int a = 0; a < 3; a++) {
                const double x = g->tris[t].v[k][a], q = x - L->position[a];
                m = fmax(m, fabs(x));
                d2 += q * q;
                lo[a] = fmin(lo[a], q), hi[a] = fmax(hi[a], q);
            }
            far = fmax(far, d2);
        }
        for (int a = 0; a < 3; a++) tri_gap = fmax(tri_gap, lo[a] > 0.0 ? lo[a] : hi[a] < 0.0 ? -hi[a] : 0.0);
        gap = fmin(gap, tri_gap);
    }
    far = sqrt(far);
    L->far = far;
    L->magnitude = m;
    L->slack = ldexp(m > 0.0 ? m : 1.0, -14);
    /* the near region: at least twice the light's reach, and up to half the
     * max-norm gap to the nearest triangle (empty of triangles, and the
     * soft rays' pieces, which fan out within a few radii of L, stay
     * narrow) */
    L->near = fmax(fmax(2.0 * (double)(isfinite(extent) ? extent : 0.0f), 256.0 * L->slack),
                   isfinite(gap) ? 0.5 * gap : 0.0);
    /* slices: geometric from near to the farthest corner, the first from 0, the last to infinity */
    if (!(far > 2.0 * L->near)) far = 2.0 * L->near;
    L->bound[0] = 0.0, L->bound[slices] = INFINITY;
    for (uint32_t k = 1; k < slices; k++) L->bound[k] = L->near * pow(far / L->near, (double)k / (double)slices);
    const size_t cells = (size_t)slices * PGRID_LIGHT_FACES * res * res;
    L->cell_first = calloc(cells + 1, sizeof *L->cell_first);
    L->near_list = malloc(((size_t)g->tri_count + 1) * sizeof *L->near_list);
    L->least = malloc(((size_t)g->tri_count + 1) * sizeof *L->least);
    if (!L->cell_first || !L->near_list || !L->least) return false;
    /* two passes: count each cell's references, then place them */
    for (int pass = 0; pass < 2; pass++) {
        for (uint32_t t = 0; t < g->tri_count; t++) {
            double c[3][3];
            uint32_t k0, k1;
            if (triangle_place(L, &g->tris[t], c, &k0, &k1, &L->least[t])) {
                if (pass == 0) L->near_list[L->near_count++] = t;
                continue;
            }
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) {
                uint32_t r[4];
                if (!face_rect(L, c, f, r)) continue;
                for (uint32_t k = k0; k <= k1; k++)
                    for (uint32_t y = r[2]; y <= r[3]; y++)
                        for (uint32_t x = r[0]; x <= r[1]; x++) {
                            const size_t cell = (((size_t)k * PGRID_LIGHT_FACES + f) * res + y) * res + x;
                            if (pass == 0)
                                L->cell_first[cell + 1]++;
                            else
                                L->refs[L->cell_first[cell]++] = t;
                        }
            }
        }
        if (pass == 0) {
            for (size_t c = 0; c < cells; c++) L->cell_first[c + 1] += L->cell_first[c];
            L->ref_count = L->cell_first[cells];
            L->refs = malloc((L->ref_count + 1) * sizeof *L->refs);
            if (!L->refs) return false;
        } else { /* each cell's start moved to the next's: shift back */
            memmove(L->cell_first + 1, L->cell_first, cells * sizeof *L->cell_first);
            L->cell_first[0] = 0;
        }
    }
    return true;
}

void pgrid_soft_light_free(pgrid_soft_light *L)
{
    free(L->cell_first);
    free(L->refs);
    free(L->near_list);
    free(L->least);
    memset(L, 0, sizeof *L);
}

/* How far the light's samples reach from its centre. */
float pgrid_soft_light_extent(const rtt_light *light)
{
    if (light->type == RTT_LIGHT_SPHERE) return light->radius;
    if (light->type == RTT_LIGHT_QUAD) return rtt_v3_length(light->edge_u) + rtt_v3_length(light->edge_v);
    return 0.0f;
}

bool pgrid_soft_prepare(pgrid_soft *g, const rtt_scene *scene, const uint8_t *degenerate, rtt_error *err)
{
    memset(g, 0, sizeof *g);
    g->tris = malloc(((size_t)scene->triangle_count + 1) * sizeof *g->tris);
    g->lights = calloc((size_t)scene->light_count + 1, sizeof *g->lights);
    if (!g->tris || !g->lights) {
        pgrid_soft_free(g);
        return rtt_error_set(err, "soft light grid: out of memory");
    }
    for (uint32_t t = 0; t < scene->triangle_count; t++) {
        if (degenerate && degenerate[t]) continue;
        rtt_vec3 c[3];
        rtt_scene_triangle(scene, t, c);
        pgrid_soft_tri *tri = &g->tris[g->tri_count++];
        for (int k = 0; k < 3; k++) tri->v[k][0] = c[k].x, tri->v[k][1] = c[k].y, tri->v[k][2] = c[k].z;
        tri->prim = t;
    }
    return true;
}

bool pgrid_soft_build(pgrid_soft *g, const rtt_scene *scene, const uint8_t *degenerate, uint32_t res,
                      uint32_t slices, rtt_error *err)
{
    const uint64_t t0 = rtt_clock_ns();
    memset(g, 0, sizeof *g);
    if (res > PGRID_LIGHT_RES_MAX || slices > PGRID_SOFT_SLICES_MAX)
        return rtt_error_set(err, "soft light grid: at most %u cells a side and %u slices", PGRID_LIGHT_RES_MAX,
                             PGRID_SOFT_SLICES_MAX);
    if (!pgrid_soft_prepare(g, scene, degenerate, err)) return false;
    for (uint32_t l = 0; l < scene->light_count; l++) {
        const rtt_light *light = &scene->lights[l];
        const float at[3] = {light->position.x, light->position.y, light->position.z};
        g->light_count = l + 1;
        if (!pgrid_soft_light_build(&g->lights[l], g, at, pgrid_soft_light_extent(light), res, slices)) {
            pgrid_soft_free(g);
            return rtt_error_set(err, "soft light grid: out of memory");
        }
    }
    g->build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    return true;
}

void pgrid_soft_free(pgrid_soft *g)
{
    for (uint32_t l = 0; g->lights && l < g->light_count; l++) pgrid_soft_light_free(&g->lights[l]);
    free(g->lights);
    free(g->tris);
    memset(g, 0, sizeof *g);
}

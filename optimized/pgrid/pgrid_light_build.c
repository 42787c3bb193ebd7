/* The light grids' per-frame build (pgrid_light.h): corners once, then per
 * light every triangle's footprint on the six faces in double (on the
 * thread pool, by chunks of records), counted and placed by a counting sort
 * (on the thread pool, by bands of cell rows: each band's cells are its
 * task's alone, each cell's list in global triangle order), into arrays
 * kept between frames. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "engine/threads.h"
#include "pgrid_light.h"
#include "pgrid_sort.h"
#include "solids.h"

#define NEAR_FACTOR 256.0
#define MU_MAX 4e-2

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
static pgrid_footprint face_footprint(const double c[3][3], uint32_t face, double mu, uint32_t res)
{
    const uint32_t axis = face / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double sign = face % 2 ? -1.0 : 1.0, wide = 1.0 + mu;
    double poly[2][16][3];
    int n = 3;
    memcpy(poly[0], c, 3 * sizeof poly[0][0]);
    pgrid_footprint f = {PGRID_FOOTPRINT_NONE, 0, 0, 0};
    /* the four planes' values at the corners: wholly outside one, no
     * footprint; inside all four, no clipping */
    bool inside = true;
    for (int k = 0; k < 4; k++) {
        const uint32_t across = k < 2 ? u : v;
        const double side = k % 2 ? 1.0 : -1.0;
        int out = 0;
        for (int i = 0; i < 3; i++) out += sign * wide * c[i][axis] + side * c[i][across] < 0.0;
        if (out == 3) return f;
        inside = inside && out == 0;
    }
    for (int k = 0; !inside && k < 4 && n > 0; k++) {
        double plane[3] = {0.0, 0.0, 0.0};
        plane[axis] = sign * wide;
        plane[k < 2 ? u : v] = k % 2 ? 1.0 : -1.0;
        n = clip_plane((const double(*)[3])poly[k % 2], n, plane, poly[(k + 1) % 2]);
    }
    if (n == 0) return f;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++) {
        const double *q = poly[0][i], major = sign * q[axis];
        if (!(major > 0.0)) return f; /* only at the apex: such triangles are near ones */
        const double s = q[u] / major, t = q[v] / major;
        lo[0] = s < lo[0] ? s : lo[0], hi[0] = s > hi[0] ? s : hi[0];
        lo[1] = t < lo[1] ? t : lo[1], hi[1] = t > hi[1] ? t : hi[1];
    }
    int32_t cell[4];
    for (int k = 0; k < 2; k++) {
        const double a = ((lo[k] - mu) + 1.0) * 0.5 * res, b = ((hi[k] + mu) + 1.0) * 0.5 * res;
        cell[k] = a < 0.0 ? 0 : a >= res ? (int32_t)res - 1 : (int32_t)a;
        cell[2 + k] = b < 0.0 ? 0 : b >= res ? (int32_t)res - 1 : (int32_t)b;
    }
    f = (pgrid_footprint){(uint16_t)cell[0], (uint16_t)cell[1], (uint16_t)cell[2], (uint16_t)cell[3]};
    return f;
}

/* The one face whose pyramid narrowed by mu holds every corner of c (then
 * the triangle lies there, its pyramid being convex, and meets no other
 * face's pyramid widened by mu), or PGRID_LIGHT_FACES when there is none. */
static uint32_t single_face(const double c[3][3], double mu)
{
    uint32_t face = PGRID_LIGHT_FACES;
    for (int i = 0; i < 3; i++) {
        const double ax = fabs(c[i][0]), ay = fabs(c[i][1]), az = fabs(c[i][2]);
        const uint32_t axis = (ax >= ay && ax >= az) ? 0u : (ay >= az ? 1u : 2u);
        const double major = axis == 0 ? ax : axis == 1 ? ay : az, narrow = major * (1.0 - 2.0 * mu);
        const double u = fabs(c[i][(axis + 1) % 3]), v = fabs(c[i][(axis + 2) % 3]);
        if (!(u < narrow && v < narrow)) return PGRID_LIGHT_FACES;
        const uint32_t f = 2u * axis + (c[i][axis] < 0.0 ? 1u : 0u);
        if (i > 0 && f != face) return PGRID_LIGHT_FACES;
        face = f;
    }
    return face;
}

/* A lower bound of the distance from the origin to the triangle c: the
 * larger of the distances to its box and to its plane; *len and *dot are
 * its normal's (c1 - c0) x (c2 - c0) length and dot product with c0, which
 * the front test reuses (the vector stage computes them once too). */
static double distance_bound(const double c[3][3], double *len, double *dot)
{
    double box = 0.0;
    for (int k = 0; k < 3; k++) {
        double lo = c[0][k], hi = c[0][k];
        for (int i = 1; i < 3; i++) lo = c[i][k] < lo ? c[i][k] : lo, hi = c[i][k] > hi ? c[i][k] : hi;
        const double gap = lo > 0.0 ? lo : hi < 0.0 ? -hi : 0.0;
        box += gap * gap;
    }
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = c[1][k] - c[0][k], e2[k] = c[2][k] - c[0][k];
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    *len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    *dot = n[0] * c[0][0] + n[1] * c[0][1] + n[2] * c[0][2];
    const double plane = *len > 0.0 ? fabs(*dot) / *len : 0.0;
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
    free(light->bound);
    free(light->refs);
    free(light->cell_front);
    free(light->front);
    free(light->near);
    free(light->prints);
    free(light->fill);
    free(light->record_front);
    free(light->face_mask);
    free(light->row_records);
    free(light->chunk_counts);
    for (uint32_t task = 0; task < PGRID_LIGHT_FACES * PGRID_LIGHT_BANDS_MAX; task++) free(light->band_spans[task]);
    memset(light, 0, sizeof *light);
}

/* Grows *p to hold `count` elements of `size` bytes (kept when it does). */
static bool grow(void *p, size_t *capacity, size_t count, size_t size)
{
    if (count <= *capacity) return true;
    void **array = p, *bigger = realloc(*array, count * size);
    if (!bigger) return false;
    *array = bigger, *capacity = count;
    return true;
}

/* The count and fill stages' bands per face at most are
 * PGRID_LIGHT_BANDS_MAX (two threads or more: two); the fill's spare slots
 * past the references: one per task, each
 * in a 64-byte line of its own (two tasks' slots in one line had the
 * threads pass it to and fro at every record: the fill slower on two
 * threads than on one). */
#define PGRID_LIGHT_SPARE_STRIDE 16u
#define PGRID_LIGHT_SPARE_SLOTS ((PGRID_LIGHT_FACES * PGRID_LIGHT_BANDS_MAX + 1u) * PGRID_LIGHT_SPARE_STRIDE)

/* What a build's tasks share. */
typedef struct light_build {
    pgrid_print_job job;
    pgrid_prints_fn prints;
    uint32_t bands, row_threads; /* row_threads: the threads whose rows light->row_records holds (bands > 1) */
    uint32_t band_row[PGRID_LIGHT_FACES][3]; /* face f's band k: rows band_row[f][k] .. band_row[f][k + 1] */
    uint32_t band_refs[PGRID_LIGHT_FACES][PGRID_LIGHT_BANDS_MAX];  /* per band its references (the count stage's) */
    uint32_t band_base[PGRID_LIGHT_FACES][PGRID_LIGHT_BANDS_MAX];  /* per band where its references start in refs */
    bool failed[PGRID_LIGHT_FACES * PGRID_LIGHT_BANDS_MAX];        /* per band task: out of memory for its spans */
    size_t cells;
} light_build;

enum { CHUNK = 2048 };
/* per chunk of records: its records with a footprint on each face, its
 * near ones, then per face the least first row and the greatest last row
 * of its footprints there (a band's tasks skip the chunks outside it) */
enum { CHUNK_NEAR = PGRID_LIGHT_FACES, CHUNK_ROW_LO = PGRID_LIGHT_FACES + 1,
       CHUNK_ROW_HI = CHUNK_ROW_LO + PGRID_LIGHT_FACES, CHUNK_COUNTS = CHUNK_ROW_HI + PGRID_LIGHT_FACES };

/* mu_T for a triangle whose distance bound from the light is d (pgrid_light.h) */
static inline double record_margin(double E, double d) { return 1e-5 + 4.0 * (2.0 * E / (d - 2.0 * E)); }

void pgrid_light_print_record(const pgrid_print_job *job, uint32_t i)
{
    pgrid_light *light = job->light;
    const pgrid_shadows *grids = job->grids;
    const float *position = light->position;
    const double E = job->E;
    const uint32_t n = job->n;
    const kd_corners *k = &grids->corners[i];
    double c[3][3];
    for (int a = 0; a < 3; a++)
        c[0][a] = (double)k->a[a] - position[a], c[1][a] = (double)k->b[a] - position[a],
        c[2][a] = (double)k->c[a] - position[a];
    double len, dot;
    const double d = distance_bound(c, &len, &dot);
    light->bound[i] = (float)(d * (1.0 - 1e-6));
    bool front = false, steep = false;
    if (k->outward) {
        /* the light on the outer side of the plane by more than 4E: every ray towards it leaves the solid there */
        const double side = -dot * k->outward;
        front = side > 4.0 * E * len;
        /* every ray from the triangle to the light at a cosine of PGRID_STEEP_COSINE or more with its
         * normal: side / len, the light's height over the plane, over its farthest corner's distance */
        double far = 0.0;
        for (int v = 0; v < 3; v++) {
            const double q = c[v][0] * c[v][0] + c[v][1] * c[v][1] + c[v][2] * c[v][2];
            far = q > far ? q : far;
        }
        steep = front && side > PGRID_STEEP_COSINE * len * sqrt(far);
    }
    light->record_front[i] = front ? (steep ? PGRID_PRIM_STEEP : PGRID_PRIM_FACING) : 0;
    const double mu = record_margin(E, d);
    if (!(d > NEAR_FACTOR * E) || !(mu <= MU_MAX)) {
        /* a near one: no footprint, face 0's y0 marks it for the near list */
        light->prints[i] = (pgrid_footprint){PGRID_FOOTPRINT_NONE, PGRID_FOOTPRINT_NONE, 0, 0};
        light->face_mask[i] = 0;
        return;
    }
    /* only the faces it has a footprint on are written (pgrid_light.prints) */
    const uint32_t only = single_face((const double(*)[3])c, mu);
    uint8_t mask = 0;
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
        if (only != PGRID_LIGHT_FACES && face != only) continue;
        const pgrid_footprint f = face_footprint((const double(*)[3])c, face, mu, job->res);
        if (f.x0 == PGRID_FOOTPRINT_NONE) continue;
        light->prints[(size_t)face * n + i] = f;
        mask |= (uint8_t)(1u << face);
    }
    if (!mask) light->prints[i] = (pgrid_footprint){PGRID_FOOTPRINT_NONE, 0, 0, 0};
    light->face_mask[i] = mask;
}

bool pgrid_light_prints_equal(const pgrid_light *a, const pgrid_light *b, uint32_t records)
{
    if (!records) return true;
    if (memcmp(a->bound, b->bound, records * sizeof *a->bound) || memcmp(a->record_front, b->record_front, records) ||
        memcmp(a->face_mask, b->face_mask, records))
        return false;
    for (uint32_t i = 0; i < records; i++) {
        const uint32_t mask = a->face_mask[i] ? a->face_mask[i] : 1u; /* none: face 0's marker */
        for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++)
            if (mask >> face & 1u && memcmp(&a->prints[(size_t)face * records + i],
                                            &b->prints[(size_t)face * records + i], sizeof *a->prints))
                return false;
    }
    return true;
}

void pgrid_light_prints_scalar(const pgrid_print_job *job, uint32_t first, uint32_t end)
{
    for (uint32_t i = first; i < end; i++) pgrid_light_print_record(job, i);
}

/* Whether record i is a near one (pgrid_light_print_record: no footprint,
 * face 0's y0 marks it), for the near list. */
static inline bool record_is_near(const pgrid_light *light, uint32_t i)
{
    return !light->face_mask[i] && light->prints[i].x0 == PGRID_FOOTPRINT_NONE &&
           light->prints[i].y0 == PGRID_FOOTPRINT_NONE;
}

/* Task: the footprints, bounds and front classes of records [CHUNK task
 * ..); then, read back while in this thread's cache, the chunk's counts
 * (pgrid_light.chunk_counts: records with a footprint per face, near
 * ones, rows per face), the kernel's front byte of its facing triangles
 * (pgrid_light.front: other tasks' triangles may share a line, never a
 * byte), and with two bands this thread's count of the rows the
 * footprints start on. */
static void footprint_chunk(void *context, uint32_t thread, uint32_t task)
{
    const light_build *b = context;
    const uint32_t n = b->job.n, end = (task + 1) * CHUNK < n ? (task + 1) * CHUNK : n;
    b->prints(&b->job, task * CHUNK, end);
    pgrid_light *light = b->job.light;
    const uint32_t res = b->job.res;
    const uint32_t *record_prim = b->job.grids->record_prim;
    uint32_t counts[CHUNK_COUNTS] = {0};
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) counts[CHUNK_ROW_LO + face] = UINT32_MAX;
    uint32_t *rows = b->bands > 1 ? light->row_records + (size_t)thread * PGRID_LIGHT_FACES * res : NULL;
    for (uint32_t i = task * CHUNK; i < end; i++) {
        const uint32_t face_mask = light->face_mask[i];
        if (light->record_front[i]) light->front[record_prim[i]] = light->record_front[i];
        counts[CHUNK_NEAR] += record_is_near(light, i);
        for (uint32_t mask = face_mask; mask; mask &= mask - 1) {
            const uint32_t face = (uint32_t)__builtin_ctz(mask);
            const pgrid_footprint f = light->prints[(size_t)face * n + i];
            counts[face]++;
            if (f.y0 < counts[CHUNK_ROW_LO + face]) counts[CHUNK_ROW_LO + face] = f.y0;
            if (f.y1 > counts[CHUNK_ROW_HI + face]) counts[CHUNK_ROW_HI + face] = f.y1;
            if (rows) rows[(size_t)face * res + f.y0]++;
        }
    }
    memcpy(light->chunk_counts + (size_t)task * CHUNK_COUNTS, counts, sizeof counts);
}

/* The rows of band `task % bands` of face `task / bands`. */
static void band_rows(const light_build *b, uint32_t task, uint32_t *face, uint32_t *y0, uint32_t *y1)
{
    const uint32_t band = task % b->bands;
    *face = task / b->bands;
    *y0 = b->band_row[*face][band];
    *y1 = b->band_row[*face][band + 1];
}

/* Whether chunk `chunk`'s records have a footprint on `face` within rows [r0, r1). */
static inline bool chunk_meets_band(const pgrid_light *light, uint32_t chunk, uint32_t face, uint32_t r0, uint32_t r1)
{
    const uint32_t *counts = light->chunk_counts + (size_t)chunk * CHUNK_COUNTS;
    return counts[face] && counts[CHUNK_ROW_LO + face] < r1 && counts[CHUNK_ROW_HI + face] >= r0;
}

/* A footprint of CONE_CUT_CELLS cells or more covers the rectangle around
 * the triangle's region on the face; a cell of it that the region, widened
 * by mu as the rectangle is, does not meet takes no reference (a map's
 * large slanted triangles left two fifths of their rectangles' cells).  The
 * region is the cone from the light over the triangle: the directions d
 * with n_e . d >= 0 for its three edge planes through the light (n_e = (p -
 * L) x (q - L) for the edge pq, turned towards the third corner), on face f
 * the points (s, t) with n_e . (sign, s, t) >= 0 in (axis, u, v) order.  A
 * cell (x, y), widened by mu, lies outside edge e's half-plane when the
 * largest value of n_e . (sign, s, t) over it, (A_e + y C_e) + x B_e, is
 * below -tol_e, tol_e = 1e-12 |p - L|_1 |q - L|_1: far above the rounding of
 * n_e and of the sums in double (some 1e-15 of it), so a cell is dropped
 * only when the exact region widened by mu misses it.  mu from the
 * record's bound (below its d_T: a larger mu than the footprint's).  A
 * triangle nearly in a plane through the light (the corners' triple
 * product below 1e-9 of their 1-norms' product: the cone flat, its
 * orientation unsure) keeps its rectangle.  Per row the cells left are an
 * interval (each edge's value is monotone in x), cone_row's; the count
 * stage keeps each row's interval in its band's span list, which the fill
 * stage reads back in the same order (pgrid_light.band_spans). */
/* 16 against 9 and 25, best of 3 a frame on the six bench scenes
 * (bench/results/pgrid.md, fifteenth session): smaller footprints, a
 * mesh's, lose less than their cut costs */
#define CONE_CUT_CELLS 16u
typedef struct cone_cut {
    double a[3], b[3], c[3], tol[3], inverse_b[3];
} cone_cut;

static bool cone_cut_make(const light_build *lb, uint32_t record, uint32_t face, cone_cut *k)
{
    const kd_corners *r = &lb->job.grids->corners[record];
    const float *L = lb->job.light->position;
    const float *corner[3] = {r->a, r->b, r->c};
    double v[3][3], norm1[3];
    for (int j = 0; j < 3; j++) {
        for (int a = 0; a < 3; a++) v[j][a] = (double)corner[j][a] - (double)L[a];
        norm1[j] = fabs(v[j][0]) + fabs(v[j][1]) + fabs(v[j][2]);
    }
    const double E = lb->job.E, res = (double)lb->job.res;
    const double mu = record_margin(E, (double)lb->job.light->bound[record]);
    if (!(mu > 0.0 && mu < 1.0)) return false;
    const uint32_t axis = face / 2, u = (axis + 1) % 3, w = (axis + 2) % 3;
    const double sign = face % 2 ? -1.0 : 1.0, high = -1.0 + 2.0 / res + mu, low = -1.0 - mu;
    for (int e = 0; e < 3; e++) {
        const double *p = v[e], *q = v[(e + 1) % 3], *o = v[(e + 2) % 3];
        double n[3] = {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
        const double side = n[0] * o[0] + n[1] * o[1] + n[2] * o[2];
        if (!(fabs(side) > 1e-9 * norm1[0] * norm1[1] * norm1[2])) return false; /* also NaN */
        if (side < 0.0)
            for (int a = 0; a < 3; a++) n[a] = -n[a];
        k->a[e] = sign * n[axis] + n[u] * (n[u] > 0.0 ? high : low) + n[w] * (n[w] > 0.0 ? high : low);
        k->b[e] = 2.0 * n[u] / res;
        k->c[e] = 2.0 * n[w] / res;
        k->tol[e] = 1e-12 * norm1[e] * norm1[(e + 1) % 3];
        k->inverse_b[e] = k->b[e] != 0.0 ? 1.0 / k->b[e] : 0.0;
    }
    return true;
}

/* The cells of row y within [x0, x1] the cone leaves, [*lo, *hi]; false
 * when none.  Each edge's value crosses -tol_e at x = (-tol_e - (A_e + y
 * C_e)) / B_e, computed with an error (some 1e-15 |p - L|_1 |q - L|_1 / B_e
 * cells) far below tol_e / B_e, the cells between that crossing and the
 * exact value's zero: so the cells before the computed crossing (or after
 * it, B_e < 0) lie outside the widened region, and the same computation in
 * the count and the fill stages leaves the same cells. */
static inline bool cone_row(const cone_cut *k, uint32_t y, uint32_t x0, uint32_t x1, uint32_t *lo, uint32_t *hi)
{
    double first = x0, last = x1;
    for (int e = 0; e < 3; e++) {
        const double r = k->a[e] + (double)y * k->c[e], limit = -k->tol[e];
        if (k->b[e] == 0.0) {
            if (!(r >= limit)) return false;
            continue;
        }
        const double at = (limit - r) * k->inverse_b[e];
        if (k->b[e] > 0.0) {
            const double x = ceil(at);
            first = x > first ? x : first; /* NaN: no cut */
        } else {
            const double x = floor(at);
            last = x < last ? x : last;
        }
    }
    if (!(first <= last)) return false;
    *lo = (uint32_t)first, *hi = (uint32_t)last;
    return true;
}

/* One band's cells: counted (`fill` false: references into the main
 * cursors, front ones into cell_front, the distance bound, the band's
 * total in band_refs), or (`fill` true) their lists laid out from the
 * band's base (cell_first, cell_front, the cursors: the prefix sum in the
 * band's own task) and their references placed in record order (two
 * cursors per cell, the main references from cell_first, the front ones
 * from cell_front), the records read in order: the chunks with no
 * footprint on the band's face or none on its rows skipped whole (a chunk's
 * records lie close together, so most chunks fall in one band), the other
 * records without a footprint on the face skipped by their face mask (a
 * list of each face's records, made serially, cost more than the scan:
 * sixth session).  The loops are not vectorised: their rows of one or two
 * cells paid the vector path's checks (ninth session).
 * The arrays are read through local restrict pointers: a store through the
 * light's own would oblige the compiler to load them again from the light
 * after every reference (measured: bench/results/pgrid.md, "sixth
 * session"). */
/* GCC's loop vectorizer kept off band_pass (above) and the two stages it
 * is inlined into, one copy each (`fill` a constant there, so the record
 * scan is written once and the per-record branch on the stage folds away);
 * clang takes no such attribute */
#if defined(__GNUC__) && !defined(__clang__)
#define BAND_PASS_NO_VECTORIZE __attribute__((optimize("no-tree-vectorize")))
#else
#define BAND_PASS_NO_VECTORIZE
#endif
BAND_PASS_NO_VECTORIZE static inline __attribute__((always_inline)) void band_pass(light_build *b, uint32_t task,
                                                                                   bool fill)
{
    pgrid_light *light = b->job.light;
    uint32_t face, r0, r1;
    band_rows(b, task, &face, &r0, &r1);
    if (light->face_first[face] == light->face_first[face + 1]) return; /* no footprint: its cells are not kept */
    const uint32_t res = b->job.res, records_end = b->job.n;
    const uint8_t *restrict face_mask = light->face_mask;
    const size_t cells = b->cells, first = ((size_t)face * res + r0) * res, last = ((size_t)face * res + r1) * res;
    const pgrid_footprint *restrict prints = light->prints + (size_t)face * b->job.n; /* face-major */
    const uint8_t *restrict record_front = light->record_front;
    const float *restrict bound = light->bound;
    /* the main cursors hold the count stage's counts (all references), cell_front its front ones */
    uint32_t *restrict main_cursor = light->fill, *restrict front_cursor = light->fill + cells;
    uint32_t *restrict refs = light->refs, *restrict cell_first = light->cell_first,
                       *restrict cell_front = light->cell_front;
    float *restrict cell_min = light->cell_min;
    /* the task's own spare slot past the references (a slot per face and band, a line apart: tasks of two
     * faces run at once; pgrid_light_rebuild grows refs by PGRID_LIGHT_SPARE_SLOTS) */
    const size_t spare = light->ref_count + (size_t)(task + 1u) * PGRID_LIGHT_SPARE_STRIDE; /* none in the last references' line */
    if (fill) {
        uint32_t at = b->band_base[face][task % b->bands];
        for (size_t c = first; c < last; c++) {
            const uint32_t main = main_cursor[c], front = cell_front[c];
            cell_first[c] = main_cursor[c] = at;
            at += main;
            cell_front[c] = front_cursor[c] = at - front;
        }
    } else {
        memset(main_cursor + first, 0, (last - first) * sizeof *main_cursor);
        memset(cell_front + first, 0, (last - first) * sizeof *cell_front);
        for (size_t c = first; c < last; c++) cell_min[c] = INFINITY;
    }
    uint32_t total = 0;
    const uint32_t chunks = (records_end + CHUNK - 1) / CHUNK;
    /* the band's span list (cone_cut): written by the count, read by the fill */
    uint32_t *restrict spans = light->band_spans[task];
    size_t span_count = 0, span_capacity = light->band_span_capacity[task];
    for (uint32_t chunk = 0; chunk < chunks && !b->failed[task]; chunk++) {
        if (!chunk_meets_band(light, chunk, face, r0, r1)) continue;
        const uint32_t end = (chunk + 1) * CHUNK < records_end ? (chunk + 1) * CHUNK : records_end;
        for (uint32_t i = chunk * CHUNK; i < end; i++) {
            if (!(face_mask[i] >> face & 1u)) continue;
            const pgrid_footprint f = prints[i];
            if (f.y1 < r0 || f.y0 >= r1) continue;
            const uint32_t y0 = f.y0 > r0 ? f.y0 : r0, y1 = f.y1 < r1 - 1 ? f.y1 : r1 - 1;
            const uint32_t wx = (uint32_t)(f.x1 - f.x0), wy = y1 - y0;
            /* a large footprint: the rows' cells the triangle's region meets (cone_cut), one span a row
             * (decided on the whole footprint, not the band's rows: the same cells at any thread count) */
            const bool large = (uint32_t)(f.x1 - f.x0 + 1) * (uint32_t)(f.y1 - f.y0 + 1) >= CONE_CUT_CELLS;
            if ((wx | wy) <= 1u && !large) {
                /* at most 2 x 2 cells (a mesh's triangles mostly): the four
                 * corners without a loop, a corner outside the footprint
                 * being the first cell again with nothing added (its cursor
                 * untouched, its record written to the task's spare slot
                 * past the references; a minimum taken twice is the same):
                 * the loops' exits were mispredicted every few records */
                const size_t c00 = ((size_t)face * res + y0) * res + f.x0, c01 = c00 + wx;
                const size_t c10 = c00 + (size_t)wy * res, c11 = c10 + wx;
                const uint32_t v01 = wx, v10 = wy, v11 = wx & wy;
                if (fill) {
                    uint32_t *restrict own = record_front[i] ? front_cursor : main_cursor;
                    refs[own[c00]++] = i;
                    refs[v01 ? own[c01] : spare] = i, own[c01] += v01;
                    refs[v10 ? own[c10] : spare] = i, own[c10] += v10;
                    refs[v11 ? own[c11] : spare] = i, own[c11] += v11;
                    continue;
                }
                total += (wx + 1u) * (wy + 1u);
                if (record_front[i]) {
                    main_cursor[c00]++, cell_front[c00]++;
                    main_cursor[c01] += v01, cell_front[c01] += v01;
                    main_cursor[c10] += v10, cell_front[c10] += v10;
                    main_cursor[c11] += v11, cell_front[c11] += v11;
                    continue;
                }
                const float d = bound[i];
                main_cursor[c00]++, main_cursor[c01] += v01, main_cursor[c10] += v10, main_cursor[c11] += v11;
                cell_min[c00] = d < cell_min[c00] ? d : cell_min[c00];
                cell_min[c01] = d < cell_min[c01] ? d : cell_min[c01];
                cell_min[c10] = d < cell_min[c10] ? d : cell_min[c10];
                cell_min[c11] = d < cell_min[c11] ? d : cell_min[c11];
                continue;
            }
            if (fill) {
                uint32_t *restrict own = record_front[i] ? front_cursor : main_cursor;
                for (uint32_t y = y0; y <= y1; y++) {
                    uint32_t lo = f.x0, hi = f.x1;
                    if (large) {
                        const uint32_t span = spans[span_count++];
                        lo = span & 0xffffu, hi = span >> 16;
                    }
                    const size_t row = ((size_t)face * res + y) * res;
                    for (size_t cell = row + lo; cell <= row + hi; cell++) refs[own[cell]++] = i;
                }
                continue;
            }
            if (large && span_count + (y1 - y0 + 1) > span_capacity) {
                const size_t bigger = 2 * span_capacity + (y1 - y0 + 1) + 1024;
                uint32_t *grown = realloc(spans, bigger * sizeof *spans);
                if (!grown) {
                    b->failed[task] = true;
                    break;
                }
                spans = grown, span_capacity = bigger;
            }
            cone_cut cut;
            const bool cutting = large && cone_cut_make(b, i, face, &cut);
            const bool facing = record_front[i] != 0; /* counted in both, bounds nothing */
            const float d = bound[i];
            for (uint32_t y = y0; y <= y1; y++) {
                uint32_t lo = f.x0, hi = f.x1;
                if (cutting && !cone_row(&cut, y, f.x0, f.x1, &lo, &hi)) {
                    spans[span_count++] = 1u; /* none: lo 1 > hi 0 */
                    continue;
                }
                if (large) spans[span_count++] = lo | hi << 16;
                const size_t row = ((size_t)face * res + y) * res;
                total += hi - lo + 1;
                if (facing) {
                    for (size_t cell = row + lo; cell <= row + hi; cell++) main_cursor[cell]++, cell_front[cell]++;
                    continue;
                }
                for (size_t cell = row + lo; cell <= row + hi; cell++) {
                    main_cursor[cell]++;
                    cell_min[cell] = d < cell_min[cell] ? d : cell_min[cell];
                }
            }
        }
    }
    if (!fill) {
        b->band_refs[face][task % b->bands] = total;
        light->band_spans[task] = spans, light->band_span_capacity[task] = span_capacity;
    }
}

BAND_PASS_NO_VECTORIZE static void count_band(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    band_pass(context, task, false);
}

BAND_PASS_NO_VECTORIZE static void fill_band(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    band_pass(context, task, true);
}

bool pgrid_light_build(pgrid_light *light, const pgrid_shadows *grids, const rtt_scene *scene,
                       const float position[3], uint32_t res)
{
    memset(light, 0, sizeof *light);
    return pgrid_light_rebuild(light, grids, scene, position, res, 1);
}

bool pgrid_light_rebuild(pgrid_light *light, const pgrid_shadows *grids, const rtt_scene *scene,
                         const float position[3], uint32_t res, uint32_t threads)
{
    const uint32_t n = grids->corner_count;
    if (res == 0) res = pgrid_light_res_rule(n);
    if (res > PGRID_LIGHT_RES_MAX) res = PGRID_LIGHT_RES_MAX;
    if (threads == 0) threads = 1;
    memcpy(light->position, position, sizeof light->position);
    light->res = res;
    const double E = error_bound(scene, position);
    light->reach = (float)(4.0 * E);
    light->magnitude = ldexp(E, 15); /* 2M (pgrid_light.h) */
    const size_t cells = (size_t)PGRID_LIGHT_FACES * res * res;
    /* the arrays are grown to what this build needs, never shrunk */
    bool ok = true;
    if (cells > light->cell_capacity) {
        size_t c1 = 0, c2 = 0, c3 = 0, c4 = 0;
        ok = grow(&light->cell_first, &c1, cells + 1, sizeof *light->cell_first) &&
             grow(&light->cell_front, &c2, cells + 1, sizeof *light->cell_front) &&
             grow(&light->cell_min, &c3, cells + 1, sizeof *light->cell_min) &&
             grow(&light->fill, &c4, 2 * cells + 1, sizeof *light->fill);
        if (ok) light->cell_capacity = cells;
    }
    if (ok && n > light->corner_capacity) {
        size_t c1 = 0, c2 = 0, c3 = 0, c4 = 0, c5 = 0;
        ok = grow(&light->record_front, &c4, (size_t)n + 1, 1) && grow(&light->near, &c1, (size_t)n + 1, sizeof *light->near) &&
             grow(&light->bound, &c2, (size_t)n + 1, sizeof *light->bound) &&
             grow(&light->prints, &c3, (size_t)n * PGRID_LIGHT_FACES + 1, sizeof *light->prints) &&
             grow(&light->face_mask, &c5, (size_t)n + 1, 1);
        if (ok) light->corner_capacity = n;
    }
    const uint32_t row_threads = rtt_thread_count(threads), chunks = (n + CHUNK - 1) / CHUNK;
    ok = ok && grow(&light->front, &light->triangle_capacity, (size_t)scene->triangle_count + 1, 1) &&
         grow(&light->row_records, &light->row_capacity, (size_t)row_threads * PGRID_LIGHT_FACES * res,
              sizeof *light->row_records) &&
         grow(&light->chunk_counts, &light->chunk_capacity, (size_t)chunks * CHUNK_COUNTS + 1,
              sizeof *light->chunk_counts);
    if (!ok) {
        pgrid_light_free(light);
        return false;
    }
    memcpy(light->front, grids->prim_side, (size_t)scene->triangle_count + 1);
    light_build b = {.job = {.light = light, .grids = grids, .E = E, .res = res, .n = n},
                     .prints = grids->prints ? grids->prints : pgrid_light_prints_scalar,
                     .cells = cells,
                     .bands = threads > 1 ? PGRID_LIGHT_BANDS_MAX : 1,
                     .row_threads = row_threads};
    if (b.bands > 1) memset(light->row_records, 0, (size_t)row_threads * PGRID_LIGHT_FACES * res * sizeof *light->row_records);
    rtt_parallel_run(chunks, threads, footprint_chunk, &b);
    /* per face how many records have a footprint on it (none: its cells
     * are not kept), from the chunks' counts; the near list, in record
     * order, from the chunks that have some */
    uint32_t at[PGRID_LIGHT_FACES + 1] = {0}, row_lo[PGRID_LIGHT_FACES], row_hi[PGRID_LIGHT_FACES] = {0};
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) row_lo[face] = res;
    light->near_count = 0;
    for (uint32_t chunk = 0; chunk < chunks; chunk++) {
        const uint32_t *counts = light->chunk_counts + (size_t)chunk * CHUNK_COUNTS;
        for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
            if (!counts[face]) continue;
            at[face + 1] += counts[face];
            row_lo[face] = counts[CHUNK_ROW_LO + face] < row_lo[face] ? counts[CHUNK_ROW_LO + face] : row_lo[face];
            row_hi[face] = counts[CHUNK_ROW_HI + face] > row_hi[face] ? counts[CHUNK_ROW_HI + face] : row_hi[face];
        }
        if (!counts[CHUNK_NEAR]) continue;
        const uint32_t end = (chunk + 1) * CHUNK < n ? (chunk + 1) * CHUNK : n;
        for (uint32_t i = chunk * CHUNK; i < end; i++)
            if (record_is_near(light, i)) light->near[light->near_count++] = i;
    }
    /* a face's bands cover the rows its footprints meet, [row_lo, row_hi]
     * (a mesh seen from a light covers a part of a face: the cells of the
     * other rows are neither counted nor laid out); two bands: cut where
     * half the face's records have started (even rows would leave one
     * thread most of them), from the rows the footprint tasks counted per
     * thread */
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
        if (!at[face + 1]) {
            memset(b.band_row[face], 0, sizeof b.band_row[face]);
            continue;
        }
        const uint32_t end = row_hi[face] + 1;
        uint32_t cut = end;
        if (b.bands > 1) {
            uint32_t seen = 0, y = row_lo[face];
            for (; y + 1 < end; y++) {
                uint32_t starting = 0;
                for (uint32_t t = 0; t < b.row_threads; t++) starting += light->row_records[((size_t)t * PGRID_LIGHT_FACES + face) * res + y];
                if (2 * (seen + starting) > at[face + 1]) break;
                seen += starting;
            }
            cut = y > row_lo[face] ? y : row_lo[face] + 1;
        }
        b.band_row[face][0] = row_lo[face], b.band_row[face][1] = cut, b.band_row[face][2] = end;
    }
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) at[face + 1] += at[face];
    memcpy(light->face_first, at, sizeof at);
    rtt_parallel_run(PGRID_LIGHT_FACES * b.bands, threads, count_band, &b);
    for (uint32_t task = 0; task < PGRID_LIGHT_FACES * b.bands; task++)
        if (b.failed[task]) {
            pgrid_light_free(light);
            return false;
        }
    /* the kept cells (pgrid_light.kept_cells) in face order: the others
     * (a mesh seen from outside lies on one or two faces, and on some of
     * their rows) cost nothing.  Each band's references start where the
     * bands before it end (its task lays its cells out from there); the
     * cell past a face's kept rows gets the face's end here (when it is
     * the next face's first kept cell, that face's first band writes the
     * same there after). */
    uint32_t total = 0;
    light->faces = 0;
    memset(light->kept_cells, 0, sizeof light->kept_cells);
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
        if (light->face_first[face] == light->face_first[face + 1]) continue;
        light->faces |= 1u << face;
        light->kept_cells[face][0] = (uint32_t)(((size_t)face * res + b.band_row[face][0]) * res);
        light->kept_cells[face][1] = (uint32_t)(((size_t)face * res + b.band_row[face][2]) * res);
        for (uint32_t band = 0; band < b.bands; band++) {
            b.band_base[face][band] = total;
            total += b.band_refs[face][band];
        }
        light->cell_first[light->kept_cells[face][1]] = total;
    }
    light->cell_first[cells] = total;
    light->ref_count = total;
    if (!grow(&light->refs, &light->ref_capacity, light->ref_count + PGRID_LIGHT_SPARE_SLOTS, sizeof *light->refs)) {
        pgrid_light_free(light);
        return false;
    }
    rtt_parallel_run(PGRID_LIGHT_FACES * b.bands, threads, fill_band, &b);
    return true;
}

void pgrid_shadows_free(pgrid_shadows *grids)
{
    pgrid_shadows_free_lights(grids);
    free(grids->lights);
    free(grids->corners);
    free(grids->corner_lanes);
    free(grids->record_prim);
    free(grids->mesh_culled);
    free(grids->mesh_outward);
    free(grids->mesh_box);
    free(grids->culled);
    free(grids->outward_normal);
    free(grids->prim_side);
    memset(grids, 0, sizeof *grids);
}

/* Spreads the low 10 bits of x over every third bit (a Morton code's axis). */
static uint32_t spread_bits(uint32_t x)
{
    x &= 0x3ffu;
    x = (x | x << 16) & 0x030000ffu;
    x = (x | x << 8) & 0x0300f00fu;
    x = (x | x << 4) & 0x030c30c3u;
    x = (x | x << 2) & 0x09249249u;
    return x;
}

/* The corner records in the Morton order of their centroids (1024 steps
 * an axis over the scene's box; ties in scene order): a cell's triangles,
 * and a footprint's neighbours, then lie near one another in memory, for
 * the build's counting sort and the kernel's reads.  False when out of
 * memory (the order is then the scene's). */
static bool order_records_in_space(pgrid_shadows *grids, const rtt_scene *scene)
{
    const uint32_t n = grids->corner_count;
    uint64_t *keys = malloc(((size_t)n + 1) * sizeof *keys), *spare = malloc(((size_t)n + 1) * sizeof *spare);
    kd_corners *copy = malloc(((size_t)n + 1) * sizeof *copy);
    if (!keys || !spare || !copy) {
        free(keys), free(spare), free(copy);
        return false;
    }
    const float *lo = &scene->bounds.lo.x, *hi = &scene->bounds.hi.x;
    for (uint32_t i = 0; i < n; i++) {
        const kd_corners *k = &grids->corners[i];
        uint32_t code = 0;
        for (int a = 0; a < 3; a++) {
            const float extent = hi[a] - lo[a], centre = (k->a[a] + k->b[a] + k->c[a]) / 3.0f;
            float step = extent > 0.0f ? (centre - lo[a]) / extent * 1024.0f : 0.0f;
            step = step >= 0.0f ? (step < 1023.0f ? step : 1023.0f) : 0.0f; /* NaN: 0 */
            code |= spread_bits((uint32_t)step) << a;
        }
        keys[i] = (uint64_t)code << 32 | i;
    }
    /* radix, not qsort: the renderer prepares every frame */
    const uint64_t *sorted = pgrid_sort_keys(keys, spare, n, 0, (1u << 30) - 1u);
    memcpy(copy, grids->corners, (size_t)n * sizeof *copy);
    for (uint32_t i = 0; i < n; i++) grids->corners[i] = copy[(uint32_t)sorted[i]];
    free(keys), free(spare), free(copy);
    return true;
}

/* grids->corner_lanes and grids->record_prim from grids->corners
 * (pgrid_light.h).  False when out of memory. */
static bool corners_as_lanes(pgrid_shadows *grids)
{
    const size_t stride = ((size_t)grids->corner_count + 16) & ~(size_t)15; /* a vector's reach past the last record */
    float *lanes = calloc(10 * stride, sizeof *lanes);
    uint32_t *prim = malloc(((size_t)grids->corner_count + 1) * sizeof *prim);
    if (!lanes || !prim) {
        free(lanes), free(prim);
        return false;
    }
    for (uint32_t i = 0; i < grids->corner_count; i++) {
        const kd_corners *k = &grids->corners[i];
        prim[i] = k->prim;
        for (int a = 0; a < 3; a++)
            lanes[(size_t)a * stride + i] = k->a[a], lanes[(size_t)(3 + a) * stride + i] = k->b[a],
                                   lanes[(size_t)(6 + a) * stride + i] = k->c[a];
        lanes[9 * stride + i] = (float)k->outward;
    }
    grids->corner_lanes = lanes, grids->corner_stride = stride, grids->record_prim = prim;
    return true;
}

bool pgrid_shadows_prepare(pgrid_shadows *grids, const rtt_scene *scene, const uint8_t *degenerate, rtt_error *err)
{
    memset(grids, 0, sizeof *grids);
    /* aligned_alloc wants a size that is a multiple of the alignment (fuzz_pgrid under ASan) */
    const size_t corner_bytes = (((size_t)scene->triangle_count + 1) * sizeof *grids->corners + 63) & ~(size_t)63;
    grids->corners = aligned_alloc(64, corner_bytes);
    grids->lights = calloc(scene->light_count + 1, sizeof *grids->lights);
    grids->mesh_culled = calloc(scene->mesh_count + 1, 1);
    grids->mesh_outward = calloc(scene->mesh_count + 1, 1);
    grids->mesh_box = calloc(scene->mesh_count + 1, sizeof *grids->mesh_box);
    grids->culled = calloc(scene->mesh_count + 1, sizeof *grids->culled);
    grids->outward_normal = calloc((size_t)scene->triangle_count + 1, sizeof *grids->outward_normal);
    grids->prim_side = calloc((size_t)scene->triangle_count + 1, 1); /* PGRID_PRIM_OPEN */
    grids->triangle_mesh = scene->mesh_count ? scene->triangle_mesh : NULL;
    bool ok = grids->corners && grids->lights && grids->mesh_culled && grids->mesh_outward && grids->mesh_box &&
              grids->culled && grids->outward_normal && grids->prim_side;
    /* a culled mesh's box, grown by four ray epsilons and 2^-12 of the coordinates' magnitude */
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    const float grow = 4.0f * rtt_scene_ray_epsilon(scene) + (float)ldexp(error_bound(scene, zero), 2);
    for (uint32_t m = 0; ok && m < scene->mesh_count; m++) {
        const rtt_mesh *mesh = &scene->meshes[m];
        if (!mesh->closed || !mesh->triangle_count || !scene_mesh_oriented(scene, degenerate, mesh, &grids->mesh_outward[m]))
            continue;
        float *box = grids->mesh_box[m];
        scene_mesh_box(scene, mesh, box);
        for (int a = 0; a < 3; a++) box[a] -= grow + fabsf(box[a]) * 1e-5f, box[3 + a] += grow + fabsf(box[3 + a]) * 1e-5f;
        for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++) {
            rtt_vec3 c[3];
            rtt_scene_triangle(scene, t, c);
            double e1[3], e2[3];
            for (int a = 0; a < 3; a++)
                e1[a] = (double)rtt_v3_get(c[1], a) - rtt_v3_get(c[0], a), e2[a] = (double)rtt_v3_get(c[2], a) - rtt_v3_get(c[0], a);
            const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
            const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * grids->mesh_outward[m];
            for (int a = 0; a < 3; a++) grids->outward_normal[t][a] = len != 0.0 ? (float)(n[a] / len) : 0.0f;
            grids->prim_side[t] = PGRID_PRIM_AWAY;
        }
        grids->mesh_culled[m] = 1;
        grids->culled[grids->culled_count++] = m;
    }
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
        const uint32_t mesh = grids->triangle_mesh ? grids->triangle_mesh[i] : UINT32_MAX;
        k->outward = mesh != UINT32_MAX && grids->mesh_culled[mesh] ? grids->mesh_outward[mesh] : 0;
    }
    ok = ok && order_records_in_space(grids, scene) && corners_as_lanes(grids);
    if (!ok) pgrid_shadows_free(grids);
    return ok || rtt_error_set(err, "%s: out of memory building the light grids", scene->path);
}

void pgrid_shadows_free_lights(pgrid_shadows *grids)
{
    for (uint32_t l = 0; grids->lights && l < grids->light_count; l++) pgrid_light_free(&grids->lights[l]);
    grids->light_count = 0;
}

bool pgrid_shadows_build_lights(pgrid_shadows *grids, const rtt_scene *scene, uint32_t res, rtt_error *err)
{
    const uint64_t t0 = rtt_clock_ns();
    /* the lights' arrays are kept from the last build (light_count says how many were built) */
    bool ok = true;
    for (uint32_t l = 0; ok && l < scene->light_count; l++) {
        const rtt_vec3 p = scene->lights[l].position;
        const float position[3] = {p.x, p.y, p.z};
        ok = pgrid_light_rebuild(&grids->lights[l], grids, scene, position, res, grids->threads);
        if (ok && l + 1 > grids->light_count) grids->light_count = l + 1;
    }
    grids->build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    if (!ok) pgrid_shadows_free_lights(grids);
    return ok || rtt_error_set(err, "%s: out of memory building the light grids", scene->path);
}

bool pgrid_shadows_build(pgrid_shadows *grids, const rtt_scene *scene, const uint8_t *degenerate, uint32_t res,
                         rtt_error *err)
{
    const uint64_t t0 = rtt_clock_ns();
    if (!pgrid_shadows_prepare(grids, scene, degenerate, err)) return false;
    if (!pgrid_shadows_build_lights(grids, scene, res, err)) {
        pgrid_shadows_free(grids);
        return false;
    }
    grids->build_seconds = 1e-9 * (double)(rtt_clock_ns() - t0);
    return true;
}

/* Measured (bench/results/pgrid.md, "Light grid resolution"): on the
 * maps (4k to 35k triangles, large floor and wall triangles) 100 cells a
 * face beat 200 in five rows of six by 1.2 to 1.4x and 400 by 1.3 to 2.2x
 * (a finer grid splits a batch's rays over more cells, so packets run
 * emptier, and references each large triangle from more cells); on the
 * meshes (52k to 89k small triangles) 200 and 400 were within the noise,
 * 100 and 50 slower (the per-cell distance bound is coarser), 800 slower
 * everywhere (its build).  Since the faces no footprint meets keep no
 * cells and the build's footprints run in vectors (a finer grid costs the
 * build less), 300 beat 200 on the three meshes by 0-20% a frame in three
 * rounds, and 64 beat 100 on the maps by 2-8% (one thread and two, both in
 * each run, twice; 32 and 48 lost ctf_inyard 4-15%) (bench/results/pgrid.md,
 * fifth session).  Since the bands lay out only the rows the footprints
 * meet, 400 beat 300 on refined_elephant by 4-7%, within 1% on armadillo,
 * bunny00 2% slower (fifteenth session). */
uint32_t pgrid_light_res_rule(uint32_t triangles)
{
    return triangles < 40000u ? PGRID_LIGHT_RES_MAPS : PGRID_LIGHT_RES_MESHES;
}

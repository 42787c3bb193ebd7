/* Hunt & Mark 2008, section 5.3: the slice-based packet traverser of the
 * soft-shadow light grids (pgrid_soft.h).  A packet is up to 16 / 8 / 4
 * rays (AVX-512 / AVX2 / SSE4.1) of one origin, a shading point's samples of
 * the light in the shader proxy's order.  It walks the slices from the
 * farthest its rays reach (the origin's side) towards the light; per slice
 * each live ray's piece is clipped (in double) to each face's pyramid and
 * projected, the packet's footprint on a face is the union of its rays'
 * rectangles, and every triangle of those cells meets the packet's live
 * lanes once (a 256-entry mailbox per packet) with the watertight test of
 * ../bvh/bvh_isect_wide.h, the reference's arithmetic.  A ray leaves the
 * packet when occluded; the packet ends when every ray has.  The near list
 * comes first. */
#include <math.h>
#include <string.h>

#include "bvh_isect_wide.h"
#include "pgrid_isa.h"
#include "pgrid_soft.h"

#define pgrid_soft_occluded PGRID_ISA(pgrid_soft_occluded)

/* One ray relative to the light, in double: q(t) = o + t d over [t0, t1]. */
typedef struct soft_seg {
    double o[3], d[3], t0, t1;
} soft_seg;

/* The t where |q(t)| <= R: [*a, *b]; false when none. */
static bool ball_interval(const soft_seg *s, double r, double *a, double *b)
{
    const double dd = s->d[0] * s->d[0] + s->d[1] * s->d[1] + s->d[2] * s->d[2];
    if (!(dd > 0.0)) return false;
    const double tc = -(s->o[0] * s->d[0] + s->o[1] * s->d[1] + s->o[2] * s->d[2]) / dd;
    double m2 = 0.0;
    for (int k = 0; k < 3; k++) {
        const double x = s->o[k] + tc * s->d[k];
        m2 += x * x;
    }
    if (!(m2 <= r * r)) return false;
    const double h = sqrt((r * r - m2) / dd);
    *a = tc - h, *b = tc + h;
    return true;
}

/* The hull of the piece of s in slice k (distances widened by E): [*a, *b]. */
static bool slice_piece(const pgrid_soft_light *L, const soft_seg *s, uint32_t k, double *a, double *b)
{
    double lo = s->t0, hi = s->t1, ia, ib;
    if (!(lo <= hi)) return false;
    if (isfinite(L->bound[k + 1])) {
        if (!ball_interval(s, L->bound[k + 1] + L->slack, &ia, &ib)) return false;
        lo = fmax(lo, ia), hi = fmin(hi, ib);
    }
    if (!(lo <= hi)) return false;
    const double inner = L->bound[k] - L->slack;
    if (inner > 0.0 && ball_interval(s, inner, &ia, &ib)) {
        if (ia <= lo && ib >= hi) return false; /* wholly nearer than the slice */
        if (ia <= lo && ib > lo) lo = ib;
        else if (ib >= hi && ia < hi) hi = ia;
    }
    *a = lo, *b = hi;
    return lo <= hi;
}

/* Clips [*a, *b] to alpha + beta t >= 0. */
static bool clip_linear(double alpha, double beta, double *a, double *b)
{
    if (beta > 0.0)
        *a = fmax(*a, -alpha / beta);
    else if (beta < 0.0)
        *b = fmin(*b, -alpha / beta);
    else if (!(alpha >= 0.0))
        return false;
    return *a <= *b;
}

/* Grows face f's rectangle (u0, u1, v0, v1) by s's piece [a, b] on it. */
static void face_piece(const pgrid_soft_light *L, const soft_seg *s, uint32_t f, double a, double b, double rect[4])
{
    const uint32_t axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double sign = (f & 1u) ? -1.0 : 1.0;
    const double ma = sign * s->o[axis], mb = sign * s->d[axis];
    if (!clip_linear(ma - L->near, mb, &a, &b) || !clip_linear(ma - s->o[u], mb - s->d[u], &a, &b) ||
        !clip_linear(ma + s->o[u], mb + s->d[u], &a, &b) || !clip_linear(ma - s->o[v], mb - s->d[v], &a, &b) ||
        !clip_linear(ma + s->o[v], mb + s->d[v], &a, &b))
        return;
    const double t[2] = {a, b};
    for (int e = 0; e < 2; e++) {
        const double major = ma + t[e] * mb;
        const double x = (s->o[u] + t[e] * s->d[u]) / major, y = (s->o[v] + t[e] * s->d[v]) / major;
        rect[0] = fmin(rect[0], x), rect[1] = fmax(rect[1], x);
        rect[2] = fmin(rect[2], y), rect[3] = fmax(rect[3], y);
    }
}

static uint32_t cell_of(double u, uint32_t res)
{
    const double x = floor((u + 1.0) * 0.5 * (double)res);
    return x < 0.0 ? 0u : x > (double)res - 1.0 ? res - 1u : (uint32_t)x;
}

/* Table 5's steps of one ray over its whole segment, occluded or not: per
 * slice and face its piece crosses, |dx| + |dy| + 1 cells (a 2D DDA's). */
static uint64_t ray_steps(const pgrid_soft_light *L, const soft_seg *s)
{
    uint64_t steps = 0;
    for (uint32_t k = 0; k < L->slices; k++) {
        double a, b;
        if (!slice_piece(L, s, k, &a, &b)) continue;
        for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) {
            double rect[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
            face_piece(L, s, f, a, b, rect);
            if (!(rect[0] <= rect[1])) continue;
            steps += (cell_of(rect[1] + 1e-9, L->res) - cell_of(rect[0] - 1e-9, L->res)) +
                     (cell_of(rect[3] + 1e-9, L->res) - cell_of(rect[2] - 1e-9, L->res)) + 1u;
        }
    }
    return steps;
}

/* The mailbox: per entry the triangle, the packet and the lanes it has met. */
enum { MAILBOX = 1024 };
typedef struct mailbox_entry {
    uint32_t tri, packet, lanes;
} mailbox_entry;

typedef struct soft_packet {
    bvh_packet rays;
    bvh_wt_shears shears;
    uint32_t id;
    mailbox_entry mailbox[MAILBOX];
} soft_packet;

/* The lanes of `want` that a triangle of list[0 .. count) occludes, each
 * triangle meeting each lane once per packet. */
static uint32_t test_list(const pgrid_soft *g, const pgrid_soft_light *L, const uint32_t *list, uint32_t count,
                          soft_packet *p, uint32_t want, double reach, pgrid_soft_counts *counts)
{
    uint32_t hit = 0;
    for (uint32_t i = 0; i < count && (hit & want) != want; i++) {
        const uint32_t t = list[i];
        if (L->least[t] > reach) continue; /* beyond every wanted piece */
        mailbox_entry *e = &p->mailbox[t & (MAILBOX - 1u)];
        if (e->tri != t || e->packet != p->id) *e = (mailbox_entry){t, p->id, 0};
        const uint32_t lanes = want & ~hit & ~e->lanes;
        if (!lanes) continue;
        e->lanes |= lanes;
        if (counts) counts->tests += (uint32_t)__builtin_popcount(lanes);
        hit |= bvh_occluded_watertight(&g->tris[t], &p->rays, &p->shears, lanes);
    }
    return hit & want;
}

void pgrid_soft_occluded(const pgrid_soft *grids, uint32_t light, const rtt_ray *rays, uint32_t count,
                         uint8_t *occluded, pgrid_soft_counts *counts);

void pgrid_soft_occluded(const pgrid_soft *grids, uint32_t light, const rtt_ray *rays, uint32_t count,
                         uint8_t *occluded, pgrid_soft_counts *counts)
{
    const pgrid_soft_light *L = &grids->lights[light];
    static _Thread_local soft_packet p; /* 12 KB of mailbox: off the stack, reset by packet id */
    for (uint32_t first = 0; first < count;) {
        if (++p.id == 0) memset(p.mailbox, 0, sizeof p.mailbox), p.id = 1;
        uint32_t n = 1;
        while (n < BVH_W && first + n < count && memcmp(rays[first + n].org, rays[first].org, sizeof rays->org) == 0)
            n++;
        uint32_t live = bvh_packet_load(&p.rays, rays + first, n);
        uint32_t hit = 0;
        soft_seg seg[BVH_W];
        double reach = 0.0;
        for (uint32_t l = 0; l < n; l++) {
            const rtt_ray *r = &rays[first + l];
            soft_seg *s = &seg[l];
            for (int a = 0; a < 3; a++) s->o[a] = (double)r->org[a] - L->position[a], s->d[a] = r->dir[a];
            s->t0 = (double)r->tnear - L->slack, s->t1 = (double)r->tfar + L->slack;
            /* nothing lies beyond the farthest corner: a finite piece for any ray */
            double a, b;
            if (!ball_interval(s, L->far + 4.0 * L->slack, &a, &b) || !(a <= s->t1) || !(b >= s->t0)) {
                s->t0 = 1.0, s->t1 = 0.0; /* empty: only the near list */
                continue;
            }
            s->t0 = fmax(s->t0, a), s->t1 = fmin(s->t1, b);
            /* the farthest the ray reaches from L (the distance is convex along it: an end) */
            for (int e = 0; e < 2; e++) {
                const double t = e ? s->t1 : s->t0;
                double d2 = 0.0;
                for (int c = 0; c < 3; c++) d2 += (s->o[c] + t * s->d[c]) * (s->o[c] + t * s->d[c]);
                reach = fmax(reach, sqrt(d2));
            }
        }
        if (counts) {
            counts->rays += (uint32_t)__builtin_popcount(live);
            for (uint32_t bits = live; bits; bits &= bits - 1u) counts->steps += ray_steps(L, &seg[__builtin_ctz(bits)]);
        }
        if (live) {
            bvh_wt_prepare(&p.rays, live, &p.shears);
            if (L->near_count)
                hit = test_list(grids, L, L->near_list, L->near_count, &p, live, INFINITY, counts);
            /* origins beyond the grid's magnitude: every triangle (pgrid_soft.h) */
            uint32_t wild = 0;
            for (uint32_t l = 0; l < n; l++)
                for (int a = 0; a < 3; a++)
                    if (!(fabs((double)rays[first + l].org[a]) <= L->magnitude)) wild |= (live >> l & 1u) << l;
            for (uint32_t t = 0; wild & ~hit && t < grids->tri_count; t++)
                hit |= bvh_occluded_watertight(&grids->tris[t], &p.rays, &p.shears, wild & ~hit);
            live &= ~wild;
        }
        /* the slices from the origins' side towards the light */
        uint32_t top = L->slices - 1;
        while (top > 0 && L->bound[top] > reach + 4.0 * L->slack) top--;
        for (uint32_t k = top + 1; k-- > 0 && (hit & live) != live;) {
            /* each live ray's cell rectangle per face (x0, x1, y0, y1; empty: x0 > x1), and their union */
            uint32_t cell[PGRID_LIGHT_FACES][BVH_W][4], any[PGRID_LIGHT_FACES][4];
            double far[BVH_W]; /* the farthest each ray's piece in this slice reaches from L */
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) any[f][0] = any[f][2] = UINT32_MAX, any[f][1] = any[f][3] = 0;
            for (uint32_t l = 0; l < n; l++) {
                double a, b;
                const bool piece = ((live & ~hit) >> l & 1u) && slice_piece(L, &seg[l], k, &a, &b);
                far[l] = 0.0;
                for (int e = 0; piece && e < 2; e++) { /* the distance is convex along the ray: an end */
                    const double t = e ? b : a;
                    double d2 = 0.0;
                    for (int c = 0; c < 3; c++) d2 += (seg[l].o[c] + t * seg[l].d[c]) * (seg[l].o[c] + t * seg[l].d[c]);
                    far[l] = fmax(far[l], sqrt(d2) + L->slack);
                }
                for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) {
                    uint32_t *c = cell[f][l];
                    c[0] = 1, c[1] = 0;
                    if (!piece) continue;
                    double rect[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
                    face_piece(L, &seg[l], f, a, b, rect);
                    if (!(rect[0] <= rect[1])) continue;
                    c[0] = cell_of(rect[0] - 1e-9, L->res), c[1] = cell_of(rect[1] + 1e-9, L->res);
                    c[2] = cell_of(rect[2] - 1e-9, L->res), c[3] = cell_of(rect[3] + 1e-9, L->res);
                    if (c[0] < any[f][0]) any[f][0] = c[0];
                    if (c[1] > any[f][1]) any[f][1] = c[1];
                    if (c[2] < any[f][2]) any[f][2] = c[2];
                    if (c[3] > any[f][3]) any[f][3] = c[3];
                }
            }
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES && (hit & live) != live; f++) {
                if (any[f][0] > any[f][1]) continue;
                for (uint32_t y = any[f][2]; y <= any[f][3] && (hit & live) != live; y++)
                    for (uint32_t x = any[f][0]; x <= any[f][1] && (hit & live) != live; x++) {
                        const size_t at = (((size_t)k * PGRID_LIGHT_FACES + f) * L->res + y) * L->res + x;
                        const uint32_t begin = L->cell_first[at], end = L->cell_first[at + 1];
                        uint32_t want = 0; /* the live rays whose own rectangle holds the cell */
                        double reach = 0.0;
                        for (uint32_t bits = live & ~hit; bits; bits &= bits - 1u) {
                            const uint32_t l = (uint32_t)__builtin_ctz(bits);
                            const uint32_t *c = cell[f][l];
                            if (c[0] <= x && x <= c[1] && c[2] <= y && y <= c[3]) want |= 1u << l, reach = fmax(reach, far[l]);
                        }
                        if (!want) continue;
                        if (counts) counts->cells += (uint32_t)__builtin_popcount(want);
                        if (begin != end)
                            hit |= test_list(grids, L, L->refs + begin, end - begin, &p, want, reach, counts);
                    }
            }
        }
        for (uint32_t l = 0; l < n; l++) occluded[first + l] = (uint8_t)(hit >> l & 1u);
        first += n;
    }
}

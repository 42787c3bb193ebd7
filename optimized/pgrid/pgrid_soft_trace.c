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

typedef struct soft_packet {
    bvh_packet rays;
    bvh_wt_shears shears;
    uint32_t mailbox[256];
} soft_packet;

/* The lanes of `active` that a triangle of list[0 .. count) occludes. */
static uint32_t test_list(const pgrid_soft *g, const uint32_t *list, uint32_t count, soft_packet *p, uint32_t active,
                          pgrid_soft_counts *counts, uint32_t lanes)
{
    uint32_t hit = 0;
    for (uint32_t i = 0; i < count && (hit & active) != active; i++) {
        const uint32_t t = list[i];
        if (p->mailbox[t & 255u] == t) continue;
        p->mailbox[t & 255u] = t;
        if (counts) counts->tests += lanes;
        hit |= bvh_occluded_watertight(&g->tris[t], &p->rays, &p->shears, active & ~hit);
    }
    return hit & active;
}

void pgrid_soft_occluded(const pgrid_soft *grids, uint32_t light, const rtt_ray *rays, uint32_t count,
                         uint8_t *occluded, pgrid_soft_counts *counts);

void pgrid_soft_occluded(const pgrid_soft *grids, uint32_t light, const rtt_ray *rays, uint32_t count,
                         uint8_t *occluded, pgrid_soft_counts *counts)
{
    const pgrid_soft_light *L = &grids->lights[light];
    soft_packet p;
    for (uint32_t first = 0; first < count;) {
        uint32_t n = 1;
        while (n < BVH_W && first + n < count && memcmp(rays[first + n].org, rays[first].org, sizeof rays->org) == 0)
            n++;
        const uint32_t live = bvh_packet_load(&p.rays, rays + first, n);
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
        const uint32_t lanes_live = (uint32_t)__builtin_popcount(live);
        if (counts) counts->rays += lanes_live;
        if (live) {
            bvh_wt_prepare(&p.rays, live, &p.shears);
            memset(p.mailbox, 0xff, sizeof p.mailbox);
            if (L->near_count) hit = test_list(grids, L->near_list, L->near_count, &p, live, counts, lanes_live);
        }
        /* the slices from the origins' side towards the light */
        uint32_t top = L->slices - 1;
        while (top > 0 && L->bound[top] > reach + 4.0 * L->slack) top--;
        for (uint32_t k = top + 1; k-- > 0 && (hit & live) != live;) {
            double rect[PGRID_LIGHT_FACES][4];
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++)
                rect[f][0] = rect[f][2] = INFINITY, rect[f][1] = rect[f][3] = -INFINITY;
            for (uint32_t l = 0; l < n; l++) {
                double a, b;
                if (!((live & ~hit) >> l & 1u) || !slice_piece(L, &seg[l], k, &a, &b)) continue;
                for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) face_piece(L, &seg[l], f, a, b, rect[f]);
            }
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES && (hit & live) != live; f++) {
                if (!(rect[f][0] <= rect[f][1])) continue;
                const uint32_t x0 = cell_of(rect[f][0] - 1e-9, L->res), x1 = cell_of(rect[f][1] + 1e-9, L->res);
                const uint32_t y0 = cell_of(rect[f][2] - 1e-9, L->res), y1 = cell_of(rect[f][3] + 1e-9, L->res);
                for (uint32_t y = y0; y <= y1 && (hit & live) != live; y++)
                    for (uint32_t x = x0; x <= x1 && (hit & live) != live; x++) {
                        const size_t cell = (((size_t)k * PGRID_LIGHT_FACES + f) * L->res + y) * L->res + x;
                        const uint32_t begin = L->cell_first[cell], end = L->cell_first[cell + 1];
                        const uint32_t left = live & ~hit;
                        if (counts) counts->cells += (uint32_t)__builtin_popcount(left);
                        if (begin != end)
                            hit |= test_list(grids, L->refs + begin, end - begin, &p, left, counts,
                                             (uint32_t)__builtin_popcount(left));
                    }
            }
        }
        for (uint32_t l = 0; l < n; l++) occluded[first + l] = (uint8_t)(hit >> l & 1u);
        first += n;
    }
}

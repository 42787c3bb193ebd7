/* Hunt & Mark 2008, section 5.3: the slice-based packet traverser of the
 * soft-shadow light grids (pgrid_soft.h).  A packet is up to 16 / 8 / 4
 * rays (AVX-512 / AVX2 / SSE4.1) of one origin, a shading point's samples of
 * the light in the shader proxy's order.  It walks the slices from the
 * farthest its rays reach (the origin's side) towards the light; per slice
 * each live ray's piece is clipped (in double) to each face's pyramid and
 * projected; on a grid of up to 512 cells a side each ray's cells are the
 * ones its projected segment crosses (a column scan, cover_of), visited
 * once per packet for every lane whose segment crosses them, the empty
 * ones skipped at once (finer grids take the rectangle round each ray's
 * segment and the union of the packet's); every triangle of those cells
 * meets the packet's live lanes once (a 1024-entry mailbox per packet)
 * with the watertight test of ../bvh/bvh_isect_wide.h, the reference's
 * arithmetic.  A ray leaves the
 * packet when occluded; the packet ends when every ray has.  The near list
 * comes first. */
#include <math.h>
#include <string.h>

#include "bvh_isect_wide.h"
#include "pgrid_isa.h"
#include "pgrid_soft.h"

#define pgrid_soft_occluded PGRID_ISA(pgrid_soft_occluded)

/* fmax and fmin inline (libm's are calls): the same answers, a NaN
 * operand giving the other. */
static inline double dmax(double a, double b) { return a > b || b != b ? a : b; }
static inline double dmin(double a, double b) { return a < b || b != b ? a : b; }

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
        lo = dmax(lo, ia), hi = dmin(hi, ib);
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
        *a = dmax(*a, -alpha / beta);
    else if (beta < 0.0)
        *b = dmin(*b, -alpha / beta);
    else if (!(alpha >= 0.0))
        return false;
    return *a <= *b;
}

/* The ends of s's piece [a, b] on face f, projected (face coordinates in
 * [-1, 1]): false when the piece misses the face's pyramid.  A line
 * projects to a line, so the piece's projection is the segment between
 * them. */
static bool face_segment(const pgrid_soft_light *L, const soft_seg *s, uint32_t f, double a, double b, double xy[2][2])
{
    const uint32_t axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double sign = (f & 1u) ? -1.0 : 1.0;
    const double ma = sign * s->o[axis], mb = sign * s->d[axis];
    if (!clip_linear(ma - L->near, mb, &a, &b) || !clip_linear(ma - s->o[u], mb - s->d[u], &a, &b) ||
        !clip_linear(ma + s->o[u], mb + s->d[u], &a, &b) || !clip_linear(ma - s->o[v], mb - s->d[v], &a, &b) ||
        !clip_linear(ma + s->o[v], mb + s->d[v], &a, &b))
        return false;
    const double t[2] = {a, b};
    for (int e = 0; e < 2; e++) {
        const double major = ma + t[e] * mb;
        xy[e][0] = (s->o[u] + t[e] * s->d[u]) / major, xy[e][1] = (s->o[v] + t[e] * s->d[v]) / major;
    }
    return true;
}

/* Grows face f's rectangle (u0, u1, v0, v1) by s's piece [a, b] on it. */
static void face_piece(const pgrid_soft_light *L, const soft_seg *s, uint32_t f, double a, double b, double rect[4])
{
    double xy[2][2];
    if (!face_segment(L, s, f, a, b, xy)) return;
    for (int e = 0; e < 2; e++) {
        rect[0] = dmin(rect[0], xy[e][0]), rect[1] = dmax(rect[1], xy[e][0]);
        rect[2] = dmin(rect[2], xy[e][1]), rect[3] = dmax(rect[3], xy[e][1]);
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

/* A ray's cells on one face, column by column (the column scan below):
 * columns x0 .. x1, in column x the rows lo[x - x0] .. hi[x - x0]. */
enum { COVER_RES_MAX = 512 }; /* finer grids take the rectangles */
typedef struct cover {
    uint32_t x0, x1;
    uint16_t lo[COVER_RES_MAX], hi[COVER_RES_MAX];
} cover;

typedef struct soft_packet {
    bvh_packet rays;
    bvh_wt_shears shears;
    uint32_t id;
    mailbox_entry mailbox[MAILBOX];
    cover covers[BVH_W];
} soft_packet;

/* The cells of the face that the segment xy[0] - xy[1] crosses, widened by
 * 1e-9 of the face's coordinates (the rectangles' margin) across and
 * along: per column the rows of the segment's part over the column's
 * widened span.  About |dx| + |dy| + 1 cells, where the rectangle around
 * the segment has |dx| |dy|. */
static void cover_of(const double xy[2][2], uint32_t res, cover *c)
{
    const int lo_end = xy[0][0] <= xy[1][0] ? 0 : 1;
    const double xa = xy[lo_end][0], ya = xy[lo_end][1], xb = xy[1 - lo_end][0], yb = xy[1 - lo_end][1];
    const double margin = 1e-9, span = xb - xa;
    c->x0 = cell_of(xa - margin, res), c->x1 = cell_of(xb + margin, res);
    for (uint32_t x = c->x0; x <= c->x1; x++) {
        /* the column's face coordinates [-1 + 2x/res, -1 + 2(x+1)/res], widened */
        const double left = dmax(xa, -1.0 + 2.0 * x / res - margin), right = dmin(xb, -1.0 + 2.0 * (x + 1) / res + margin);
        double ylo = ya, yhi = yb;
        if (span > 0.0) {
            const double ul = dmin(dmax((left - xa) / span, 0.0), 1.0), ur = dmin(dmax((right - xa) / span, 0.0), 1.0);
            ylo = ya + ul * (yb - ya), yhi = ya + ur * (yb - ya);
        }
        if (ylo > yhi) {
            const double swap = ylo;
            ylo = yhi, yhi = swap;
        }
        c->lo[x - c->x0] = (uint16_t)cell_of(ylo - margin, res), c->hi[x - c->x0] = (uint16_t)cell_of(yhi + margin, res);
    }
}

static inline bool cover_holds(const cover *c, uint32_t x, uint32_t y)
{
    return c->x0 <= x && x <= c->x1 && c->lo[x - c->x0] <= y && y <= c->hi[x - c->x0];
}

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
    static _Thread_local soft_packet packet; /* 45 KB of mailbox and covers: off the stack, reset by packet id */
    soft_packet *const pp = &packet;         /* the thread-local address once, not at every use */
    for (uint32_t first = 0; first < count;) {
        if (++pp->id == 0) memset(pp->mailbox, 0, sizeof pp->mailbox), pp->id = 1;
        uint32_t n = 1;
        while (n < BVH_W && first + n < count && memcmp(rays[first + n].org, rays[first].org, sizeof rays->org) == 0)
            n++;
        uint32_t live = bvh_packet_load(&pp->rays, rays + first, n);
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
            s->t0 = dmax(s->t0, a), s->t1 = dmin(s->t1, b);
            /* the farthest the ray reaches from L (the distance is convex along it: an end) */
            for (int e = 0; e < 2; e++) {
                const double t = e ? s->t1 : s->t0;
                double d2 = 0.0;
                for (int c = 0; c < 3; c++) d2 += (s->o[c] + t * s->d[c]) * (s->o[c] + t * s->d[c]);
                reach = dmax(reach, sqrt(d2));
            }
        }
        if (counts) {
            counts->rays += (uint32_t)__builtin_popcount(live);
            for (uint32_t bits = live; bits; bits &= bits - 1u) counts->steps += ray_steps(L, &seg[__builtin_ctz(bits)]);
        }
        if (live) {
            bvh_wt_prepare(&pp->rays, live, &pp->shears);
            if (L->near_count)
                hit = test_list(grids, L, L->near_list, L->near_count, pp, live, INFINITY, counts);
            /* origins beyond the grid's magnitude: every triangle (pgrid_soft.h) */
            uint32_t wild = 0;
            for (uint32_t l = 0; l < n; l++)
                for (int a = 0; a < 3; a++)
                    if (!(fabs((double)rays[first + l].org[a]) <= L->magnitude)) wild |= (live >> l & 1u) << l;
            for (uint32_t t = 0; wild & ~hit && t < grids->tri_count; t++)
                hit |= bvh_occluded_watertight(&grids->tris[t], &pp->rays, &pp->shears, wild & ~hit);
            live &= ~wild;
        }
        /* the slices from the origins' side towards the light */
        uint32_t top = L->slices - 1;
        while (top > 0 && L->bound[top] > reach + 4.0 * L->slack) top--;
        for (uint32_t k = top + 1; k-- > 0 && (hit & live) != live;) {
            double far[BVH_W]; /* the farthest each ray's piece in this slice reaches from L */
            double piece_a[BVH_W], piece_b[BVH_W]; /* each ray's piece in this slice */
            uint32_t pieces = 0;                   /* the live rays with a piece in it */
            for (uint32_t l = 0; l < n; l++) {
                double a = 0.0, b = 0.0;
                const bool piece = ((live & ~hit) >> l & 1u) && slice_piece(L, &seg[l], k, &a, &b);
                far[l] = 0.0, piece_a[l] = a, piece_b[l] = b, pieces |= (uint32_t)piece << l;
                for (int e = 0; piece && e < 2; e++) { /* the distance is convex along the ray: an end */
                    const double t = e ? b : a;
                    double d2 = 0.0;
                    for (int c = 0; c < 3; c++) d2 += (seg[l].o[c] + t * seg[l].d[c]) * (seg[l].o[c] + t * seg[l].d[c]);
                    far[l] = dmax(far[l], sqrt(d2) + L->slack);
                }
            }
            if (L->res <= COVER_RES_MAX) {
                /* each ray's own cells (a column scan of its segment), each cell once per packet: a cell
                 * an earlier lane's scan went through was tested then for every lane whose scan holds it */
                for (uint32_t f = 0; f < PGRID_LIGHT_FACES && (hit & live) != live; f++) {
                    uint32_t scanned = 0, lanes = 0;
                    for (uint32_t bits = pieces; bits; bits &= bits - 1u) {
                        const uint32_t l = (uint32_t)__builtin_ctz(bits);
                        double xy[2][2];
                        if (!face_segment(L, &seg[l], f, piece_a[l], piece_b[l], xy) || xy[0][0] != xy[0][0] ||
                            xy[0][1] != xy[0][1] || xy[1][0] != xy[1][0] || xy[1][1] != xy[1][1])
                            continue; /* off the face, or a NaN end (as face_piece leaves its rectangle empty) */
                        cover_of(xy, L->res, &pp->covers[l]);
                        lanes |= 1u << l;
                    }
                    for (uint32_t order = lanes; order && (hit & live) != live; order &= order - 1u) {
                        const uint32_t l = (uint32_t)__builtin_ctz(order);
                        const cover *c = &pp->covers[l];
                        for (uint32_t x = c->x0; x <= c->x1 && (hit & live) != live; x++)
                            for (uint32_t y = c->lo[x - c->x0]; y <= c->hi[x - c->x0] && (hit & live) != live; y++) {
                                const size_t at = (((size_t)k * PGRID_LIGHT_FACES + f) * L->res + y) * L->res + x;
                                const uint32_t begin = L->cell_first[at], end = L->cell_first[at + 1];
                                if (begin == end && !counts) continue; /* an empty cell: nothing to test */
                                bool done = false;
                                for (uint32_t e = scanned; e && !done; e &= e - 1u) done = cover_holds(&pp->covers[__builtin_ctz(e)], x, y);
                                if (done) continue;
                                uint32_t want = 0;
                                double reach = 0.0;
                                for (uint32_t bits = lanes & live & ~hit; bits; bits &= bits - 1u) {
                                    const uint32_t m = (uint32_t)__builtin_ctz(bits);
                                    if (m == l || cover_holds(&pp->covers[m], x, y)) {
                                        want |= 1u << m;
                                        reach = far[m] > reach ? far[m] : reach;
                                    }
                                }
                                if (!want) continue;
                                if (counts) counts->cells += (uint32_t)__builtin_popcount(want);
                                if (begin != end)
                                    hit |= test_list(grids, L, L->refs + begin, end - begin, pp, want, reach, counts);
                            }
                        scanned |= 1u << l;
                    }
                }
                continue;
            }
            /* finer grids: each live ray's cell rectangle per face (x0, x1, y0, y1; empty: x0 > x1), and their union */
            uint32_t cell[PGRID_LIGHT_FACES][BVH_W][4], any[PGRID_LIGHT_FACES][4];
            for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) any[f][0] = any[f][2] = UINT32_MAX, any[f][1] = any[f][3] = 0;
            for (uint32_t l = 0; l < n; l++) {
                for (uint32_t f = 0; f < PGRID_LIGHT_FACES; f++) {
                    uint32_t *c = cell[f][l];
                    c[0] = 1, c[1] = 0;
                    if (!(pieces >> l & 1u)) continue;
                    double rect[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
                    face_piece(L, &seg[l], f, piece_a[l], piece_b[l], rect);
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
                            if (c[0] <= x && x <= c[1] && c[2] <= y && y <= c[3]) want |= 1u << l, reach = dmax(reach, far[l]);
                        }
                        if (!want) continue;
                        if (counts) counts->cells += (uint32_t)__builtin_popcount(want);
                        if (begin != end)
                            hit |= test_list(grids, L, L->refs + begin, end - begin, pp, want, reach, counts);
                    }
            }
        }
        for (uint32_t l = 0; l < n; l++) occluded[first + l] = (uint8_t)(hit >> l & 1u);
        first += n;
    }
}

/* The comparison of one engine's hits with the oracle's: the tolerance on t,
 * the per-ray categories (agree, tie, boundary, t-mismatch, grazing and
 * other hit/miss); conform_judge.c judges rows with them.  The rules are
 * stated in conformance/README.md; change both together. */
#include <math.h>
#include <string.h>

#include "conform.h"
#include "rtt/reference.h"

/* Relative precision the tolerance allows: about 170 float ulps. */
#define T_RELATIVE 1e-5
/* A hit/miss is grazing when the hit lies this many t-tolerances (in world
 * units) from an edge of its triangle, or the ray is this close to parallel
 * to the triangle's plane (|cos| of the angle to the plane's normal). */
#define GRAZING_FACTOR 10.0
#define GRAZING_COSINE 1e-4

static const char *const category_names[RTT_CONFORM_CATEGORY_COUNT] = {
    "agree", "tie", "boundary", "t-mismatch", "hit/miss grazing", "hit/miss other", "unspecified",
};

const char *rtt_conform_category_name(rtt_conform_category c)
{
    return (unsigned)c < RTT_CONFORM_CATEGORY_COUNT ? category_names[c] : "unknown";
}

float rtt_conform_scene_magnitude(const rtt_scene *scene)
{
    if (rtt_bounds_is_empty(scene->bounds)) return 0.0f;
    float m = 0.0f;
    for (int a = 0; a < 3; a++) {
        m = fmaxf(m, fabsf(rtt_v3_get(scene->bounds.lo, a)));
        m = fmaxf(m, fabsf(rtt_v3_get(scene->bounds.hi, a)));
    }
    return m;
}

static double dir_length(const rtt_ray *r)
{
    double x = r->dir[0], y = r->dir[1], z = r->dir[2];
    return sqrt(x * x + y * y + z * z);
}

static double org_magnitude(const rtt_ray *r)
{
    return fmax(fabs((double)r->org[0]), fmax(fabs((double)r->org[1]), fabs((double)r->org[2])));
}

double rtt_conform_t_tolerance(const rtt_ray *r, double t, double magnitude)
{
    double len = dir_length(r);
    return T_RELATIVE * (fabs(t) + (org_magnitude(r) + magnitude) / len);
}

/* The ray against the plane of triangle prim in double precision: plane t,
 * barycentrics of the plane point, distance from it to the nearest edge
 * (negative outside), and |cos| between ray and normal.  False for a
 * degenerate triangle or a ray parallel to it. */
typedef struct plane_hit {
    double t, b[3], edge_distance, cosine;
} plane_hit;

static bool plane_intersect(const rtt_scene *scene, const rtt_ray *r, uint32_t prim, plane_hit *out)
{
    if (prim >= scene->triangle_count) return false;
    rtt_vec3 tri[3];
    rtt_scene_triangle(scene, prim, tri);
    double p[3][3] = {{tri[0].x, tri[0].y, tri[0].z}, {tri[1].x, tri[1].y, tri[1].z}, {tri[2].x, tri[2].y, tri[2].z}};
    double e1[3], e2[3], o[3], d[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = p[1][k] - p[0][k];
        e2[k] = p[2][k] - p[0][k];
        o[k] = r->org[k];
        d[k] = r->dir[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double area2 = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    double dlen = dir_length(r);
    if (!(area2 > 0.0) || dn == 0.0 || !(dlen > 0.0) || !isfinite(dn)) return false;
    out->cosine = fabs(dn) / (area2 * dlen);
    double x[3];
    out->t = ((p[0][0] - o[0]) * n[0] + (p[0][1] - o[1]) * n[1] + (p[0][2] - o[2]) * n[2]) / dn;
    for (int k = 0; k < 3; k++) x[k] = o[k] + out->t * d[k];
    /* barycentrics from sub-triangle areas signed along n */
    double min_distance = INFINITY;
    for (int i = 0; i < 3; i++) {
        const double *a = p[(i + 1) % 3], *b = p[(i + 2) % 3];
        double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ax[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
        double c[3] = {ab[1] * ax[2] - ab[2] * ax[1], ab[2] * ax[0] - ab[0] * ax[2], ab[0] * ax[1] - ab[1] * ax[0]};
        double signed_area2 = (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / area2;
        out->b[i] = signed_area2 / area2;
        double edge = sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
        double distance = edge > 0.0 ? signed_area2 / edge : -INFINITY;
        if (distance < min_distance) min_distance = distance;
    }
    out->edge_distance = min_distance;
    return isfinite(out->t);
}

/* World-space tolerance around a hit at t (the t tolerance times |dir|). */
static double position_tolerance(const rtt_ray *r, double t, double magnitude)
{
    return rtt_conform_t_tolerance(r, t, magnitude) * dir_length(r);
}

static bool is_hit(const rtt_hit *h) { return h->prim != RTT_MISS; }

/* A hit within tolerance of tnear or tfar is unspecified.  Near tnear the
 * tolerance is divided by the cosine between the ray and the hit's plane
 * (as for same-prim hits below): a ray leaving a surface it starts on at a
 * grazing angle re-crosses that plane at an ill-conditioned t. */
static bool at_boundary(const rtt_scene *scene, const rtt_ray *r, const rtt_hit *h, double magnitude)
{
    if (!is_hit(h)) return false;
    double tol = rtt_conform_t_tolerance(r, h->t, magnitude);
    if (isfinite(r->tfar) && (double)r->tfar - h->t <= tol) return true;
    if ((double)h->t - r->tnear <= tol) return true;
    plane_hit ph;
    return plane_intersect(scene, r, h->prim, &ph) && (double)h->t - r->tnear <= tol / fmax(ph.cosine, GRAZING_COSINE);
}

/* Is prim really hit near t?  Either the watertight test hits it within
 * tolerance of t, or the double-precision plane point at t lies inside the
 * triangle or within the grazing distance of an edge. */
static bool verified_hit(const rtt_scene *scene, double magnitude, const rtt_ray *r, uint32_t prim, double t)
{
    if (prim >= scene->triangle_count) return false;
    double tol = rtt_conform_t_tolerance(r, t, magnitude);
    rtt_vec3 tri[3];
    rtt_scene_triangle(scene, prim, tri);
    rtt_ray wide = *r;
    wide.tnear = -INFINITY;
    wide.tfar = INFINITY;
    float wt, wu, wv;
    if (rtt_reference_intersect_triangle(&wide, tri, &wt, &wu, &wv) && fabs(wt - t) <= tol) return true;
    plane_hit ph;
    if (!plane_intersect(scene, r, prim, &ph)) return false;
    return fabs(ph.t - t) <= tol && ph.edge_distance >= -GRAZING_FACTOR * position_tolerance(r, t, magnitude);
}

static bool grazing_hit(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *h)
{
    plane_hit ph;
    if (!plane_intersect(scene, r, h->prim, &ph)) return h->prim < scene->triangle_count && isfinite(h->t);
    if (ph.cosine < GRAZING_COSINE) return true;
    return fabs(ph.edge_distance) <= GRAZING_FACTOR * position_tolerance(r, ph.t, magnitude);
}

/* Pass-through: the ray crosses the plane of the nearer hit's prim (in
 * double precision) before the farther hit, within the grazing distance of
 * one of its edges, so one engine hit that triangle at its edge and the
 * other slipped past the edge.  The crossing's own t is used, not the
 * reported one, which is ill-conditioned on needles. */
static bool passes_an_edge(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *nearer,
                           const rtt_hit *farther)
{
    plane_hit ph;
    if (!plane_intersect(scene, r, nearer->prim, &ph)) return false;
    if (!(ph.t < (double)farther->t)) return false;
    return ph.cosine < GRAZING_COSINE ||
           fabs(ph.edge_distance) <= GRAZING_FACTOR * position_tolerance(r, ph.t, magnitude);
}

/* A tie at one crossing: the planes of both prims are crossed (in double
 * precision) at the same t within tolerance, at a point on each triangle
 * (or within the grazing distance of its edges), and each engine's t is its
 * own prim's crossing within the tolerance divided by that crossing's
 * cosine (at most by 1/GRAZING_COSINE): the allowance same-prim hits get
 * below, for the same reason.  Near a shared vertex or edge at a grazing
 * angle the two engines then report t values further apart than the plain
 * tolerance although they hit neighbours at the same point.  The crossings
 * themselves must coincide within the plain tolerance, so a hit on a
 * triangle crossed elsewhere along the ray stays a t-mismatch. */
static bool tie_at_one_crossing(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *test,
                                const rtt_hit *oracle)
{
    plane_hit a, b;
    if (!plane_intersect(scene, r, test->prim, &a) || !plane_intersect(scene, r, oracle->prim, &b)) return false;
    double t_max = fmax(fmax(fabs(a.t), fabs(b.t)), fmax(fabs((double)test->t), fabs((double)oracle->t)));
    double tol = rtt_conform_t_tolerance(r, t_max, magnitude);
    double reach = GRAZING_FACTOR * position_tolerance(r, t_max, magnitude);
    return fabs(a.t - b.t) <= tol && a.edge_distance >= -reach && b.edge_distance >= -reach &&
           fabs((double)test->t - a.t) <= tol / fmax(a.cosine, GRAZING_COSINE) &&
           fabs((double)oracle->t - b.t) <= tol / fmax(b.cosine, GRAZING_COSINE);
}

/* Two hits on the same prim at different t still agree when the plane
 * crossing is ill-conditioned: a position error e normal to the plane moves
 * t by e / (|dir| cos), so the tolerance is divided by the cosine (at most
 * by 1/GRAZING_COSINE).  They also agree when the test's t is the exact
 * (double precision) crossing: the oracle's t is then the one that is off
 * (the watertight test derives t from barycentrics, whose error on needle
 * triangles grows as 1/area). */
static bool same_prim_same_crossing(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *test,
                                    const rtt_hit *oracle)
{
    plane_hit ph;
    if (!plane_intersect(scene, r, test->prim, &ph)) return false;
    double cosine = fmax(ph.cosine, GRAZING_COSINE);
    double tol = rtt_conform_t_tolerance(r, fmax(fabs((double)test->t), fabs((double)oracle->t)), magnitude) / cosine;
    return fabs((double)test->t - oracle->t) <= tol || fabs((double)test->t - ph.t) <= tol;
}

rtt_conform_category rtt_conform_classify(const rtt_scene *scene, double magnitude, const rtt_ray *r,
                                          const rtt_hit *test, const rtt_hit *oracle)
{
    bool th = is_hit(test), oh = is_hit(oracle);
    if (!th && !oh) return RTT_CONFORM_AGREE;
    if (at_boundary(scene, r, test, magnitude) || at_boundary(scene, r, oracle, magnitude)) return RTT_CONFORM_BOUNDARY;
    if (th && oh) {
        double tol = rtt_conform_t_tolerance(r, fmax(fabs((double)test->t), fabs((double)oracle->t)), magnitude);
        bool same_t = fabs((double)test->t - oracle->t) <= tol;
        if (test->prim == oracle->prim)
            return same_t || same_prim_same_crossing(scene, magnitude, r, test, oracle) ? RTT_CONFORM_AGREE
                                                                                        : RTT_CONFORM_T_MISMATCH;
        if (same_t && verified_hit(scene, magnitude, r, test->prim, test->t) &&
            verified_hit(scene, magnitude, r, oracle->prim, oracle->t))
            return RTT_CONFORM_TIE;
        /* Pass-through: one engine hit a triangle at its edge, the other
         * slipped through that edge to a farther hit.  It is a hit/miss on
         * the nearer triangle, so it counts as grazing. */
        const rtt_hit *nearer = test->t < oracle->t ? test : oracle, *farther = nearer == test ? oracle : test;
        if (!same_t && passes_an_edge(scene, magnitude, r, nearer, farther)) return RTT_CONFORM_GRAZING;
        /* Neighbours hit at the same point, their t apart only by the
         * ill-conditioning of a grazing crossing.  Tried last, so that it
         * only decides rays that would otherwise be t-mismatches. */
        return tie_at_one_crossing(scene, magnitude, r, test, oracle) ? RTT_CONFORM_TIE : RTT_CONFORM_T_MISMATCH;
    }
    const rtt_hit *h = th ? test : oracle;
    return grazing_hit(scene, magnitude, r, h) ? RTT_CONFORM_GRAZING : RTT_CONFORM_HITMISS_OTHER;
}

bool rtt_conform_referee_accepts(const rtt_scene *scene, double magnitude, const rtt_ray *r, const rtt_hit *h,
                                 const rtt_conform_referee_hit *referee)
{
    rtt_hit decided = rtt_conform_referee_as_hit(referee);
    rtt_conform_category c = rtt_conform_classify(scene, magnitude, r, h, &decided);
    return c == RTT_CONFORM_AGREE || c == RTT_CONFORM_TIE || c == RTT_CONFORM_BOUNDARY;
}

/* Brute-force oracle: every ray against every triangle, and the rules an
 * engine's answer must satisfy (see fuzz_oracle.h for the tolerances). */
#include "fuzz_oracle.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_common.h"
#include "rtt/reference.h"

#define T_TOLERANCE 1e-4
#define EDGE_TOLERANCE 1e-4
#define EXACT_EDGE_TOLERANCE 1e-6
#define GRAZING_TOLERANCE 1e-5
#define CHECKED_MAGNITUDE 1e30f
#define SMALLEST_CHECKED_DIRECTION 1e-30f
#define SMALLEST_CHECKED_DISTANCE 1e-30
#define ROUNDED_POINT_ULPS 8.0

typedef struct ray_triangle {
    bool hit;           /* the watertight test's verdict */
    float t;            /* its t when hit */
    bool near_inside;   /* double-precision plane hit within EDGE_TOLERANCE of the triangle */
    bool near_edge;     /* ... and within it of an edge (or grazing / degenerate) */
    bool on_edge;       /* within EXACT_EDGE_TOLERANCE of an edge or vertex */
    bool beyond_range;  /* a coordinate past CHECKED_MAGNITUDE: any answer is acceptable */
    double plane_t;     /* double-precision distance to the triangle's plane */
    double t_slack;     /* how far a lenient engine's t may be off (rounded_point_tolerance) */
} ray_triangle;

struct fuzz_oracle {
    const rtt_scene *scene;
    const rtt_ray *rays;
    size_t ray_count;
    uint32_t triangle_count;
    double scene_scale;
    ray_triangle *table;   /* ray_count x triangle_count */
};

static double max_abs3(const float v[3])
{
    double m = 0.0;
    for (int k = 0; k < 3; k++)
        if (fabs((double)v[k]) > m)
            m = fabs((double)v[k]);
    return m;
}

static double tolerance(const fuzz_oracle *o, const rtt_ray *ray, double t)
{
    double s = fmax(o->scene_scale, max_abs3(ray->org));
    double d = sqrt((double)ray->dir[0] * ray->dir[0] + (double)ray->dir[1] * ray->dir[1] +
                    (double)ray->dir[2] * ray->dir[2]);
    double scale = d > 0.0 && isfinite(s / d) ? s / d : 0.0;
    return T_TOLERANCE * ((isfinite(t) ? fabs(t) : 0.0) + scale);
}

static double triangle_magnitude(const rtt_vec3 tri[3])
{
    double m = 0.0;
    for (int i = 0; i < 3; i++) {
        float v[3] = { tri[i].x, tri[i].y, tri[i].z };
        m = fmax(m, max_abs3(v));
    }
    return m;
}

static double length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* The lenient engines test the edges on the float hit point o + t d, which
 * is off by a few ulps of the largest coordinate involved (origin, hit
 * point, vertices) and more when t itself is off, i.e. at grazing incidence
 * (1 / cos, here |e1||e2||d| / |det|).  Far from the origin that is a
 * sizeable part of a small triangle (a unit triangle at 1e7, where the ulp
 * is 1).  Returns that distance as a barycentric margin: distance over the
 * smallest altitude (2 area / longest edge). */
static double rounded_point_tolerance(const rtt_ray *ray, const rtt_vec3 tri[3], double plane_t, double det,
                                      double norms, double *t_slack)
{
    double magnitude = max_abs3(ray->org);
    for (int i = 0; i < 3; i++) {
        float v[3] = { tri[i].x, tri[i].y, tri[i].z };
        magnitude = fmax(magnitude, max_abs3(v));
    }
    if (isfinite(plane_t))
        for (int k = 0; k < 3; k++)
            magnitude = fmax(magnitude, fabs((double)ray->org[k] + plane_t * ray->dir[k]));
    double distance = ROUNDED_POINT_ULPS * FLT_EPSILON * magnitude * (1.0 + norms / fabs(det));
    /* the same error along the ray: t = plane distance / (d . n) is off by
     * that much over |d| (grazing rays, found with a ray from 1e-3 off a
     * triangle's plane aimed at its far vertex) */
    double d_length = sqrt((double)ray->dir[0] * ray->dir[0] + (double)ray->dir[1] * ray->dir[1] +
                           (double)ray->dir[2] * ray->dir[2]);
    *t_slack = d_length > 0.0 ? distance / d_length : 0.0;
    double e[3][3], longest = 0.0;
    for (int i = 0; i < 3; i++) {
        const rtt_vec3 a = tri[i], b = tri[(i + 1) % 3];
        e[i][0] = (double)b.x - a.x, e[i][1] = (double)b.y - a.y, e[i][2] = (double)b.z - a.z;
        longest = fmax(longest, length3(e[i]));
    }
    double n[3] = { e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                    e[0][0] * e[1][1] - e[0][1] * e[1][0] };
    double twice_area = length3(n);
    return twice_area > 0.0 ? distance * longest / twice_area : INFINITY;
}

/* Moeller-Trumbore in double, without rejecting anything: where the ray
 * meets the triangle's plane, and how close to the triangle that is. */
static void plane_test(const rtt_ray *ray, const rtt_vec3 tri[3], ray_triangle *out)
{
    double o[3] = { ray->org[0], ray->org[1], ray->org[2] };
    double d[3] = { ray->dir[0], ray->dir[1], ray->dir[2] };
    double p0[3] = { tri[0].x, tri[0].y, tri[0].z };
    double e1[3] = { tri[1].x - p0[0], tri[1].y - p0[1], tri[1].z - p0[2] };
    double e2[3] = { tri[2].x - p0[0], tri[2].y - p0[1], tri[2].z - p0[2] };
    double pv[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0] };
    double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    double norms = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]) *
                   sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]) *
                   sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    out->near_inside = false;
    out->near_edge = false;
    out->on_edge = false;
    out->beyond_range = false;
    out->plane_t = NAN;
    out->t_slack = 0.0;
    if (!isfinite(det) || !isfinite(norms))
        return;
    out->beyond_range = triangle_magnitude(tri) > CHECKED_MAGNITUDE;
    if (fabs(det) <= GRAZING_TOLERANCE * norms || out->beyond_range) {
        /* edge-on, degenerate, or past 1e30 where float records overflow:
         * unspecified, for strict engines too (such a triangle is all edge:
         * a sliver 5e-41 wide seen face-on was hit by the reference's float
         * test and dropped by the optimized tree's record check) */
        out->near_inside = out->near_edge = out->on_edge = true;
        return;
    }
    double tv[3] = { o[0] - p0[0], o[1] - p0[1], o[2] - p0[2] };
    double qv[3] = { tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0] };
    double b1 = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
    double b2 = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    double b0 = 1.0 - b1 - b2;
    double lowest = fmin(b0, fmin(b1, b2));
    out->plane_t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
    double edge_tolerance = EDGE_TOLERANCE + rounded_point_tolerance(ray, tri, out->plane_t, det, norms, &out->t_slack);
    out->near_inside = lowest >= -edge_tolerance;
    out->near_edge = out->near_inside && lowest <= edge_tolerance;
    out->on_edge = fabs(lowest) <= EXACT_EDGE_TOLERANCE;
}

fuzz_oracle *fuzz_oracle_create(const rtt_scene *scene, const rtt_ray *rays, size_t ray_count)
{
    fuzz_oracle *o = calloc(1, sizeof *o);
    if (!o)
        fuzz_fail("out of memory");
    *o = (fuzz_oracle){ scene, rays, ray_count, scene->triangle_count, 0.0, NULL };
    o->table = calloc(ray_count * (size_t)o->triangle_count + 1, sizeof *o->table);
    if (!o->table)
        fuzz_fail("out of memory");
    for (uint32_t i = 0; i < scene->vertex_count; i++) {
        float v[3] = { scene->vertices[i].x, scene->vertices[i].y, scene->vertices[i].z };
        o->scene_scale = fmax(o->scene_scale, max_abs3(v));
    }
    for (size_t r = 0; r < ray_count; r++) {
        for (uint32_t i = 0; i < o->triangle_count; i++) {
            rtt_vec3 tri[3];
            rtt_scene_triangle(scene, i, tri);
            ray_triangle *e = &o->table[r * o->triangle_count + i];
            float t, u, v;
            e->hit = rtt_reference_intersect_triangle(&rays[r], tri, &t, &u, &v);
            e->t = e->hit ? t : INFINITY;
            plane_test(&rays[r], tri, e);
        }
    }
    return o;
}

void fuzz_oracle_free(fuzz_oracle *oracle)
{
    if (oracle)
        free(oracle->table);
    free(oracle);
}

/* A watertight hit the engine may leave out. */
static bool optional_hit(const fuzz_oracle *o, const rtt_ray *ray, const ray_triangle *e, bool lenient)
{
    if (e->beyond_range)
        return true;
    double tol = tolerance(o, ray, e->t) + (lenient ? e->t_slack : 0.0);
    if (fabs((double)e->t - ray->tnear) <= tol || fabs((double)e->t - ray->tfar) <= tol)
        return true;
    return lenient ? e->near_edge : e->on_edge;
}

/* Whether the engine may report prim p at distance t. */
static bool acceptable_hit(const fuzz_oracle *o, const rtt_ray *ray, const ray_triangle *e, double t, bool lenient)
{
    double tol = tolerance(o, ray, t) + (lenient ? e->t_slack : 0.0);
    if (e->hit && fabs((double)e->t - t) <= tol)
        return true;
    if (e->beyond_range)
        return t >= (double)ray->tnear - tol && t <= (double)ray->tfar + tol;
    if (!lenient || !e->near_inside || !(t >= (double)ray->tnear - tol && t <= (double)ray->tfar + tol))
        return false;
    return isnan(e->plane_t) || fabs(e->plane_t - t) <= tol;   /* grazing: no usable plane t */
}

/* Before failing: the ray and the triangles involved, as exact hex floats,
 * so a report can be turned into a unit test. */
static void describe(const fuzz_oracle *o, size_t r, uint32_t prim_a, uint32_t prim_b)
{
    const rtt_ray *ray = &o->rays[r];
    fprintf(stderr, "ray %zu: org %a %a %a dir %a %a %a tnear %a tfar %a\n", r, ray->org[0], ray->org[1],
            ray->org[2], ray->dir[0], ray->dir[1], ray->dir[2], ray->tnear, ray->tfar);
    uint32_t prims[2] = { prim_a, prim_b };
    for (int k = 0; k < 2; k++) {
        if (prims[k] >= o->triangle_count)
            continue;
        rtt_vec3 tri[3];
        rtt_scene_triangle(o->scene, prims[k], tri);
        fprintf(stderr, "prim %u: %a %a %a / %a %a %a / %a %a %a\n", prims[k], tri[0].x, tri[0].y, tri[0].z,
                tri[1].x, tri[1].y, tri[1].z, tri[2].x, tri[2].y, tri[2].z);
    }
}

/* Rays whose answer is specified: finite, magnitudes within 1e30 and a
 * direction whose largest component is at least 1e-30 (beyond the 1e-20 ..
 * 1e20 extremes of docs/ARCHITECTURE.md, where 1/dir and t overflow, and where the
 * products of the direction with a triangle's coefficients go denormal and
 * keep only a few bits: a direction of 2^-142 put t off by 0.6%), tnear and
 * tfar not NaN, and distances in the scene of at least 1e-30 in units of
 * the direction (the scene's and the origin's magnitude over the largest
 * direction component: a direction of 2^96 through a scene of 1e-19 puts
 * every t at 1e-48, below the smallest float, where a hit at t = 0 and a
 * miss are the same answer).  Others must only not crash and report a prim
 * in range. */
static bool answer_is_specified(const fuzz_oracle *o, const rtt_ray *ray)
{
    float largest_dir = 0.0f;
    for (int k = 0; k < 3; k++) {
        if (!(fabsf(ray->org[k]) <= CHECKED_MAGNITUDE) || !(fabsf(ray->dir[k]) <= CHECKED_MAGNITUDE))
            return false;
        largest_dir = fmaxf(largest_dir, fabsf(ray->dir[k]));
    }
    double distances = fmax(o->scene_scale, max_abs3(ray->org)) / largest_dir;
    return largest_dir >= SMALLEST_CHECKED_DIRECTION && !(distances < SMALLEST_CHECKED_DISTANCE) &&
           !isnan(ray->tnear) && !isnan(ray->tfar);
}

static void check_intersect(const fuzz_oracle *o, size_t r, const rtt_hit *hit, const char *label, bool lenient)
{
    const rtt_ray *ray = &o->rays[r];
    const ray_triangle *row = &o->table[r * o->triangle_count];
    double t = hit->prim == RTT_MISS ? INFINITY : hit->t;
    if (hit->prim != RTT_MISS && hit->prim >= o->triangle_count)
        fuzz_fail("%s: ray %zu hit prim %u of %u", label, r, hit->prim, o->triangle_count);
    if (!answer_is_specified(o, ray))
        return;
    if (hit->prim != RTT_MISS) {
        if (!isfinite(hit->t))
            fuzz_fail("%s: ray %zu hit prim %u at t = %g", label, r, hit->prim, hit->t);
        if (!acceptable_hit(o, ray, &row[hit->prim], t, lenient)) {
            describe(o, r, hit->prim, RTT_MISS);
            fuzz_fail("%s: ray %zu hit prim %u at t = %.9g, brute force: %s t = %.9g", label, r, hit->prim,
                      hit->t, row[hit->prim].hit ? "hit at" : "miss, plane", row[hit->prim].hit ? row[hit->prim].t
                                                                                          : row[hit->prim].plane_t);
        }
    }
    for (uint32_t i = 0; i < o->triangle_count; i++) {
        const ray_triangle *e = &row[i];
        if (!e->hit || optional_hit(o, ray, e, lenient))
            continue;
        double slack = lenient ? e->t_slack + (hit->prim != RTT_MISS ? row[hit->prim].t_slack : 0.0) : 0.0;
        if ((double)e->t < t - tolerance(o, ray, e->t) - slack) {
            describe(o, r, i, hit->prim);
            fuzz_fail("%s: ray %zu missed prim %u at t = %.9g (reported %s %u at t = %.9g)", label, r, i, e->t,
                      hit->prim == RTT_MISS ? "miss" : "prim", hit->prim, hit->t);
        }
    }
}

static void check_occluded(const fuzz_oracle *o, size_t r, uint8_t occluded, const char *label, bool lenient)
{
    const rtt_ray *ray = &o->rays[r];
    const ray_triangle *row = &o->table[r * o->triangle_count];
    if (!answer_is_specified(o, ray))
        return;
    bool possible = false, required = false;
    for (uint32_t i = 0; i < o->triangle_count; i++) {
        const ray_triangle *e = &row[i];
        if (e->hit && !optional_hit(o, ray, e, lenient))
            required = true;
        if (e->hit || (lenient && e->near_inside))
            possible = true;
        if (e->hit && optional_hit(o, ray, e, false))
            possible = true;
    }
    if (occluded && !possible) {
        describe(o, r, RTT_MISS, RTT_MISS);
        fuzz_fail("%s: ray %zu occluded, brute force finds nothing", label, r);
    }
    if (!occluded && required) {
        describe(o, r, RTT_MISS, RTT_MISS);
        fuzz_fail("%s: ray %zu not occluded, brute force finds a hit", label, r);
    }
}

/* A direction with a subnormal component: the optimized engine traces such
 * a ray scaled by a power of two (engine_optimized.c, subnormal_rescale),
 * which is exact for normal floats but not for the subnormal products the
 * test then forms from it (a sliver 5e-41 wide hit by a ray whose x
 * direction is 3e-40: the scaled ray's sheared corners round otherwise than
 * the reference's), so such rays are checked by the lenient rules. */
static bool subnormal_direction(const rtt_ray *ray)
{
    for (int k = 0; k < 3; k++)
        if (ray->dir[k] != 0.0f && fabsf(ray->dir[k]) < FLT_MIN) return true;
    return false;
}

void fuzz_oracle_check(const fuzz_oracle *oracle, rtt_engine *engine, const char *label, bool lenient)
{
    size_t n = oracle->ray_count;
    rtt_hit *hits = calloc(n + 1, sizeof *hits);
    uint8_t *occluded = calloc(n + 1, 1);
    if (!hits || !occluded)
        fuzz_fail("out of memory");
    rtt_engine_intersect(engine, oracle->rays, hits, n);
    rtt_engine_occluded(engine, oracle->rays, occluded, n);
    for (size_t r = 0; r < n; r++) {
        const bool lenient_here = lenient || subnormal_direction(&oracle->rays[r]);
        check_intersect(oracle, r, &hits[r], label, lenient_here);
        check_occluded(oracle, r, occluded[r], label, lenient_here);
    }
    free(hits);
    free(occluded);
}

/* Triangles a lenient engine must keep: not degenerate, not needles seen by
 * the grazing rule (smallest angle's sine below GRAZING_TOLERANCE), coordinates
 * within 1e30 (past it the float plane offset overflows), and with an
 * altitude above 1e-30, so that the reciprocal edge coefficients of a
 * projected test stay finite in float.  The optimized engine documents that
 * it drops the others (optimized/isect/isect_projected_bary.c); their hits are
 * optional for it (see plane_test). */
static uint32_t robust_triangle_count(const rtt_scene *scene)
{
    uint32_t count = 0;
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, i, tri);
        double e[3][3], len[3];
        for (int k = 0; k < 3; k++) {
            const rtt_vec3 a = tri[k], b = tri[(k + 1) % 3];
            e[k][0] = (double)b.x - a.x, e[k][1] = (double)b.y - a.y, e[k][2] = (double)b.z - a.z;
            len[k] = length3(e[k]);
        }
        double n[3] = { e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                        e[0][0] * e[1][1] - e[0][1] * e[1][0] };
        double twice_area = length3(n);
        double longest = fmax(len[0], fmax(len[1], len[2]));
        double shortest = fmin(len[0], fmin(len[1], len[2]));
        double middle = len[0] + len[1] + len[2] - longest - shortest;
        /* 2 area / (the two longest edges) is the sine of the smallest angle */
        if (twice_area > GRAZING_TOLERANCE * longest * middle && twice_area > 1e-30 * longest &&
            triangle_magnitude(tri) <= CHECKED_MAGNITUDE)
            count++;
    }
    return count;
}

void fuzz_check_tree_info(rtt_engine *engine, const char *label, const rtt_scene *scene, bool lenient)
{
    rtt_tree_info info;
    if (!rtt_engine_tree_info(engine, &info))
        fuzz_fail("%s: no tree info", label);
    if (info.depth > info.max_depth)
        fuzz_fail("%s: tree depth %u exceeds its bound %u", label, info.depth, info.max_depth);
    if (info.references > info.reference_cap)
        fuzz_fail("%s: %llu references exceed the cap %llu", label, (unsigned long long)info.references,
                  (unsigned long long)info.reference_cap);
    if (info.leaf_count > info.node_count || info.empty_leaf_count > info.leaf_count)
        fuzz_fail("%s: %u leaves (%u empty) of %u nodes", label, info.leaf_count, info.empty_leaf_count,
                  info.node_count);
    /* every triangle that can be hit is in at least one leaf */
    uint32_t required = lenient ? robust_triangle_count(scene) : scene->triangle_count - scene->degenerate_count;
    if (info.references < (uint64_t)required)
        fuzz_fail("%s: %llu references for %u hittable triangles", label, (unsigned long long)info.references,
                  required);
}

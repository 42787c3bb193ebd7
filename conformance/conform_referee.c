/* The double-precision referee of `rtt conform`: a brute force over every
 * triangle with the watertight test (Woop, Benthin & Wald 2013) computed in
 * double.  It decides the rays where an engine and the oracle disagree
 * (conformance/README.md, "Judged in double").
 *
 * Why the watertight test and not Moeller-Trumbore with an edge band: the
 * watertight test's edge functions of a shared edge are exact negations of
 * each other (the same two transformed vertices, the same products), so a
 * ray through a closed mesh hits at least one of the triangles around an
 * edge or vertex, and a ray exactly on an edge hits both (edges count as
 * inside).  No band has to be chosen: whether a hit near an edge is close
 * enough is the classifier's tolerance, the one every other comparison uses.
 * In double the edge functions of float input carry a relative error of
 * about 1e-16, nine orders below the engines' float error. */
#include <math.h>

#include "conform.h"

/* The ray's frame of the watertight test: the axis of the largest direction
 * component becomes z, and the shear that maps the direction onto it. */
typedef struct referee_frame {
    int kx, ky, kz;
    double sx, sy, sz;
    double org[3];
} referee_frame;

bool rtt_conform_ray_decidable(const rtt_ray *r)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(r->org[k]) || !isfinite(r->dir[k])) return false;
    if (isnan(r->tnear) || isnan(r->tfar) || !(r->tnear < r->tfar)) return false;
    return r->dir[0] != 0.0f || r->dir[1] != 0.0f || r->dir[2] != 0.0f;
}

static void frame_make(const rtt_ray *r, referee_frame *f)
{
    double d[3] = {r->dir[0], r->dir[1], r->dir[2]};
    int kz = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(d[k]) > fabs(d[kz])) kz = k;
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (d[kz] < 0.0) {
        int swap = kx;
        kx = ky;
        ky = swap;
    }
    f->kx = kx;
    f->ky = ky;
    f->kz = kz;
    f->sx = d[kx] / d[kz];
    f->sy = d[ky] / d[kz];
    f->sz = 1.0 / d[kz];
    for (int k = 0; k < 3; k++) f->org[k] = r->org[k];
}

/* One triangle; true with its t when the ray's line crosses it (edges
 * included) at a t in the open interval (tnear, tfar). */
static bool referee_triangle(const referee_frame *f, const rtt_vec3 tri[3], double tnear, double tfar, double *t_out)
{
    double x[3], y[3], z[3];
    for (int i = 0; i < 3; i++) {
        double p[3] = {(double)tri[i].x - f->org[0], (double)tri[i].y - f->org[1], (double)tri[i].z - f->org[2]};
        x[i] = p[f->kx] - f->sx * p[f->kz];
        y[i] = p[f->ky] - f->sy * p[f->kz];
        z[i] = f->sz * p[f->kz];
    }
    /* edge functions: u of edge (1, 2), v of (2, 0), w of (0, 1) */
    double u = x[2] * y[1] - y[2] * x[1];
    double v = x[0] * y[2] - y[0] * x[2];
    double w = x[1] * y[0] - y[1] * x[0];
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    double det = u + v + w;
    if (det == 0.0 || !isfinite(det)) return false;
    double t = (u * z[0] + v * z[1] + w * z[2]) / det;
    if (!(t > tnear && t < tfar)) return false;
    *t_out = t;
    return true;
}

bool rtt_conform_referee(const rtt_scene *scene, const rtt_ray *r, rtt_conform_referee_hit *out)
{
    out->t = INFINITY;
    out->prim = RTT_MISS;
    if (!rtt_conform_ray_decidable(r)) return false;
    referee_frame f;
    frame_make(r, &f);
    double tnear = r->tnear, tfar = r->tfar;
    for (uint32_t p = 0; p < scene->triangle_count; p++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, p, tri);
        double t;
        if (referee_triangle(&f, tri, tnear, tfar, &t) && t < out->t) {
            out->t = t;
            out->prim = p;
        }
    }
    return true;
}

rtt_hit rtt_conform_referee_as_hit(const rtt_conform_referee_hit *h)
{
    return (rtt_hit){h->prim == RTT_MISS ? INFINITY : (float)h->t, 0.0f, 0.0f, h->prim};
}

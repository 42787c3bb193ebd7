/* Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT 2(1)):
 * section 3 and the appendix listing, without back-face culling.
 *
 * The ray is mapped to the +z axis by a permutation and a shear; the triangle's
 * edge functions U, V, W are then evaluated in 2D at the origin.  Neighbouring
 * triangles compute the edge function of a shared edge from the same two
 * transformed vertices, with opposite sign, so a ray cannot slip between them.
 * When any edge function is exactly 0 the three are recomputed in double
 * precision (the products of two floats are exact there, only the difference
 * rounds), so a ray through an edge or vertex is not decided by float
 * cancellation. */
#include <math.h>

#include "isect_watertight.h"
#include "rtt/reference.h"

void rtt_watertight_ray_setup(const rtt_ray *ray, rtt_watertight_ray *out)
{
    float ax = fabsf(ray->dir[0]), ay = fabsf(ray->dir[1]), az = fabsf(ray->dir[2]);
    int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (ray->dir[kz] < 0.0f) {
        int swap = kx;
        kx = ky;
        ky = swap;
    }
    for (int i = 0; i < 3; i++) out->org[i] = ray->org[i];
    out->kx = kx;
    out->ky = ky;
    out->kz = kz;
    out->sx = ray->dir[kx] / ray->dir[kz];
    out->sy = ray->dir[ky] / ray->dir[kz];
    out->sz = 1.0f / ray->dir[kz];
    out->tnear = ray->tnear;
    out->tfar = ray->tfar;
}

bool rtt_reference_triangle_is_degenerate(const rtt_vec3 tri[3]) { return rtt_triangle_is_degenerate(tri); }

/* A float that is neither zero, subnormal, infinite nor NaN. */
static bool float_is_normal(float x)
{
    return isnormal(x);
}

/* The hit is in range and the triangle has an area: write it out. */
static bool accept_hit(const rtt_watertight_ray *ray, const rtt_vec3 tri[3], float t, float u, float v,
                       float *t_out, float *u_out, float *v_out)
{
    if (!(t > ray->tnear && t < ray->tfar)) return false; /* also rejects NaN */
    /* A zero-area triangle can still produce a tiny non-zero det from
     * rounding; it is refused here, on the rare hit path, where it is cheap. */
    if (rtt_reference_triangle_is_degenerate(tri)) return false;
    *t_out = t;
    *u_out = u;
    *v_out = v;
    return true;
}

bool rtt_watertight_intersect(const rtt_watertight_ray *ray, const rtt_vec3 tri[3], float *t_out, float *u_out,
                              float *v_out)
{
    /* vertices relative to the ray origin */
    float a[3], b[3], c[3];
    for (int i = 0; i < 3; i++) {
        a[i] = rtt_v3_get(tri[0], i) - ray->org[i];
        b[i] = rtt_v3_get(tri[1], i) - ray->org[i];
        c[i] = rtt_v3_get(tri[2], i) - ray->org[i];
    }
    const int kx = ray->kx, ky = ray->ky, kz = ray->kz;

    /* shear and scale of the vertices */
    const float ax = a[kx] - ray->sx * a[kz], ay = a[ky] - ray->sy * a[kz];
    const float bx = b[kx] - ray->sx * b[kz], by = b[ky] - ray->sy * b[kz];
    const float cx = c[kx] - ray->sx * c[kz], cy = c[ky] - ray->sy * c[kz];
    const float az = ray->sz * a[kz], bz = ray->sz * b[kz], cz = ray->sz * c[kz];

    /* scaled barycentric coordinates (edge functions) */
    const float u = cx * by - cy * bx;
    const float v = ax * cy - ay * cx;
    const float w = bx * ay - by * ax;
    const float det = u + v + w;
    const float t_scaled = u * az + v * bz + w * cz;

    if (float_is_normal(u) && float_is_normal(v) && float_is_normal(w) && float_is_normal(det) &&
        float_is_normal(t_scaled)) {
        /* both sides: the origin must be inside the projected triangle,
         * with either winding */
        if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
        return accept_hit(ray, tri, t_scaled / det, v / det, w / det, t_out, u_out, v_out);
    }

    /* The paper recomputes in double when an edge function is exactly 0 (the
     * ray passes through an edge or vertex).  We also do when any of the
     * values above is subnormal, infinite or NaN: edge functions grow as
     * scale^2 and t_scaled as scale^3, so scenes at 1e+-13 and beyond leave
     * float's range.  A non-zero float edge function has the sign of the
     * exact one (rounding is monotonic), so mixing the two paths keeps
     * shared edges watertight. */
    const double ud = (double)cx * by - (double)cy * bx;
    const double vd = (double)ax * cy - (double)ay * cx;
    const double wd = (double)bx * ay - (double)by * ax;
    if ((ud < 0.0 || vd < 0.0 || wd < 0.0) && (ud > 0.0 || vd > 0.0 || wd > 0.0)) return false;
    const double detd = ud + vd + wd;
    if (detd == 0.0) return false; /* the ray lies in the triangle's plane */
    const double td = (ud * az + vd * bz + wd * cz) / detd;
    /* + 0.0f: a zero t, u or v is +0 whichever sign detd has (the kernels
     * wind the edge functions by kz alone, not by dir[kz]'s sign, so their
     * detd may have the other sign; the values agree, and so must the bits) */
    return accept_hit(ray, tri, (float)td + 0.0f, (float)(vd / detd) + 0.0f, (float)(wd / detd) + 0.0f, t_out, u_out,
                      v_out);
}

bool rtt_reference_intersect_triangle(const rtt_ray *ray, const rtt_vec3 tri[3], float *t, float *u, float *v)
{
    rtt_watertight_ray prepared;
    rtt_watertight_ray_setup(ray, &prepared);
    return rtt_watertight_intersect(&prepared, tri, t, u, v);
}

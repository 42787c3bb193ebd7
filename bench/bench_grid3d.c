/* Hunt & Mark 2008 Table 5's comparison grid: a uniform, axis-aligned 3D
 * grid over the scene's bounds with about as many cells as the 3D light
 * grid (cubic cells, per-axis counts in proportion to the box's sides), and
 * a 3D-DDA (Amanatides & Woo) that only counts the cells each ray visits
 * over [tnear, tfar] clipped to the box: the regular grid's traversal steps
 * on the same rays.  Nothing is binned and nothing is timed. */
#include <math.h>

#include "bench_internal.h"

/* Cells the ray visits in the grid of dims[] cells over [lo, lo + size]. */
static uint64_t dda_steps(const rtt_ray *r, const double lo[3], const double size[3], const uint32_t dims[3])
{
    double t0 = r->tnear, t1 = r->tfar;
    for (int a = 0; a < 3; a++) { /* the slab clip, in double */
        const double o = r->org[a], d = r->dir[a], hi = lo[a] + size[a];
        if (d == 0.0) {
            if (o < lo[a] || o > hi) return 0;
            continue;
        }
        double ta = (lo[a] - o) / d, tb = (hi - o) / d;
        if (ta > tb) { const double x = ta; ta = tb, tb = x; }
        t0 = fmax(t0, ta), t1 = fmin(t1, tb);
    }
    if (!(t0 <= t1)) return 0;
    int cell[3], step[3];
    double next[3], delta[3];
    for (int a = 0; a < 3; a++) {
        const double w = size[a] / dims[a], d = r->dir[a];
        const double p0 = r->org[a] + t0 * d - lo[a];
        cell[a] = (int)fmin(fmax(floor(p0 / w), 0.0), dims[a] - 1.0);
        step[a] = d > 0.0 ? 1 : d < 0.0 ? -1 : 0;
        delta[a] = d != 0.0 ? w / fabs(d) : INFINITY;
        next[a] = d > 0.0 ? t0 + ((cell[a] + 1) * w - p0) / d : d < 0.0 ? t0 + (cell[a] * w - p0) / d : INFINITY;
    }
    uint64_t steps = 1;
    for (;;) { /* the next crossing within [t0, t1] and the grid: one more cell */
        const int a = next[0] <= next[1] ? (next[0] <= next[2] ? 0 : 2) : (next[1] <= next[2] ? 1 : 2);
        if (!(next[a] <= t1)) break;
        cell[a] += step[a], next[a] += delta[a];
        if (cell[a] < 0 || cell[a] >= (int)dims[a]) break;
        steps++;
    }
    return steps;
}

double bench_grid3d_steps_per_ray(const rtt_scene *scene, const bench_rays *rays, uint64_t cells, uint32_t dims[3])
{
    double lo[3], size[3];
    const float *blo = &scene->bounds.lo.x, *bhi = &scene->bounds.hi.x;
    double volume = 1.0;
    for (int a = 0; a < 3; a++) {
        lo[a] = blo[a], size[a] = fmax((double)bhi[a] - blo[a], 1e-9 * (fabs(blo[a]) + 1.0));
        volume *= size[a];
    }
    const double side = cbrt(volume / (double)cells); /* a cubic cell's side */
    for (int a = 0; a < 3; a++) {
        const double k = round(size[a] / side);
        dims[a] = k < 1.0 ? 1u : k > 65536.0 ? 65536u : (uint32_t)k;
    }
    uint64_t steps = 0, count = 0;
    for (size_t i = 0; i < (size_t)rays->width * rays->height; i++) {
        const rtt_ray *r = &rays->rays[i];
        if (!bench_ray_active(r)) continue;
        steps += dda_steps(r, lo, size, dims);
        count++;
    }
    return count ? (double)steps / (double)count : 0.0;
}

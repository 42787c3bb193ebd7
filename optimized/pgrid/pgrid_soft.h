/* Hunt & Mark 2008, section 5.3: soft shadows through a 3D perspective grid
 * per light, rebuilt every frame (--shadows pgrid:N).  The light's view is
 * the hard grids' six-face arrangement (pgrid_light.h: face 2 * axis +
 * (d[axis] < 0), face coordinates d[axis + 1] / |d[axis]|, d[axis + 2] /
 * |d[axis]| in [-1, 1]), res x res cells per face, cut into `slices` depth
 * slices by the distance |q| of a point q from the light's centre L.
 *
 * Any ray may use it, wherever it starts and ends: a soft shadow ray runs
 * from a shading point to a sample on the light's surface, not to L, so it
 * crosses many directions seen from L.  The ray's segment is cut by slice
 * (the t where its distance from L lies in the slice, a hull of at most two
 * intervals), each piece clipped (in double) to each face's pyramid above
 * the plane s q[axis] >= near (s the face's sign); a segment in front of L
 * projects to a segment on the face, so its two end points' face
 * coordinates bound the cells it crosses there.  What no face's piece
 * covers lies within max-norm `near` of L: the triangles that come that
 * close are in the near list, tested by every ray.
 *
 * Exactness: the test is the reference's watertight one (Woop, Benthin &
 * Wald) with the same arithmetic (../bvh/bvh_isect_wide.h), so a triangle
 * tested answers as the reference; binning is conservative, every triangle
 * the reference could accept on a ray is in a cell the ray visits:
 *  - E = 2^-14 M (M the largest coordinate magnitude of the scene's bounds
 *    and the light) bounds how far from the exact segment (and its
 *    [tnear, tfar]) a point the reference accepts can lie (pgrid_light.h);
 *    ray pieces are computed over [tnear - E, tfar + E] and distances
 *    widened by E.
 *  - A triangle point q' within E of a ray point q of face f's piece (so
 *    s q[axis] >= near) has s q'[axis] >= near - E and face coordinates
 *    within 2E / (near - E) of q's: a triangle is clipped (in double) to the
 *    face's pyramid widened by 4E / near above s q[axis] >= near / 2, and
 *    binned by its clipped corners' face coordinates widened by
 *    mu = 4E / near + 1e-6, over the slices its distance range [least
 *    distance of its box, largest of its corners] widened by 2E meets.
 *  - A ray whose origin has a coordinate larger than M (the triangles' and
 *    the light's) rounds in the reference's test by more than E: it is
 *    tested against every triangle instead.
 *  - near >= 256 E; a triangle whose box comes within max-norm near + 2E
 *    of L goes to the near list instead.
 * Both faces of every triangle are kept (no back-face culling: a soft ray
 * starts anywhere and ends off L).  The pgrid README says what it costs. */
#ifndef RTT_OPTIMIZED_PGRID_SOFT_H
#define RTT_OPTIMIZED_PGRID_SOFT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bvh_tree.h"
#include "pgrid_light.h"
#include "rtt/engine.h"
#include "rtt/error.h"

#define PGRID_SOFT_RES_DEFAULT 200u    /* cells per face side (the paper's 200 x 200 x 4) */
#define PGRID_SOFT_SLICES_DEFAULT 4u
#define PGRID_SOFT_SLICES_MAX 64u

/* A triangle's corners as the watertight test reads them. */
typedef bvh_corners pgrid_soft_tri;

/* The 3D grid of one light. */
typedef struct pgrid_soft_light {
    double position[3];
    uint32_t res, slices;
    double near;                 /* max-norm radius around L the near list covers */
    double slack;                /* E */
    double magnitude;            /* M: E's scale; a ray whose origin has a larger coordinate is tested
                                  * against every triangle (the reference's rounding follows the origin) */
    double far;                  /* the farthest triangle corner's distance from L */
    double bound[PGRID_SOFT_SLICES_MAX + 1]; /* slice k holds distances [bound[k], bound[k + 1]) */
    uint32_t *cell_first;        /* slices * 6 res^2 + 1; cell (k, face, y, x) = ((k * 6 + face) * res + y) * res + x */
    uint32_t *refs;              /* indices into pgrid_soft.tris, ascending per cell */
    size_t ref_count;
    double *least;               /* per triangle: a lower bound of its distance from L, less 2E (a ray
                                  * piece reaching no farther than that meets none of it) */
    uint32_t *near_list;
    uint32_t near_count;
} pgrid_soft_light;

/* The soft light grids of one frame. */
typedef struct pgrid_soft {
    pgrid_soft_tri *tris;        /* the scene's non-degenerate triangles, in global order */
    uint32_t tri_count;
    pgrid_soft_light *lights;
    uint32_t light_count;
    double build_seconds;
} pgrid_soft;

/* Builds a grid of res x res x slices cells (0: the defaults) at the centre
 * of every light of the scene over the triangles not flagged in
 * `degenerate` (NULL: none).  False (err filled) when out of memory or the
 * sizes are out of range; pgrid_soft_free frees what was built. */
bool pgrid_soft_build(pgrid_soft *grids, const rtt_scene *scene, const uint8_t *degenerate, uint32_t res,
                      uint32_t slices, rtt_error *err);
/* The scene's half of pgrid_soft_build: the triangles' corners (built once
 * per scene where the caller keeps them: the bench), no light. */
bool pgrid_soft_prepare(pgrid_soft *grids, const rtt_scene *scene, const uint8_t *degenerate, rtt_error *err);
/* One light at `position` reaching `extent` from it (the tests and the fuzzer). */
bool pgrid_soft_light_build(pgrid_soft_light *light, const pgrid_soft *grids, const float position[3], float extent,
                            uint32_t res, uint32_t slices);
void pgrid_soft_light_free(pgrid_soft_light *light);
/* How far a light's samples reach from its centre (sphere: the radius;
 * quad: |edge_u| + |edge_v|; point: 0): pgrid_soft_build's `extent`. */
float pgrid_soft_light_extent(const rtt_light *light);
void pgrid_soft_free(pgrid_soft *grids);

/* Traversal counters (bench/: Table 5), summed over rays: cells a packet
 * visits (once per live ray), triangle tests (per lane), and steps, a
 * ray's own cells as a 2D DDA would cross them (|dx| + |dy| + 1 per slice
 * and face its piece crosses: Table 5's traversal steps). */
typedef struct pgrid_soft_counts {
    uint64_t rays, cells, tests, steps;
} pgrid_soft_counts;

/* The slice traverser (pgrid_soft_trace.c, one copy per instruction set):
 * occluded[i] = 1 when rays[i] meets a triangle in (tnear, tfar), else 0.
 * Consecutive rays with the same origin (a shading point's N samples) are
 * packets of 16 / 8 / 4 rays; each walks the slices from its origin's side
 * towards the light, testing the cells of the packet's footprint, its rays
 * leaving as they are occluded.  counts (NULL: none) is added to. */
typedef void (*pgrid_soft_occluded_fn)(const pgrid_soft *grids, uint32_t light, const rtt_ray *rays, uint32_t count,
                                       uint8_t *occluded, pgrid_soft_counts *counts);

#endif

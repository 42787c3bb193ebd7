/* Hunt & Mark 2008, section 5.2: hard shadows through a perspective grid
 * per light, rebuilt every frame.  The light's view is the six-face
 * arrangement (a cube around the light: face 2 * axis + (d[axis] < 0) for
 * the direction d = p - L of a point p from the light L, its major axis by
 * the reference's tie rule), each face a res x res grid of the face
 * coordinates (d[axis + 1], d[axis + 2]) / |d[axis]| in [-1, 1].  The paper
 * bounds the visible hit points with one frustum; the six faces take any
 * shadow ray, wherever its origin, with no pass over the hit points first.
 *
 * A shadow ray of the shader proxy runs from p towards L over
 * (epsilon, |L - p| - epsilon): it is looked up in the cell of p's
 * direction and tested against the triangles of that cell (and of the near
 * list) with the reference's watertight test (Woop, Benthin & Wald), the
 * same arithmetic in the same order, so a triangle tested answers as the
 * reference's.  Exactness is then the binning's: every triangle the
 * reference could find on the ray must be in the ray's cell.
 *
 *  - A triangle is binned by its exact footprint on each face, clipped
 *    (in double) to the face's pyramid widened by the margin mu_T and
 *    bounded by its clipped corners' face coordinates widened by mu_T too;
 *    of a footprint of 16 cells or more, only the cells that the cone from
 *    L over the triangle, widened by mu_T, meets (pgrid_light_build.c,
 *    cone_cut: two fifths of the cells of a map's large slanted triangles'
 *    rectangles lie outside their cones).
 *  - mu_T covers the rounding of the ray's own direction and of the
 *    reference's test: every point the reference can accept on the ray is
 *    within E = 2^-14 M of the exact segment p-L (M the largest coordinate
 *    magnitude of the scene's bounds and the light), which seen from L is an
 *    angle of at most 2E / (d_T - 2E) for a triangle at least d_T from L;
 *    mu_T = 1e-5 + 4 times that angle (a face coordinate is tan of an angle
 *    at most 45 degrees off the axis, so at most twice the angle; twice
 *    again for margin), with 1e-5 for the rounding of the ray's face
 *    coordinates themselves.  E assumes origins of magnitude at most 2M
 *    (the test's rounding, a few float ulps of 3M, stays far below 2^-14 M):
 *    the shader proxy's rays start on the scene's triangles, within M up to
 *    the hit point's rounding; a ray whose origin has a coordinate beyond 2M
 *    (an arbitrary caller's) rounds on its origin's scale instead and is
 *    tested against every triangle.
 *  - A triangle within 256 E of the light, or whose mu_T would pass 4e-2,
 *    goes to the near list, tested by every ray.  (The factor 4 holds
 *    while the perturbed direction stays within 60 degrees of the axis,
 *    tan's slope up to 4: mu_T <= 4e-2 keeps the perturbation below 0.6
 *    degrees past the face's 45.  Beyond 256 E, mu_T is below 3.2e-2, so the
 *    distance alone decides; the bound was 1e-2, which sent triangles up to
 *    about 800 E away to the near list: 86 on czest3ctf's light, tested by
 *    every ray, against 6 now.)
 *  - Per cell the smallest lower bound d_T over its triangles (the larger of
 *    the distance from L to its box and to its plane): a ray from p reaches
 *    no triangle of the cell when |L - p| + 4E < that bound, and is clear
 *    without a test (the per-cell distance culling of section 5.2).
 *
 *
 * Back-face culling (the paper's): on a closed, consistently oriented mesh
 * (pgrid_shadows.mesh_culled) a triangle with the light on its outer side
 * by more than 4E faces the light; such triangles are kept apart at the
 * end of each cell's list (cell_front .. cell_first[c + 1]) and tested only
 * for the rays that may start inside a culled solid: from a triangle of a
 * culled mesh that does not face the light, from inside another culled
 * mesh's grown box, or crossing a kept triangle within (-epsilon, epsilon]
 * of the origin.  A ray starting outside every solid meets an entering
 * face, which is kept, before any face that faces the light.  The pgrid
 * README ("Hard shadows") says what this assumes. */
#ifndef RTT_OPTIMIZED_PGRID_LIGHT_H
#define RTT_OPTIMIZED_PGRID_LIGHT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "kd_tree.h"
#include "rtt/engine.h"
#include "rtt/error.h"

/* Cells per face side: the paper's is 200; a caller giving 0 gets
 * pgrid_light_res_rule's choice for the scene (pgrid README, "Resolution"):
 * PGRID_LIGHT_RES_MAPS on few large triangles, PGRID_LIGHT_RES_MESHES on
 * many small ones. */
#define PGRID_LIGHT_RES_MAPS 64u
#define PGRID_LIGHT_RES_MESHES 400u
#define PGRID_LIGHT_RES_MAX 2048u
#define PGRID_LIGHT_FACES 6u
/* The light build's count and fill bands per face at most (pgrid_light_build.c) */
#define PGRID_LIGHT_BANDS_MAX 2u
/* A ray from a light-facing triangle of a culled mesh whose direction makes
 * a cosine below this with the triangle's outward normal grazes it: its
 * origin, rounded, may lie inside the solid, so it meets the front faces
 * too (pgrid README, "Hard shadows"). */
#define PGRID_GRAZING_COSINE 0.1f

/* A scene triangle's side of a light (pgrid_light.front): not a culled
 * mesh's, a culled mesh's turned from the light, facing it, or facing it
 * so steeply that no ray from the triangle to the light grazes it (the
 * cosine with its normal PGRID_STEEP_COSINE or more from every point:
 * with PGRID_GRAZING_COSINE 0.1, a tenth of margin for the float normal,
 * direction and origin, so the kernel skips the normal's test). */
enum { PGRID_PRIM_OPEN = 0, PGRID_PRIM_AWAY = 1, PGRID_PRIM_FACING = 2, PGRID_PRIM_STEEP = 3 };
#define PGRID_STEEP_COSINE 0.11

/* A triangle's cell rectangle on one face (inclusive; x0 = PGRID_FOOTPRINT_NONE: none). */
#define PGRID_FOOTPRINT_NONE UINT16_MAX
typedef struct pgrid_footprint {
    uint16_t x0, y0, x1, y1;
} pgrid_footprint;

/* The grid of one light. */
typedef struct pgrid_light {
    float position[3];
    uint32_t res;              /* cells per face side */
    float reach;               /* 4E: slack of the per-cell distance test */
    double magnitude;          /* 2M: a ray whose origin has a larger coordinate is tested against
                                * every triangle (the reference's rounding follows the origin) */
    uint32_t faces;            /* bit f: face f's cells are kept (some triangle has a footprint there) */
    uint32_t kept_cells[PGRID_LIGHT_FACES][2]; /* face f's kept cells, [first, end): the whole rows its footprints
                                * meet ({0, 0} when it keeps none); the other cells hold stale words: a ray
                                * there meets the near list only */
    uint32_t *cell_first;      /* 6 res^2 + 1: cell c's references are refs[cell_first[c] .. cell_first[c + 1]) */
    float *cell_min;           /* per cell: the least distance bound d_T of its triangles (+inf: none) */
    float *bound;              /* per corner record: its d_T (the same test per triangle) */
    uint32_t *refs;            /* indices into pgrid_shadows.corners, ascending per cell */
    size_t ref_count;
    uint32_t *cell_front;      /* per cell: its references from here to cell_first[c + 1] face the light */
    uint8_t *front;            /* per scene triangle: PGRID_PRIM_FACING or _STEEP when it is one of those (a
                                * culled mesh's, facing the light), PGRID_PRIM_AWAY when it is a culled mesh's
                                * turned from it, PGRID_PRIM_OPEN the rest (from pgrid_shadows.prim_side) */
    uint32_t *near;            /* tested by every ray */
    uint32_t near_count;
    /* the build's own, kept between rebuilds (pgrid_light_rebuild): the
     * footprints (face-major: face * corner_count + record; a record's
     * entries on the faces of its face_mask, or, when that is 0, on face 0:
     * {NONE, NONE} for a near one, {NONE, 0} for one with no footprint; its
     * other entries are not written), the per-cell counts that become the
     * fill cursors (the main ones, then the front ones), and what the
     * arrays hold */
    pgrid_footprint *prints;
    uint8_t *record_front;     /* per corner record: PGRID_PRIM_FACING or _STEEP when it faces the light, else 0
                                * (the footprint stage's tasks copy it to front[its prim]) */
    uint8_t *face_mask;        /* per corner record: bit f when it has a footprint on face f */
    uint32_t face_first[PGRID_LIGHT_FACES + 1]; /* the records with a footprint on faces before f: face f has
                                                 * some iff face_first[f] < face_first[f + 1] */
    uint32_t *fill;
    uint32_t *row_records;     /* per build thread, face and cell row: the records whose footprint starts there,
                                * that thread's count (two threads or more: the face's rows are cut where
                                * half its records have started, two bands of as many) */
    uint32_t *chunk_counts;    /* per chunk of the footprint stage: its records with a footprint on each face,
                                * its near ones, then per face its footprints' least first row and greatest
                                * last row (pgrid_light_build.c, CHUNK_COUNTS) */
    uint32_t *band_spans[PGRID_LIGHT_FACES * PGRID_LIGHT_BANDS_MAX]; /* per count/fill band task: the cells
                               * each row of its large footprints keeps, lo | hi << 16 (pgrid_light_build.c,
                               * cone_cut), in the band's order */
    size_t band_span_capacity[PGRID_LIGHT_FACES * PGRID_LIGHT_BANDS_MAX];
    size_t cell_capacity, ref_capacity, corner_capacity, triangle_capacity, row_capacity, chunk_capacity;
} pgrid_light;

/* The footprint stage of a light's build (pgrid_light_build.c): for the
 * corner records [first, end) of `grids`, each one's distance bound d_T,
 * front class and footprint on the six faces, written into `light`
 * (bound, record_front, prints, face_mask).  E: the light's error
 * bound (pgrid_light.h's E), res: its cells per face side. */
struct pgrid_shadows;
typedef struct pgrid_print_job {
    pgrid_light *light;
    const struct pgrid_shadows *grids;
    double E;
    uint32_t res, n;
} pgrid_print_job;
typedef void (*pgrid_prints_fn)(const pgrid_print_job *job, uint32_t first, uint32_t end);
/* One record in scalar double: the stage's definition (the baseline's
 * stage, and what the kernel side's copies (pgrid_light_prints.c) do for
 * the records their vectors leave out, bit for bit the same otherwise). */
void pgrid_light_print_record(const pgrid_print_job *job, uint32_t i);
void pgrid_light_prints_scalar(const pgrid_print_job *job, uint32_t first, uint32_t end);
/* Whether two builds' footprint stages wrote the same: per record its
 * bound, front class, face mask and the footprint entries it writes (the
 * tests and the fuzzer compare the vector stages with the scalar one). */
bool pgrid_light_prints_equal(const pgrid_light *a, const pgrid_light *b, uint32_t records);

/* The light grids of one frame: the scene's non-degenerate triangles'
 * corners (in the Morton order of their centroids, prim kept) and a grid
 * per light. */
typedef struct pgrid_shadows {
    kd_corners *corners;
    uint32_t corner_count;
    /* the same corners as structure of arrays for the footprint stage's
     * vectors: coordinate a of corner v of record i at
     * corner_lanes[(3 v + a) * corner_stride + i], then the records'
     * outward sides (kd_corners.outward) as floats at 9 corner_stride */
    float *corner_lanes;
    size_t corner_stride;
    uint32_t *record_prim;         /* per record its corners' prim: the footprint stage's tasks read it, not
                                    * the 48-byte records */
    /* back-face culling: per mesh 1 when it is closed and consistently
     * oriented (every directed edge's reverse used once, by vertex index),
     * its outward side (+1: the winding's normal, -1: the opposite) and
     * its box grown by `box_grow` (lo xyz, hi xyz); the culled meshes */
    uint8_t *mesh_culled;
    int8_t *mesh_outward;
    float (*mesh_box)[6];
    uint32_t *culled;
    uint32_t culled_count;
    float (*outward_normal)[3];    /* per scene triangle of a culled mesh: its unit outward normal */
    uint8_t *prim_side;            /* per scene triangle: PGRID_PRIM_AWAY for a culled mesh's, else
                                    * PGRID_PRIM_OPEN (each light's front starts from it) */
    const uint32_t *triangle_mesh; /* the scene's */
    pgrid_light *lights;
    uint32_t light_count;
    uint32_t threads;              /* the per-light build's threads (0 or 1: the caller's alone) */
    pgrid_prints_fn prints;        /* the build's footprint stage: a kernel row's light_prints (the
                                    * caller's instruction set), or NULL for pgrid_light_prints_scalar */
    double build_seconds;
} pgrid_shadows;

/* Builds a grid of res x res cells per face (0 → pgrid_light_res_rule,
 * at most PGRID_LIGHT_RES_MAX) at the centre of every light of the scene,
 * over the triangles not flagged in `degenerate` (NULL: none).  False (err
 * filled) when out of memory; pgrid_shadows_free frees what was built. */
bool pgrid_shadows_build(pgrid_shadows *grids, const rtt_scene *scene, const uint8_t *degenerate, uint32_t res,
                         rtt_error *err);
/* The two halves of pgrid_shadows_build: what depends on the scene alone
 * (the corners, which meshes are culled; as a kd-tree, built once per
 * scene where the caller keeps it: the bench) and the grids of the lights
 * (per frame; pgrid_shadows_free_lights frees them, keeping the first
 * half).  build_seconds is the second's. */
bool pgrid_shadows_prepare(pgrid_shadows *grids, const rtt_scene *scene, const uint8_t *degenerate, rtt_error *err);
bool pgrid_shadows_build_lights(pgrid_shadows *grids, const rtt_scene *scene, uint32_t res, rtt_error *err);
void pgrid_shadows_free_lights(pgrid_shadows *grids);
/* The same for one light at `position` (the tests and the fuzzer);
 * `light` need not be initialised. */
bool pgrid_light_build(pgrid_light *light, const pgrid_shadows *grids, const rtt_scene *scene,
                       const float position[3], uint32_t res);
/* The same into a light that is zeroed or was built before: its arrays are
 * kept and grown, never shrunk (no allocation per frame once they fit), the
 * build runs on `threads` (0 or 1: the caller's alone).  The result is the
 * same at any thread count.  False when out of memory (the light is then
 * freed). */
bool pgrid_light_rebuild(pgrid_light *light, const pgrid_shadows *grids, const rtt_scene *scene,
                         const float position[3], uint32_t res, uint32_t threads);
/* The cells per face side for a scene of `triangles` (after degenerate
 * ones are dropped): the rule measured in the pgrid README, "Resolution". */
uint32_t pgrid_light_res_rule(uint32_t triangles);
void pgrid_light_free(pgrid_light *light);
void pgrid_shadows_free(pgrid_shadows *grids);

/* The light-grid kernel (pgrid_shadow.c, one copy per instruction set):
 * occluded[i] = 1 when rays[i] (from its origin towards light `light`, as
 * the shader proxy makes them; origin_prim[i] the triangle its origin lies
 * on, RTT_MISS or origin_prim NULL when none or unknown) is blocked, else 0; the rays are keyed by
 * cell and dominant axis and traced per key in packets of the set's lanes (pgrid_shadow.c).
 * False when out of memory. */
typedef bool (*pgrid_occluded_fn)(const pgrid_shadows *grids, uint32_t light, const rtt_ray *rays,
                                  const uint32_t *origin_prim, uint32_t count, uint8_t *occluded);

#endif

/* Pieces shared by the files of bench/: timing, the rays of one frame, the
 * tile blocks our kernels read, and the Embree peer.  Not installed. */
#ifndef RTT_BENCH_INTERNAL_H
#define RTT_BENCH_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "bench.h"
#include "engine/clock.h"
#include "bvh_kernels.h"
#include "bvh_tree.h"
#include "kd_tree.h"
#include "packet.h"
#include "rtt/shade.h"

/* Monotonic seconds. */

/* Runs fn `warmup` times untimed, then `frames` times timed, and fills
 * row->frames, seconds (median), seconds_min and fps. */
typedef void (*bench_frame_fn)(void *context);
void bench_time_frames(bench_frame_fn fn, void *context, uint32_t warmup, uint32_t frames, rtt_bench_row *row);

/* One ray per pixel, row-major.  Pixels without a ray (a shadow ray of a
 * pixel whose primary ray missed) hold tnear = +inf > tfar = -inf, which
 * every kernel and ray_packet4_load treat as an inactive lane. */
typedef struct bench_rays {
    uint32_t width, height;
    rtt_ray *rays;
    uint64_t active;
    /* primary rays: pixel (x, y)'s ray is rtt_camera_ray(&camera, x, y), so
     * a kernel may make them itself (bvh-mft's trace_camera) */
    bool from_camera;
    rtt_camera_frame camera;
} bench_rays;

static inline bool bench_ray_active(const rtt_ray *r) { return r->tnear <= r->tfar; }

/* Primary rays of the scene's camera at width x height (rtt_camera_ray, the
 * renderers' own). */
bool bench_rays_primary(const rtt_scene *scene, uint32_t width, uint32_t height, bench_rays *out);
/* Hard-shadow rays from each primary hit to the first light's centre, as
 * shade.h defines them (tnear = epsilon, tfar = distance - epsilon). */
bool bench_rays_shadow(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                       bench_rays *out);
void bench_rays_free(bench_rays *rays);

/* The rays cut into tile blocks exactly as render_optimized.c cuts a frame:
 * tiles row-major, per tile (tile/2)^2 2x2 packets of pixel quads in
 * row-major order of quads, lanes (x,y) (x+1,y) (x,y+1) (x+1,y+1); lanes
 * off the image or without a ray are inactive. */
typedef struct bench_blocks {
    uint32_t tile, tiles_x, tiles_y, block_packets;
    ray_packet4 *packets;   /* tiles_x * tiles_y * block_packets */
    uint32_t *pixel;        /* 4 per packet; UINT32_MAX for an inactive lane */
} bench_blocks;

bool bench_blocks_make(const bench_rays *rays, uint32_t tile, bench_blocks *out);
void bench_blocks_free(bench_blocks *blocks);

/* What one row traces: our kernel (traversal, tile, culling) or an Embree
 * query, closest hit or occlusion, on `threads` threads. */
typedef struct bench_trace_spec {
    bool occlusion;
    uint32_t threads, warmup, frames;
    bool count;             /* one extra frame with kd_counters for N and I */
    rtt_isa isa;            /* our kernels' instruction set (rtt_bench_config.isa) */
} bench_trace_spec;

/* Times one of our kernels on the blocks.  result (may be NULL) receives one
 * value per pixel of the last frame: the prim (RTT_MISS on a miss) or the
 * occlusion bit. */
bool bench_kernel_row(const kd_tree *tree, const bench_blocks *blocks, uint32_t width, uint32_t height,
                      const char *kernel_name, int leaf_culling, const bench_trace_spec *spec, rtt_bench_row *row,
                      uint32_t *result);

/* Times one of our BVH kernels (bench_bvh.c) on the rays in 16x16 tiles of
 * 4x4 pixel blocks; result as bench_kernel_row's.  N and I: AABB tests and
 * packet-wide triangle tests per 2x2 rays.  toward (may be NULL): the point
 * every ray heads to (bvh_query.toward: the hard-shadow rays' light); sum
 * (may be NULL, with spec->count): the counting frame's totals. */
bool bench_bvh_row(const bvh_tree *tree, const bench_rays *rays, const char *kernel_name, const float *toward,
                   const bench_trace_spec *spec, rtt_bench_row *row, bvh_counters *sum, uint32_t *result);

/* The soft-shadow rows' work (bench_frusta.c): per pixel of the image its
 * primary hit point and the first light's frame from it (the light must
 * have area), the 16 samples of its interleaved set, and the same samples as
 * rays laid out 4x4 per pixel (an image 4x wider and higher: a 4x4 block is
 * one pixel's rays). */
#define BENCH_SOFT_SAMPLES 16u
typedef struct bench_soft {
    uint32_t width, height;
    bvh_shadow_point *points;   /* per pixel */
    uint8_t *has;               /* per pixel: a primary hit */
    bvh_shadow_sets sets;
    float epsilon;
    bench_rays rays;            /* 4 width x 4 height */
} bench_soft;
bool bench_soft_make(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                     bench_soft *out, rtt_error *err);
void bench_soft_free(bench_soft *soft);
/* multi:N's samples of the first light (rtt_light_sample, pixel index i)
 * from every primary hit as rays, laid out 4 x N/4 per pixel (an image 4x
 * wider and N/4 higher: a 4 x N/4 block is one pixel's rays, one packet of
 * Embree's rtcOccludedN); N a multiple of 4 up to 16.  Free out->rays. */
bool bench_soft_multi_make(const rtt_scene *scene, const bench_rays *primary, const uint32_t *prim, const float *t,
                           uint32_t n, bench_rays *out, rtt_error *err);
/* --shadows pgrid:N on those rays (bench_pgrid_soft.c): a frame is the 3D
 * light grid's build for light 0 (the triangles' corners made once, as the
 * kd-tree) plus every pixel's N rays as packets through the slice
 * traverser, rows of pixels on the thread pool.  Fills row and build_row as
 * bench_pgrid_row; row->n and row->i are Table 5's traversal steps (the
 * cells a 2D DDA crosses per slice and face, over the whole segment) and the
 * triangle tests per ray (not per 2x2); result gets each ray's occlusion bit at its
 * place. */
bool bench_pgrid_soft_row(const rtt_scene *scene, const uint8_t *degenerate, const bench_rays *rays, uint32_t n,
                          const bench_trace_spec *spec, rtt_bench_row *row, rtt_bench_row *build_row, uint32_t *result);
/* Table 5's comparison (bench_grid3d.c): the cells a 3D-DDA visits per ray
 * through a uniform axis-aligned grid of about `cells` cubic cells over the
 * scene's bounds, each ray over [tnear, tfar] clipped to the box.  It only
 * counts.  dims gets the grid's cells per axis. */
double bench_grid3d_steps_per_ray(const rtt_scene *scene, const bench_rays *rays, uint64_t cells, uint32_t dims[3]);
/* Times the soft-shadow frusta kernel (frusta:16) on the points in 16x16
 * tiles of 4x4 pixel blocks; sum (with spec->count) the counting frame's
 * totals and N, I per 2x2 rays; result (may be NULL) each ray's occlusion
 * bit at its place in soft->rays. */
bool bench_frusta_row(const bvh_tree *tree, const bench_soft *soft, const bench_trace_spec *spec, rtt_bench_row *row,
                      bvh_counters *sum, uint32_t *result);

/* Times the perspective grid's eye rays (bench_pgrid.c): each frame the
 * grid's build, every cell and every pixel's hit.  Fills row (fps, rays/s)
 * and build_row (the build's median, its memory); result as above. */
bool bench_pgrid_row(const rtt_scene *scene, const uint8_t *degenerate, uint32_t width, uint32_t height,
                     uint32_t cell, const bench_trace_spec *spec, rtt_bench_row *row, rtt_bench_row *build_row, uint32_t *result);

/* The shadow rays as the light grid's kernel takes them (bench_pgrid.c),
 * made once before any timed frame: every eye-ray cell's (side pixels
 * square) active rays in pixel order, the cells one after the other, with
 * their origins' triangles and pixels; first[c] .. first[c + 1] are cell
 * c's, first[cells] all of them. */
typedef struct bench_shadow_batches {
    rtt_ray *rays;
    uint32_t *prim, *pixel, *first;
    uint32_t cells;
} bench_shadow_batches;
bool bench_shadow_batches_make(bench_shadow_batches *b, const bench_rays *rays, const uint32_t *origin_prim,
                               uint32_t side);
void bench_shadow_batches_free(bench_shadow_batches *b);
/* Every batch through the light grid's kernel (light 0), a batch a task on
 * `threads` of the pool; answers[k] for batches.rays[k].  False when the
 * kernel ran out of memory. */
struct pgrid_kernel;
struct pgrid_shadows;
bool bench_shadow_batches_trace(const bench_shadow_batches *b, const struct pgrid_kernel *kernel,
                                const struct pgrid_shadows *grids, uint8_t *answers, uint32_t threads);

/* Times hard shadows through the light grid (bench_pgrid.c): each frame
 * the grid of light 0 and every pixel's shadow ray, batched per eye-ray
 * cell; origin_prim: per pixel the triangle its ray starts on; light_res
 * the cells per face side (0: pgrid_light_res_rule).  Fills row
 * and build_row as bench_pgrid_row; result gets the
 * occlusion bit per pixel. */
bool bench_pgrid_shadow_row(const rtt_scene *scene, const uint8_t *degenerate, const bench_rays *rays,
                            const uint32_t *origin_prim, uint32_t light_res, const bench_trace_spec *spec, rtt_bench_row *row, rtt_bench_row *build_row,
                            uint32_t *result);

/* The software Z-buffer anchor (bench_llvmpipe.c): Mesa's llvmpipe through
 * OSMesa drawing the view with the prim as colour; result gets each pixel's
 * prim (RTT_MISS for the background).  Unavailable without OSMesa. */
bool bench_llvmpipe_available(void);
bool bench_llvmpipe_row(const rtt_scene *scene, uint32_t width, uint32_t height, const bench_trace_spec *spec,
                        rtt_bench_row *row, uint32_t *result, rtt_error *err);

/* The Embree peer: one device and scene per variant. */
typedef struct bench_embree bench_embree;

bool bench_embree_available(void);
/* native: Embree's own ISA choice, else pinned to SSE4.2 (our kernels' ISA);
 * robust: RTC_SCENE_FLAG_ROBUST, else RTC_SCENE_FLAG_NONE.  Always
 * RTC_BUILD_QUALITY_HIGH and a one-thread build, timed into build_row. */
bench_embree *bench_embree_create(const rtt_scene *scene, bool native, bool robust, rtt_bench_row *build_row,
                                  rtt_error *err);
const char *bench_embree_variant(const bench_embree *peer);
/* Times rtcIntersectN / rtcOccludedN (lanes 1, 4, 8 or 16) on the rays:
 * lanes 1 in pixel order per tile, 4 = 2x2, 8 = 4x2, 16 = 4x4 pixel blocks,
 * coherent context flag for lanes > 1. */
bool bench_embree_row(bench_embree *peer, const bench_rays *rays, uint32_t lanes, const bench_trace_spec *spec,
                      rtt_bench_row *row, uint32_t *result, rtt_error *err);
void bench_embree_destroy(bench_embree *peer);

/* Appends a row (zeroed, then copied); false when out of memory. */
/* The file name of `path` without directories and extensions, at most 63 bytes. */
void bench_base_name(const char *path, char out[64]);

bool bench_report_push(rtt_bench_report *report, const rtt_bench_row *row);

#endif

/* The BVH's kernel descriptor table (the layout of kd/kernels.h): a
 * kernel's name exists only in its rows of bvh_kernel_table.c, one row per
 * instruction set it is compiled for; the engine, the bench and the tests
 * find kernels there with bvh_kernel_find. */
#ifndef RTT_BVH_KERNELS_H
#define RTT_BVH_KERNELS_H

#include <stddef.h>
#include <stdint.h>

#include "bvh_tree.h"
#include "rtt/engine.h"

/* Benthin & Wald's Table 1 counters: AABB tests (one per box and packet, or
 * per box and frustum set), triangles reached in leaves (one per record and
 * packet), and packet-wide ray/triangle tests. */
typedef struct bvh_counters {
    uint64_t packets, aabb_tests, triangles, isect_tests;
} bvh_counters;

/* What a kernel is asked: `count` rays and either closest hits (`hits`,
 * written for every ray) or occlusion (`occluded`, 1 = occluded); the other
 * pointer NULL.  Counters only when non-NULL; they never change results. */
typedef struct bvh_query {
    const rtt_ray *rays;
    size_t count;
    rtt_hit *hits;
    uint8_t *occluded;
    bvh_counters *counters;
    /* Occlusion only, optional: a point every ray heads to (a point light;
     * each ray's segment ends at or short of it).  bvh-mft then bounds a
     * group of rays that share no origin by the frustum from this point back
     * to their origins (hard shadows, Benthin & Wald 2009, 3.2); the other
     * kernels ignore it.  Never changes results. */
    const float *toward;
} bvh_query;

typedef void (*bvh_kernel_fn)(const bvh_tree *tree, const bvh_query *query);

/* Primary rays made by the kernel from the camera frame, never stored
 * (Benthin & Wald 2009, 4.1: start and delta vectors): pixel (x, y)'s ray
 * is rtt_camera_ray(frame, x, y) bit for bit, for the pixels
 * [x0, x1) x [y0, y1); its closest hit goes to
 * hits[(y - y0) * (x1 - x0) + (x - x0)].  With `stream` (a frame's hits,
 * read only after the frame, not a tile the caller shades at once) rows
 * that start on a 64-byte line are written past the caches, non-temporal
 * stores, NOT fenced: the calling thread sees them in program order, and
 * one that hands them to another thread fences first (_mm_sfence) -- the
 * thread pool does, once per worker after its tasks (engine/thread_pool.c),
 * so the tiles of rtt_tiles_run need nothing more. */
typedef struct bvh_camera_block {
    float eye[3], corner[3], du[3], dv[3]; /* rtt_camera_frame's */
    uint32_t x0, y0, x1, y1;
    bool stream;
} bvh_camera_block;

typedef void (*bvh_camera_fn)(const bvh_tree *tree, const bvh_camera_block *block, rtt_hit *hits,
                              bvh_counters *counters);

typedef struct bvh_kernel {
    const char *name;          /* what --traversal calls it (with --accel bvh) */
    const char *implements;    /* the paper and section */
    bvh_kernel_fn trace;
    bvh_camera_fn trace_camera; /* primary rays from the camera frame: bvh-mft's; NULL for the others */
    uint32_t width;            /* rays a packet holds: 1, or the ISA's lanes */
    rtt_isa isa;               /* the instruction set its object was compiled for */
} bvh_kernel;

/* The row for `name` ("" → the default, bvh-packet) for the widest
 * instruction set not wider than `isa` (resolved) that this CPU runs; NULL
 * for an unknown name. */
const bvh_kernel *bvh_kernel_find(const char *name, rtt_isa isa);
/* The i-th distinct kernel name, NULL past the last. */
const char *bvh_kernel_name_at(uint32_t i);
/* The i-th row whatever this CPU runs, NULL past the last (tests). */
const bvh_kernel *bvh_kernel_row_at(uint32_t i);

/* ---- soft shadows through multi-frusta: --shadows frusta:N ----
 *
 * One shading point (a pixel's hit) and one light with area: the N sample
 * rays of the pixel's interleaved set (rtt/interleaved.h), generated on
 * demand from the point, the light's frame as seen from the point and the
 * set's domain coordinates, never stored: sample k's target is
 * (base + du x_k) + dv y_k and its ray the segment of rtt/shade.h (from org
 * towards the target, tnear = epsilon, tfar = |target - org| - epsilon;
 * none when the distance is not above 2 epsilon: that sample is clear), the
 * same bits as the scalar renderers' rays. */
typedef struct bvh_shadow_point {
    float org[3];
    float base[3], du[3], dv[3];    /* rtt_light_frame of the light from org */
    uint32_t set;                   /* the pixel's interleaved set, 0..15 */
} bvh_shadow_point;

/* The sets' domain coordinates, the same for every point of one light:
 * x[set][k], y[set][k] (k < samples, rtt_interleaved_coords) and each set's
 * 2D bounds (rtt_interleaved_bounds), which bound the frusta. */
#define BVH_SHADOW_MAX_SAMPLES 32u
typedef struct bvh_shadow_sets {
    uint32_t samples;               /* N, 1..BVH_SHADOW_MAX_SAMPLES */
    float x[16][BVH_SHADOW_MAX_SAMPLES], y[16][BVH_SHADOW_MAX_SAMPLES];
    float lo[16][2], hi[16][2];
} bvh_shadow_sets;

/* `count` points of one light; occluded[i] gets bit k set when sample k of
 * point i is occluded.  The kernel traces its width's points at once, one
 * frustum each (16 on AVX-512: a 4x4 block of pixels when the caller orders
 * them so). */
typedef struct bvh_shadow_query {
    const bvh_shadow_point *points;
    size_t count;
    const bvh_shadow_sets *sets;
    float epsilon;
    uint32_t *occluded;
    bvh_counters *counters;
} bvh_shadow_query;

typedef void (*bvh_shadow_fn)(const bvh_tree *tree, const bvh_shadow_query *query);

typedef struct bvh_shadow_kernel {
    const char *name;
    const char *implements;
    bvh_shadow_fn trace;
    uint32_t width;                 /* frusta traced together: the ISA's lanes */
    rtt_isa isa;
} bvh_shadow_kernel;

/* The soft-shadow frusta row for the widest instruction set not wider than
 * `isa` that this CPU runs (never NULL: SSE4.1 is the baseline). */
const bvh_shadow_kernel *bvh_shadow_kernel_find(rtt_isa isa);
/* The i-th row whatever this CPU runs, NULL past the last (tests). */
const bvh_shadow_kernel *bvh_shadow_kernel_row_at(uint32_t i);

#define BVH_KERNEL_PROTOTYPES(isa)                                              \
    void bvh_kernel_mono_##isa(const bvh_tree *tree, const bvh_query *q);      \
    void bvh_kernel_packet_##isa(const bvh_tree *tree, const bvh_query *q);     \
    void bvh_kernel_mft_##isa(const bvh_tree *tree, const bvh_query *q);        \
    void bvh_kernel_mft_camera_##isa(const bvh_tree *tree, const bvh_camera_block *b, rtt_hit *hits,            \
                                     bvh_counters *counters);                                                 \
    void bvh_shadow_frusta_##isa(const bvh_tree *tree, const bvh_shadow_query *q);
BVH_KERNEL_PROTOTYPES(sse4)
BVH_KERNEL_PROTOTYPES(avx2)
BVH_KERNEL_PROTOTYPES(avx512)

#endif

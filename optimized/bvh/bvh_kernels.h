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
} bvh_query;

typedef void (*bvh_kernel_fn)(const bvh_tree *tree, const bvh_query *query);

typedef struct bvh_kernel {
    const char *name;          /* what --traversal calls it (with --accel bvh) */
    const char *implements;    /* the paper and section */
    bvh_kernel_fn trace;
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

#define BVH_KERNEL_PROTOTYPES(isa)                                              \
    void bvh_kernel_mono_##isa(const bvh_tree *tree, const bvh_query *q);      \
    void bvh_kernel_packet_##isa(const bvh_tree *tree, const bvh_query *q);     \
    void bvh_kernel_mft_##isa(const bvh_tree *tree, const bvh_query *q);
BVH_KERNEL_PROTOTYPES(sse4)
BVH_KERNEL_PROTOTYPES(avx2)
BVH_KERNEL_PROTOTYPES(avx512)

#endif

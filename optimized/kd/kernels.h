/* The kd-tree's kernel descriptor table (Embree's kernel records; one entry
 * signature for closest hit and occlusion as in madmann91/bvh's one traversal
 * for two queries).  A kernel's name exists only in its rows of
 * kernel_table.c, one row per instruction set it is compiled for; the
 * engine, the renderer, the bench and the tests all find kernels there.
 * Adding a kernel is one row of the table's row list and its file. */
#ifndef RTT_OPTIMIZED_KERNELS_H
#define RTT_OPTIMIZED_KERNELS_H

#include "kd_tree.h"
#include "packet.h"

#define KD_BLOCK_MAX_PACKETS 256u    /* a 32x32 tile: the largest block a kernel reads */

/* What a kernel is asked: `packet_count` packets and either closest hits
 * (`hits`: lowered only where a lane finds a closer hit than the one it
 * holds; callers clear them first) or occlusion (`occluded`: packet i gets
 * its 4-bit lane mask, 1 = occluded); the other pointer NULL.  Counters and
 * the leaf-intersection timer run only when non-NULL and never change
 * results. */
typedef struct kd_query {
    const ray_packet4 *packets;
    uint32_t packet_count;
    hit_packet4 *hits;
    uint8_t *occluded;
    int leaf_culling;            /* the frustum family's packet/leaf culling */
    kd_counters *counters;       /* N and I of Tables 4.1 - 4.5, or NULL */
    uint64_t *isect_ns;          /* time in leaf intersection (Table 3.1), or NULL */
} kd_query;

typedef void (*kd_kernel_fn)(const kd_tree *tree, const kd_query *query);

/* The block a kernel reads: independent 2x2 packets, or one tile of
 * tile*tile/4 packets (quads in row-major order) under proxies. */
typedef enum kd_block_shape { KD_BLOCK_PACKETS = 0, KD_BLOCK_TILE } kd_block_shape;

typedef struct kd_kernel {
    const char *name;            /* what --traversal calls it */
    const char *implements;      /* the thesis listing or section */
    kd_kernel_fn trace;
    kd_block_shape block;
    rtt_isa isa;                 /* the instruction set its object was compiled for */
} kd_kernel;

/* The row for `name` ("" → the default, mft) compiled for the widest
 * instruction set that is not wider than `isa` (already resolved, never
 * AUTO) and that this CPU runs (rtt_isa_supported); NULL for an unknown
 * name.  The one way baseline code reaches a kernel. */
const kd_kernel *kd_kernel_find(const char *name, rtt_isa isa);
/* The kernels the renderer uses for a role rather than by the user's
 * choice: reflection and refraction rays (omni: any directions), and the
 * sample groups of pyramid:N (one interval frustum each). */
const kd_kernel *kd_kernel_for_secondary_rays(rtt_isa isa);
const kd_kernel *kd_kernel_for_pyramid_groups(rtt_isa isa);
/* The i-th distinct kernel name (from 0), NULL past the last. */
const char *kd_kernel_name_at(uint32_t i);
/* The i-th row of the table (from 0), whatever this CPU runs; NULL past the
 * last.  For listings and tests: only kd_kernel_find hands out kernels. */
const kd_kernel *kd_kernel_row_at(uint32_t i);
/* Packets per block: 1 for KD_BLOCK_PACKETS, tile*tile/4 for KD_BLOCK_TILE
 * (tile 4, 8, 16 or 32; anything else counts as 8). */
uint32_t kd_kernel_block_packets(const kd_kernel *kernel, uint32_t tile);

/* The kernels (traverse_*.c), one copy per instruction set (kernel_isa.h):
 * kd_kernel_mono_sse4, kd_kernel_mono_avx2, kd_kernel_mono_avx512, ... */
#define KD_KERNEL_PROTOTYPES(isa)                                                  \
    void kd_kernel_mono_##isa(const kd_tree *tree, const kd_query *q);             \
    void kd_kernel_packet_##isa(const kd_tree *tree, const kd_query *q);           \
    void kd_kernel_omni_##isa(const kd_tree *tree, const kd_query *q);             \
    void kd_kernel_frustum_##isa(const kd_tree *tree, const kd_query *q);          \
    void kd_kernel_mft_##isa(const kd_tree *tree, const kd_query *q);              \
    void kd_kernel_cone_##isa(const kd_tree *tree, const kd_query *q);             \
    void kd_kernel_mft_cone_##isa(const kd_tree *tree, const kd_query *q);
KD_KERNEL_PROTOTYPES(sse4)
KD_KERNEL_PROTOTYPES(avx2)
KD_KERNEL_PROTOTYPES(avx512)

#endif

/* The kd-tree's kernel descriptor table (Embree's kernel records; one entry
 * signature for closest hit and occlusion as in madmann91/bvh's one traversal
 * for two queries).  A kernel's name exists only in its row of
 * kernel_table.c; the engine, the renderer, the bench and the tests all
 * find kernels there.  Adding a kernel is one row and its file. */
#ifndef RTT_OPTIMIZED_KERNELS_H
#define RTT_OPTIMIZED_KERNELS_H

#include "packet.h"

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
 * instruction set not wider than `isa` (already resolved, never AUTO);
 * NULL for an unknown name. */
const kd_kernel *kd_kernel_find(const char *name, rtt_isa isa);
/* The i-th distinct kernel name (from 0), NULL past the last. */
const char *kd_kernel_name_at(uint32_t i);
/* Packets per block: 1 for KD_BLOCK_PACKETS, tile*tile/4 for KD_BLOCK_TILE
 * (tile 4, 8, 16 or 32; anything else counts as 8). */
uint32_t kd_kernel_block_packets(const kd_kernel *kernel, uint32_t tile);

/* The kernels (traverse_*.c). */
void kd_kernel_mono(const kd_tree *tree, const kd_query *q);
void kd_kernel_packet(const kd_tree *tree, const kd_query *q);
void kd_kernel_omni(const kd_tree *tree, const kd_query *q);
void kd_kernel_frustum(const kd_tree *tree, const kd_query *q);
void kd_kernel_mft(const kd_tree *tree, const kd_query *q);
void kd_kernel_cone(const kd_tree *tree, const kd_query *q);
void kd_kernel_mft_cone(const kd_tree *tree, const kd_query *q);

#endif

/* The BVH's kernel descriptor table (bvh_kernels.h): every kernel once per
 * instruction set its object was compiled for (bvh_isa.h).  Baseline code:
 * it only takes the copies' addresses, and bvh_kernel_find hands out a copy
 * only where the CPU runs it. */
#include <string.h>

#include "bvh_kernels.h"

#define BVH_DEFAULT_KERNEL "bvh-packet"

#define BVH_KERNEL_ROWS(isa_enum, isa, lanes)                                                                     \
    {"bvh-mono", "Kay & Kajiya slabs, ordered depth-first walk: one ray", bvh_kernel_mono_##isa, NULL, 1, isa_enum},    \
    {"bvh-packet", "Benthin & Wald 2009, 5.1: the 16-wide packet baseline (8 on AVX2, 4 on SSE4.1)",             \
     bvh_kernel_packet_##isa, NULL, lanes, isa_enum},                                                                  \
    {"bvh-mft", "Benthin & Wald 2009, 4.1-4.3: 16 frusta of 16 rays (8 on AVX2, 4 on SSE4.1) at once",          \
     bvh_kernel_mft_##isa, bvh_kernel_mft_camera_##isa, lanes * 16u, isa_enum},

static const bvh_kernel bvh_kernels[] = {
    BVH_KERNEL_ROWS(RTT_ISA_SSE4, sse4, 4)
    BVH_KERNEL_ROWS(RTT_ISA_AVX2, avx2, 8)
    BVH_KERNEL_ROWS(RTT_ISA_AVX512, avx512, 16)
};
#define BVH_KERNEL_ROW_COUNT (sizeof bvh_kernels / sizeof bvh_kernels[0])

const bvh_kernel *bvh_kernel_find(const char *name, rtt_isa isa)
{
    if (!name || !name[0]) name = BVH_DEFAULT_KERNEL;
    const bvh_kernel *best = NULL;
    for (size_t i = 0; i < BVH_KERNEL_ROW_COUNT; i++) {
        const bvh_kernel *k = &bvh_kernels[i];
        if (strcmp(k->name, name) != 0 || k->isa > isa || !rtt_isa_supported(k->isa)) continue;
        if (!best || k->isa > best->isa) best = k;
    }
    return best;
}

const char *bvh_kernel_name_at(uint32_t i)
{
    uint32_t seen = 0;
    for (size_t r = 0; r < BVH_KERNEL_ROW_COUNT; r++) {
        size_t first = 0;
        while (strcmp(bvh_kernels[first].name, bvh_kernels[r].name) != 0) first++;
        if (first != r) continue;
        if (seen++ == i) return bvh_kernels[r].name;
    }
    return NULL;
}

const bvh_kernel *bvh_kernel_row_at(uint32_t i) { return i < BVH_KERNEL_ROW_COUNT ? &bvh_kernels[i] : NULL; }

static const bvh_shadow_kernel bvh_shadow_kernels[] = {
    {"frusta", "Benthin & Wald 2009, 4.4-4.5: 4 soft-shadow frusta of N on-demand rays at once", bvh_shadow_frusta_sse4,
     4, RTT_ISA_SSE4},
    {"frusta", "Benthin & Wald 2009, 4.4-4.5: 8 soft-shadow frusta of N on-demand rays at once", bvh_shadow_frusta_avx2,
     8, RTT_ISA_AVX2},
    {"frusta", "Benthin & Wald 2009, 4.4-4.5: 16 soft-shadow frusta of N on-demand rays at once",
     bvh_shadow_frusta_avx512, 16, RTT_ISA_AVX512},
};
#define BVH_SHADOW_ROW_COUNT (sizeof bvh_shadow_kernels / sizeof bvh_shadow_kernels[0])

const bvh_shadow_kernel *bvh_shadow_kernel_find(rtt_isa isa)
{
    const bvh_shadow_kernel *best = &bvh_shadow_kernels[0];
    for (size_t i = 1; i < BVH_SHADOW_ROW_COUNT; i++) {
        const bvh_shadow_kernel *k = &bvh_shadow_kernels[i];
        if (k->isa <= isa && rtt_isa_supported(k->isa) && k->isa > best->isa) best = k;
    }
    return best;
}

const bvh_shadow_kernel *bvh_shadow_kernel_row_at(uint32_t i)
{
    return i < BVH_SHADOW_ROW_COUNT ? &bvh_shadow_kernels[i] : NULL;
}

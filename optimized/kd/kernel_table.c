/* The kd-tree's kernel descriptor table (kernels.h): every kernel once per
 * instruction set its object was compiled for (kernel_isa.h).  Baseline
 * code: it only takes the copies' addresses, and kd_kernel_find hands out
 * a copy only where the CPU runs it. */
#include <string.h>

#include "kernels.h"

#define KD_DEFAULT_KERNEL "mft"

/* The seven kernels' rows for one instruction set. */
#define KD_KERNEL_ROWS(isa_enum, isa)                                                                           \
    {"mono", "Thesis Listing 2.2: one ray, explicit stack", kd_kernel_mono_##isa, KD_BLOCK_PACKETS, isa_enum},  \
    {"packet", "Thesis Listing 2.4: 2x2 packets, equal signs", kd_kernel_packet_##isa, KD_BLOCK_PACKETS,        \
     isa_enum},                                                                                                 \
    {"omni", "Thesis Listing 4.1: omni-directional 2x2 packets", kd_kernel_omni_##isa, KD_BLOCK_PACKETS,        \
     isa_enum},                                                                                                 \
    {"frustum", "Thesis Listing 4.2 + 4.1.4: one frustum per tile", kd_kernel_frustum_##isa, KD_BLOCK_TILE,     \
     isa_enum},                                                                                                 \
    {"mft", "Thesis 4.1.5: four quadrant frusta per tile", kd_kernel_mft_##isa, KD_BLOCK_TILE, isa_enum},       \
    {"cone", "Thesis Listings 4.3 - 4.5: one cone per tile", kd_kernel_cone_##isa, KD_BLOCK_TILE, isa_enum},    \
    {"mft-cone", "Thesis 4.1.9: four quadrant cones per tile", kd_kernel_mft_cone_##isa, KD_BLOCK_TILE, isa_enum},

static const kd_kernel kd_kernels[] = {
    KD_KERNEL_ROWS(RTT_ISA_SSE4, sse4)
    KD_KERNEL_ROWS(RTT_ISA_AVX2, avx2)
    KD_KERNEL_ROWS(RTT_ISA_AVX512, avx512)
};
#define KD_KERNEL_ROW_COUNT (sizeof kd_kernels / sizeof kd_kernels[0])

const kd_kernel *kd_kernel_find(const char *name, rtt_isa isa)
{
    if (!name || !name[0]) name = KD_DEFAULT_KERNEL;
    const kd_kernel *best = NULL;
    for (size_t i = 0; i < KD_KERNEL_ROW_COUNT; i++) {
        const kd_kernel *k = &kd_kernels[i];
        if (strcmp(k->name, name) != 0 || k->isa > isa || !rtt_isa_supported(k->isa)) continue;
        if (!best || k->isa > best->isa) best = k;
    }
    return best;
}

const kd_kernel *kd_kernel_for_secondary_rays(rtt_isa isa) { return kd_kernel_find("omni", isa); }
const kd_kernel *kd_kernel_for_pyramid_groups(rtt_isa isa) { return kd_kernel_find("frustum", isa); }

const char *kd_kernel_name_at(uint32_t i)
{
    uint32_t seen = 0;
    for (size_t r = 0; r < KD_KERNEL_ROW_COUNT; r++) {
        size_t first = 0;
        while (strcmp(kd_kernels[first].name, kd_kernels[r].name) != 0) first++;
        if (first != r) continue; /* a later ISA's row of a name already counted */
        if (seen++ == i) return kd_kernels[r].name;
    }
    return NULL;
}

const kd_kernel *kd_kernel_row_at(uint32_t i) { return i < KD_KERNEL_ROW_COUNT ? &kd_kernels[i] : NULL; }

uint32_t kd_kernel_block_packets(const kd_kernel *kernel, uint32_t tile)
{
    if (kernel->block == KD_BLOCK_PACKETS) return 1;
    if (tile != 4 && tile != 8 && tile != 16 && tile != 32) tile = 8;
    return tile * tile / 4u;
}

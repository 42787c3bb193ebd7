/* The kd-tree's kernel descriptor table (kernels.h). */
#include <string.h>

#include "kernels.h"

#define KD_DEFAULT_KERNEL "mft"

static const kd_kernel kd_kernels[] = {
    {"mono", "Thesis Listing 2.2: one ray, explicit stack", kd_kernel_mono, KD_BLOCK_PACKETS, RTT_ISA_SSE4},
    {"packet", "Thesis Listing 2.4: 2x2 packets, equal signs", kd_kernel_packet, KD_BLOCK_PACKETS, RTT_ISA_SSE4},
    {"omni", "Thesis Listing 4.1: omni-directional 2x2 packets", kd_kernel_omni, KD_BLOCK_PACKETS, RTT_ISA_SSE4},
    {"frustum", "Thesis Listing 4.2 + 4.1.4: one frustum per tile", kd_kernel_frustum, KD_BLOCK_TILE, RTT_ISA_SSE4},
    {"mft", "Thesis 4.1.5: four quadrant frusta per tile", kd_kernel_mft, KD_BLOCK_TILE, RTT_ISA_SSE4},
    {"cone", "Thesis Listings 4.3 - 4.5: one cone per tile", kd_kernel_cone, KD_BLOCK_TILE, RTT_ISA_SSE4},
    {"mft-cone", "Thesis 4.1.9: four quadrant cones per tile", kd_kernel_mft_cone, KD_BLOCK_TILE, RTT_ISA_SSE4},
};
#define KD_KERNEL_ROWS (sizeof kd_kernels / sizeof kd_kernels[0])

const kd_kernel *kd_kernel_find(const char *name, rtt_isa isa)
{
    if (!name || !name[0]) name = KD_DEFAULT_KERNEL;
    const kd_kernel *best = NULL;
    for (size_t i = 0; i < KD_KERNEL_ROWS; i++) {
        const kd_kernel *k = &kd_kernels[i];
        if (strcmp(k->name, name) != 0 || k->isa > isa) continue;
        if (!best || k->isa > best->isa) best = k;
    }
    return best;
}

const char *kd_kernel_name_at(uint32_t i)
{
    uint32_t seen = 0;
    for (size_t r = 0; r < KD_KERNEL_ROWS; r++) {
        size_t first = 0;
        while (strcmp(kd_kernels[first].name, kd_kernels[r].name) != 0) first++;
        if (first != r) continue; /* a later ISA's row of a name already counted */
        if (seen++ == i) return kd_kernels[r].name;
    }
    return NULL;
}

uint32_t kd_kernel_block_packets(const kd_kernel *kernel, uint32_t tile)
{
    if (kernel->block == KD_BLOCK_PACKETS) return 1;
    if (tile != 4 && tile != 8 && tile != 16 && tile != 32) tile = 8;
    return tile * tile / 4u;
}

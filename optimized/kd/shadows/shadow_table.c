/* The shadow kernels' descriptor table (shadow_kernels.h): one row per
 * instruction set, chosen at run time as kernel_table.c chooses. */
#include "shadow_kernels.h"

#define KD_SHADOW_ROW(isa_enum, isa) {sc_trace_groups_##isa, ew_occlusion4_##isa, ew_occlusion_stream_##isa, isa_enum}

/* in ascending instruction-set order: kd_shadow_kernels_find keeps the last that fits */
static const kd_shadow_kernels kd_shadow_rows[] = {
    KD_SHADOW_ROW(RTT_ISA_SSE4, sse4),
    KD_SHADOW_ROW(RTT_ISA_AVX2, avx2),
    KD_SHADOW_ROW(RTT_ISA_AVX512, avx512),
};
#define KD_SHADOW_ROW_COUNT (sizeof kd_shadow_rows / sizeof kd_shadow_rows[0])

const kd_shadow_kernels *kd_shadow_kernels_find(rtt_isa isa)
{
    const kd_shadow_kernels *best = &kd_shadow_rows[0];
    for (size_t i = 1; i < KD_SHADOW_ROW_COUNT; i++)
        if (kd_shadow_rows[i].isa <= isa && rtt_isa_supported(kd_shadow_rows[i].isa)) best = &kd_shadow_rows[i];
    return best;
}

const kd_shadow_kernels *kd_shadow_kernels_row_at(uint32_t i)
{
    return i < KD_SHADOW_ROW_COUNT ? &kd_shadow_rows[i] : NULL;
}

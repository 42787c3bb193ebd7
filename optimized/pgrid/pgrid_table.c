/* The perspective grid's kernel descriptor table (pgrid_eye.h): the cell
 * kernel once per instruction set its object was compiled for
 * (pgrid_isa.h).  Baseline code: it only takes the copies' addresses, and
 * pgrid_kernel_find hands out a copy only where the CPU runs it. */
#include <string.h>

#include "pgrid_eye.h"

#define PGRID_KERNEL_COPY(isa)                                                                                \
    void pgrid_trace_cell_##isa(const pgrid_eye *, uint32_t, pgrid_cell_buffers *);                          \
    void pgrid_resolve_cell_##isa(const pgrid_eye *, uint32_t, pgrid_cell_buffers *, rtt_hit *, size_t, bool);  \
    bool pgrid_shadow_occluded_##isa(const pgrid_shadows *, uint32_t, const rtt_ray *, const uint32_t *, uint32_t, \
                                     uint8_t *);                                                                    \
    void pgrid_soft_occluded_##isa(const pgrid_soft *, uint32_t, const rtt_ray *, uint32_t, uint8_t *, pgrid_soft_counts *); \
    void pgrid_light_prints_##isa(const pgrid_print_job *, uint32_t, uint32_t);
PGRID_KERNEL_COPY(sse4)
PGRID_KERNEL_COPY(avx2)
PGRID_KERNEL_COPY(avx512)

#define PGRID_IMPLEMENTS "Hunt & Mark 5.1: 2D perspective grid, cells in object order against a depth buffer"

static const pgrid_kernel pgrid_kernels[] = {
    {"pgrid", PGRID_IMPLEMENTS, pgrid_trace_cell_sse4, pgrid_resolve_cell_sse4, pgrid_shadow_occluded_sse4, pgrid_soft_occluded_sse4, pgrid_light_prints_sse4, 4, RTT_ISA_SSE4},
    {"pgrid", PGRID_IMPLEMENTS, pgrid_trace_cell_avx2, pgrid_resolve_cell_avx2, pgrid_shadow_occluded_avx2, pgrid_soft_occluded_avx2, pgrid_light_prints_avx2, 8, RTT_ISA_AVX2},
    {"pgrid", PGRID_IMPLEMENTS, pgrid_trace_cell_avx512, pgrid_resolve_cell_avx512, pgrid_shadow_occluded_avx512, pgrid_soft_occluded_avx512, pgrid_light_prints_avx512, 16, RTT_ISA_AVX512},
};
#define PGRID_KERNEL_ROW_COUNT (sizeof pgrid_kernels / sizeof pgrid_kernels[0])

const pgrid_kernel *pgrid_kernel_find(const char *name, rtt_isa isa)
{
    if (!name || !name[0]) name = "pgrid";
    const pgrid_kernel *best = NULL;
    for (size_t i = 0; i < PGRID_KERNEL_ROW_COUNT; i++) {
        const pgrid_kernel *k = &pgrid_kernels[i];
        if (strcmp(k->name, name) != 0 || k->isa > isa || !rtt_isa_supported(k->isa)) continue;
        if (!best || k->isa > best->isa) best = k;
    }
    return best;
}

const char *pgrid_kernel_name_at(uint32_t i) { return i == 0 ? pgrid_kernels[0].name : NULL; }

const pgrid_kernel *pgrid_kernel_row_at(uint32_t i)
{
    return i < PGRID_KERNEL_ROW_COUNT ? &pgrid_kernels[i] : NULL;
}

/* The perspective grid's kernel side is compiled three times, like the
 * kd-tree's (../kd/kernel_isa.h): once per instruction set, with
 * RTT_ISA_SUFFIX = sse4, avx2 or avx512 (optimized/CMakeLists.txt, the
 * object libraries rtt_pgrid_kernels_*).  This header renames each external
 * symbol of that side to name_<suffix>; baseline code reaches the copies
 * only through pgrid_table.c. */
#ifndef RTT_OPTIMIZED_PGRID_ISA_H
#define RTT_OPTIMIZED_PGRID_ISA_H

#ifndef RTT_ISA_SUFFIX
#error "a kernel-side header: only the rtt_pgrid_kernels_* object libraries (RTT_ISA_SUFFIX) may include it"
#endif

#define PGRID_ISA_PASTE(name, suffix) name##_##suffix
#define PGRID_ISA_EXPAND(name, suffix) PGRID_ISA_PASTE(name, suffix)
#define PGRID_ISA(name) PGRID_ISA_EXPAND(name, RTT_ISA_SUFFIX)

#define pgrid_trace_cell PGRID_ISA(pgrid_trace_cell)
#define pgrid_resolve_cell PGRID_ISA(pgrid_resolve_cell)
#define pgrid_shadow_occluded PGRID_ISA(pgrid_shadow_occluded)

#endif

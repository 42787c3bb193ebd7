/* The kernel side is compiled three times, once per instruction set
 * (optimized/CMakeLists.txt: the object libraries rtt_kd_kernels_sse4,
 * _avx2 and _avx512, each with its -m flags and RTT_ISA_SUFFIX = sse4, avx2
 * or avx512).  This header, included by every kernel-side header and
 * source, renames each external symbol the kernel side defines to
 * name_<suffix>, so the three copies link into one library side by side,
 * and a kernel calls only its own copy of what it shares with the others.
 *
 * Baseline code never calls a renamed symbol itself: it takes a row of the
 * descriptor tables (kernel_table.c, shadows/shadow_table.c), which name
 * each copy explicitly and hand out one only where rtt_isa_supported says
 * the CPU runs it.  A baseline file that includes a kernel-side header
 * stops here. */
#ifndef RTT_OPTIMIZED_KERNEL_ISA_H
#define RTT_OPTIMIZED_KERNEL_ISA_H

#ifndef RTT_ISA_SUFFIX
#error "a kernel-side header: only the rtt_kd_kernels_* object libraries (RTT_ISA_SUFFIX) may include it"
#endif

#define KD_ISA_PASTE(name, suffix) name##_##suffix
#define KD_ISA_EXPAND(name, suffix) KD_ISA_PASTE(name, suffix)
#define KD_ISA(name) KD_ISA_EXPAND(name, RTT_ISA_SUFFIX)

/* the kernels: kernels.h's and shadows/shadow_kernels.h's per-ISA prototypes */
#define kd_kernel_mono KD_ISA(kd_kernel_mono)
#define kd_kernel_packet KD_ISA(kd_kernel_packet)
#define kd_kernel_omni KD_ISA(kd_kernel_omni)
#define kd_kernel_frustum KD_ISA(kd_kernel_frustum)
#define kd_kernel_mft KD_ISA(kd_kernel_mft)
#define kd_kernel_cone KD_ISA(kd_kernel_cone)
#define kd_kernel_mft_cone KD_ISA(kd_kernel_mft_cone)
#define sc_trace_groups KD_ISA(sc_trace_groups)
#define ew_occlusion4 KD_ISA(ew_occlusion4)
#define ew_occlusion_stream KD_ISA(ew_occlusion_stream)

/* what they share: block.h, frustum.h, cone.h */
#define kd_block_init KD_ISA(kd_block_init)
#define kd_block_group_quadrants KD_ISA(kd_block_group_quadrants)
#define kd_block_group_lanes KD_ISA(kd_block_group_lanes)
#define kd_block_visit_leaf KD_ISA(kd_block_visit_leaf)
#define kd_block_trace_packets KD_ISA(kd_block_trace_packets)
#define kd_block_trace_frustum KD_ISA(kd_block_trace_frustum)
#define kd_block_trace_mft KD_ISA(kd_block_trace_mft)
#define kd_block_trace_cone KD_ISA(kd_block_trace_cone)
#define kd_block_trace_mft_cone KD_ISA(kd_block_trace_mft_cone)
#define kd_blocks_trace KD_ISA(kd_blocks_trace)
#define kd_frustum_build KD_ISA(kd_frustum_build)
#define kd_frustum_is_incoherent KD_ISA(kd_frustum_is_incoherent)
#define kd_frustum4_pack KD_ISA(kd_frustum4_pack)
#define kd_frustum4_of_lanes KD_ISA(kd_frustum4_of_lanes)
#define kd_cone_build KD_ISA(kd_cone_build)
#define kd_cone4_pack KD_ISA(kd_cone4_pack)

#endif

/* The BVH kernels are compiled once per instruction set like the kd
 * kernels (optimized/CMakeLists.txt: rtt_bvh_kernels_sse4, _avx2, _avx512,
 * each with RTT_ISA_SUFFIX); this header renames each external symbol the
 * BVH kernel side defines to name_<suffix>.  Baseline code reaches them only
 * through bvh_kernel_table.c. */
#ifndef RTT_BVH_ISA_H
#define RTT_BVH_ISA_H

#ifndef RTT_ISA_SUFFIX
#error "a BVH kernel-side header: only the rtt_bvh_kernels_* object libraries (RTT_ISA_SUFFIX) may include it"
#endif

#define BVH_ISA_PASTE(name, suffix) name##_##suffix
#define BVH_ISA_EXPAND(name, suffix) BVH_ISA_PASTE(name, suffix)
#define BVH_ISA(name) BVH_ISA_EXPAND(name, RTT_ISA_SUFFIX)

#define bvh_kernel_mono BVH_ISA(bvh_kernel_mono)
#define bvh_kernel_packet BVH_ISA(bvh_kernel_packet)
#define bvh_kernel_mft BVH_ISA(bvh_kernel_mft)
#define bvh_kernel_mft_camera BVH_ISA(bvh_kernel_mft_camera)
#define bvh_trace_packet BVH_ISA(bvh_trace_packet)
#define bvh_shadow_frusta BVH_ISA(bvh_shadow_frusta)

#endif

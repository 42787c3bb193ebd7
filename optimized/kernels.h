/* Every traversal kernel of the optimized engine, with the block signatures
 * of packet.h (kd_block_kernel / kd_block_occlusion_kernel).
 *
 *   mono     traverse_mono.c     Thesis Listing 2.2: one ray, explicit stack
 *   packet   traverse_packet.c   Thesis Listing 2.4: 2x2, equal direction signs
 *   omni     traverse_omni.c     Thesis Listing 4.1: omni-directional 2x2
 *   frustum  traverse_frustum.c  Thesis Listing 4.2 + 4.1.4 leaf culling
 *   mft      traverse_mft.c      Thesis 4.1.5 multiple frustum traversal
 *   cone     traverse_cone.c     Thesis Listings 4.3 - 4.5
 *   mft_cone traverse_cone.c     four cones per tile
 *
 * mono/packet/omni read `packet_count` independent 2x2 packets; frustum, mft,
 * cone and mft_cone read one tile of packet_count packets (T*T/4 quads in
 * row-major order of quads).  Closest-hit kernels update `hits` only where a
 * lane finds a closer hit than the one it holds (callers clear them first);
 * occlusion kernels write occluded[i] = 4-bit lane mask of packet i. */
#ifndef RTT_OPTIMIZED_KERNELS_H
#define RTT_OPTIMIZED_KERNELS_H

#include "packet.h"

void kd_traverse_mono(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_mono_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_packet(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_packet_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_omni(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_omni_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_frustum(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_frustum_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_mft(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_mft_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_cone(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_cone_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);
void kd_traverse_mft_cone(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits, uint32_t packet_count,
    int leaf_culling, kd_counters *counters);
void kd_traverse_mft_cone_occluded(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
    uint32_t packet_count, int leaf_culling, kd_counters *counters);

/* The kernels indexed by rtt_traversal (RTT_TRAVERSAL_MONO .. MFT_CONE). */
kd_block_kernel kd_kernel_for(rtt_traversal traversal);
kd_block_occlusion_kernel kd_occlusion_kernel_for(rtt_traversal traversal);

/* Packets per block a kernel reads: 1 for mono/packet/omni, tile*tile/4 for
 * the frustum family (tile 4, 8, 16 or 32). */
uint32_t kd_kernel_block_packets(rtt_traversal traversal, uint32_t tile);

#endif

/* The traversal kernels by rtt_traversal (kernels.h): the one table that
 * maps the --traversal names to code. */
#include "kernels.h"

static const kd_block_kernel closest_kernels[RTT_TRAVERSAL_COUNT] = {
    [RTT_TRAVERSAL_MONO] = kd_traverse_mono,       [RTT_TRAVERSAL_PACKET] = kd_traverse_packet,
    [RTT_TRAVERSAL_OMNI] = kd_traverse_omni,       [RTT_TRAVERSAL_FRUSTUM] = kd_traverse_frustum,
    [RTT_TRAVERSAL_MFT] = kd_traverse_mft,         [RTT_TRAVERSAL_CONE] = kd_traverse_cone,
    [RTT_TRAVERSAL_MFT_CONE] = kd_traverse_mft_cone,
};

static const kd_block_occlusion_kernel occlusion_kernels[RTT_TRAVERSAL_COUNT] = {
    [RTT_TRAVERSAL_MONO] = kd_traverse_mono_occluded,       [RTT_TRAVERSAL_PACKET] = kd_traverse_packet_occluded,
    [RTT_TRAVERSAL_OMNI] = kd_traverse_omni_occluded,       [RTT_TRAVERSAL_FRUSTUM] = kd_traverse_frustum_occluded,
    [RTT_TRAVERSAL_MFT] = kd_traverse_mft_occluded,         [RTT_TRAVERSAL_CONE] = kd_traverse_cone_occluded,
    [RTT_TRAVERSAL_MFT_CONE] = kd_traverse_mft_cone_occluded,
};

/* An unknown value gets the mono kernel: every kernel gives the same hits,
 * so a bad enum can only cost speed, never correctness. */
kd_block_kernel kd_kernel_for(rtt_traversal traversal)
{
    return (unsigned)traversal < RTT_TRAVERSAL_COUNT ? closest_kernels[traversal] : kd_traverse_mono;
}

kd_block_occlusion_kernel kd_occlusion_kernel_for(rtt_traversal traversal)
{
    return (unsigned)traversal < RTT_TRAVERSAL_COUNT ? occlusion_kernels[traversal] : kd_traverse_mono_occluded;
}

uint32_t kd_kernel_block_packets(rtt_traversal traversal, uint32_t tile)
{
    switch (traversal) {
    case RTT_TRAVERSAL_FRUSTUM:
    case RTT_TRAVERSAL_MFT:
    case RTT_TRAVERSAL_CONE:
    case RTT_TRAVERSAL_MFT_CONE:
        if (tile != 4 && tile != 8 && tile != 16 && tile != 32) tile = 8;
        return tile * tile / 4u;
    default:
        return 1;
    }
}

/* SSE ray packets: the unit every optimized kernel works on.
 *
 * A packet is four rays in the four SSE lanes (structure of arrays, 16-byte
 * aligned).  Lanes that carry no ray have tnear > tfar (inactive).  Kernels
 * take blocks of packets: a 2x2 packet is one block of 1; a frustum tile of
 * side T is one block of T*T/4 packets (2x2 pixel quads in row-major order of
 * quads).  Arbitrary ray streams are cut into such blocks by the engine. */
#ifndef RTT_OPTIMIZED_PACKET_H
#define RTT_OPTIMIZED_PACKET_H

#include <immintrin.h>
#include <stdint.h>

#include "kd_tree.h"
#include "rtt/engine.h"

/* 176 bytes: origin, direction, reciprocal direction and the interval. */
typedef struct ray_packet4 {
    __m128 org[3], dir[3], inv_dir[3];
    __m128 tnear, tfar;
} ray_packet4;
_Static_assert(sizeof(ray_packet4) == 176, "ray_packet4 is 11 SSE registers");

/* 64 bytes; prim lanes RTT_MISS and t = +inf on a miss. */
typedef struct hit_packet4 {
    __m128 t, u, v;
    __m128i prim;
} hit_packet4;
_Static_assert(sizeof(hit_packet4) == 64, "hit_packet4 is one cache line");

/* The thesis' counters (Tables 4.1-4.5): N = steps / packets, I = isects /
 * packets, counted per 2x2 packet.  Kernels add to them only when the
 * pointer is non-NULL, so counting never changes results and costs nothing
 * when off. */
typedef struct kd_counters {
    uint64_t packets, steps, isects;
} kd_counters;

/* Loads up to four rays (count 1..4) into a packet; missing lanes inactive. */
void ray_packet4_load(ray_packet4 *packet, const rtt_ray *rays, uint32_t count);
void hit_packet4_clear(hit_packet4 *hits);
void hit_packet4_store(const hit_packet4 *hits, rtt_hit *out, uint32_t count);

/* Kernel signatures.  Each finds the closest hit of every active lane in
 * (tnear, tfar) (closest-hit) or whether anything lies there (occlusion:
 * `occluded` gets a lane mask bit per ray, 1 = occluded).
 *   mono:    one ray at a time, lanes of the packet looped (Listing 2.2)
 *   packet:  2x2 packets with equal direction signs, split otherwise (2.4)
 *   omni:    omni-directional 2x2 packets (Listing 4.1)
 *   frustum: a block of packets under one frustum (Listing 4.2 + 4.1.4)
 *   mft:     four frusta of a block in the SSE lanes (4.1.5)
 *   cone / mft_cone: cone proxy traversal (Listings 4.3-4.5) */
typedef void (*kd_block_kernel)(const kd_tree *tree, const ray_packet4 *packets, hit_packet4 *hits,
                                uint32_t packet_count, int leaf_culling, kd_counters *counters);
typedef void (*kd_block_occlusion_kernel)(const kd_tree *tree, const ray_packet4 *packets, uint8_t *occluded,
                                          uint32_t packet_count, int leaf_culling, kd_counters *counters);

#endif

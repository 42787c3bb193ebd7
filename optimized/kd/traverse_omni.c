/* Thesis Listing 4.1: omni-directional 2x2 packet traversal, no restriction
 * on direction signs and no splitting of packets.
 *
 * The listing's two modifications, per lane: (1) each lane traverses from
 * its front voxel (the side of the plane its origin is on) to its back
 * voxel, and (2) a negative plane distance counts as infinite (the lane
 * never crosses).  Here, per lane, with d = (split - o) / dir, the part of
 * the interval before the plane, [near, min(far, d)], lies in the child the
 * direction comes from (left when the sign bit of dir is clear, right when
 * set), and the part after it, [max(near, d), far], in the other child.  For
 * tnear >= 0 that is exactly the listing's rule: a lane moving toward the
 * plane is on its origin side first; a lane moving away has d < 0 <= near,
 * so its "after" part is all of its interval and lies on its origin side,
 * its "before" part is empty.  Unlike the origin-side rule it stays exact
 * for tnear < 0.  So per node: blends on the sign bit of inv_dir give each
 * child its lanes' parts, two movemasks give the lanes that go left and
 * right, and the packet visits one child or both (the other pushed with its
 * lanes' intervals).  The listing has one origin per packet; here origins
 * may differ per lane.
 *
 * Which child goes first when both are needed: the one that is in front for
 * most live lanes (decided once per axis per packet).  The order only
 * changes speed, never results (traverse_ray.h).
 *
 * Trades: four blends per step more than the equal-sign packet (Listing
 * 2.4) and no fallback path; incoherent packets visit the union of their
 * rays' cells with the rays masked.  leaf_culling is ignored. */
#include <math.h>
#include <stdint.h>

#include "kernels.h"
#include "traverse_ray.h"
#include "isect_leaf.h"

/* One inner node for a packet of any directions: per-lane intervals of
 * both children (blends on the sign of 1/dir); right_first[axis] = 1 when
 * most live lanes have the right child in front on `axis`. */
static inline const kd_node *omni_step(const kd_node *nodes, const kd_node *n, const ray_packet4 *r,
                                       const uint32_t right_first[3], __m128 *near_io, __m128 *far_io,
                                       kd_packet_task *stack, uint32_t *sp)
{
    const __m128 near = *near_io, far = *far_io;
    const uint32_t axis = kd_node_axis(n), left = kd_node_child(n);
    const __m128 inv = r->inv_dir[axis];
    const __m128 d = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(n->split), r->org[axis]), inv);
    /* _mm_min_ps / _mm_max_ps return their second operand for a NaN d
     * (a lane lying in the plane): both parts are then the whole
     * interval. */
    const __m128 front_far = _mm_min_ps(kd_widen_hi4(d, KD_RAY_WIDEN), far);
    const __m128 back_near = _mm_max_ps(kd_widen_lo4(d, KD_RAY_WIDEN), near);
    /* blendv reads the sign bit of inv: set → the right child is in front */
    const __m128 lnear = _mm_blendv_ps(near, back_near, inv), lfar = _mm_blendv_ps(front_far, far, inv);
    const __m128 rnear = _mm_blendv_ps(back_near, near, inv), rfar = _mm_blendv_ps(far, front_far, inv);
    const int lmask = _mm_movemask_ps(_mm_cmple_ps(lnear, lfar));
    const int rmask = _mm_movemask_ps(_mm_cmple_ps(rnear, rfar));
    if (lmask && rmask) {
        if (right_first[axis]) {
            if (*sp < KD_TRAVERSAL_STACK) stack[(*sp)++] = (kd_packet_task){lnear, lfar, left};
            *near_io = rnear, *far_io = rfar;
            return &nodes[left + 1];
        }
        if (*sp < KD_TRAVERSAL_STACK) stack[(*sp)++] = (kd_packet_task){rnear, rfar, left + 1};
        *near_io = lnear, *far_io = lfar;
        return &nodes[left];
    }
    if (lmask) {
        *near_io = lnear, *far_io = lfar;
        return &nodes[left];
    }
    /* some lane is active, so it is active on one side */
    *near_io = rnear, *far_io = rfar;
    return &nodes[left + 1];
}

/* One packet from the root (kd_packet_walk with omni_step), out of line as
 * the packet kernel's. */
static __attribute__((noinline)) int trace_omni(const kd_tree *tree, const ray_packet4 *r, __m128 near, __m128 far,
                                                const uint32_t right_first[3], int live, hit_packet4 *hits,
                                                kd_counters *counters)
{
    return kd_packet_walk(tree, r, near, far, right_first, live, hits, counters, omni_step);
}

/* Per axis: 1 when the right child is in front for more than half the live
 * lanes (ties go left). */
static inline void front_order(const ray_packet4 *r, int live, uint32_t right_first[3])
{
    const int lanes = __builtin_popcount((unsigned)live);
    for (int a = 0; a < 3; a++)
        right_first[a] = 2 * __builtin_popcount((unsigned)(_mm_movemask_ps(r->inv_dir[a]) & live)) > lanes;
}

/* Thesis Listing 4.1: omni-directional 2x2 packets, per-lane intervals.
 * Trades: four blends per step more than Listing 2.4, for no fallback on
 * mixed direction signs. */
void kd_kernel_omni(const kd_tree *tree, const kd_query *q)
{
    kd_ray_box box;
    kd_ray_box_init(tree, &box);
    for (uint32_t p = 0; p < q->packet_count; p++) {
        const ray_packet4 *r = &q->packets[p];
        hit_packet4 *hits = q->hits ? &q->hits[p] : NULL;
        __m128 near, far;
        int valid;
        const int live = kd_ray_packet_setup(&box, r, &near, &far, &valid);
        if (q->occluded) q->occluded[p] = 0;
        if (q->counters && valid) q->counters->packets++;
        if (!live) continue;
        uint32_t right_first[3];
        front_order(r, live, right_first);
        int mask = trace_omni(tree, r, near, hits ? _mm_min_ps(far, hits->t) : far, right_first, live, hits, q->counters);
        if (q->occluded) q->occluded[p] = (uint8_t)mask;
    }
}

/* Thesis Listing 2.4: iterative kd-tree traversal of a 2x2 packet whose rays
 * have equal direction signs per axis, and the caller that splits packets
 * whose signs differ (here: into single rays, the mono kernel).
 *
 * Each lane keeps its own interval [near, far] in an SSE lane; a lane is
 * inactive where its interval is empty (near > far), so the active mask is
 * never stored: it is recomputed by one compare where it is needed.  At a
 * node every lane's front part [near, min(far, d)] belongs to the common
 * near child (by the shared direction signs) and its back part
 * [max(near, d), far] to the far child; the far child is pushed with the
 * lanes' intervals when any lane reaches it, and the packet goes on into the
 * near child when any lane needs it.  The origins may differ per lane.
 *
 * What it assumes and trades: equal signs on all three axes among the live
 * lanes (a +0.0 and a -0.0 component differ: their inv_dir are +inf and
 * -inf); otherwise the packet is traced ray by ray (Listing 2.2), which the
 * counters show as more steps.  One node fetch serves four rays; a lane
 * that does not need a subtree still rides along masked.  As in every
 * kernel here, hits are kept wherever on the ray they lie and a popped task
 * is dropped when it starts past every lane's best hit (traverse_ray.h), in
 * place of the listing's early exit at the first leaf that hits.
 * leaf_culling is ignored (a 2x2 packet has no leaf box test). */
#include <math.h>
#include <stdint.h>

#include "kernels.h"
#include "traverse_ray.h"
#include "isect_leaf.h"

/* One inner node for a packet whose live lanes share direction signs:
 * neg[axis] = 1 when they point negative on `axis` (the near child is then
 * the right one). */
static inline const kd_node *packet_step(const kd_node *nodes, const kd_node *n, const ray_packet4 *r,
                                         const uint32_t neg[3], __m128 *near_io, __m128 *far_io,
                                         kd_packet_task *stack, uint32_t *sp)
{
    const __m128 near = *near_io, far = *far_io;
    const uint32_t axis = kd_node_axis(n), left = kd_node_child(n);
    const __m128 d = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(n->split), r->org[axis]), r->inv_dir[axis]);
    /* _mm_min_ps / _mm_max_ps return their second operand for a NaN d. */
    const __m128 front_far = _mm_min_ps(kd_widen_hi4(d, KD_RAY_WIDEN), far);
    const __m128 back_near = _mm_max_ps(kd_widen_lo4(d, KD_RAY_WIDEN), near);
    const int front = _mm_movemask_ps(_mm_cmple_ps(near, front_far));
    const int back = _mm_movemask_ps(_mm_cmple_ps(back_near, far));
    const uint32_t near_child = left + neg[axis], far_child = left + (neg[axis] ^ 1u);
    if (front) {
        if (back && *sp < KD_TRAVERSAL_STACK) stack[(*sp)++] = (kd_packet_task){back_near, far, far_child};
        *far_io = front_far;
        return &nodes[near_child];
    }
    /* some lane is active, so it is active behind the plane */
    *near_io = back_near;
    return &nodes[far_child];
}

/* One packet from the root (kd_packet_walk with packet_step).  Kept out of
 * line: inlined into the per-packet loop it costs 2% more instructions
 * (callgrind, the demo at 256x256). */
static __attribute__((noinline)) int trace_packet(const kd_tree *tree, const ray_packet4 *r, __m128 near, __m128 far,
                                                  const uint32_t neg[3], int live, hit_packet4 *hits,
                                                  kd_counters *counters)
{
    return kd_packet_walk(tree, r, near, far, neg, live, hits, counters, packet_step);
}

/* The shared direction signs of the live lanes; 0 when they differ. */
static inline int common_signs(const ray_packet4 *r, int live, uint32_t neg[3])
{
    for (int a = 0; a < 3; a++) {
        const int m = _mm_movemask_ps(r->inv_dir[a]) & live;
        if (m != 0 && m != live) return 0;
        neg[a] = m != 0;
    }
    return 1;
}

/* Thesis Listing 2.4: 2x2 packets whose live rays share direction signs;
 * a packet of mixed signs goes ray by ray through the mono kernel.  Trades:
 * one node fetch for four rays, for the fallback's cost on mixed signs. */
void kd_kernel_packet(const kd_tree *tree, const kd_query *q)
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
        if (!live) {
            if (q->counters && valid) q->counters->packets++;
            continue;
        }
        uint32_t neg[3];
        if (!common_signs(r, live, neg)) {
            kd_query one = *q;
            one.packets = r, one.packet_count = 1;
            one.hits = hits, one.occluded = q->occluded ? &q->occluded[p] : NULL;
            kd_kernel_mono(tree, &one);
            continue;
        }
        if (q->counters) q->counters->packets++;
        int mask = trace_packet(tree, r, near, hits ? _mm_min_ps(far, hits->t) : far, neg, live, hits, q->counters);
        if (q->occluded) q->occluded[p] = (uint8_t)mask;
    }
}

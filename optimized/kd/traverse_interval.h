/* The interval traversal loops shared by the proxy kernels (Thesis Listing
 * 4.2 for one proxy, 4.1.5 for four proxies in the SSE lanes).  What makes a
 * kernel a frustum or a cone kernel is only how it computes, at a split
 * plane, the distances at which its proxy enters the back child (dmin) and
 * leaves the front child (dmax), and which child is in front (the side of
 * the proxy's origin: the omni-directional modification).  That is the
 * `split` function each kernel passes in; these loops are the rest of the
 * listings:
 *
 *   front gets [near, min(far, dmax)], back gets [max(near, dmin), far];
 *   a child whose interval is empty is skipped, the back child is pushed.
 *
 * Early termination: after a leaf the interval's far end is clipped to the
 * group's max best (block.h), so subtrees behind every live ray's current
 * hit are dropped.  Straddling proxies (origins on both sides of a plane)
 * return dmin = -inf, dmax = +inf: both children, full interval.
 *
 * Counting: one step per node visited (inner nodes and leaves) by the
 * proxy, or by the four proxies together; N = steps / 2x2 packets. */
#ifndef RTT_OPTIMIZED_TRAVERSE_INTERVAL_H
#define RTT_OPTIMIZED_TRAVERSE_INTERVAL_H

#include <math.h>

#include "block.h"
#include "simd4.h"

typedef void (*kd_split1_fn)(const void *proxy, uint32_t axis, float split, float near, int *front_left,
                             float *dmin, float *dmax);
typedef void (*kd_split4_fn)(const void *proxy, uint32_t axis, float split, __m128 near, __m128 *front_left,
                             __m128 *dmin, __m128 *dmax);

/* Bits set in a 4-bit lane mask (SSE4.1 has no POPCNT: __builtin_popcount
 * would be a libgcc call per node). */
static const uint8_t kd_popcount4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

/* Stack entries: a subtree and the interval to search it in.  12 bytes for
 * one proxy; 48 for four (two SSE intervals, the node padded to the
 * 16-byte alignment of the next entry's vectors). */
typedef struct kd_entry1 {
    uint32_t node;
    float near, far;
} kd_entry1;
_Static_assert(sizeof(kd_entry1) == 12, "kd_entry1 is three words");

typedef struct kd_entry4 {
    __m128 near, far;
    uint32_t node;
} kd_entry4;
_Static_assert(sizeof(kd_entry4) == 48, "kd_entry4 is two SSE intervals and a node");

/* One proxy (group 0 of the block), scalar: Listing 4.2 / 4.5. */
/* always_inline: the kernel's split function is then a known call and is
 * inlined into the loop (a call per node otherwise: about 5% of MFT). */
static inline __attribute__((always_inline)) void kd_traverse1(kd_block *b, const void *proxy, kd_split1_fn split,
                                                               float near, float far)
{
    const kd_node *nodes = b->tree->nodes;
    kd_entry1 stack[KD_TRAVERSAL_STACK];
    uint32_t sp = 0, node = 0;
    uint64_t steps = 0;
    float best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    for (;;) {
        far = kd_min1(far, best[0]);
        if (near <= far) {
            const kd_node *n = &nodes[node];
            while (!kd_node_is_leaf(n)) {
                steps++;
                uint32_t left = kd_node_child(n);
                int front_left;
                float dmin, dmax;
                split(proxy, kd_node_axis(n), n->split, near, &front_left, &dmin, &dmax);
                uint32_t front = front_left ? left : left + 1, back = front_left ? left + 1 : left;
                if (dmax < near) {          /* the proxy is past the plane: back only */
                    n = &nodes[back];
                    continue;
                }
                if (dmin > far) {           /* it does not reach the plane: front only */
                    n = &nodes[front];
                    continue;
                }
                if (sp < KD_TRAVERSAL_STACK) stack[sp++] = (kd_entry1){back, kd_max1(dmin, near), far};
                far = kd_min1(dmax, far);
                n = &nodes[front];
            }
            steps++;
            const float leaf_near[4] = {near, near, near, near};
            kd_block_visit_leaf(b, &b->tree->leaves[n->leaf], 1u, leaf_near, best);
        }
        for (;;) {
            if (sp == 0) goto done;
            kd_entry1 e = stack[--sp];
            node = e.node, near = e.near, far = kd_min1(e.far, best[0]);
            if (near <= far) break;
        }
    }
done:
    if (b->counters) b->counters->steps += steps;
}

/* Four proxies in the SSE lanes (MFT, 4.1.5): each lane keeps its own
 * interval; a lane is masked when its interval is empty or its group is
 * finished; the active mask travels on the stack as the intervals
 * themselves (empty = masked).  The child most active lanes see in front is
 * visited first. */
static inline __attribute__((always_inline)) void kd_traverse4(kd_block *b, const void *proxy, kd_split4_fn split,
                                                               __m128 near, __m128 far)
{
    const kd_node *nodes = b->tree->nodes;
    kd_entry4 stack[KD_TRAVERSAL_STACK];
    uint32_t sp = 0, node = 0;
    uint64_t steps = 0;
    float best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    __m128 max_best = _mm_loadu_ps(best);
    for (;;) {
        far = _mm_min_ps(far, max_best);
        int mask = _mm_movemask_ps(_mm_cmple_ps(near, far));
        if (mask) {
            const kd_node *n = &nodes[node];
            while (!kd_node_is_leaf(n)) {
                steps++;
                uint32_t left = kd_node_child(n);
                __m128 front_left, dmin, dmax;
                split(proxy, kd_node_axis(n), n->split, near, &front_left, &dmin, &dmax);
                __m128 front_far = _mm_min_ps(dmax, far), back_near = _mm_max_ps(dmin, near);
                __m128 lnear = _mm_blendv_ps(back_near, near, front_left);
                __m128 lfar = _mm_blendv_ps(far, front_far, front_left);
                __m128 rnear = _mm_blendv_ps(near, back_near, front_left);
                __m128 rfar = _mm_blendv_ps(front_far, far, front_left);
                int lmask = _mm_movemask_ps(_mm_cmple_ps(lnear, lfar));
                int rmask = _mm_movemask_ps(_mm_cmple_ps(rnear, rfar));
                int fl = _mm_movemask_ps(front_left) & mask;
                int left_first = 2 * kd_popcount4[fl] >= kd_popcount4[mask];
                uint32_t first = left_first ? left : left + 1, second = left_first ? left + 1 : left;
                __m128 fnear = left_first ? lnear : rnear, ffar = left_first ? lfar : rfar;
                __m128 snear = left_first ? rnear : lnear, sfar = left_first ? rfar : lfar;
                int fmask = left_first ? lmask : rmask, smask = left_first ? rmask : lmask;
                if (!fmask) {
                    if (!smask) goto pop;
                    n = &nodes[second], near = snear, far = sfar, mask = smask;
                    continue;
                }
                if (smask && sp < KD_TRAVERSAL_STACK) stack[sp++] = (kd_entry4){snear, sfar, second};
                n = &nodes[first], near = fnear, far = ffar, mask = fmask;
            }
            steps++;
            float leaf_near[4];
            _mm_storeu_ps(leaf_near, near);
            kd_block_visit_leaf(b, &b->tree->leaves[n->leaf], (uint32_t)mask, leaf_near, best);
            max_best = _mm_loadu_ps(best);
        }
    pop:
        for (;;) {
            if (sp == 0) goto done;
            kd_entry4 e = stack[--sp];
            node = e.node, near = e.near, far = _mm_min_ps(e.far, max_best);
            if (_mm_movemask_ps(_mm_cmple_ps(near, far))) break;
        }
    }
done:
    if (b->counters) b->counters->steps += steps;
}

#endif

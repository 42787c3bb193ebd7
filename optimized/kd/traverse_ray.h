/* What the per-ray-interval kernels share (traverse_mono.c, traverse_packet.c,
 * traverse_omni.c): which lanes of a packet can hit anything, each lane's
 * interval inside the tree's box, and the widened split distance.
 *
 * Exactness, for arbitrary rays (the same argument as block.h).  A leaf's
 * records are tested against the ray's own (tnear, tfar), not against the
 * cell's interval, and a hit is kept wherever along the ray it lies (closest
 * wins, ties to the smaller prim in isect_leaf.h).  A subtree is
 * dropped only when its interval starts past the lane's current best hit.
 * So the traversal order never changes the result; the cell intervals only
 * have to contain every parameter at which the ray is inside the cell.
 * Rounding could break that by an ulp or two at a split plane, so the split
 * distance is widened by KD_RAY_WIDEN (relative) on each side and the
 * comparisons are inclusive: a ray within rounding of a plane visits both
 * children.  That costs four SSE operations per step and a few extra visits
 * of cells a ray only grazes; it buys that rays through split planes, cell
 * corners and flat cells (perfect splits put planes through vertices) find
 * the triangles there.
 *
 * Rays that cannot hit are dead lanes from the start: non-finite origin or
 * direction, a zero direction, or !(tnear < tfar) (NaN included).  Dead
 * lanes carry near = +inf > far = -inf, so no comparison ever makes them
 * active and no NaN ever reaches a traversal decision of a live lane except
 * the split distance of a ray lying in a split plane (0 * inf), which the
 * min/max order below turns into "both children, full interval". */
#ifndef RTT_OPTIMIZED_TRAVERSE_RAY_H
#define RTT_OPTIMIZED_TRAVERSE_RAY_H

#include "kernel_isa.h"

#include <immintrin.h>
#include <math.h>
#include <stdint.h>

#include "isect_leaf.h"
#include "kd_tree.h"
#include "packet.h"
#include "simd4.h"

#define KD_RAY_WIDEN (1.0f / 1048576.0f)  /* 2^-20: ~8 ulps of a split distance */

/* The tree's box grown by kd_tree_margin, so a ray parallel to a face and
 * exactly on it is outside (it cannot hit anything) and rounding at the
 * faces never clips a hit off.  `empty` when the tree holds nothing to hit
 * (no nodes, no leaves, an empty or non-finite box). */
typedef struct kd_ray_box {
    float lo[3], hi[3];
    int empty;
} kd_ray_box;

static inline void kd_ray_box_init(const kd_tree *tree, kd_ray_box *box)
{
    const rtt_bounds *b = &tree->bounds;
    const float lo[3] = {b->lo.x, b->lo.y, b->lo.z}, hi[3] = {b->hi.x, b->hi.y, b->hi.z};
    box->empty = tree->node_count == 0 || tree->leaf_count == 0 || tree->triangle_count == 0;
    for (int a = 0; a < 3; a++)
        if (!(lo[a] <= hi[a]) || !isfinite(lo[a]) || !isfinite(hi[a])) box->empty = 1;
    const float margin = box->empty ? 0.0f : kd_tree_margin(tree);
    for (int a = 0; a < 3; a++) {
        box->lo[a] = lo[a] - margin;
        box->hi[a] = hi[a] + margin;
    }
}

/* Per lane: the interval [near, far] of the ray inside the box, within
 * [tnear, tfar] and widened; +inf / -inf for lanes that cannot hit.  Returns
 * the live lane mask; *valid_mask gets the lanes carrying a ray that can hit
 * anything at all (what the `packets` counter counts, as kd_block_init). */
static inline int kd_ray_packet_setup(const kd_ray_box *box, const ray_packet4 *r, __m128 *near, __m128 *far,
                                      int *valid_mask)
{
    const __m128 valid = ray_packet4_valid(r);
    *valid_mask = _mm_movemask_ps(valid);
    __m128 t0, t1;
    ray_packet4_slab(r, box->lo, box->hi, r->tnear, r->tfar, &t0, &t1);
    t0 = kd_widen_lo4(t0, KD_RAY_WIDEN);
    t1 = kd_widen_hi4(t1, KD_RAY_WIDEN);
    __m128 live = _mm_and_ps(valid, _mm_cmple_ps(t0, t1));
    if (box->empty) live = _mm_setzero_ps();
    *near = _mm_blendv_ps(_mm_set1_ps(INFINITY), t0, live);
    *far = _mm_blendv_ps(_mm_set1_ps(-INFINITY), t1, live);
    return _mm_movemask_ps(live);
}

/* A stack entry of the 2x2 packet kernels (packet, omni): a subtree and the
 * per-lane interval to search it in.  48 bytes: two SSE intervals and the
 * node, padded to keep the next entry's vectors 16-byte aligned. */
typedef struct kd_packet_task {
    __m128 near, far;
    uint32_t node;
} kd_packet_task;
_Static_assert(sizeof(kd_packet_task) == 48, "kd_packet_task is two SSE intervals and a node");

/* One leaf for one packet, lanes active where near <= far: closest hits into
 * *hits, or (hits NULL) occlusion into *occluded.  Narrows *limit, the far
 * end popped tasks are clipped to (the best hit, or -inf once occluded).
 * Returns 1 when every live lane is occluded: the search is over. */
static inline int kd_packet_leaf(const kd_tree *tree, const kd_leaf *leaf, const ray_packet4 *r, hit_packet4 *hits,
                                 __m128 near, __m128 far, int live, __m128 *limit, __m128 *occluded,
                                 kd_counters *counters)
{
    if (!leaf->count) return 0;
    const __m128 active = _mm_cmple_ps(near, far);
    if (hits) {
        isect4_leaf(tree, leaf, r, hits, active, counters);
        *limit = hits->t;
        return 0;
    }
    *occluded = _mm_or_ps(*occluded, occluded4_leaf(tree, leaf, r, active, counters));
    if (_mm_movemask_ps(*occluded) == live) return 1;
    *limit = _mm_blendv_ps(*limit, _mm_set1_ps(-INFINITY), *occluded);
    return 0;
}

/* Pops the next task whose interval, clipped to limit, is not empty; 0 when
 * the stack runs out. */
static inline int kd_packet_pop(const kd_packet_task *stack, uint32_t *sp, __m128 limit, const kd_node *nodes,
                                const kd_node **n, __m128 *near, __m128 *far)
{
    while (*sp) {
        const kd_packet_task task = stack[--*sp];
        *near = task.near;
        *far = _mm_min_ps(task.far, limit);
        if (_mm_movemask_ps(_mm_cmple_ps(*near, *far))) {
            *n = &nodes[task.node];
            return 1;
        }
    }
    return 0;
}

/* A packet kernel's inner-node step: from inner node n with the lanes'
 * interval [*near, *far], the child to descend into (its interval written
 * back), the other child pushed when some lane must visit it too.  `order`
 * is the kernel's per-packet front-to-back choice. */
typedef const kd_node *(*kd_packet_step_fn)(const kd_node *nodes, const kd_node *n, const ray_packet4 *r,
                                           const uint32_t order[3], __m128 *near, __m128 *far,
                                           kd_packet_task *stack, uint32_t *sp);

/* The walk the 2x2 packet kernels share (Listings 2.4 and 4.1): descend with
 * `step`, intersect at leaves, pop the nearest pending subtree clipped to the
 * best hit.  Closest hits into *hits, or (hits NULL) returns the mask of
 * occluded lanes, stopping once every live lane is.  always_inline: the step
 * is then a known call and is inlined into each kernel's loop. */
static inline __attribute__((always_inline)) int kd_packet_walk(const kd_tree *tree, const ray_packet4 *r,
                                                                 __m128 near, __m128 far, const uint32_t order[3],
                                                                 int live, hit_packet4 *hits,
                                                                 kd_counters *counters, kd_packet_step_fn step)
{
    const kd_node *nodes = tree->nodes;
    kd_packet_task stack[KD_TRAVERSAL_STACK];
    uint32_t sp = 0;
    uint64_t steps = 0;
    const kd_node *n = nodes;
    __m128 occluded = _mm_setzero_ps();
    /* the far end popped tasks are clipped to: best hit, or -inf once occluded */
    __m128 limit = hits ? hits->t : _mm_set1_ps(INFINITY);
    if (!_mm_movemask_ps(_mm_cmple_ps(near, far))) return 0;
    for (;;) {
        while (!kd_node_is_leaf(n)) {
            steps++;
            n = step(nodes, n, r, order, &near, &far, stack, &sp);
        }
        steps++;
        if (kd_packet_leaf(tree, &tree->leaves[n->leaf], r, hits, near, far, live, &limit, &occluded, counters))
            break;
        if (!kd_packet_pop(stack, &sp, limit, nodes, &n, &near, &far)) break;
    }
    if (counters) counters->steps += steps;
    return _mm_movemask_ps(occluded);
}

#endif

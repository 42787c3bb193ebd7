/* Thesis Listing 4.2: frustum interval traversal with the omni-directional
 * modifications, plus packet/leaf culling (4.1.4).
 *
 * One interval frustum bounds the whole block (a tile of T x T primary rays
 * is T*T/4 2x2 packets); the traversal loop does a constant amount of work
 * per node whatever the number of rays.  At a leaf, packets are culled
 * against the leaf box and the survivors intersected (frustum.c).
 *
 * Generalised to arbitrary rays (the engine feeds random and shadow rays in
 * blocks): the "corner ray" distances are interval arithmetic over the
 * block's origin box and reciprocal direction ranges (frustum.c), the front
 * child is the side of the origin box (both children with the full interval
 * when the box straddles the plane), and a ray moving away from the plane
 * gets distance +inf (modification 2).  Blocks a frustum would bound too
 * loosely are traced packet by packet (frustum.h).  Trades: more
 * intersection tests than 2x2 packets (Table 4.1), far fewer node visits. */
#include <math.h>

#include "frustum.h"
#include "traverse_interval.h"

/* dmin/dmax of the rays of f at plane `split` on `axis`, in front-to-back
 * terms.  Origins in front on the left (split - origin > 0): a ray with a
 * positive direction crosses at (split - o) / dir; one with a negative
 * direction never does (+inf). */
static void frustum_split(const void *proxy, uint32_t axis, float split, float near, int *front_left, float *dmin,
                          float *dmax)
{
    const kd_frustum *f = proxy;
    float a_lo = split - f->org_hi[axis], a_hi = split - f->org_lo[axis];
    if (near >= 0.0f && a_lo > 0.0f) {
        *front_left = 1;
        *dmin = a_lo * f->pos_lo[axis];
        *dmax = f->has_neg[axis] ? INFINITY : a_hi * f->pos_hi[axis];
    } else if (near >= 0.0f && a_hi < 0.0f) {
        *front_left = 0;
        *dmin = -a_hi * f->neg_lo[axis];
        *dmax = f->has_pos[axis] ? INFINITY : -a_lo * f->neg_hi[axis];
    } else {
        *front_left = 1;
        *dmin = -INFINITY;
        *dmax = INFINITY;
        return;
    }
    *dmin *= 1.0f - KD_WIDEN;
    *dmax *= 1.0f + KD_WIDEN;
}

void kd_block_trace_frustum(kd_block *b)
{
    kd_frustum f;
    if (!kd_frustum_build(b, 0, &f)) return;
    if (kd_frustum_is_incoherent(b, &f)) {
        kd_block_trace_packets(b);
        return;
    }
    const int present[4] = {1, 0, 0, 0};
    const kd_frustum lanes[4] = {f, f, f, f};
    kd_frustum4 f4;
    kd_frustum4_pack(lanes, present, &f4);
    b->leaf_frusta = &f4;
    kd_traverse1(b, &f, frustum_split, f.near, f.far);
    b->leaf_frusta = NULL;
}

/* Thesis Listing 4.2 with 4.1.4's packet/leaf culling: one frustum per block. */
void kd_kernel_frustum(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_frustum);
}

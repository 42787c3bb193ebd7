/* What the BVH kernels share (kernel side, one copy per instruction set):
 * the packet walk of traverse_packet.c, which the frusta kernel also uses
 * for the packets whose rays share no origin, and its box test, which the
 * soft-shadow frusta also run on a frustum's rays at a leaf. */
#ifndef RTT_BVH_TRAVERSE_H
#define RTT_BVH_TRAVERSE_H

#include "bvh_isa.h"
#include "bvh_kernels.h"
#include "bvh_packet.h"
#include "bvh_tree.h"

/* The lanes of `active` whose interval [tnear, tfar] enters child c's box, and
 * their entry distances.  Each slab distance is rounded three times (the
 * difference, the reciprocal, the product), so by up to 3 ulps of itself
 * -- of the origin's distance, not of the box's size, which the builder's
 * widening covers: a tiny box far from the origin loses a ray grazing it
 * unless the interval is tested grown (bvh_interval_holds). */
static inline vm bvh_packet_box(const bvh_child *c, const bvh_packet *p, vf tfar, vm active, vf *entry)
{
    vf t0 = p->tnear, t1 = tfar;
    for (int k = 0; k < 3; k++) {
        const vf a = vf_mul(vf_sub(vf_set1(c->lo[k]), p->org[k]), p->inv_dir[k]);
        const vf b = vf_mul(vf_sub(vf_set1(c->hi[k]), p->org[k]), p->inv_dir[k]);
        t0 = vf_max(vf_min(a, b), t0);
        t1 = vf_min(vf_max(a, b), t1);
    }
    *entry = t0;
    return vm_and(active, bvh_interval_holds(t0, t1));
}

/* The lanes `live` of packet p through the tree: closest hits lowered in
 * `hits` (cleared by the caller), or with hits NULL the occluded lanes into
 * *occluded. */
void bvh_trace_packet(const bvh_tree *tree, const bvh_packet *p, uint32_t live, bvh_hits *hits, uint32_t *occluded,
                      bvh_counters *counters);

#endif

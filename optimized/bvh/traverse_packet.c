/* Packets of BVH_W rays (16 on AVX-512, 8 on AVX2, 4 on SSE4.1) through
 * the BVH: the packet traversal Benthin & Wald 2009 compare against (5.1,
 * "P-Packet" and "S-Packet", after Wald, Boulos & Shirley 2007): per node
 * one slab test of both children's boxes for every active ray, the child
 * more lanes enter first first, the other with its lane mask on the stack;
 * at a leaf the packet-wide triangle test the tree names (bvh_isect_wide.h:
 * projected or watertight, the watertight shears made once per packet) on
 * the active lanes.  Any rays: no common origin or direction signs are
 * assumed, and an occlusion lane leaves the packet as soon as it is hit.
 *
 * What it trades: a popped subtree's box is tested again against the
 * lanes' current closest hits (one AABB test more per pop, fewer subtrees
 * entered); no per-packet frustum, so incoherent packets cost what their
 * rays cost. */
#include <math.h>

#include "bvh_isa.h"
#include "bvh_isect_wide.h"
#include "bvh_kernels.h"
#include "bvh_traverse.h"

typedef struct packet_entry {
    const bvh_child *child;
    uint32_t lanes;
} packet_entry;

void bvh_trace_packet(const bvh_tree *tree, const bvh_packet *p, uint32_t live, bvh_hits *hits, uint32_t *occluded,
                      bvh_counters *counters)
{
    packet_entry stack[BVH_TRAVERSAL_STACK];
    uint32_t top = 0, occ = 0;
    vf tfar = p->tfar;
    bvh_wt_shears shears;
    const bvh_wt_shears *s = bvh_record_setup(tree, p, live, &shears);
    stack[top++] = (packet_entry){&tree->root, live};
    while (top > 0) {
        const packet_entry e = stack[--top];
        vf entry;
        uint32_t lanes = vm_bits(bvh_packet_box(e.child, p, tfar, vm_of_bits(e.lanes & ~occ), &entry));
        if (counters) counters->aabb_tests++;
        const bvh_child *c = e.child;
        while (lanes && c->count == 0) {
            const bvh_node *node = &tree->nodes[c->index];
            vf e0, e1;
            const vm active = vm_of_bits(lanes);
            const uint32_t l0 = vm_bits(bvh_packet_box(&node->child[0], p, tfar, active, &e0));
            const uint32_t l1 = vm_bits(bvh_packet_box(&node->child[1], p, tfar, active, &e1));
            if (counters) counters->aabb_tests += 2;
            if (l0 && l1) {
                const uint32_t both = l0 & l1;
                const uint32_t first0 = vm_bits(vm_and(vm_of_bits(both), vf_le(e0, e1)));
                const int near = __builtin_popcount(first0) * 2 < __builtin_popcount(both);
                if (top < BVH_TRAVERSAL_STACK) stack[top++] = (packet_entry){&node->child[!near], near ? l0 : l1};
                c = &node->child[near];
                lanes = near ? l1 : l0;
            } else {
                c = &node->child[l1 != 0];
                lanes = l0 | l1;
            }
        }
        if (!lanes) continue;
        for (uint32_t i = 0; i < c->count; i++) {
            if (counters) counters->triangles++, counters->isect_tests++;
            if (hits) {
                if (bvh_isect_record(tree, c->index + i, p, s, hits, lanes)) tfar = vf_min(hits->t, tfar);
            } else {
                occ |= bvh_occluded_record(tree, c->index + i, p, s, lanes);
                lanes &= ~occ;
                if (!lanes) break;
            }
        }
        if (!hits && (live & ~occ) == 0) break;
    }
    if (occluded) *occluded = occ;
}

void bvh_kernel_packet(const bvh_tree *tree, const bvh_query *q)
{
    for (size_t first = 0; first < q->count; first += BVH_W) {
        const size_t n = q->count - first < BVH_W ? q->count - first : BVH_W;
        bvh_packet p;
        const uint32_t live = bvh_packet_load(&p, &q->rays[first], n);
        if (q->counters) q->counters->packets++;
        bvh_hits hits;
        bvh_hits_clear(&hits);
        uint32_t occ = 0;
        if (live && tree->triangle_count > 0) bvh_trace_packet(tree, &p, live, q->hits ? &hits : NULL, &occ, q->counters);
        if (q->hits)
            bvh_hits_store(&hits, &q->hits[first], n);
        else
            for (size_t l = 0; l < n; l++) q->occluded[first + l] = (occ >> l) & 1u;
    }
}

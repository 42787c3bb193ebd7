/* Thesis 4.1.5: Multiple Frustum Traversal.  The block is split into four
 * quadrant frusta traced together in the SSE lanes, each with its own
 * interval; a frustum is masked where its interval is empty or when all its
 * rays have their closest hit (the active mask travels on the stack with
 * the intervals), and at a leaf only the packets of active frusta are culled
 * and intersected.  Trades: four intervals per node (a 2x2 packet's worth of
 * SSE work) for fewer node visits and far fewer intersection tests than one
 * frustum (Table 4.3).
 *
 * The per-lane split (kd_frustum4_split, frustum.h) is the interval-
 * arithmetic frustum of traverse_frustum.c in SSE; the same traversal
 * serves as the omni-directional per-ray traversal for blocks too
 * incoherent for any proxy (each lane one ray, block.c). */
#include "frustum.h"

void kd_block_trace_mft(kd_block *b)
{
    kd_block_group_quadrants(b);
    kd_frustum f[4];
    int present[4], any = 0;
    for (uint32_t g = 0; g < 4; g++) {
        present[g] = kd_frustum_build(b, g, &f[g]);
        any |= present[g];
        if (present[g] && kd_frustum_is_incoherent(b, &f[g])) {
            kd_block_trace_packets(b);
            return;
        }
    }
    if (!any) return;
    kd_frustum4 f4;
    kd_frustum4_pack(f, present, &f4);
    b->leaf_frusta = &f4;
    kd_traverse4_frusta(b, &f4);
    b->leaf_frusta = NULL;
}

/* Thesis 4.1.5: the block's four quadrant frusta in the SSE lanes.
 * Trades: four intervals per node for fewer visits and tests than one
 * frustum (Table 4.3). */
void kd_kernel_mft(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_mft);
}

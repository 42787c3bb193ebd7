/* Thesis Listings 4.3 - 4.5: cone proxy traversal, one cone per block
 * (cone) or four cones in the SSE lanes (mft-cone, 4.1.9).
 *
 * The cone of a group (cone.c) is walked through the tree by the interval
 * loops of Listing 4.2 / 4.1.5 (traverse_interval.h) with the plane
 * crossing of Listing 4.5 (cone.h): at a plane the cone's disk starts to
 * cross into the back child at axis parameter t1 and has left the front
 * child at t2.  The intervals are in tau units (cone.c); leaf visits convert
 * each ray's best hit to tau for early termination.  Trades: looser than a
 * pyramid for square tiles (Table 4.5), no per-node horizontal min/max. */
#include "cone.h"
#include "traverse_interval.h"

void kd_block_trace_cone(kd_block *b)
{
    kd_cone c;
    int built = kd_cone_build(b, 0, &c);
    if (built < 0)
        kd_block_trace_packets(b);
    else if (built > 0)
        kd_traverse1(b, &c, kd_cone_split, c.near, c.far);
}

void kd_block_trace_mft_cone(kd_block *b)
{
    kd_block_group_quadrants(b);
    kd_cone c[4];
    int present[4], any = 0;
    for (uint32_t g = 0; g < 4; g++) {
        int built = kd_cone_build(b, g, &c[g]);
        if (built < 0) {
            kd_block_trace_packets(b);
            return;
        }
        present[g] = built;
        any |= built;
    }
    if (!any) return;
    kd_cone4 c4;
    kd_cone4_pack(c, present, &c4);
    kd_traverse4(b, &c4, kd_cone4_split, c4.near, c4.far);
}

/* Thesis Listings 4.3 - 4.5: one cone per block.  Trades: one multiply per
 * plane and no horizontal min/max, for a looser bound than a pyramid. */
void kd_kernel_cone(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_cone);
}

/* Thesis 4.1.9: four quadrant cones per block.  Trades: four intervals per
 * node for tighter bounds than one cone, as MFT does for frusta. */
void kd_kernel_mft_cone(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_mft_cone);
}

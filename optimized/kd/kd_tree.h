/* The optimized engine's kd-tree in memory: the layout every traversal
 * kernel reads and the .kdt file stores.  Built by kd_build_sah.c.
 *
 * Nodes are 8 bytes and children are adjacent (right = left + 1), so one
 * 64-byte cache line holds eight nodes and a node needs one index (Thesis
 * 3.2.1; the compact 8-byte form the thesis cites but did not use).
 * Leaves hold their triangle records contiguously, duplicated across
 * leaves (Thesis 3.2.2: records are read in sequence during intersection),
 * and their bounds for packet/leaf culling (4.1.4). */
#ifndef RTT_KD_TREE_H
#define RTT_KD_TREE_H

#include <float.h>
#include <math.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/vec3.h"

#define KD_AXIS_LEAF 3u

/* No tree here is deeper, whatever the options say: the builder stops
 * splitting there, and the .kdt loader refuses deeper files (the engine
 * asserts KD_DEPTH_LIMIT == KDT_DEPTH_LIMIT).  Depth counts edges from the
 * root (depth 0) to a leaf. */
#define KD_DEPTH_LIMIT RTT_KD_DEPTH_LIMIT

/* Entries of every depth-first traversal stack (the kernels' and edge
 * width's).  A traversal pushes at most one subtree per inner node it
 * descends through (the child it does not take first) and pops the top one
 * when it leaves a leaf, so the stack holds subtrees of strictly increasing
 * depth, one per level from 1 to the depth of the node being visited: at
 * most KD_DEPTH_LIMIT of them.  Pushes stay guarded, so a tree built by hand
 * deeper than the limit can lose hits but never write past a stack. */
#define KD_TRAVERSAL_STACK KD_DEPTH_LIMIT
_Static_assert(KD_TRAVERSAL_STACK >= KD_DEPTH_LIMIT, "a traversal stack holds one subtree per level");

/* 8 bytes.  bits = (index << 2) | axis.  Internal node (axis 0..2): `split`
 * is the plane, index is the left child, index + 1 the right child.  Leaf
 * (axis 3): `leaf` is its index into kd_tree.leaves; index is unused (0). */
typedef struct kd_node {
    union {
        float split;
        uint32_t leaf;
    };
    uint32_t bits;
} kd_node;
_Static_assert(sizeof(kd_node) == 8, "kd_node is 8 bytes: eight to a cache line");

static inline uint32_t kd_node_axis(const kd_node *n) { return n->bits & 3u; }
static inline uint32_t kd_node_child(const kd_node *n) { return n->bits >> 2; }
static inline int kd_node_is_leaf(const kd_node *n) { return (n->bits & 3u) == KD_AXIS_LEAF; }

/* Wald's projected barycentric triangle record (Wald 2004, thesis 4.2),
 * 48 bytes so that records stay 16-byte aligned in leaves.  Projection axis
 * k is the dominant normal axis, u, v the other two (u = (k+1)%3, v = (k+2)%3):
 *   plane:        n_u * (p_u - a_u) + n_v * (p_v - a_v) + (p_k - a_k) = 0   (normal scaled so n_k = 1)
 *   barycentric:  beta  = b_nu * (h_u) + b_nv * (h_v),  gamma = c_nu * h_u + c_nv * h_v
 *   with h = hit - vertex0 projected; beta, gamma weight vertices 1, 2.
 * The plane is stored through vertex 0 (a_k), not as a constant n_d, so the
 * test works relative to that vertex (isect_projected_bary.h). */
typedef struct kd_triangle {
    float n_u, n_v, a_k;        /* normal (n_k = 1) and vertex 0 on axis k */
    float a_u, a_v;             /* vertex 0 projected */
    float b_nu, b_nv;           /* beta edge equation */
    float c_nu, c_nv;           /* gamma edge equation */
    uint32_t k;                 /* projection axis 0..2 */
    uint32_t prim;              /* global triangle index */
    uint32_t pad;
} kd_triangle;
_Static_assert(sizeof(kd_triangle) == 48, "kd_triangle is 48 bytes, 16-byte aligned in leaves");

/* 48 bytes: a triangle's three corners as the scene stores them, for the
 * watertight test (isect_woop_watertight.h), parallel to kd_tree.triangles
 * (entry i belongs to record i: read in the same sequence).  Not in the .kdt:
 * the engine derives them from the scene's triangles when it traces with the
 * watertight test.  The padding keeps entries 16-byte aligned. */
typedef struct kd_corners {
    float a[3], b[3], c[3];
    uint32_t prim;
    int32_t outward; /* the light grids' (pgrid_light.h): the outward side of a culled mesh's triangle, +1 or -1
                      * (pgrid_shadows.mesh_outward), 0 for the others; 0 elsewhere */
    uint32_t pad;
} kd_corners;
_Static_assert(sizeof(kd_corners) == 48, "kd_corners is 48 bytes, 16-byte aligned like the records");

/* 32 bytes: the leaf's triangle records and its box (for leaf culling). */
typedef struct kd_leaf {
    uint32_t first, count;      /* range in kd_tree.triangles */
    float lo[3], hi[3];
} kd_leaf;
_Static_assert(sizeof(kd_leaf) == 32, "kd_leaf is 32 bytes");

typedef struct kd_tree {
    kd_node *nodes;             /* nodes[0] is the root */
    kd_leaf *leaves;
    kd_triangle *triangles;     /* 16-byte aligned, leaf order, duplicated across leaves */
    uint32_t node_count, leaf_count, triangle_count;
    rtt_bounds bounds;          /* the root's box */
    rtt_tree_info info;
    /* The triangle test every kernel runs (isect_leaf.h): NULL → Wald's
     * projected test on `triangles`; else Woop's watertight test on these
     * corners, one per record.  Owned by whoever sets it (the engine). */
    const kd_corners *corners;
} kd_tree;

/* The margin (world units) the kernels grow the root and leaf boxes by, so
 * a ray parallel to a face and exactly on it is outside and rounding at a
 * face never clips a hit off: 1e-5 of the largest coordinate of the root
 * box, 0 when that box is empty or not finite. */
static inline float kd_tree_margin(const kd_tree *tree)
{
    const rtt_bounds *b = &tree->bounds;
    const float c[6] = {b->lo.x, b->hi.x, b->lo.y, b->hi.y, b->lo.z, b->hi.z};
    float scale = 0.0f;
    for (int i = 0; i < 6; i++) scale = scale > fabsf(c[i]) ? scale : fabsf(c[i]);
    return isfinite(scale) ? scale * 1e-5f + FLT_MIN : 0.0f;
}

#endif

/* The optimized engine's BVH in memory: the layout every BVH kernel reads.
 * Built by bvh_build.c (binned SAH).
 *
 * A node is one 64-byte cache line holding the boxes of BOTH its children
 * (Benthin & Wald 2009, 4.1: "the AABBs for the left and right child of a
 * BVH node are stored consecutively in a 64-byte block"), so one load per
 * traversal step feeds the test of both children against every ray or
 * frustum.  Each 32-byte child record is its box (min xyz, max xyz) with the
 * reference to what it holds in the two spare words: `count == 0` names an
 * inner node (`index` into bvh_tree.nodes), `count > 0` a leaf of `count`
 * triangle records from `index` in bvh_tree.triangles.
 *
 * The root is not a node's child, so the tree carries its box and reference
 * apart (a scene of one leaf has no node at all).  Each leaf record is two
 * parallel entries in leaf order, so a leaf reads them in sequence: the
 * 48-byte projected-barycentric record of optimized/isect/ (kd_triangle,
 * with the prim) and the triangle's corners as the scene stores them, with
 * the prim again (bvh_corners, 40 bytes).  `watertight` names the test every kernel runs on
 * them, as `kd_tree.corners` does for the kd kernels: false, Wald's
 * projected test on the records; true, Woop, Benthin & Wald's watertight
 * test on the corners (optimized/isect/; both in bvh_isect_wide.h).  Either
 * way a ray gets the bits the kd kernels give it under the same test.
 * Degenerate triangles get no record and are never hit. */
#ifndef RTT_BVH_TREE_H
#define RTT_BVH_TREE_H

#include <stdbool.h>
#include <stdint.h>

#include "kd_tree.h"
#include "rtt/engine.h"

/* 32 bytes: one child's box and what it holds. */
typedef struct bvh_child {
    float lo[3];
    uint32_t index;  /* inner: node index; leaf: first record */
    float hi[3];
    uint32_t count;  /* 0: inner node; else the leaf's record count */
} bvh_child;
_Static_assert(sizeof(bvh_child) == 32, "a BVH child record is 32 bytes");

/* 64 bytes, aligned to a cache line: both children of one node. */
typedef struct bvh_node {
    _Alignas(64) bvh_child child[2];
} bvh_node;
_Static_assert(sizeof(bvh_node) == 64, "a BVH node is one 64-byte cache line");

/* No BVH is deeper (edges from the root to a leaf): the builder makes a
 * leaf there whatever it holds, and the traversal stacks derive from it. */
#define BVH_DEPTH_LIMIT RTT_KD_DEPTH_LIMIT
#define BVH_TRAVERSAL_STACK (BVH_DEPTH_LIMIT + 1u)

/* 40 bytes: a record's corners (v[0], v[1], v[2]: the scene's vertex
 * order), for the watertight test and the frusta kernels' common-origin
 * (Pluecker) culling, which need the vertices rather than the projection,
 * and its prim: the watertight test's hits read it from the line the
 * corners came in (the projected record is another array). */
typedef struct bvh_corners {
    float v[3][3];
    uint32_t prim;
} bvh_corners;
_Static_assert(sizeof(bvh_corners) == 40, "a record's corners and prim are 40 bytes");

typedef struct bvh_tree {
    bvh_node *nodes;
    kd_triangle *triangles;   /* records in leaf order */
    bvh_corners *corners;     /* per record, the same order */
    void *arrays;             /* the one allocation holding nodes, triangles and corners (engine/pages.h) */
    uint32_t node_count, triangle_count; /* triangle_count: records, in leaf order (a pre-split triangle has one
                                          * per leaf its parts went to, bvh_build.c) */
    bvh_child root;           /* the root's box and reference (count 0 and node 0, or a leaf) */
    bool watertight;          /* the triangle test: false projected (records), true watertight (corners) */
    /* Back-face culling (../solids.h; bvh-mft's camera path): per record,
     * 0 when its triangle belongs to no solid, else +-(k + 1) with k its
     * mesh's entry in solid_box and the sign its part's outward side (+:
     * the winding's normal points out of the solid).  NULL when the scene
     * has no solid. */
    int32_t *solid;
    float (*solid_box)[6];    /* per solid mesh: the box of its vertices (lo xyz, hi xyz) */
    uint32_t solid_count;
    rtt_tree_info info;
} bvh_tree;

void bvh_tree_free(bvh_tree *tree);

#endif

/* The binned SAH BVH builder (bvh_build.c). */
#ifndef RTT_BVH_BUILD_H
#define RTT_BVH_BUILD_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_tree.h"
#include "rtt/error.h"
#include "rtt/scene.h"

/* Leaf sizes the builder accepts, and the defaults per use (the figures
 * that chose them: bench/results/bvh-build.md). */
#define BVH_LEAF_SIZE_MAX 64u
#define BVH_DEFAULT_LEAF_SIZE 4u
/* The SAH's cost of a node step in triangle tests: 1.5, not the textbook
 * 1, since the frusta kernels test a leaf's triangles against every
 * frustum at once (bvh-mft's camera path makes four triangles' set-up at a
 * time) while a node step waits on its box test and its branches.  Against
 * 1: bvh-mft primary +5 to 6% on the meshes, the maps within 0.2%;
 * frusta:16 -0.6 to +3%; bvh-packet -0.2 to +2.8%.  2 gained the meshes'
 * primary rays up to 9% but cost frusta:16 on the maps 2 to 5%
 * (bench/results/bvh-mft.md, eleventh session). */
#define BVH_DEFAULT_NODE_COST 1.5f
#define BVH_NODE_COST_MAX 64.0f
/* Pre-splitting (bvh_build.c): the references it may add, a share of the
 * triangles, and which triangles it cuts: those whose box's area is this
 * many times the top of the median box area's binade or more.  0.1 and 8:
 * czest3ctf's primary rays +23%, its soft shadows +4% (+2 to +31% over
 * five views), ctf_inyard's soft shadows +10%, primary rays -4 to -5% on
 * ctf_inyard and oa_dm4; the meshes have no such triangles (none on
 * armadillo and the elephant, 67 on bunny00); the build +20% on the maps
 * (bench/results/bvh-mft.md, twelfth session). */
#define BVH_DEFAULT_SPLIT_SHARE 0.1f
#define BVH_SPLIT_SHARE_MAX 1.0f
#define BVH_SPLIT_AREA_FACTOR 8.0f

typedef struct bvh_build_options {
    uint32_t leaf_size;   /* most records a leaf holds below the depth bound, 1..BVH_LEAF_SIZE_MAX (0 → default) */
    uint32_t max_depth;   /* 1..BVH_DEPTH_LIMIT (0 → BVH_DEPTH_LIMIT); a node there is a leaf whatever it holds */
    float node_cost;      /* the SAH's C_trav over C_isect, (0, BVH_NODE_COST_MAX] (0 or outside → default) */
    float split_share;    /* pre-splitting's extra references over the triangles, at most BVH_SPLIT_SHARE_MAX
                           * (0 → BVH_DEFAULT_SPLIT_SHARE, negative → none: one reference per triangle) */
    uint32_t threads;     /* 0 → one per core */
} bvh_build_options;

/* Builds the BVH of the scene's non-degenerate triangles.  False (one line
 * in err) only when memory runs out. */
bool bvh_build_sah(const rtt_scene *scene, const bvh_build_options *options, bvh_tree *tree, rtt_error *err);

/* The scene's solids for bvh-mft's back-face culling (bvh_tree.solid,
 * solid_box; ../solids.h), over the triangles that have a record: a
 * per-scene analysis, as rtt's closedness is, apart from the build (no
 * other kernel reads it; a tree without it culls nothing).  False (one line
 * in err, the tree as it was but without solids) only when memory runs
 * out. */
bool bvh_tree_mark_solids(bvh_tree *tree, const rtt_scene *scene, rtt_error *err);

#endif

/* The reference kd-tree: built by kd_build_reference.c, walked by
 * traverse_recursive.c.  Private to reference/ (and its tests, which check
 * the builder's invariants on it).  Laid out for obviousness, not speed. */
#ifndef RTT_REFERENCE_KD_REFERENCE_H
#define RTT_REFERENCE_KD_REFERENCE_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/scene.h"

#define RTT_KD_LEAF 3u          /* axis value that marks a leaf */
#define RTT_KD_COST_TRAVERSAL 1.0
#define RTT_KD_COST_INTERSECT 5.0
#define RTT_KD_DEPTH_LIMIT 64u  /* no tree is deeper, whatever the options say */

/* One node.  Internal: split plane `split` on `axis`, children[0] holds the
 * space below the plane, children[1] the space above.  Leaf (axis ==
 * RTT_KD_LEAF): prims[first .. first+count) of the tree, in ascending order. */
typedef struct rtt_kd_node {
    uint32_t axis;
    float split;
    uint32_t children[2];
    uint32_t first, count;
} rtt_kd_node;

typedef struct rtt_kd_tree {
    rtt_kd_node *nodes;       /* nodes[0] is the root */
    uint32_t node_count, node_capacity;
    uint32_t *prims;          /* leaf triangle lists, global triangle indices */
    uint64_t prim_count, prim_capacity;
    rtt_vec3 (*triangles)[3]; /* corner positions of every scene triangle */
    uint32_t triangle_count;
    rtt_bounds bounds;        /* of the non-degenerate triangles; empty when none */
    rtt_tree_info info;
} rtt_kd_tree;

typedef struct rtt_kd_build_options {
    uint32_t max_depth;       /* 0 → rtt_kd_default_max_depth(N), at most RTT_KD_DEPTH_LIMIT */
    uint64_t reference_cap;   /* 0 → 16 N + 1M */
} rtt_kd_build_options;

/* Builds the SAH tree with perfect splits over every triangle of the scene
 * (degenerate ones are left out).  opt may be NULL.  On failure the tree is
 * left empty and err names what went wrong (only memory can run out). */
bool rtt_kd_reference_build(const rtt_scene *scene, const rtt_kd_build_options *opt, rtt_kd_tree *tree,
                            rtt_error *err);
void rtt_kd_reference_free(rtt_kd_tree *tree);

/* Closest hit (prim RTT_MISS, t = +inf on a miss); ties in t go to the
 * smaller prim index. */
void rtt_kd_reference_intersect(const rtt_kd_tree *tree, const rtt_ray *ray, rtt_hit *hit);
/* Any hit with tnear < t < tfar. */
bool rtt_kd_reference_occluded(const rtt_kd_tree *tree, const rtt_ray *ray);

#endif

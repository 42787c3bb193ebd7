/* The optimized engine's kd-tree builder ("RTTest offline", Thesis 3.2.1):
 * O(N log N) SAH with perfect splits (Wald & Havran 2006), kd_build_sah.c. */
#ifndef RTT_OPTIMIZED_KD_BUILD_H
#define RTT_OPTIMIZED_KD_BUILD_H

#include <stdbool.h>
#include <stdint.h>

#include "kd_tree.h"
#include "rtt/error.h"
#include "rtt/scene.h"

#define KD_COST_TRAVERSAL 1.0   /* Thesis Eq. 2.1: C_intersect is 5x C_traversal */
#define KD_COST_INTERSECT 5.0
#define KD_MAX_TRIANGLES (1u << 30) /* events pack the prim id in 30 bits */
#define KD_PARALLEL_MIN_TRIANGLES 20000u /* from here two threads build (and check) the root's subtrees */

typedef struct kd_build_options {
    uint32_t max_depth;         /* 0 → rtt_kd_default_max_depth(N), at most KD_DEPTH_LIMIT */
    uint64_t reference_cap;     /* 0 → 16 N + 1M triangle references in leaves */
    uint32_t threads;           /* 0 → one per core; above 1, big scenes build the root's two
                                   subtrees at once (the same bytes as one thread) */
} kd_build_options;

/* Builds the tree of every non-degenerate triangle of the scene (those whose
 * projected-barycentric record kd_triangle_record refuses never enter it and
 * keep their index).  opt may be NULL.  Fills tree->info.  On failure (out
 * of memory, too many triangles) the tree is left zeroed and err says why. */
bool kd_build_sah(const rtt_scene *scene, const kd_build_options *opt, kd_tree *tree, rtt_error *err);

/* Whether a tree loaded from a .kdt is the tree of the scene's triangles
 * as far as O(references) can tell (records, root box, leaf boxes, no
 * triangle left out; kdt_verify.c), on two threads for big trees when
 * `threads` (0: one per core) allows.  err says what disagrees. */
bool kd_baked_tree_verify(const rtt_scene *scene, const kd_tree *tree, uint32_t threads, rtt_error *err);

/* Frees the arrays of a tree built by kd_build_sah. */
void kd_tree_free(kd_tree *tree);

#endif

/* A baked tree must be the tree of the triangles it ships with.
 *
 * scene/kdt_file.c checks a .kdt's checksum, every count, offset and index
 * and the tree's shape, which keeps the kernels in bounds.  The checksum
 * only catches accidents: a file changed on purpose and re-checksummed
 * passes it (fuzz/README.md, the kdt findings), and the engine would then
 * trace records that are not the stored vertices', or leaves that miss
 * triangles.  So before the engine adopts a tree it replays the builder's
 * distribution of the triangles over the file's own split planes:
 *
 *  - every split plane lies strictly inside its cell (as the sweep picks);
 *  - each triangle with a record (kd_triangle_record accepts it) descends
 *    from the root with its bounds, re-clipped to a child's cell where it
 *    straddles the plane (kd_clip.c, the builder's clipping and side rule),
 *    and must be in every leaf it reaches, with its record byte for byte;
 *  - every leaf holds exactly the triangles that reach it, in ascending
 *    prim order, and its culling box covers their clipped bounds;
 *  - the root box is the union of the recorded triangles' bounds.
 *
 * Then the leaves are what kd_build_sah would have made of those planes, and
 * whatever planes a file chose, no hit is lost (the builder's argument).
 * The cost is that of the builder's clipping without its sorts and sweeps:
 * measured in bench/results/report.md ("Baked trees"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "isect_projected_bary.h"
#include "kd_build.h"
#include "kd_clip.h"

typedef struct verifier {
    const rtt_scene *scene;
    const kd_tree *tree;
    uint32_t *reached;          /* per leaf: triangles that reach it */
    rtt_error *err;
} verifier;

typedef struct descent {
    uint32_t prim;
    rtt_vec3 corners[3];
    kd_triangle record;
} descent;

static bool in_leaf(const verifier *v, uint32_t leaf_index, const descent *t, rtt_bounds cell, rtt_bounds bounds)
{
    const kd_leaf *leaf = &v->tree->leaves[leaf_index];
    const kd_triangle *records = &v->tree->triangles[leaf->first];
    uint32_t lo = 0, hi = leaf->count; /* ascending prims: checked before the descent */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (records[mid].prim < t->prim) lo = mid + 1;
        else hi = mid;
    }
    if (lo == leaf->count || records[lo].prim != t->prim)
        return rtt_error_set(v->err, "%s: leaf %u: triangle %u reaches it but is not in it", v->scene->path,
                             leaf_index, t->prim);
    if (memcmp(&records[lo], &t->record, sizeof t->record) != 0)
        return rtt_error_set(v->err, "%s: leaf %u: the record of triangle %u is not that triangle's",
                             v->scene->path, leaf_index, t->prim);
    for (int a = 0; a < 3; a++) {
        float need_lo = fmaxf(rtt_v3_get(bounds.lo, a), rtt_v3_get(cell.lo, a));
        float need_hi = fminf(rtt_v3_get(bounds.hi, a), rtt_v3_get(cell.hi, a));
        if (leaf->lo[a] > need_lo || leaf->hi[a] < need_hi)
            return rtt_error_set(v->err, "%s: leaf %u: its box does not cover triangle %u", v->scene->path,
                                 leaf_index, t->prim);
    }
    v->reached[leaf_index]++;
    return true;
}

/* depth <= KDT_DEPTH_LIMIT: the loader has checked the tree's shape */
static bool descend(const verifier *v, uint32_t node_index, rtt_bounds cell, const descent *t, rtt_bounds bounds)
{
    const kd_node *node = &v->tree->nodes[node_index];
    if (kd_node_is_leaf(node)) return in_leaf(v, node->leaf, t, cell, bounds);
    const int axis = (int)kd_node_axis(node);
    const float plane = node->split;
    if (!(plane > rtt_v3_get(cell.lo, axis) && plane < rtt_v3_get(cell.hi, axis)))
        return rtt_error_set(v->err, "%s: node %u: split plane %g lies outside its cell", v->scene->path, node_index,
                             (double)plane);
    rtt_bounds child[2] = {cell, cell};
    rtt_v3_set(&child[0].hi, axis, plane);
    rtt_v3_set(&child[1].lo, axis, plane);
    const float lo = rtt_v3_get(bounds.lo, axis), hi = rtt_v3_get(bounds.hi, axis);
    const bool below = kd_goes_below(lo, hi, plane), above = kd_goes_above(lo, hi, plane);
    const uint32_t first = kd_node_child(node);
    if (below && above)
        return descend(v, first, child[0], t, kd_clip_triangle_to_box(t->corners, child[0])) &&
               descend(v, first + 1, child[1], t, kd_clip_triangle_to_box(t->corners, child[1]));
    return below ? descend(v, first, child[0], t, bounds) : descend(v, first + 1, child[1], t, bounds);
}

static bool leaves_sorted(const verifier *v)
{
    for (uint32_t l = 0; l < v->tree->leaf_count; l++) {
        const kd_leaf *leaf = &v->tree->leaves[l];
        for (uint32_t i = 1; i < leaf->count; i++)
            if (v->tree->triangles[leaf->first + i - 1].prim >= v->tree->triangles[leaf->first + i].prim)
                return rtt_error_set(v->err, "%s: leaf %u: triangles not in ascending order", v->scene->path, l);
    }
    return true;
}

static bool same_box(rtt_bounds a, rtt_bounds b)
{
    return memcmp(&a, &b, sizeof a) == 0 || (rtt_bounds_is_empty(a) && rtt_bounds_is_empty(b));
}

bool kd_baked_tree_verify(const rtt_scene *scene, const kd_tree *tree, rtt_error *err)
{
    verifier v = {scene, tree, calloc((size_t)tree->leaf_count + 1, sizeof(uint32_t)), err};
    if (!v.reached) return rtt_error_set(err, "%s: out of memory checking the baked tree", scene->path);
    bool ok = leaves_sorted(&v);
    rtt_bounds root = rtt_bounds_empty();
    for (uint32_t i = 0; ok && i < scene->triangle_count; i++) {
        descent t = {.prim = i};
        rtt_scene_triangle(scene, i, t.corners);
        if (!rtt_v3_is_finite(t.corners[0]) || !rtt_v3_is_finite(t.corners[1]) || !rtt_v3_is_finite(t.corners[2]) ||
            !kd_triangle_record(&t.record, t.corners, i))
            continue;
        rtt_bounds bounds = kd_triangle_bounds(t.corners);
        root = rtt_bounds_union(root, bounds);
        ok = descend(&v, 0, tree->bounds, &t, bounds);
    }
    if (ok && !same_box(root, tree->bounds))
        ok = rtt_error_set(err, "%s: the baked tree's root box is not the bounds of its triangles", scene->path);
    for (uint32_t l = 0; ok && l < tree->leaf_count; l++)
        if (v.reached[l] != tree->leaves[l].count)
            ok = rtt_error_set(err, "%s: leaf %u holds %u triangles, %u of which reach it", scene->path, l,
                               tree->leaves[l].count, v.reached[l]);
    free(v.reached);
    return ok;
}

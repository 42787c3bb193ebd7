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
 * Like the builder it walks the tree once, depth first, carrying each
 * node's triangles (in ascending prim order, so a leaf's list is compared
 * with its records in one pass): the builder's partition without its sorts
 * and sweeps, read in order rather than one triangle's path at a time
 * (measured in bench/results/tree-depth.md, "Baked trees"). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "isect_projected_bary.h"
#include "kd_build.h"
#include "kd_clip.h"
#include "engine/threads.h"

typedef struct verifier {
    const rtt_scene *scene;
    const kd_tree *tree;
    rtt_error *err;
} verifier;

/* A triangle in a node: its prim and its bounds clipped as the builder
 * clipped them (re-clipped only where it straddled a plane). */
typedef struct node_item {
    uint32_t prim;
    rtt_bounds bounds;
} node_item;

static bool check_leaf(const verifier *v, uint32_t leaf_index, rtt_bounds cell, const node_item *items, size_t n)
{
    const kd_leaf *leaf = &v->tree->leaves[leaf_index];
    const kd_triangle *records = &v->tree->triangles[leaf->first];
    for (size_t i = 0; i < n || i < leaf->count; i++) {
        /* both lists ascend: the smaller of two different prims is the one missing from the other */
        if (i == leaf->count || (i < n && records[i].prim > items[i].prim))
            return rtt_error_set(v->err, "%s: leaf %u: triangle %u reaches it but is not in it", v->scene->path,
                                 leaf_index, items[i].prim);
        if (i == n || records[i].prim != items[i].prim)
            return rtt_error_set(v->err, "%s: leaf %u: holds triangle %u, which does not reach it", v->scene->path,
                                 leaf_index, records[i].prim);
        rtt_vec3 p[3];
        rtt_scene_triangle(v->scene, items[i].prim, p);
        kd_triangle expected;
        kd_triangle_record(&expected, p, items[i].prim);
        if (memcmp(&records[i], &expected, sizeof expected) != 0)
            return rtt_error_set(v->err, "%s: leaf %u: the record of triangle %u is not that triangle's",
                                 v->scene->path, leaf_index, items[i].prim);
        for (int a = 0; a < 3; a++) {
            float need_lo = fmaxf(rtt_v3_get(items[i].bounds.lo, a), rtt_v3_get(cell.lo, a));
            float need_hi = fminf(rtt_v3_get(items[i].bounds.hi, a), rtt_v3_get(cell.hi, a));
            if (leaf->lo[a] > need_lo || leaf->hi[a] < need_hi)
                return rtt_error_set(v->err, "%s: leaf %u: its box does not cover triangle %u", v->scene->path,
                                     leaf_index, items[i].prim);
        }
    }
    return true;
}

/* The triangles of an internal node that go to its child s (0 below, 1
 * above the plane), re-clipped where they straddle it; false for a plane
 * outside the cell.  `child` holds n items. */
static bool node_child_items(const verifier *v, uint32_t node_index, rtt_bounds cell, const node_item *items,
                             size_t n, int s, node_item *child, size_t *count, rtt_bounds *child_cell)
{
    const kd_node *node = &v->tree->nodes[node_index];
    const int axis = (int)kd_node_axis(node);
    const float plane = node->split;
    if (!(plane > rtt_v3_get(cell.lo, axis) && plane < rtt_v3_get(cell.hi, axis)))
        return rtt_error_set(v->err, "%s: node %u: split plane %g lies outside its cell", v->scene->path, node_index,
                             (double)plane);
    *child_cell = cell;
    if (s == 0) rtt_v3_set(&child_cell->hi, axis, plane);
    else rtt_v3_set(&child_cell->lo, axis, plane);
    *count = 0;
    for (size_t i = 0; i < n; i++) {
        const float lo = rtt_v3_get(items[i].bounds.lo, axis), hi = rtt_v3_get(items[i].bounds.hi, axis);
        const bool below = kd_goes_below(lo, hi, plane), above = kd_goes_above(lo, hi, plane);
        if (!(s == 0 ? below : above)) continue;
        child[*count] = items[i];
        if (below && above) {
            rtt_vec3 p[3];
            rtt_scene_triangle(v->scene, items[i].prim, p);
            child[*count].bounds = kd_clip_triangle_to_box(p, *child_cell);
        }
        (*count)++;
    }
    return true;
}

/* depth <= KDT_DEPTH_LIMIT: the loader has checked the tree's shape */
static bool check_node(const verifier *v, uint32_t node_index, rtt_bounds cell, const node_item *items, size_t n)
{
    const kd_node *node = &v->tree->nodes[node_index];
    if (kd_node_is_leaf(node)) return check_leaf(v, node->leaf, cell, items, n);
    node_item *child = malloc((n + 1) * sizeof *child);
    if (!child) return rtt_error_set(v->err, "%s: out of memory checking the baked tree", v->scene->path);
    bool ok = true;
    for (int s = 0; ok && s < 2; s++) {
        size_t count;
        rtt_bounds child_cell;
        ok = node_child_items(v, node_index, cell, items, n, s, child, &count, &child_cell) &&
             check_node(v, kd_node_child(node) + (uint32_t)s, child_cell, child, count);
    }
    free(child);
    return ok;
}

/* The root's two subtrees checked at once (a second thread for the one
 * above the plane), each with its own error; the one below reports first,
 * as one thread would. */

typedef struct subtree_check {
    verifier v;
    rtt_error err;
    uint32_t node;
    rtt_bounds cell;
    node_item *items;
    size_t count;
    bool ok;
} subtree_check;

static void *subtree_check_main(void *arg)
{
    subtree_check *c = arg;
    c->ok = check_node(&c->v, c->node, c->cell, c->items, c->count);
    return NULL;
}

static bool check_root_two_threads(const verifier *v, const node_item *items, size_t n)
{
    const kd_node *root = &v->tree->nodes[0];
    subtree_check checks[2];
    bool ok = true;
    for (int s = 0; s < 2; s++) {
        checks[s] = (subtree_check){.v = *v, .node = kd_node_child(root) + (uint32_t)s};
        checks[s].v.err = &checks[s].err;
        checks[s].items = malloc((n + 1) * sizeof *checks[s].items);
        ok = ok && checks[s].items &&
             node_child_items(v, 0, v->tree->bounds, items, n, s, checks[s].items, &checks[s].count, &checks[s].cell);
    }
    if (ok) {
        pthread_t thread;
        bool threaded = pthread_create(&thread, NULL, subtree_check_main, &checks[1]) == 0;
        subtree_check_main(&checks[0]);
        if (threaded) pthread_join(thread, NULL);
        else subtree_check_main(&checks[1]);
        for (int s = 0; ok && s < 2; s++)
            if (!checks[s].ok) ok = rtt_error_set(v->err, "%s", checks[s].err.message);
    } else if (!checks[0].items || !checks[1].items) {
        rtt_error_set(v->err, "%s: out of memory checking the baked tree", v->scene->path);
    }
    free(checks[0].items);
    free(checks[1].items);
    return ok;
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

bool kd_baked_tree_verify(const rtt_scene *scene, const kd_tree *tree, uint32_t threads, rtt_error *err)
{
    verifier v = {scene, tree, err};
    node_item *items = malloc(((size_t)scene->triangle_count + 1) * sizeof *items);
    if (!items) return rtt_error_set(err, "%s: out of memory checking the baked tree", scene->path);
    size_t n = 0;
    rtt_bounds root = rtt_bounds_empty();
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 p[3];
        rtt_scene_triangle(scene, i, p);
        kd_triangle record;
        if (!rtt_v3_is_finite(p[0]) || !rtt_v3_is_finite(p[1]) || !rtt_v3_is_finite(p[2]) ||
            !kd_triangle_record(&record, p, i))
            continue;
        items[n] = (node_item){i, kd_triangle_bounds(p)};
        root = rtt_bounds_union(root, items[n].bounds);
        n++;
    }
    bool ok = leaves_sorted(&v) && (same_box(root, tree->bounds) ||
              rtt_error_set(err, "%s: the baked tree's root box is not the bounds of its triangles", scene->path));
    if (threads == 0) threads = rtt_cpu_count();
    bool two = threads > 1 && n >= KD_PARALLEL_MIN_TRIANGLES && !kd_node_is_leaf(&tree->nodes[0]);
    ok = ok && (two ? check_root_two_threads(&v, items, n) : check_node(&v, 0, tree->bounds, items, n));
    free(items);
    return ok;
}

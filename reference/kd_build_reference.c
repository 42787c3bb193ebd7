/* Thesis 2.2.1 ("kd-Tree Building") and 3.2.1: SAH kd-tree with perfect splits.
 *
 * Cost of splitting a node of area SA holding N triangles (Eq. 2.1):
 *   C = C_trav + C_isect * (N_L * SA_L / SA + N_R * SA_R / SA),
 * C_trav = 1, C_isect = 5.  A node becomes a leaf when no plane costs less
 * than C_isect * N (termination rule 1), at the maximum depth (rule 2), when
 * it is empty (rule 3), or when splitting would take the total number of
 * triangle references past the cap (a memory bound of ours, reported in
 * rtt_tree_info).
 *
 * Perfect splits: each triangle is clipped to the node box (Sutherland-Hodgman
 * against the box's 6 planes, in double precision, with the result rounded
 * outwards to float so the clipped bounds never shrink below the true ones)
 * and the candidate planes are the faces of the clipped bounds that lie
 * strictly inside the node.  The candidates of one axis are sorted and swept
 * once (Wald & Havran's start/planar/end events), so a node costs O(N log N)
 * and the tree O(N log^2 N).
 *
 * Which side a triangle goes to, from its clipped bounds [lo, hi] on the split
 * axis and the plane p:
 *   lo < p          → below (children[0])
 *   hi > p          → above (children[1])   (both when lo < p < hi)
 *   lo == hi == p   → below: a triangle lying in the split plane goes to the
 *                     lower child only.  A ray can only hit it where it
 *                     crosses the plane, and the traversal visits the cells on
 *                     both sides of a crossing, so one side is enough.
 * A triangle touching the plane from one side (hi == p or lo == p) stays on
 * its own side.  Flat (axis-aligned) triangles need no special case: their
 * clipped bounds are flat and they are "planar" events on that axis.
 *
 * Degenerate triangles (zero area, or non-finite corners) never hit, so they
 * never enter the tree; they keep their index in the scene.  The recursion
 * is bounded by the maximum depth, itself at most RTT_KD_DEPTH_LIMIT. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "isect_watertight.h"
#include "engine/clip.h"
#include "engine/clock.h"
#include "kd_reference.h"

/* A triangle in a node under construction, with its bounds clipped to the node. */
typedef struct build_item {
    uint32_t prim;
    rtt_bounds clipped;
} build_item;

/* Candidate plane events of one axis; the order within one position is
 * end < planar < start, which is what the sweep needs. */
enum { EVENT_END = 0, EVENT_PLANAR = 1, EVENT_START = 2 };
typedef struct split_event {
    float position;
    int type;
} split_event;

typedef struct split_choice {
    int axis;
    float position;
    double cost;
    uint32_t below, above;
} split_choice;

typedef struct builder {
    rtt_kd_tree *tree;
    uint32_t max_depth;
    uint64_t reference_cap;
    uint64_t pending_references; /* references of every leaf made and every node not yet built */
    double sah_sum;              /* cost of the tree times the root's area */
    bool out_of_memory;
} builder;

/* ---- clipping -------------------------------------------------------- */

static bool bounds_inside(rtt_bounds inner, rtt_bounds outer)
{
    for (int a = 0; a < 3; a++)
        if (rtt_v3_get(inner.lo, a) < rtt_v3_get(outer.lo, a) || rtt_v3_get(inner.hi, a) > rtt_v3_get(outer.hi, a))
            return false;
    return true;
}

/* ---- the SAH sweep --------------------------------------------------- */

static int event_compare(const void *pa, const void *pb)
{
    const split_event *a = pa, *b = pb;
    if (a->position != b->position) return a->position < b->position ? -1 : 1;
    return a->type - b->type;
}

/* Surface area in double: in float it overflows for boxes of 1e19 and loses
 * its digits below 1e-19, and the scenes are tested from 1e-20 to 1e+20. */
static double box_area(rtt_bounds b)
{
    if (rtt_bounds_is_empty(b)) return 0.0;
    double x = (double)b.hi.x - b.lo.x, y = (double)b.hi.y - b.lo.y, z = (double)b.hi.z - b.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

static double split_cost(rtt_bounds box, double area, int axis, float position, uint32_t below, uint32_t above)
{
    rtt_bounds lower = box, upper = box;
    rtt_v3_set(&lower.hi, axis, position);
    rtt_v3_set(&upper.lo, axis, position);
    return RTT_KD_COST_TRAVERSAL +
           RTT_KD_COST_INTERSECT * (below * box_area(lower) / area + above * box_area(upper) / area);
}

/* Sweeps the candidate planes of one axis and keeps the cheapest in *best. */
static void sweep_axis(const build_item *items, uint32_t n, rtt_bounds box, int axis, split_event *events,
                       split_choice *best)
{
    const float box_lo = rtt_v3_get(box.lo, axis), box_hi = rtt_v3_get(box.hi, axis);
    const double area = box_area(box);
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++) {
        float lo = rtt_v3_get(items[i].clipped.lo, axis), hi = rtt_v3_get(items[i].clipped.hi, axis);
        if (lo == hi) {
            events[count++] = (split_event){lo, EVENT_PLANAR};
        } else {
            events[count++] = (split_event){lo, EVENT_START};
            events[count++] = (split_event){hi, EVENT_END};
        }
    }
    qsort(events, count, sizeof events[0], event_compare);

    uint32_t below = 0, above = n;
    for (uint32_t i = 0; i < count;) {
        const float position = events[i].position;
        uint32_t ending = 0, planar = 0, starting = 0;
        for (; i < count && events[i].position == position && events[i].type == EVENT_END; i++) ending++;
        for (; i < count && events[i].position == position && events[i].type == EVENT_PLANAR; i++) planar++;
        for (; i < count && events[i].position == position && events[i].type == EVENT_START; i++) starting++;
        above -= ending + planar;
        if (position > box_lo && position < box_hi) {
            double cost = split_cost(box, area, axis, position, below + planar, above);
            if (cost < best->cost) *best = (split_choice){axis, position, cost, below + planar, above};
        }
        below += starting + planar;
    }
}

static bool find_best_split(const build_item *items, uint32_t n, rtt_bounds box, split_event *events,
                            split_choice *best)
{
    best->cost = INFINITY;
    best->axis = -1;
    if (!(box_area(box) > 0.0)) return false;
    for (int axis = 0; axis < 3; axis++)
        if (rtt_v3_get(box.lo, axis) < rtt_v3_get(box.hi, axis)) sweep_axis(items, n, box, axis, events, best);
    return best->axis >= 0;
}

/* ---- nodes ----------------------------------------------------------- */

static uint32_t new_node(builder *b)
{
    rtt_kd_tree *tree = b->tree;
    if (tree->node_count == tree->node_capacity) {
        uint32_t capacity = tree->node_capacity ? tree->node_capacity * 2 : 64;
        rtt_kd_node *nodes = realloc(tree->nodes, capacity * sizeof *nodes);
        if (!nodes) {
            b->out_of_memory = true;
            return UINT32_MAX;
        }
        tree->nodes = nodes;
        tree->node_capacity = capacity;
    }
    memset(&tree->nodes[tree->node_count], 0, sizeof tree->nodes[0]);
    return tree->node_count++;
}

static void make_leaf(builder *b, uint32_t node, const build_item *items, uint32_t n, rtt_bounds box, uint32_t depth)
{
    rtt_kd_tree *tree = b->tree;
    if (tree->prim_count + n > tree->prim_capacity) {
        uint64_t capacity = tree->prim_capacity ? tree->prim_capacity : 1024;
        while (capacity < tree->prim_count + n) capacity *= 2;
        uint32_t *prims = realloc(tree->prims, capacity * sizeof *prims);
        if (!prims) {
            b->out_of_memory = true;
            return;
        }
        tree->prims = prims;
        tree->prim_capacity = capacity;
    }
    rtt_kd_node *leaf = &tree->nodes[node];
    leaf->axis = RTT_KD_LEAF;
    leaf->first = (uint32_t)tree->prim_count;
    leaf->count = n;
    for (uint32_t i = 0; i < n; i++) tree->prims[tree->prim_count++] = items[i].prim;

    tree->info.leaf_count++;
    if (n == 0) tree->info.empty_leaf_count++;
    if (depth > tree->info.depth) tree->info.depth = depth;
    b->sah_sum += RTT_KD_COST_INTERSECT * n * box_area(box);
}

/* The items of one child: those on its side of the plane, with bounds
 * re-clipped to the child's box where they stick out of it. */
static build_item *child_items(const rtt_kd_tree *tree, const build_item *items, uint32_t n, split_choice split,
                               int side, rtt_bounds child_box)
{
    build_item *out = malloc((n ? n : 1) * sizeof *out);
    if (!out) return NULL;
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++) {
        float lo = rtt_v3_get(items[i].clipped.lo, split.axis), hi = rtt_v3_get(items[i].clipped.hi, split.axis);
        bool below = lo < split.position || (lo == hi && lo == split.position);
        bool above = hi > split.position;
        if (side == 0 ? !below : !above) continue;
        build_item item = items[i];
        if (!bounds_inside(item.clipped, child_box)) {
            rtt_bounds clipped;
            /* an empty clip can only come from rounding at the plane: keep the
             * sliver of the old bounds rather than lose the triangle */
            item.clipped = rtt_clip_triangle_bounds(tree->triangles[item.prim], child_box, &clipped)
                               ? clipped
                               : rtt_bounds_intersection(item.clipped, child_box);
        }
        out[count++] = item;
    }
    return out;
}

/* Builds the subtree of `node` over items (which it frees). */
static void build_node(builder *b, uint32_t node, build_item *items, uint32_t n, rtt_bounds box, uint32_t depth)
{
    split_choice split = {.axis = -1};
    bool split_found = false;
    if (n > 0 && depth < b->max_depth) {
        split_event *events = malloc(2 * (size_t)n * sizeof *events);
        if (!events) {
            b->out_of_memory = true;
            free(items);
            return;
        }
        split_found = find_best_split(items, n, box, events, &split);
        free(events);
    }
    bool worth_it = split_found && split.cost < RTT_KD_COST_INTERSECT * n;
    uint64_t references_after = b->pending_references + split.below + split.above - n;
    if (!worth_it || references_after > b->reference_cap) {
        make_leaf(b, node, items, n, box, depth);
        free(items);
        return;
    }

    rtt_bounds lower = box, upper = box;
    rtt_v3_set(&lower.hi, split.axis, split.position);
    rtt_v3_set(&upper.lo, split.axis, split.position);
    build_item *below = child_items(b->tree, items, n, split, 0, lower);
    build_item *above = child_items(b->tree, items, n, split, 1, upper);
    free(items);
    uint32_t first_child = new_node(b);
    uint32_t second_child = new_node(b);
    if (!below || !above || b->out_of_memory) {
        b->out_of_memory = true;
        free(below);
        free(above);
        return;
    }
    b->pending_references = references_after;
    rtt_kd_node *inner = &b->tree->nodes[node];
    inner->axis = (uint32_t)split.axis;
    inner->split = split.position;
    inner->children[0] = first_child;
    inner->children[1] = second_child;
    b->sah_sum += RTT_KD_COST_TRAVERSAL * box_area(box);

    build_node(b, first_child, below, split.below, lower, depth + 1);
    if (b->out_of_memory) {
        free(above);
        return;
    }
    build_node(b, second_child, above, split.above, upper, depth + 1);
}

/* ---- the tree -------------------------------------------------------- */

static bool copy_triangles(const rtt_scene *scene, rtt_kd_tree *tree, build_item **items, uint32_t *item_count)
{
    uint32_t n = scene->triangle_count;
    tree->triangle_count = n;
    tree->triangles = malloc((n ? n : 1) * sizeof *tree->triangles);
    *items = malloc((n ? n : 1) * sizeof **items);
    if (!tree->triangles || !*items) return false;
    tree->bounds = rtt_bounds_empty();
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++) {
        rtt_scene_triangle(scene, i, tree->triangles[i]);
        if (rtt_reference_triangle_is_degenerate(tree->triangles[i])) continue;
        rtt_bounds b = rtt_bounds_empty();
        for (int k = 0; k < 3; k++) b = rtt_bounds_grow(b, tree->triangles[i][k]);
        (*items)[count++] = (build_item){i, b};
        tree->bounds = rtt_bounds_union(tree->bounds, b);
    }
    *item_count = count;
    return true;
}

bool rtt_kd_reference_build(const rtt_scene *scene, const rtt_kd_build_options *opt, rtt_kd_tree *tree,
                            rtt_error *err)
{
    double start = rtt_clock_seconds();
    memset(tree, 0, sizeof *tree);
    build_item *items = NULL;
    uint32_t n = 0;
    if (!copy_triangles(scene, tree, &items, &n)) {
        free(items);
        rtt_kd_reference_free(tree);
        return rtt_error_set(err, "%s: out of memory copying %u triangles for the reference kd-tree", scene->path,
                             scene->triangle_count);
    }

    builder b = {.tree = tree};
    b.max_depth = opt && opt->max_depth ? opt->max_depth : rtt_kd_default_max_depth(n);
    if (b.max_depth > RTT_KD_DEPTH_LIMIT) b.max_depth = RTT_KD_DEPTH_LIMIT;
    b.reference_cap = opt && opt->reference_cap ? opt->reference_cap
                                                : 16u * (uint64_t)scene->triangle_count + 1000000u;
    if (b.reference_cap < n) b.reference_cap = n; /* every triangle needs one reference */
    b.pending_references = n;

    uint32_t root = new_node(&b);
    if (root != UINT32_MAX) build_node(&b, root, items, n, tree->bounds, 0);
    else free(items);
    if (b.out_of_memory) {
        rtt_kd_reference_free(tree);
        return rtt_error_set(err, "%s: out of memory building the reference kd-tree of %u triangles", scene->path,
                             scene->triangle_count);
    }

    rtt_tree_info *info = &tree->info;
    double root_area = box_area(tree->bounds);
    info->max_depth = b.max_depth;
    info->node_count = tree->node_count;
    info->references = tree->prim_count;
    info->reference_cap = b.reference_cap;
    info->sah_cost = root_area > 0.0 ? b.sah_sum / root_area : RTT_KD_COST_INTERSECT * n;
    info->memory_bytes = tree->node_count * sizeof(rtt_kd_node) + tree->prim_count * sizeof(uint32_t) +
                         tree->triangle_count * sizeof tree->triangles[0];
    info->build_seconds = rtt_clock_seconds() - start;
    return true;
}

void rtt_kd_reference_free(rtt_kd_tree *tree)
{
    free(tree->nodes);
    free(tree->prims);
    free(tree->triangles);
    memset(tree, 0, sizeof *tree);
}

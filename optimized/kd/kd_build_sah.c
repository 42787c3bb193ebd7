/* Thesis 2.2.1 and 3.2.1 ("RTTest offline"): SAH kd-tree with perfect
 * splits, built in O(N log N) after Wald & Havran 2006 ("On building fast
 * kd-trees for ray tracing, and on doing that in O(N log N)", section 4.3).
 *
 * Cost model (Thesis Eq. 2.1, the same as reference/kd_build_reference.c):
 *   C = C_trav + C_isect * (N_L * SA_L / SA + N_R * SA_R / SA),
 * C_trav = 1, C_isect = 5.  A node becomes a leaf (Thesis 2.2.1 termination
 * rules; the thesis uses no empty-space bonus, so neither do we) when no
 * plane costs less than C_isect * N, at the maximum depth, when it is empty,
 * or when splitting would take the triangle references past the cap (a
 * memory bound of ours against hostile scenes, reported in rtt_tree_info).
 *
 * Perfect splits: a triangle's candidate planes are the faces of its bounds
 * clipped to the node box (Sutherland-Hodgman in double, rounded outwards to
 * float so the clipped bounds never shrink below the exact ones).  Events
 * (start, planar, end) of each axis are sorted ONCE at the root; a split
 * partitions each sorted list into the two children's lists in one pass,
 * and only the triangles straddling the plane are re-clipped, their new
 * events sorted (few) and merged in.  So a level costs O(N) and the tree
 * O(N log N).  The node is built iteratively with an explicit stack (Thesis
 * 3.2.1), depth first, left child first.
 *
 * Side rule (identical to the reference so both trees have the same cost):
 * with clipped bounds [lo, hi] on the split axis and plane p, a triangle is
 * below when lo < p or lo == hi == p (a triangle in the plane goes below
 * only: a ray hits it where it crosses the plane and the traversal visits
 * the cells on both sides of a crossing), above when hi > p.
 *
 * What it trades against the reference: nothing in tree quality (same
 * candidates, same costs, same rule); events carry the prim id in 30 bits,
 * so a scene holds at most 2^30 triangles (refused above).  Leaves hold
 * their triangle records in ascending prim order, so builds are
 * deterministic. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine/buffer.h"
#include "engine/clock.h"
#include "engine/threads.h"
#include "isect_projected_bary.h"
#include "kd_build.h"
#include "kd_clip.h"

/* 8 bytes: (order-preserving key of the position << 32) | type << 30 | prim.
 * Sorting the integers sorts by position, then end < planar < start, which
 * is the order the sweep needs. */
typedef uint64_t kd_event;
enum { EVENT_END = 0, EVENT_PLANAR = 1, EVENT_START = 2 };
#define EVENT_PRIM_MASK 0x3FFFFFFFu

enum { SIDE_BOTH = 0, SIDE_LEFT = 1, SIDE_RIGHT = 2 };

static uint32_t float_key(float f)
{
    f += 0.0f; /* -0 → +0: equal positions must have equal keys */
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

static float key_float(uint32_t k)
{
    uint32_t u = (k & 0x80000000u) ? (k ^ 0x80000000u) : ~k;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline kd_event event_make(float position, uint32_t type, uint32_t prim)
{
    return ((uint64_t)float_key(position) << 32) | ((uint64_t)type << 30) | prim;
}
static inline uint32_t event_type(kd_event e) { return (uint32_t)(e >> 30) & 3u; }
static inline uint32_t event_prim(kd_event e) { return (uint32_t)e & EVENT_PRIM_MASK; }
static inline float event_position(kd_event e) { return key_float((uint32_t)(e >> 32)); }

/* ---- sorting: LSD radix on bits 30..63 for big lists, qsort for small ---- */

static int event_compare(const void *pa, const void *pb)
{
    kd_event a = *(const kd_event *)pa, b = *(const kd_event *)pb;
    return a < b ? -1 : a > b;
}

static bool events_sort(kd_event *events, size_t count)
{
    if (count < 4096) {
        qsort(events, count, sizeof *events, event_compare);
        return true;
    }
    kd_event *tmp = malloc(count * sizeof *tmp);
    uint32_t *hist = malloc(4096 * sizeof *hist);
    if (!tmp || !hist) {
        free(tmp);
        free(hist);
        return false;
    }
    static const int shifts[3] = {30, 42, 53}, widths[3] = {12, 11, 11};
    kd_event *src = events, *dst = tmp;
    for (int pass = 0; pass < 3; pass++) {
        const int shift = shifts[pass];
        const uint32_t buckets = 1u << widths[pass], mask = buckets - 1u;
        memset(hist, 0, buckets * sizeof *hist);
        for (size_t i = 0; i < count; i++) hist[(src[i] >> shift) & mask]++;
        uint32_t sum = 0;
        for (uint32_t b = 0; b < buckets; b++) {
            uint32_t c = hist[b];
            hist[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < count; i++) dst[hist[(src[i] >> shift) & mask]++] = src[i];
        kd_event *swap = src;
        src = dst, dst = swap;
    }
    if (src != events) memcpy(events, src, count * sizeof *events);
    free(tmp);
    free(hist);
    return true;
}

/* ---- the builder's state ------------------------------------------------- */

/* A node waiting to be built: its box and the sorted events of its
 * triangles on each axis (owned). */
typedef struct build_task {
    uint32_t node, depth, count; /* count = triangles in the node */
    rtt_bounds box;
    kd_event *events[3];
    size_t event_count[3];
} build_task;

typedef struct split_choice {
    int axis;
    float position;
    double cost;
    uint32_t below, above;       /* triangles on each side (the side rule above) */
} split_choice;

typedef struct builder {
    const rtt_scene *scene;
    kd_tree *tree;
    const kd_triangle *records;  /* one per scene triangle; valid where it entered the tree */
    uint8_t *side;               /* per scene triangle, during one split */
    uint32_t *leaf_prims;        /* scratch for sorting a leaf's prims */
    kd_event *scratch;           /* the straddlers' new events of one split */
    size_t scratch_capacity;
    size_t leaf_prims_capacity;
    size_t node_capacity, leaf_capacity, triangle_capacity;
    uint32_t max_depth;
    uint64_t reference_cap;
    uint64_t pending_references; /* references of every leaf made and every node not yet built */
    uint64_t peak_accepted;      /* the largest pending_references a split was accepted under */
    double sah_sum;              /* the tree's cost times the root's area */
    bool out_of_memory;
} builder;

/* The three lists share one allocation, starting at events[0]. */
static void task_free(build_task *task)
{
    free(task->events[0]);
    for (int a = 0; a < 3; a++) task->events[a] = NULL, task->event_count[a] = 0;
}

/* Room for `needed` elements in an array of the builder or the tree,
 * whose capacity the builder keeps beside it (kd_tree holds plain arrays:
 * they are the .kdt's).  rtt_buffer grows it; the array stays free()able. */
static bool reserve(void **array, size_t *capacity, size_t needed, size_t element)
{
    rtt_buffer buffer = {.data = *array, .capacity = *capacity, .element = element};
    if (!rtt_buffer_reserve(&buffer, needed, element, 0)) return false;
    *array = buffer.data;
    *capacity = buffer.capacity;
    return true;
}

/* Surface area in double: float overflows for boxes of 1e19 and loses its
 * digits below 1e-19, and scenes are tested from 1e-20 to 1e+20. */
static double box_area(rtt_bounds b)
{
    if (rtt_bounds_is_empty(b)) return 0.0;
    double x = (double)b.hi.x - b.lo.x, y = (double)b.hi.y - b.lo.y, z = (double)b.hi.z - b.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

/* ---- the SAH sweep over pre-sorted events -------------------------------- */

/* Costs are compared without the constant terms: for one node,
 *   cost = C_trav + C_isect * 2 * weight / SA,
 *   weight = N_L * (cap + ring * x_L) + N_R * (cap + ring * x_R),
 * cap = the area of the box's face across the axis, ring = the sum of its
 * other two extents, x_L, x_R the children's extents along it; so the sweep
 * needs no division (best->cost holds the weight until find_best_split). */
static void sweep_axis(const kd_event *events, size_t count, uint32_t n, rtt_bounds box, int axis,
                       split_choice *best)
{
    const float box_lo = rtt_v3_get(box.lo, axis), box_hi = rtt_v3_get(box.hi, axis);
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const double e1 = (double)rtt_v3_get(box.hi, a1) - rtt_v3_get(box.lo, a1);
    const double e2 = (double)rtt_v3_get(box.hi, a2) - rtt_v3_get(box.lo, a2);
    const double cap = e1 * e2, ring = e1 + e2;
    uint32_t below = 0, above = n;
    for (size_t i = 0; i < count;) {
        /* events >> 30 is (key << 2) | type: one compare per event */
        const uint64_t group = events[i] >> 32 << 2;
        uint32_t ending = 0, planar = 0, starting = 0;
        for (; i < count && events[i] >> 30 == group + EVENT_END; i++) ending++;
        for (; i < count && events[i] >> 30 == group + EVENT_PLANAR; i++) planar++;
        for (; i < count && events[i] >> 30 == group + EVENT_START; i++) starting++;
        above -= ending + planar;
        const float position = key_float((uint32_t)(group >> 2));
        if (position > box_lo && position < box_hi) {
            double lower = (double)position - box_lo, upper = (double)box_hi - position;
            double weight = (below + planar) * (cap + ring * lower) + above * (cap + ring * upper);
            if (weight < best->cost) *best = (split_choice){axis, position, weight, below + planar, above};
        }
        below += starting + planar;
    }
}

static bool find_best_split(const build_task *task, split_choice *best)
{
    best->cost = INFINITY;
    best->axis = -1;
    if (!(box_area(task->box) > 0.0)) return false;
    for (int axis = 0; axis < 3; axis++)
        if (rtt_v3_get(task->box.lo, axis) < rtt_v3_get(task->box.hi, axis))
            sweep_axis(task->events[axis], task->event_count[axis], task->count, task->box, axis, best);
    if (best->axis < 0) return false;
    best->cost = KD_COST_TRAVERSAL + KD_COST_INTERSECT * 2.0 * best->cost / box_area(task->box);
    return true;
}

/* ---- leaves and nodes ----------------------------------------------------- */

static int prim_compare(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return a < b ? -1 : a > b;
}

/* Every triangle has exactly one start or planar event per axis. */
static bool event_opens_prim(kd_event e) { return event_type(e) != EVENT_END; }

static void make_leaf(builder *b, const build_task *task)
{
    kd_tree *tree = b->tree;
    if (!reserve((void **)&b->leaf_prims, &b->leaf_prims_capacity, task->count + 1, sizeof *b->leaf_prims) ||
        !reserve((void **)&tree->leaves, &b->leaf_capacity, tree->leaf_count + 1, sizeof *tree->leaves) ||
        !reserve((void **)&tree->triangles, &b->triangle_capacity, (size_t)tree->triangle_count + task->count,
                 sizeof *tree->triangles)) {
        b->out_of_memory = true;
        return;
    }
    uint32_t n = 0;
    for (size_t i = 0; i < task->event_count[0]; i++)
        if (event_opens_prim(task->events[0][i])) b->leaf_prims[n++] = event_prim(task->events[0][i]);
    if (n > 16) {
        qsort(b->leaf_prims, n, sizeof *b->leaf_prims, prim_compare);
    } else {
        for (uint32_t i = 1; i < n; i++) {
            uint32_t p = b->leaf_prims[i], j = i;
            for (; j > 0 && b->leaf_prims[j - 1] > p; j--) b->leaf_prims[j] = b->leaf_prims[j - 1];
            b->leaf_prims[j] = p;
        }
    }

    kd_leaf *leaf = &tree->leaves[tree->leaf_count];
    leaf->first = tree->triangle_count;
    leaf->count = n;
    leaf->lo[0] = task->box.lo.x, leaf->lo[1] = task->box.lo.y, leaf->lo[2] = task->box.lo.z;
    leaf->hi[0] = task->box.hi.x, leaf->hi[1] = task->box.hi.y, leaf->hi[2] = task->box.hi.z;
    /* The box packet/leaf culling tests (4.1.4) is the cell shrunk to the
     * bounds of the triangles clipped to it: the first and last event of
     * each sorted axis list (clipped bounds, rounded outwards).  A ray can
     * only hit a leaf's triangle inside some cell holding it, at a point of
     * that cell's clipped bounds, so culling against them loses no hit; on
     * the Quake maps it culls three times as many intersection tests as the
     * cell (big triangles clipped to a cell are thin slabs).  Empty leaves
     * keep their cell. */
    if (n > 0)
        for (int a = 0; a < 3; a++) {
            leaf->lo[a] = fmaxf(leaf->lo[a], event_position(task->events[a][0]));
            leaf->hi[a] = fminf(leaf->hi[a], event_position(task->events[a][task->event_count[a] - 1]));
        }
    for (uint32_t i = 0; i < n; i++) tree->triangles[tree->triangle_count++] = b->records[b->leaf_prims[i]];

    kd_node *node = &tree->nodes[task->node];
    node->leaf = tree->leaf_count;
    node->bits = KD_AXIS_LEAF;
    tree->leaf_count++;

    rtt_tree_info *info = &tree->info;
    if (n == 0) info->empty_leaf_count++;
    if (task->depth > info->depth) info->depth = task->depth;
    b->sah_sum += KD_COST_INTERSECT * n * box_area(task->box);
}

/* Marks every triangle of the task left-only, right-only or both, in one
 * pass over the split axis' events: a start before the plane marks "both"
 * until the triangle's end turns out to lie at or before it. */
static void classify(builder *b, const build_task *task, split_choice split)
{
    const kd_event *ev = task->events[split.axis];
    for (size_t i = 0; i < task->event_count[split.axis]; i++) {
        float pos = event_position(ev[i]);
        uint32_t type = event_type(ev[i]), prim = event_prim(ev[i]);
        if (type == EVENT_START) b->side[prim] = pos >= split.position ? SIDE_RIGHT : SIDE_BOTH;
        else if (type == EVENT_END) { if (pos <= split.position) b->side[prim] = SIDE_LEFT; }
        else b->side[prim] = pos <= split.position ? SIDE_LEFT : SIDE_RIGHT;
    }
}

static void push_events(kd_event *out[3], size_t count[3], rtt_bounds clipped, uint32_t prim)
{
    for (int a = 0; a < 3; a++) {
        float lo = rtt_v3_get(clipped.lo, a), hi = rtt_v3_get(clipped.hi, a);
        if (lo == hi) {
            out[a][count[a]++] = event_make(lo, EVENT_PLANAR, prim);
        } else {
            out[a][count[a]++] = event_make(lo, EVENT_START, prim);
            out[a][count[a]++] = event_make(hi, EVENT_END, prim);
        }
    }
}

static void sort_small(kd_event *events, size_t count)
{
    for (size_t i = 1; i < count; i++) {
        kd_event e = events[i];
        size_t j = i;
        for (; j > 0 && events[j - 1] > e; j--) events[j] = events[j - 1];
        events[j] = e;
    }
}

/* New events of the straddling triangles, clipped to each child's box,
 * sorted per axis, in the builder's scratch: new_events[side][axis]. */
static bool straddler_events(builder *b, const build_task *task, const rtt_bounds child_box[2],
                             kd_event *new_events[2][3], size_t new_count[2][3])
{
    size_t straddlers = 0;
    for (size_t i = 0; i < task->event_count[0]; i++)
        if (event_opens_prim(task->events[0][i]) && b->side[event_prim(task->events[0][i])] == SIDE_BOTH)
            straddlers++;
    if (!reserve((void **)&b->scratch, &b->scratch_capacity, 12 * straddlers + 1, sizeof *b->scratch)) return false;
    for (int s = 0; s < 2; s++)
        for (int a = 0; a < 3; a++) {
            new_count[s][a] = 0;
            new_events[s][a] = b->scratch + (size_t)(3 * s + a) * 2 * straddlers;
        }
    for (size_t i = 0; i < task->event_count[0]; i++) {
        kd_event e = task->events[0][i];
        if (!event_opens_prim(e) || b->side[event_prim(e)] != SIDE_BOTH) continue;
        uint32_t prim = event_prim(e);
        rtt_vec3 corners[3];
        rtt_scene_triangle(b->scene, prim, corners);
        for (int s = 0; s < 2; s++)
            push_events(new_events[s], new_count[s], kd_clip_triangle_to_box(corners, child_box[s]), prim);
    }
    for (int s = 0; s < 2; s++)
        for (int a = 0; a < 3; a++) {
            if (new_count[s][a] <= 32) sort_small(new_events[s][a], new_count[s][a]);
            else if (!events_sort(new_events[s][a], new_count[s][a])) return false;
        }
    return true;
}

/* The children's event lists, one allocation per child for its three axes
 * (NULL for an empty child), sized for the most each axis can receive;
 * shrink_children compacts them once filled. */
static bool allocate_children(const build_task *task, const size_t new_count[2][3], build_task child[2])
{
    for (int s = 0; s < 2; s++) {
        if (child[s].count == 0) continue;
        size_t total = 0;
        for (int a = 0; a < 3; a++) total += task->event_count[a] + new_count[s][a];
        kd_event *block = malloc(total * sizeof *block);
        if (!block) return false;
        for (int a = 0; a < 3; a++) {
            child[s].events[a] = block;
            block += task->event_count[a] + new_count[s][a];
        }
    }
    return true;
}

static void shrink_children(build_task child[2])
{
    for (int s = 0; s < 2; s++) {
        if (child[s].count == 0) continue;
        kd_event *block = child[s].events[0];
        size_t at = child[s].event_count[0];
        for (int a = 1; a < 3; a++) {
            memmove(block + at, child[s].events[a], child[s].event_count[a] * sizeof *block);
            at += child[s].event_count[a];
        }
        kd_event *shrunk = realloc(block, at * sizeof *block);
        if (shrunk) block = shrunk;
        size_t offset = 0;
        for (int a = 0; a < 3; a++) {
            child[s].events[a] = block + offset;
            offset += child[s].event_count[a];
        }
    }
}

/* One axis of the split: the parent's events of one-sided triangles go to
 * their side in order, merged with the straddlers' new sorted events. */
static void split_axis_events(const builder *b, const build_task *task, int axis, kd_event *const new_events[2],
                              const size_t new_count[2], build_task child[2])
{
    const kd_event *ev = task->events[axis];
    const size_t count = task->event_count[axis];
    size_t out[2] = {0, 0}, next_new[2] = {0, 0};
    for (size_t i = 0; i < count; i++) {
        uint8_t side = b->side[event_prim(ev[i])];
        if (side == SIDE_BOTH) continue;
        int s = side - 1;
        kd_event *dst = child[s].events[axis];
        while (next_new[s] < new_count[s] && new_events[s][next_new[s]] < ev[i])
            dst[out[s]++] = new_events[s][next_new[s]++];
        dst[out[s]++] = ev[i];
    }
    for (int s = 0; s < 2; s++) {
        while (next_new[s] < new_count[s]) child[s].events[axis][out[s]++] = new_events[s][next_new[s]++];
        child[s].event_count[axis] = out[s];
    }
}

static uint32_t new_node_pair(builder *b)
{
    kd_tree *tree = b->tree;
    if (!reserve((void **)&tree->nodes, &b->node_capacity, (size_t)tree->node_count + 2, sizeof *tree->nodes)) {
        b->out_of_memory = true;
        return UINT32_MAX;
    }
    uint32_t first = tree->node_count;
    memset(&tree->nodes[first], 0, 2 * sizeof *tree->nodes);
    tree->node_count += 2;
    return first;
}

/* Splits `task` into child[0] (below) and child[1] (above) and frees its
 * events.  `task` must be classified (classify) for `split`. */
static bool split_task(builder *b, build_task *task, split_choice split, build_task child[2])
{
    rtt_bounds box[2] = {task->box, task->box};
    rtt_v3_set(&box[0].hi, split.axis, split.position);
    rtt_v3_set(&box[1].lo, split.axis, split.position);
    uint32_t first = new_node_pair(b);
    if (first == UINT32_MAX) {
        task_free(task);
        return false;
    }
    child[0] = (build_task){.node = first, .depth = task->depth + 1, .count = split.below, .box = box[0]};
    child[1] = (build_task){.node = first + 1, .depth = task->depth + 1, .count = split.above, .box = box[1]};

    kd_event *new_events[2][3];
    size_t new_count[2][3];
    bool ok = straddler_events(b, task, box, new_events, new_count) && allocate_children(task, new_count, child);
    for (int a = 0; ok && a < 3; a++) {
        kd_event *ne[2] = {new_events[0][a], new_events[1][a]};
        size_t nc[2] = {new_count[0][a], new_count[1][a]};
        split_axis_events(b, task, a, ne, nc, child);
    }
    if (ok) shrink_children(child);
    task_free(task);
    if (!ok) {
        task_free(&child[0]);
        task_free(&child[1]);
        b->out_of_memory = true;
        return false;
    }
    kd_node *node = &b->tree->nodes[task->node];
    node->split = split.position;
    node->bits = (first << 2) | (uint32_t)split.axis;
    b->sah_sum += KD_COST_TRAVERSAL * box_area(task->box);
    b->pending_references += (uint64_t)split.below + split.above - task->count;
    return true;
}

/* Tasks on the builder's stack.  A split pops the top task (depth d) and
 * pushes its two children (depth d + 1), the left one on top; so below the
 * top pair the stack holds at most one task per depth, and no task is
 * deeper than KD_DEPTH_LIMIT (only shallower tasks are split): one task for
 * each depth 1 .. KD_DEPTH_LIMIT and the top pair's second one. */
#define KD_BUILD_STACK (KD_DEPTH_LIMIT + 1u)
_Static_assert(KD_BUILD_STACK >= KD_DEPTH_LIMIT + 1u, "the build stack holds a task per level and a sibling");

/* The whole tree, depth first with an explicit stack (Thesis 3.2.1). */
static void build_tree(builder *b, build_task root)
{
    build_task stack[KD_BUILD_STACK];
    uint32_t top = 0;
    stack[top++] = root;
    while (top > 0) {
        build_task task = stack[--top];
        if (b->out_of_memory) {
            task_free(&task);
            continue;
        }
        split_choice split = {.axis = -1};
        bool found = task.count > 0 && task.depth < b->max_depth && find_best_split(&task, &split);
        bool worth_it = found && split.cost < KD_COST_INTERSECT * task.count &&
                        b->pending_references + split.below + split.above - task.count <= b->reference_cap;
        build_task child[2];
        if (worth_it && b->pending_references + split.below + split.above - task.count > b->peak_accepted)
            b->peak_accepted = b->pending_references + split.below + split.above - task.count;
        if (!worth_it) {
            make_leaf(b, &task);
            task_free(&task);
        } else if (classify(b, &task, split), split_task(b, &task, split, child)) {
            stack[top++] = child[1];
            stack[top++] = child[0];
        }
    }
}

/* ---- two subtrees on two threads ------------------------------------------- */

/* Below the root the two subtrees share nothing but the scene and the
 * records, so each is built by its own builder into its own arrays, one on
 * a second thread, and spliced behind the root.  The depth-first layout
 * puts every node, leaf and record of the left subtree before those of the
 * right one, so the splice gives the very bytes of a one-thread build.  One
 * decision depends on the order: the reference cap, checked against the
 * references pending over the whole tree.  The left subtree sees exactly
 * the count a one-thread build sees; the right one sees fewer (the left's
 * growth is not known yet), so when some split it accepted would not have
 * fitted under the left's final count, the tree is rebuilt on one thread.
 * Only hostile input gets near the cap. */

typedef struct subtree_job {
    builder b;
    kd_tree tree;
    build_task root;
} subtree_job;

static bool subtree_start(const builder *parent, build_task task, subtree_job *job)
{
    memset(job, 0, sizeof *job);
    job->b = (builder){.scene = parent->scene, .tree = &job->tree, .records = parent->records,
                       .max_depth = parent->max_depth, .reference_cap = parent->reference_cap,
                       .pending_references = parent->pending_references};
    job->b.side = malloc((size_t)parent->scene->triangle_count + 1);
    if (!job->b.side || !reserve((void **)&job->tree.nodes, &job->b.node_capacity, 1, sizeof *job->tree.nodes)) {
        free(job->b.side);
        free(job->tree.nodes);
        task_free(&task);
        return false;
    }
    memset(&job->tree.nodes[0], 0, sizeof job->tree.nodes[0]);
    job->tree.node_count = 1;
    task.node = 0;
    job->root = task;
    return true;
}

static void subtree_release(subtree_job *job)
{
    free(job->b.side);
    free(job->b.leaf_prims);
    free(job->b.scratch);
    kd_tree_free(&job->tree);
}

/* Task `task` of rtt_parallel_run: one of the two subtrees. */
static void subtree_build(void *jobs, uint32_t thread, uint32_t task)
{
    (void)thread;
    subtree_job *job = &((subtree_job *)jobs)[task];
    build_tree(&job->b, job->root);
}

/* Appends a subtree built as node `root_at` of the tree: its root goes to
 * root_at, its other nodes after the tree's, child and leaf indices moved. */
static bool splice(builder *b, const kd_tree *sub, uint32_t root_at)
{
    kd_tree *tree = b->tree;
    const uint32_t node_base = tree->node_count - 1u, leaf_base = tree->leaf_count;
    const uint32_t record_base = tree->triangle_count;
    const size_t nodes = (size_t)tree->node_count + sub->node_count, leaves = (size_t)tree->leaf_count + sub->leaf_count;
    const size_t records = (size_t)tree->triangle_count + sub->triangle_count;
    if (!reserve((void **)&tree->nodes, &b->node_capacity, nodes, sizeof *tree->nodes) ||
        !reserve((void **)&tree->leaves, &b->leaf_capacity, leaves + 1, sizeof *tree->leaves) ||
        !reserve((void **)&tree->triangles, &b->triangle_capacity, records + 1, sizeof *tree->triangles))
        return false;
    for (uint32_t i = 0; i < sub->node_count; i++) {
        kd_node node = sub->nodes[i];
        if (kd_node_is_leaf(&node)) node.leaf += leaf_base;
        else node.bits = ((kd_node_child(&node) + node_base) << 2) | kd_node_axis(&node);
        tree->nodes[i == 0 ? root_at : node_base + i] = node;
    }
    tree->node_count += sub->node_count - 1u;
    for (uint32_t l = 0; l < sub->leaf_count; l++) {
        tree->leaves[leaf_base + l] = sub->leaves[l];
        tree->leaves[leaf_base + l].first += record_base;
    }
    tree->leaf_count += sub->leaf_count;
    memcpy(tree->triangles + record_base, sub->triangles, (size_t)sub->triangle_count * sizeof *sub->triangles);
    tree->triangle_count += sub->triangle_count;
    if (sub->info.depth > tree->info.depth) tree->info.depth = sub->info.depth;
    tree->info.empty_leaf_count += sub->info.empty_leaf_count;
    return true;
}

/* Splits the root, then builds its two subtrees at once.  *split_here is
 * false when the root is not split that way (the root task is left for
 * build_tree); *redo when the result would differ from a one-thread build
 * (the tree is then to be rebuilt on one thread). */
static void build_tree_two_threads(builder *b, build_task *root, bool *split_here, bool *redo)
{
    *split_here = false;
    split_choice split = {.axis = -1};
    bool found = root->depth < b->max_depth && find_best_split(root, &split);
    if (!found || !(split.cost < KD_COST_INTERSECT * root->count) || split.below == 0 || split.above == 0 ||
        b->pending_references + split.below + split.above - root->count > b->reference_cap)
        return;
    *split_here = true;
    b->peak_accepted = b->pending_references + split.below + split.above - root->count;
    classify(b, root, split);
    build_task child[2];
    if (!split_task(b, root, split, child)) return; /* out of memory: b->out_of_memory, the root freed */
    subtree_job jobs[2];
    bool started[2] = {subtree_start(b, child[0], &jobs[0]), false};
    started[1] = subtree_start(b, child[1], &jobs[1]);
    bool ok = started[0] && started[1];
    if (ok) {
        rtt_parallel_run(2, 2, subtree_build, jobs);
    } else {
        for (int s = 0; s < 2; s++)
            if (started[s]) task_free(&jobs[s].root);
    }
    ok = ok && !jobs[0].b.out_of_memory && !jobs[1].b.out_of_memory;
    /* the right subtree's splits, under the references a one-thread build would have had pending */
    const uint64_t left_growth = jobs[0].b.pending_references - b->pending_references;
    if (ok && jobs[1].b.peak_accepted + left_growth > b->reference_cap) {
        *redo = true;
    } else if (ok) {
        ok = splice(b, &jobs[0].tree, 1) && splice(b, &jobs[1].tree, 2);
        b->sah_sum += jobs[0].b.sah_sum + jobs[1].b.sah_sum;
        b->pending_references = jobs[1].b.pending_references + left_growth;
    }
    if (!ok) b->out_of_memory = true;
    for (int s = 0; s < 2; s++)
        if (started[s]) subtree_release(&jobs[s]);
}

/* ---- the tree ------------------------------------------------------------ */

/* Records of every triangle and the root's events of those that have one. */
static bool root_task(const rtt_scene *scene, kd_triangle *records, build_task *root)
{
    const uint32_t n = scene->triangle_count;
    memset(root, 0, sizeof *root);
    kd_event *block = malloc((6 * (size_t)n + 1) * sizeof *block);
    if (!block) return false;
    for (int a = 0; a < 3; a++) root->events[a] = block + 2 * (size_t)n * a;
    root->box = rtt_bounds_empty();
    for (uint32_t i = 0; i < n; i++) {
        rtt_vec3 p[3];
        rtt_scene_triangle(scene, i, p);
        if (!rtt_v3_is_finite(p[0]) || !rtt_v3_is_finite(p[1]) || !rtt_v3_is_finite(p[2]) ||
            !kd_triangle_record(&records[i], p, i)) {
            memset(&records[i], 0, sizeof records[i]);
            continue;
        }
        rtt_bounds bounds = kd_triangle_bounds(p);
        push_events(root->events, root->event_count, bounds, i);
        root->box = rtt_bounds_union(root->box, bounds);
        root->count++;
    }
    for (int a = 0; a < 3; a++)
        if (!events_sort(root->events[a], root->event_count[a])) return false;
    return true;
}

void kd_tree_free(kd_tree *tree)
{
    free(tree->nodes);
    free(tree->leaves);
    free(tree->triangles);
    memset(tree, 0, sizeof *tree);
}

/* One build into `tree` (zeroed first): the root task, then the nodes, on
 * two threads when `threads` > 1 and the scene is big enough.  *redo is set
 * when the two-thread build must be redone on one thread (the cap). */
static bool build_once(builder *b, kd_triangle *records, const kd_build_options *opt, uint32_t threads, bool *redo)
{
    const rtt_scene *scene = b->scene;
    kd_tree *tree = b->tree;
    memset(tree, 0, sizeof *tree);
    *redo = false;
    b->node_capacity = b->leaf_capacity = b->triangle_capacity = 0;
    b->sah_sum = 0.0;
    b->peak_accepted = 0;
    b->out_of_memory = false;
    build_task root = {0};
    if (!root_task(scene, records, &root)) return false;
    const uint32_t n = root.count;
    b->max_depth = opt && opt->max_depth ? opt->max_depth : rtt_kd_default_max_depth(n);
    if (b->max_depth > KD_DEPTH_LIMIT) b->max_depth = KD_DEPTH_LIMIT;
    b->reference_cap = opt && opt->reference_cap ? opt->reference_cap : 16u * (uint64_t)scene->triangle_count + 1000000u;
    if (b->reference_cap < n) b->reference_cap = n; /* every triangle needs one reference */
    b->pending_references = n;
    tree->bounds = root.box;
    if (!reserve((void **)&tree->nodes, &b->node_capacity, 1, sizeof *tree->nodes)) {
        task_free(&root);
        return false;
    }
    memset(&tree->nodes[0], 0, sizeof tree->nodes[0]);
    tree->node_count = 1;
    bool split_here = false;
    if (threads > 1 && n >= KD_PARALLEL_MIN_TRIANGLES) {
        build_tree_two_threads(b, &root, &split_here, redo);
        if (*redo) return true;
    }
    if (!split_here) build_tree(b, root);
    return !b->out_of_memory;
}

bool kd_build_sah(const rtt_scene *scene, const kd_build_options *opt, kd_tree *tree, rtt_error *err)
{
    const uint64_t start = rtt_clock_ns();
    memset(tree, 0, sizeof *tree);
    if (scene->triangle_count >= KD_MAX_TRIANGLES)
        return rtt_error_set(err, "%s: %u triangles: the optimized kd-tree holds at most %u", scene->path,
                             scene->triangle_count, KD_MAX_TRIANGLES - 1u);
    builder b = {.scene = scene, .tree = tree};
    kd_triangle *records = malloc(((size_t)scene->triangle_count + 1) * sizeof *records);
    b.side = malloc((size_t)scene->triangle_count + 1);
    b.records = records;
    const uint32_t threads = opt && opt->threads ? opt->threads : rtt_cpu_count();
    bool redo = false;
    bool ok = records && b.side && build_once(&b, records, opt, threads, &redo);
    if (ok && redo) {
        kd_tree_free(tree);
        ok = build_once(&b, records, opt, 1, &redo);
    }
    free(records);
    free(b.side);
    free(b.leaf_prims);
    free(b.scratch);
    if (!ok) {
        kd_tree_free(tree);
        return rtt_error_set(err, "%s: out of memory building the kd-tree of %u triangles", scene->path,
                             scene->triangle_count);
    }

    rtt_tree_info *info = &tree->info;
    const double root_area = box_area(tree->bounds);
    info->max_depth = b.max_depth;
    info->node_count = tree->node_count;
    info->leaf_count = tree->leaf_count;
    info->references = tree->triangle_count;
    info->reference_cap = b.reference_cap;
    info->sah_cost = root_area > 0.0 ? b.sah_sum / root_area : KD_COST_INTERSECT * (double)tree->triangle_count;
    info->memory_bytes = (uint64_t)tree->node_count * sizeof(kd_node) + (uint64_t)tree->leaf_count * sizeof(kd_leaf) +
                         (uint64_t)tree->triangle_count * sizeof(kd_triangle);
    info->build_seconds = 1e-9 * (double)(rtt_clock_ns() - start);
    return true;
}

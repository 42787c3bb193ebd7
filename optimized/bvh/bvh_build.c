/* Binned SAH BVH construction (Wald 2007, "On fast construction of SAH-based
 * bounding volume hierarchies", section 3: centroid binning, one sweep over
 * the bins per axis), the structure Benthin & Wald 2009 trace with multiple
 * frusta.
 *
 * Per node: the triangles' box centroids are put into BVH_BINS bins along
 * each axis of the centroid bounds; a sweep over the bins' counts and boxes
 * gives every plane's cost
 *   C = C_trav + C_isect * (N_L * SA_L + N_R * SA_R) / SA   (C_trav = C_isect = 1),
 * and the cheapest plane splits the node unless a leaf, C_isect * N, is no
 * dearer and N fits in a leaf (options.leaf_size).  A node with more than
 * leaf_size triangles is always split (at the median of its order when
 * every centroid coincides); at options.max_depth a node is a leaf whatever
 * it holds.  Areas and bin positions are computed in double, so scenes at
 * 1e-20 or 1e20 bin as well as at 1.
 *
 * Threads (engine/threads.h): the top of the tree is split breadth-first on
 * the calling thread until there are BVH_TASKS_PER_THREAD subtrees per
 * thread; the subtrees are then built as independent tasks of
 * rtt_parallel_run.  Subtree i owns the node slots of its triangle range
 * (a subtree of n triangles has at most n - 1 inner nodes), so no slot is
 * shared and the build is the same for any thread count.  A last
 * depth-first pass copies the nodes into their final array (children after
 * their parent, the left subtree first) and the records into leaf order.
 *
 * What it trades: binning rather than a full sweep over sorted centroids
 * (Wald 2007: within a few percent of the full SAH at a fraction of the
 * time); the top levels' binning is serial. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_build.h"
#include "engine/clock.h"
#include "engine/threads.h"
#include "isect_projected_bary.h"

#define BVH_BINS 32u
#define BVH_TASKS_PER_THREAD 8u
/* Nodes smaller than this are not worth a task of their own. */
#define BVH_TASK_MIN_TRIANGLES 4096u

typedef struct box3 {
    float lo[3], hi[3];
} box3;

static void box_empty(box3 *b)
{
    for (int k = 0; k < 3; k++) b->lo[k] = INFINITY, b->hi[k] = -INFINITY;
}

static void box_grow(box3 *b, const box3 *o)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = o->lo[k] < b->lo[k] ? o->lo[k] : b->lo[k];
        b->hi[k] = o->hi[k] > b->hi[k] ? o->hi[k] : b->hi[k];
    }
}

static double box_half_area(const box3 *b)
{
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = b->hi[k] > b->lo[k] ? (double)b->hi[k] - (double)b->lo[k] : 0.0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static double centroid(const box3 *b, int k) { return 0.5 * ((double)b->lo[k] + (double)b->hi[k]); }

typedef struct builder {
    const box3 *boxes;         /* per record */
    uint32_t *ids;             /* record indices, partitioned node by node */
    bvh_node *slots;           /* inner nodes before the compaction */
    uint32_t leaf_size, max_depth;
} builder;

/* What the builder decided for a range: a leaf, or a split at `mid`. */
typedef struct split_choice {
    bool leaf;
    uint32_t mid;
} split_choice;

static void range_bounds(const builder *b, uint32_t begin, uint32_t end, box3 *bounds, double clo[3], double chi[3])
{
    box_empty(bounds);
    for (int k = 0; k < 3; k++) clo[k] = INFINITY, chi[k] = -INFINITY;
    for (uint32_t i = begin; i < end; i++) {
        const box3 *p = &b->boxes[b->ids[i]];
        box_grow(bounds, p);
        for (int k = 0; k < 3; k++) {
            double c = centroid(p, k);
            clo[k] = c < clo[k] ? c : clo[k];
            chi[k] = c > chi[k] ? c : chi[k];
        }
    }
}

static uint32_t bin_of(double c, double lo, double scale)
{
    double f = (c - lo) * scale;
    if (!(f > 0.0)) return 0;
    return f >= (double)(BVH_BINS - 1) ? BVH_BINS - 1 : (uint32_t)f;
}

/* Partitions [begin, end) by the node's choice and says where it split. */
static split_choice choose_split(const builder *b, uint32_t begin, uint32_t end, uint32_t depth, box3 *bounds)
{
    const uint32_t n = end - begin;
    double clo[3], chi[3];
    range_bounds(b, begin, end, bounds, clo, chi);
    if (n <= 1 || depth >= b->max_depth) return (split_choice){true, 0};

    double best_cost = INFINITY;
    int best_axis = -1;
    uint32_t best_bin = 0;
    double best_scale = 0.0;
    for (int k = 0; k < 3; k++) {
        const double extent = chi[k] - clo[k];
        if (!(extent > 0.0) || !isfinite(extent)) continue;
        const double scale = (double)BVH_BINS / extent;
        uint32_t counts[BVH_BINS] = {0};
        box3 bins[BVH_BINS];
        for (uint32_t j = 0; j < BVH_BINS; j++) box_empty(&bins[j]);
        for (uint32_t i = begin; i < end; i++) {
            const box3 *p = &b->boxes[b->ids[i]];
            uint32_t j = bin_of(centroid(p, k), clo[k], scale);
            counts[j]++;
            box_grow(&bins[j], p);
        }
        /* right-to-left sweep of the area-weighted counts, then left to right */
        double right_cost[BVH_BINS];
        box3 acc;
        box_empty(&acc);
        uint32_t count = 0;
        for (uint32_t j = BVH_BINS - 1; j > 0; j--) {
            box_grow(&acc, &bins[j]);
            count += counts[j];
            right_cost[j] = count ? (double)count * box_half_area(&acc) : 0.0;
        }
        box_empty(&acc);
        count = 0;
        for (uint32_t j = 0; j + 1 < BVH_BINS; j++) {
            box_grow(&acc, &bins[j]);
            count += counts[j];
            if (count == 0 || count == n) continue;
            double cost = (double)count * box_half_area(&acc) + right_cost[j + 1];
            if (cost < best_cost) best_cost = cost, best_axis = k, best_bin = j, best_scale = scale;
        }
    }
    const double area = box_half_area(bounds);
    /* C_trav + (N_L SA_L + N_R SA_R) / SA against the leaf's N (in units of C_isect) */
    const bool leaf_cheaper = best_axis < 0 || !(area > 0.0) || 1.0 + best_cost / area >= (double)n;
    if (n <= b->leaf_size && leaf_cheaper) return (split_choice){true, 0};

    uint32_t mid;
    if (best_axis < 0) {
        mid = begin + n / 2; /* every centroid coincides: halve the order */
    } else {
        uint32_t i = begin, j = end;
        while (i < j) {
            if (bin_of(centroid(&b->boxes[b->ids[i]], best_axis), clo[best_axis], best_scale) <= best_bin) {
                i++;
            } else {
                uint32_t t = b->ids[i];
                b->ids[i] = b->ids[--j];
                b->ids[j] = t;
            }
        }
        mid = i;
    }
    return (split_choice){false, mid};
}

static void set_box(bvh_child *c, const box3 *bounds)
{
    memcpy(c->lo, bounds->lo, sizeof c->lo);
    memcpy(c->hi, bounds->hi, sizeof c->hi);
}

/* Builds [begin, end) into `out`, inner nodes from slot *next on. */
static void build_subtree(const builder *b, uint32_t begin, uint32_t end, uint32_t depth, bvh_child *out,
                          uint32_t *next)
{
    box3 bounds;
    split_choice s = choose_split(b, begin, end, depth, &bounds);
    set_box(out, &bounds);
    if (s.leaf) {
        out->index = begin;
        out->count = end - begin;
        return;
    }
    const uint32_t slot = (*next)++;
    out->index = slot;
    out->count = 0;
    build_subtree(b, begin, s.mid, depth + 1, &b->slots[slot].child[0], next);
    build_subtree(b, s.mid, end, depth + 1, &b->slots[slot].child[1], next);
}

/* A subtree left for a task: its range and where its reference goes. */
typedef struct subtree_task {
    uint32_t begin, end, depth;
    bvh_child *out;
} subtree_task;

typedef struct task_context {
    const builder *b;
    const subtree_task *tasks;
    uint32_t slot_base;
} task_context;

static void run_subtree_task(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    const task_context *c = context;
    const subtree_task *t = &c->tasks[task];
    uint32_t next = c->slot_base + t->begin;
    build_subtree(c->b, t->begin, t->end, t->depth, t->out, &next);
}

/* The final layout: depth first, children after their parent. */
typedef struct compactor {
    const builder *b;
    const kd_triangle *records;
    bvh_tree *tree;
    uint32_t next_node, next_record;
    uint32_t depth, leaves, empty;
    double sah;
} compactor;

/* A stored box is the exact box grown by 1e-4 of its extent and four
 * ulps of its largest coordinate (and FLT_MIN): a flat box gets a thickness,
 * so a ray running in its plane is inside rather than at 0 * inf, and the
 * kernels' rounded slab distances never clip a hit on the box's face. */
static void widen(bvh_child *c)
{
    float scale = 0.0f, extent = 0.0f;
    for (int k = 0; k < 3; k++) {
        scale = fmaxf(scale, fmaxf(fabsf(c->lo[k]), fabsf(c->hi[k])));
        extent = fmaxf(extent, c->hi[k] - c->lo[k]);
    }
    const float margin = extent * 1e-4f + scale * 0x1p-21f + FLT_MIN;
    for (int k = 0; k < 3; k++) c->lo[k] -= margin, c->hi[k] += margin;
}

static void compact(compactor *c, const bvh_child *src, bvh_child *dst, uint32_t depth, double root_area)
{
    *dst = *src;
    widen(dst);
    box3 box;
    memcpy(box.lo, src->lo, sizeof box.lo);
    memcpy(box.hi, src->hi, sizeof box.hi);
    const double weight = root_area > 0.0 ? box_half_area(&box) / root_area : 1.0;
    if (src->count > 0) {
        dst->index = c->next_record;
        for (uint32_t i = 0; i < src->count; i++)
            c->tree->triangles[c->next_record++] = c->records[c->b->ids[src->index + i]];
        c->depth = depth > c->depth ? depth : c->depth;
        c->leaves++;
        c->sah += weight * (double)src->count;
        return;
    }
    const uint32_t slot = c->next_node++;
    dst->index = slot;
    c->sah += weight;
    const bvh_node *node = &c->b->slots[src->index];
    compact(c, &node->child[0], &c->tree->nodes[slot].child[0], depth + 1, root_area);
    compact(c, &node->child[1], &c->tree->nodes[slot].child[1], depth + 1, root_area);
}

void bvh_tree_free(bvh_tree *tree)
{
    free(tree->nodes);
    free(tree->triangles);
    memset(tree, 0, sizeof *tree);
}

bool bvh_build_sah(const rtt_scene *scene, const bvh_build_options *options, bvh_tree *tree, rtt_error *err)
{
    const double start = rtt_clock_seconds();
    memset(tree, 0, sizeof *tree);
    builder b = {0};
    b.leaf_size = options->leaf_size ? options->leaf_size : BVH_DEFAULT_LEAF_SIZE;
    if (b.leaf_size > BVH_LEAF_SIZE_MAX) b.leaf_size = BVH_LEAF_SIZE_MAX;
    b.max_depth = options->max_depth && options->max_depth < BVH_DEPTH_LIMIT ? options->max_depth : BVH_DEPTH_LIMIT;
    const uint32_t threads = rtt_thread_count(options->threads);

    const uint32_t n_tri = scene->triangle_count;
    kd_triangle *records = malloc((size_t)(n_tri ? n_tri : 1) * sizeof *records);
    box3 *boxes = malloc((size_t)(n_tri ? n_tri : 1) * sizeof *boxes);
    uint32_t *ids = malloc((size_t)(n_tri ? n_tri : 1) * sizeof *ids);
    uint32_t n = 0;
    if (records && boxes && ids)
        for (uint32_t i = 0; i < n_tri; i++) {
            rtt_vec3 p[3];
            rtt_scene_triangle(scene, i, p);
            if (!kd_triangle_record(&records[n], p, i)) continue;
            box3 *bx = &boxes[n];
            bx->lo[0] = fminf(p[0].x, fminf(p[1].x, p[2].x)), bx->hi[0] = fmaxf(p[0].x, fmaxf(p[1].x, p[2].x));
            bx->lo[1] = fminf(p[0].y, fminf(p[1].y, p[2].y)), bx->hi[1] = fmaxf(p[0].y, fmaxf(p[1].y, p[2].y));
            bx->lo[2] = fminf(p[0].z, fminf(p[1].z, p[2].z)), bx->hi[2] = fmaxf(p[0].z, fmaxf(p[1].z, p[2].z));
            ids[n] = n;
            n++;
        }
    const uint32_t top_slots = 2u * BVH_TASKS_PER_THREAD * threads + 2u;
    bvh_node *slots = records && boxes && ids ? malloc(((size_t)top_slots + n) * sizeof *slots) : NULL;
    subtree_task *tasks = slots ? malloc((size_t)(BVH_TASKS_PER_THREAD * threads + 2u) * sizeof *tasks) : NULL;
    if (!tasks) goto out_of_memory;
    b.boxes = boxes, b.ids = ids, b.slots = slots;

    /* the top, breadth first on this thread, until there are enough subtrees */
    uint32_t task_count = 0, next_top = 0;
    if (n > 0) tasks[task_count++] = (subtree_task){0, n, 0, &tree->root};
    const uint32_t want = threads > 1 ? BVH_TASKS_PER_THREAD * threads : 1;
    while (task_count > 0 && task_count < want) {
        uint32_t largest = 0;
        for (uint32_t i = 1; i < task_count; i++)
            if (tasks[i].end - tasks[i].begin > tasks[largest].end - tasks[largest].begin) largest = i;
        subtree_task t = tasks[largest];
        if (t.end - t.begin < BVH_TASK_MIN_TRIANGLES) break;
        box3 bounds;
        split_choice s = choose_split(&b, t.begin, t.end, t.depth, &bounds);
        if (s.leaf) break; /* the largest is a leaf (depth bound): the rest are smaller */
        set_box(t.out, &bounds);
        const uint32_t slot = next_top++;
        t.out->index = slot;
        t.out->count = 0;
        tasks[largest] = (subtree_task){t.begin, s.mid, t.depth + 1, &slots[slot].child[0]};
        tasks[task_count++] = (subtree_task){s.mid, t.end, t.depth + 1, &slots[slot].child[1]};
    }
    task_context context = {&b, tasks, top_slots};
    rtt_parallel_run(task_count, threads, run_subtree_task, &context);

    /* count the inner nodes reached from the root, then lay them out */
    tree->triangles = malloc((size_t)(n ? n : 1) * sizeof *tree->triangles);
    tree->nodes = malloc(((size_t)(n ? n : 1)) * sizeof *tree->nodes);
    if (!tree->triangles || !tree->nodes) goto out_of_memory;
    compactor c = {.b = &b, .records = records, .tree = tree};
    if (n > 0) {
        box3 root_box;
        memcpy(root_box.lo, tree->root.lo, sizeof root_box.lo);
        memcpy(root_box.hi, tree->root.hi, sizeof root_box.hi);
        bvh_child root = tree->root;
        compact(&c, &root, &tree->root, 0, box_half_area(&root_box));
    }
    tree->node_count = c.next_node;
    tree->triangle_count = c.next_record;
    if (tree->node_count > 0) {
        bvh_node *shrunk = realloc(tree->nodes, (size_t)tree->node_count * sizeof *tree->nodes);
        if (shrunk) tree->nodes = shrunk;
    }
    free(records), free(boxes), free(ids), free(slots), free(tasks);

    rtt_tree_info *info = &tree->info;
    info->depth = c.depth;
    info->max_depth = b.max_depth;
    info->node_count = tree->node_count + c.leaves; /* inner nodes and leaves, as the kd-tree counts them */
    info->leaf_count = c.leaves;
    info->references = tree->triangle_count;
    info->reference_cap = tree->triangle_count;
    info->sah_cost = c.sah;
    info->memory_bytes = (uint64_t)tree->node_count * sizeof(bvh_node) +
                         (uint64_t)tree->triangle_count * sizeof(kd_triangle);
    info->build_seconds = rtt_clock_seconds() - start;
    return true;

out_of_memory:
    free(records), free(boxes), free(ids), free(slots), free(tasks);
    bvh_tree_free(tree);
    return rtt_error_set(err, "%s: out of memory building the BVH (%u triangles)", scene->path, n_tri);
}

/* Thesis chapter 5, Listing 5.1, written for obviousness: instead of
 * visiting leaves front to back and pairing as it goes, the reference finds
 * every crossing of the segment at once and then pairs them in order.
 *
 *   1. descend the tree into every child whose box the segment touches (a
 *      slab test widened by a margin relative to the scene, so rounding
 *      never drops a cell; visiting extra cells only costs time);
 *   2. in each leaf, the watertight test (both faces, tnear < t < tfar);
 *      a triangle duplicated in several leaves is kept once;
 *   3. sort by (t, prim) and feed the shared pairing (rtt/edge_width.h).
 *
 * The optimized version pairs leaf by leaf with an early exit; since the
 * occlusion only ever rises to 1 once decided, both give the same result
 * for the same crossings. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "edge_width_reference.h"
#include "isect_watertight.h"

typedef struct crossing {
    float t;
    uint32_t prim;
} crossing;

typedef struct collector {
    const rtt_kd_tree *tree;
    const rtt_ray *ray;
    rtt_watertight_ray prepared;
    float margin;
    crossing *items;
    size_t count, capacity;
    bool failed;
} collector;

/* Does the segment [tnear, tfar] of the ray touch box (grown by margin)? */
static bool segment_touches(const collector *c, rtt_bounds box)
{
    float tn = c->ray->tnear, tf = c->ray->tfar;
    for (int a = 0; a < 3; a++) {
        float o = c->ray->org[a], d = c->ray->dir[a];
        float lo = rtt_v3_get(box.lo, a) - c->margin, hi = rtt_v3_get(box.hi, a) + c->margin;
        if (d == 0.0f) {
            if (o < lo || o > hi) return false;
            continue;
        }
        float t0 = (lo - o) / d, t1 = (hi - o) / d;
        float near = fminf(t0, t1), far = fmaxf(t0, t1);
        /* a few ulps of slack on the crossings themselves */
        tn = fmaxf(tn, near - 8.0f * FLT_EPSILON * fabsf(near));
        tf = fminf(tf, far + 8.0f * FLT_EPSILON * fabsf(far));
    }
    return tn <= tf;
}

static bool already_found(const collector *c, uint32_t prim)
{
    for (size_t i = 0; i < c->count; i++)
        if (c->items[i].prim == prim) return true;
    return false;
}

static void add_crossing(collector *c, float t, uint32_t prim)
{
    if (already_found(c, prim)) return;
    if (c->count == c->capacity) {
        size_t capacity = c->capacity ? 2 * c->capacity : 32;
        crossing *grown = realloc(c->items, capacity * sizeof *grown);
        if (!grown) {
            c->failed = true;
            return;
        }
        c->items = grown;
        c->capacity = capacity;
    }
    c->items[c->count++] = (crossing){t, prim};
}

static void collect(collector *c, uint32_t index, rtt_bounds box)
{
    const rtt_kd_node *node = &c->tree->nodes[index];
    if (node->axis == RTT_KD_LEAF) {
        for (uint32_t i = 0; i < node->count; i++) {
            uint32_t prim = c->tree->prims[node->first + i];
            float t, u, v;
            if (rtt_watertight_intersect(&c->prepared, c->tree->triangles[prim], &t, &u, &v))
                add_crossing(c, t, prim);
        }
        return;
    }
    rtt_bounds below = box, above = box;
    rtt_v3_set(&below.hi, (int)node->axis, node->split);
    rtt_v3_set(&above.lo, (int)node->axis, node->split);
    if (segment_touches(c, below)) collect(c, node->children[0], below);
    if (segment_touches(c, above)) collect(c, node->children[1], above);
}

static int compare_crossings(const void *pa, const void *pb)
{
    const crossing *a = pa, *b = pb;
    if (a->t != b->t) return a->t < b->t ? -1 : 1;
    return a->prim < b->prim ? -1 : a->prim > b->prim;
}

static bool ray_is_usable(const rtt_ray *ray)
{
    for (int a = 0; a < 3; a++)
        if (!isfinite(ray->org[a]) || !isfinite(ray->dir[a])) return false;
    return ray->tnear < ray->tfar && (ray->dir[0] != 0.0f || ray->dir[1] != 0.0f || ray->dir[2] != 0.0f);
}

float rtt_edge_width_reference(const rtt_kd_tree *tree, const rtt_edge_width_model *model, const rtt_ray *ray,
                               float *max_width)
{
    rtt_edge_width_state state;
    rtt_edge_width_start(&state, ray->dir);
    if (max_width) *max_width = 0.0f;
    if (!ray_is_usable(ray) || rtt_bounds_is_empty(tree->bounds)) return 0.0f;

    rtt_vec3 extent = rtt_v3_sub(tree->bounds.hi, tree->bounds.lo);
    collector c = {.tree = tree, .ray = ray};
    c.margin = 1e-5f * fmaxf(extent.x, fmaxf(extent.y, extent.z)) + FLT_MIN;
    rtt_watertight_ray_setup(ray, &c.prepared);
    if (segment_touches(&c, tree->bounds)) collect(&c, 0, tree->bounds);
    if (c.failed) { /* out of memory: the conservative answer */
        free(c.items);
        return 1.0f;
    }
    if (c.count > 1) qsort(c.items, c.count, sizeof *c.items, compare_crossings); /* items is NULL when empty */
    for (size_t i = 0; i < c.count; i++)
        if (rtt_edge_width_feed(model, &state, c.items[i].t, c.items[i].prim)) break;
    free(c.items);
    if (max_width) *max_width = state.max_width;
    return rtt_edge_width_finish(model, &state);
}

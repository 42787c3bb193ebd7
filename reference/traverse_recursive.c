/* Thesis Listing 2.1: recursive kd-tree traversal, closest hit and occlusion.
 *
 * The ray is first clipped to the root box (slab test).  At an inner node the
 * ray's interval [tn, tf] is split at the plane crossing t = dist into the
 * near and the far child, as in the listing.  Two changes make it exact
 * rather than usually right:
 *
 * 1. Conservative cells.  dist is only known up to rounding, and the
 *    watertight test sees a ray sheared with rounding too; so the crossing is
 *    widened to [dist - err, dist + err] with err a relative bound (see
 *    crossing_error), and a child is skipped only when the whole widened
 *    crossing lies outside the interval.  A ray parallel to the plane
 *    (dir[axis] == +0 or -0) visits the side its origin is on, both sides
 *    when the origin lies in the plane.
 *
 * 2. The correctness rule.  A hit found in a leaf may lie in a later cell (a
 *    triangle spanning several cells is tested in each).  Listing 2.1 drops
 *    hits outside [tn, tf]; we keep every hit as a candidate (closest t, ties
 *    to the smaller prim index) and call it final only once the traversal has
 *    passed every cell that could hold a closer one: the far child is skipped
 *    only when the candidate's t is below the earliest point where the far
 *    cell can begin (dist - err).  So a hit on a split plane is never lost to
 *    rounding, and the result is the brute-force closest hit.
 *
 * NaN or infinite rays, and zero directions, miss without entering the tree.
 * The recursion depth is the tree depth (at most RTT_KD_DEPTH_LIMIT). */
#include <float.h>
#include <math.h>

#include "isect_watertight.h"
#include "kd_reference.h"

typedef struct traversal {
    const rtt_kd_tree *tree;
    const rtt_ray *ray;
    rtt_watertight_ray prepared;
    float dir_max;    /* largest |dir| component */
    bool any_hit;     /* occlusion: stop at the first hit */
    bool occluded;
    rtt_hit *closest; /* closest-hit queries */
} traversal;

static bool ray_is_valid(const rtt_ray *ray)
{
    for (int a = 0; a < 3; a++)
        if (!isfinite(ray->org[a]) || !isfinite(ray->dir[a])) return false;
    if (isnan(ray->tnear) || isnan(ray->tfar)) return false;
    return ray->dir[0] != 0.0f || ray->dir[1] != 0.0f || ray->dir[2] != 0.0f;
}

/* A bound on how far the true crossing of the plane, and the crossing of
 * the ray the watertight test effectively traces, can be from the computed
 * dist: a few ulps of dist, magnified by how grazing the ray is to the plane
 * (a ray off by delta in space is off by delta / |dir[axis]| in t). */
static float crossing_error(const traversal *tr, float dist, float dir_axis)
{
    return 16.0f * FLT_EPSILON * fabsf(dist) * (1.0f + tr->dir_max / fabsf(dir_axis));
}

/* Widened crossing of the plane `position` on `axis`; [-inf, inf] when it
 * cannot be computed (a dir component so small the division overflows). */
static void plane_crossing(const traversal *tr, int axis, float position, float *lo, float *hi)
{
    const float d = tr->ray->dir[axis];
    const float dist = (position - tr->ray->org[axis]) / d;
    const float err = crossing_error(tr, dist, d);
    *lo = dist - err;
    *hi = dist + err;
    if (!(*lo <= *hi) || isinf(dist)) {
        *lo = -INFINITY;
        *hi = INFINITY;
    }
}

/* Slab test against the root box, widened like the inner crossings. */
static bool clip_to_root(const traversal *tr, float *tn, float *tf)
{
    const rtt_bounds box = tr->tree->bounds;
    if (rtt_bounds_is_empty(box)) return false;
    *tn = tr->ray->tnear;
    *tf = tr->ray->tfar;
    for (int a = 0; a < 3; a++) {
        const float o = tr->ray->org[a], lo = rtt_v3_get(box.lo, a), hi = rtt_v3_get(box.hi, a);
        if (tr->ray->dir[a] == 0.0f) { /* +0 and -0 alike: parallel to the slab */
            if (o < lo || o > hi) return false;
            continue;
        }
        float lo_min, lo_max, hi_min, hi_max;
        plane_crossing(tr, a, lo, &lo_min, &lo_max);
        plane_crossing(tr, a, hi, &hi_min, &hi_max);
        *tn = fmaxf(*tn, fminf(lo_min, hi_min));
        *tf = fminf(*tf, fmaxf(lo_max, hi_max));
    }
    return *tn <= *tf;
}

static void test_leaf(traversal *tr, const rtt_kd_node *leaf)
{
    const rtt_kd_tree *tree = tr->tree;
    for (uint32_t i = 0; i < leaf->count; i++) {
        const uint32_t prim = tree->prims[leaf->first + i];
        float t, u, v;
        if (!rtt_watertight_intersect(&tr->prepared, tree->triangles[prim], &t, &u, &v)) continue;
        if (tr->any_hit) {
            tr->occluded = true;
            return;
        }
        rtt_hit *best = tr->closest;
        if (t < best->t || (t == best->t && prim < best->prim)) *best = (rtt_hit){t, u, v, prim};
    }
}

/* True when nothing at or beyond t can change the answer any more. */
static bool finished_before(const traversal *tr, float t)
{
    return tr->any_hit ? tr->occluded : tr->closest->t < t;
}

static void visit(traversal *tr, uint32_t index, float tn, float tf)
{
    if (finished_before(tr, tn)) return;
    const rtt_kd_node *node = &tr->tree->nodes[index];
    if (node->axis == RTT_KD_LEAF) {
        test_leaf(tr, node);
        return;
    }
    const int axis = (int)node->axis;
    const float origin = tr->ray->org[axis], dir = tr->ray->dir[axis];
    const uint32_t below = node->children[0], above = node->children[1];

    if (dir == 0.0f) {
        if (origin < node->split) {
            visit(tr, below, tn, tf);
        } else if (origin > node->split) {
            visit(tr, above, tn, tf);
        } else { /* in the plane: both sides hold triangles it can hit */
            visit(tr, below, tn, tf);
            visit(tr, above, tn, tf);
        }
        return;
    }

    const uint32_t near = dir > 0.0f ? below : above, far = dir > 0.0f ? above : below;
    float cross_lo, cross_hi;
    plane_crossing(tr, axis, node->split, &cross_lo, &cross_hi);
    if (cross_lo > tf) {
        visit(tr, near, tn, tf);
    } else if (cross_hi < tn) {
        visit(tr, far, tn, tf);
    } else {
        visit(tr, near, tn, fminf(tf, cross_hi));
        if (!finished_before(tr, cross_lo)) visit(tr, far, fmaxf(tn, cross_lo), tf);
    }
}

static void traverse(traversal *tr)
{
    float tn, tf;
    if (!ray_is_valid(tr->ray) || !clip_to_root(tr, &tn, &tf)) return;
    rtt_watertight_ray_setup(tr->ray, &tr->prepared);
    tr->dir_max = fmaxf(fabsf(tr->ray->dir[0]), fmaxf(fabsf(tr->ray->dir[1]), fabsf(tr->ray->dir[2])));
    visit(tr, 0, tn, tf);
}

void rtt_kd_reference_intersect(const rtt_kd_tree *tree, const rtt_ray *ray, rtt_hit *hit)
{
    *hit = (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS};
    traversal tr = {.tree = tree, .ray = ray, .closest = hit};
    traverse(&tr);
}

bool rtt_kd_reference_occluded(const rtt_kd_tree *tree, const rtt_ray *ray)
{
    traversal tr = {.tree = tree, .ray = ray, .any_hit = true};
    traverse(&tr);
    return tr.occluded;
}

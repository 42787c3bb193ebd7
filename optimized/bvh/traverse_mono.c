/* One ray at a time through the BVH: the classic ordered depth-first walk
 * (Kay & Kajiya's slab test on both children's boxes of a node, the nearer
 * child first, the other on a stack with its entry distance), for arbitrary
 * rays: the reference point of the packet and frusta kernels and what the
 * engine's single rays could use.  The leaf test is the scalar form of the
 * test the tree names (bvh_isect_wide.h, bvh_isect1_record: the projected
 * or the watertight test of optimized/isect/), so a ray gets the same bits
 * as through the packet kernel's lanes.
 *
 * What it trades: no SIMD across rays; the two boxes are tested one after
 * the other in scalar code. */
#include <math.h>

#include "bvh_isa.h"
#include "bvh_kernels.h"
#include "bvh_isect_wide.h"
#include "bvh_packet.h"

/* The entry distance of the ray's interval [t0, t1] into the box, or NaN
 * when it misses.  A NaN slab (0 * inf: a ray in a face's plane) leaves the
 * interval as it is; the interval is tested with t1 moved out by
 * BVH_SLAB_SLACK of itself (bvh_simd.h: the slab distances' rounding). */
static inline float slab1(const bvh_child *c, const float org[3], const float inv[3], float t0, float t1)
{
    for (int k = 0; k < 3; k++) {
        const float a = (c->lo[k] - org[k]) * inv[k], b = (c->hi[k] - org[k]) * inv[k];
        const float lo = a < b ? a : b, hi = a < b ? b : a;
        t0 = lo > t0 ? lo : t0;
        t1 = hi < t1 ? hi : t1;
    }
    const float up = t1 * (1.0f + BVH_SLAB_SLACK), down = t1 * (1.0f - BVH_SLAB_SLACK);
    const float grown = up > down ? up : down; /* not fmaxf: a call into libm per box (both NaN or neither) */
    return t0 <= grown ? t0 : NAN;
}

typedef struct mono_entry {
    const bvh_child *child;
    float entry;
} mono_entry;

/* Closest hit (hit non-NULL) or any hit; true when something was hit. */
static bool trace1(const bvh_tree *tree, const kd_ray1 *ray, kd_hit1 *hit, bvh_counters *counters)
{
    float inv[3];
    for (int k = 0; k < 3; k++) inv[k] = 1.0f / ray->dir[k];
    wt_ray1 shear = {0};
    if (tree->watertight) wt_ray1_setup(&shear, ray);
    mono_entry stack[BVH_TRAVERSAL_STACK];
    uint32_t top = 0;
    float tfar = ray->tfar;
    const float entry = slab1(&tree->root, ray->org, inv, ray->tnear, tfar);
    if (counters) counters->aabb_tests++;
    if (!(entry == entry)) return false;
    const bvh_child *c = &tree->root;
    bool any = false;
    for (;;) {
        while (c->count == 0) {
            const bvh_node *node = &tree->nodes[c->index];
            const float e0 = slab1(&node->child[0], ray->org, inv, ray->tnear, tfar);
            const float e1 = slab1(&node->child[1], ray->org, inv, ray->tnear, tfar);
            if (counters) counters->aabb_tests += 2;
            const bool h0 = e0 == e0, h1 = e1 == e1;
            if (h0 && h1) {
                const int near = e1 < e0;
                if (top < BVH_TRAVERSAL_STACK)
                    stack[top++] = (mono_entry){&node->child[!near], near ? e0 : e1};
                c = &node->child[near];
            } else if (h0 || h1) {
                c = &node->child[h1];
            } else {
                goto pop;
            }
        }
        for (uint32_t i = 0; i < c->count; i++) {
            if (counters) counters->triangles++, counters->isect_tests++;
            if (!hit) {
                if (bvh_isect1_record(tree, c->index + i, ray, &shear, NULL)) return true;
                continue;
            }
            const uint32_t before = hit->prim;
            const float t_before = hit->t;
            bvh_isect1_record(tree, c->index + i, ray, &shear, hit);
            if (hit->prim != before || hit->t != t_before) any = true, tfar = hit->t < tfar ? hit->t : tfar;
        }
    pop:
        for (;;) {
            if (top == 0) return any;
            const mono_entry e = stack[--top];
            if (e.entry <= tfar) {
                c = e.child;
                break;
            }
        }
    }
}

void bvh_kernel_mono(const bvh_tree *tree, const bvh_query *q)
{
    for (size_t i = 0; i < q->count; i++) {
        const rtt_ray *r = &q->rays[i];
        kd_hit1 hit = {INFINITY, 0.0f, 0.0f, RTT_MISS};
        bool found = false;
        if (q->counters) q->counters->packets++;
        if (ray_is_traceable(r) && r->tnear <= r->tfar && tree->triangle_count > 0) {
            const kd_ray1 ray = {{r->org[0], r->org[1], r->org[2]}, {r->dir[0], r->dir[1], r->dir[2]}, r->tnear,
                                 r->tfar};
            found = trace1(tree, &ray, q->hits ? &hit : NULL, q->counters);
        }
        if (q->hits)
            q->hits[i] = hit.prim == RTT_MISS ? (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS}
                                              : (rtt_hit){hit.t, hit.u, hit.v, hit.prim};
        else
            q->occluded[i] = found;
    }
}

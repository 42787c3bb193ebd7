/* Thesis Listing 2.2: iterative kd-tree traversal of one ray with an
 * explicit stack of (node, tnear, tfar) tasks.
 *
 * The lanes of each packet are traced one after the other in scalar code
 * with the scalar twin of the projected barycentric test.  The near child is
 * chosen by the sign bit of the direction (a -0.0 component counts as
 * negative, which is what its inv_dir of -inf needs), and the far child is
 * pushed only when the ray reaches the plane inside its interval.
 *
 * Differences from the listing, all for arbitrary rays (traverse_ray.h):
 * the listing returns at the first leaf with a hit inside the cell; here a
 * hit anywhere on the ray is kept and the stack is popped until the next
 * task starts past the best hit, which gives the same result without
 * trusting the cell interval to the last ulp; the split distance is widened
 * and compared inclusively; tnear may be negative (no "dist < 0" test).
 *
 * Trades: no SIMD in traversal (one node fetch per ray per step), so it is
 * the slowest kernel on coherent rays and the baseline of the counters:
 * steps and isects are per ray, summed over the four rays of a packet, so
 * N and I are per 2x2 packet like the other kernels' (leaf_culling is
 * ignored: there is no packet to cull). */
#include <math.h>
#include <stdint.h>

#include "kernels.h"
#include "traverse_ray.h"
#include "isect_leaf.h"

/* 12 bytes: a subtree and the ray's interval in it. */
typedef struct mono_task {
    uint32_t node;
    float near, far;
} mono_task;
_Static_assert(sizeof(mono_task) == 12, "mono_task is three words");

typedef struct mono_counts {
    uint64_t steps, isects;
} mono_counts;

/* One ray from the root over [near, far].  Closest hit into *hit when
 * `occlusion` is 0; else returns 1 as soon as anything lies in (tnear,
 * tfar).  `occlusion` is a constant at both call sites, so each gets its
 * own copy of the loop. */
static inline int trace_ray(const kd_tree *tree, const kd_ray1 *ray, const float inv[3], float near, float far,
                            kd_hit1 *hit, const int occlusion, mono_counts *counts)
{
    const kd_node *nodes = tree->nodes;
    const uint32_t neg[3] = {signbit(inv[0]) ? 1u : 0u, signbit(inv[1]) ? 1u : 0u, signbit(inv[2]) ? 1u : 0u};
    mono_task stack[KD_TRAVERSAL_STACK];
    uint32_t sp = 0;
    const kd_node *n = nodes;
    if (!(near <= far)) return 0;
    for (;;) {
        while (!kd_node_is_leaf(n)) {
            counts->steps++;
            const uint32_t axis = kd_node_axis(n), left = kd_node_child(n);
            const float d = (n->split - ray->org[axis]) * inv[axis];
            const float d_lo = kd_widen_lo(d, KD_RAY_WIDEN), d_hi = kd_widen_hi(d, KD_RAY_WIDEN);
            /* NaN d (a ray lying in the plane): front far = far, back near = near. */
            const float front_far = kd_min1(d_hi, far), back_near = kd_max1(d_lo, near);
            const uint32_t front = left + neg[axis], back = left + (neg[axis] ^ 1u);
            if (near <= front_far) {
                if (back_near <= far && sp < KD_TRAVERSAL_STACK) stack[sp++] = (mono_task){back, back_near, far};
                n = &nodes[front];
                far = front_far;
            } else {
                n = &nodes[back];
                near = back_near;
            }
        }
        counts->steps++;
        const kd_leaf *leaf = &tree->leaves[n->leaf];
        bool occluded;
        counts->isects += isect1_leaf(tree, leaf, ray, hit, occlusion, &occluded);
        if (occluded) return 1;
        const float limit = occlusion ? INFINITY : hit->t;
        for (;;) {
            if (sp == 0) return 0;
            const mono_task task = stack[--sp];
            near = task.near;
            far = kd_min1(task.far, limit);
            if (near <= far) {
                n = &nodes[task.node];
                break;
            }
        }
    }
}

/* The lanes of one packet, one ray at a time.  hits (closest) or occluded
 * (occlusion), the other NULL. */
static void trace_packet_lanes(const kd_tree *tree, const kd_ray_box *box, const ray_packet4 *r, hit_packet4 *hits,
                               uint8_t *occluded, kd_counters *counters)
{
    __m128 near4, far4;
    int valid;
    const int live = kd_ray_packet_setup(box, r, &near4, &far4, &valid);
    if (occluded) *occluded = 0;
    if (counters && valid) counters->packets++;
    if (!live) return;
    _Alignas(16) float org[3][4], dir[3][4], inv[3][4], tnear[4], tfar[4], near[4], far[4];
    _Alignas(16) float t[4], u[4], v[4];
    _Alignas(16) uint32_t prim[4];
    for (int a = 0; a < 3; a++) {
        _mm_store_ps(org[a], r->org[a]);
        _mm_store_ps(dir[a], r->dir[a]);
        _mm_store_ps(inv[a], r->inv_dir[a]);
    }
    _mm_store_ps(tnear, r->tnear);
    _mm_store_ps(tfar, r->tfar);
    _mm_store_ps(near, near4);
    _mm_store_ps(far, far4);
    if (hits) {
        _mm_store_ps(t, hits->t);
        _mm_store_ps(u, hits->u);
        _mm_store_ps(v, hits->v);
        _mm_store_si128((__m128i *)prim, hits->prim);
    }
    mono_counts counts = {0, 0};
    uint8_t mask = 0;
    for (int l = 0; l < 4; l++) {
        if (!(live >> l & 1)) continue;
        const kd_ray1 ray = {{org[0][l], org[1][l], org[2][l]}, {dir[0][l], dir[1][l], dir[2][l]}, tnear[l], tfar[l]};
        const float ray_inv[3] = {inv[0][l], inv[1][l], inv[2][l]};
        if (hits) {
            kd_hit1 hit = {t[l], u[l], v[l], prim[l]};
            trace_ray(tree, &ray, ray_inv, near[l], kd_min1(far[l], hit.t), &hit, 0, &counts);
            t[l] = hit.t, u[l] = hit.u, v[l] = hit.v, prim[l] = hit.prim;
        } else if (trace_ray(tree, &ray, ray_inv, near[l], far[l], NULL, 1, &counts)) {
            mask |= (uint8_t)(1u << l);
        }
    }
    if (hits) {
        hits->t = _mm_load_ps(t);
        hits->u = _mm_load_ps(u);
        hits->v = _mm_load_ps(v);
        hits->prim = _mm_load_si128((const __m128i *)prim);
    } else {
        *occluded = mask;
    }
    if (counters) counters->steps += counts.steps, counters->isects += counts.isects;
}

/* Thesis Listing 2.2: one ray at a time, explicit stack; the lanes of each
 * packet in turn.  Trades: no SIMD in traversal, a node fetch per ray per
 * step; exact on any ray, the baseline of the counters. */
void kd_kernel_mono(const kd_tree *tree, const kd_query *q)
{
    kd_ray_box box;
    kd_ray_box_init(tree, &box);
    for (uint32_t p = 0; p < q->packet_count; p++)
        trace_packet_lanes(tree, &box, &q->packets[p], q->hits ? &q->hits[p] : NULL,
                           q->occluded ? &q->occluded[p] : NULL, q->counters);
}

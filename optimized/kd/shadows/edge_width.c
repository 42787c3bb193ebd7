/* Thesis chapter 5, Listing 5.1: Edge Width Soft Shadows, four rays at a
 * time in SSE (the "proof of concept" packet version the thesis mentions).
 *
 * The four rays of a packet share their origin, the light's centre (the
 * renderer packs each light's rays together), so at every split plane all
 * lanes agree on which child is in front (the origin's side) and the packet
 * descends like an omni-directional packet of Listing 4.1: per lane an
 * interval [near, far], a lane moving away from a plane never crosses it
 * (distance +inf), a child is visited when any live lane's interval
 * reaches it.  Leaves come front to back for every lane.
 *
 * At a leaf every triangle is tested against the packet (both faces; the
 * tree's triangle test, isect_leaf.h, like every optimized kernel).  Per
 * lane, a hit goes into a small sorted "pending" list unless its triangle
 * was seen before (triangles are duplicated across leaves); then every
 * pending hit up to the lane's far end in this leaf is fed, in order, to the
 * shared pairing of rtt/edge_width.h (Listing 5.1's sort and pairing, whose
 * outstanding entry carries over to the next leaf).  Keeping hits that lie
 * beyond the leaf pending rather than dropping them (the listing keeps only
 * t in [tNear, tFar]) means rounding at a split plane can reorder two
 * crossings by a few ulps but never lose one, and a lost crossing would flip
 * inside and outside for the rest of the ray.  A lane stops once its
 * occlusion is decided (width > R: the listing's early exit, or an open
 * mesh); the packet stops when all four have.
 *
 * Trades: the traversal cannot stop at the first hit as a hard shadow ray
 * does (it must reach the point, or R), and it tests both faces; in return
 * one ray gives a penumbra.  A lane whose pending or seen list overflows
 * (more than EW_SEEN_MAX crossings) is counted fully occluded. */
#include <math.h>
#include <string.h>

#include "kernel_isa.h"

#include "isect_leaf.h"
#include "shadow_kernels.h"

#define EW_PENDING_MAX 64u
#define EW_SEEN_MAX 96u
#define EW_WIDEN (1.0f / 65536.0f)    /* relative widening of plane distances */

typedef struct ew_hit {
    float t;
    uint32_t prim;
} ew_hit;

/* Per-lane pairing state, on the stack.  The seen list is searched
 * linearly: a shadow ray meets few triangles before it ends or exits
 * early, and nothing needs clearing per packet. */
typedef struct ew_lane {
    rtt_edge_width_state state;
    uint32_t head, count, seen_count;
    ew_hit pending[EW_PENDING_MAX];   /* [head, count) sorted by (t, prim) */
    uint32_t seen[EW_SEEN_MAX];       /* prims met so far */
} ew_lane;

/* 48 bytes: a subtree and the lanes' intervals in it (as kd_packet_task). */
typedef struct ew_entry {
    __m128 near, far;
    uint32_t node;
} ew_entry;
_Static_assert(sizeof(ew_entry) == 48, "ew_entry is two SSE intervals and a node");

/* false when the prim was seen already; overflow decides the lane. */
static bool first_sighting(ew_lane *lane, uint32_t prim)
{
    for (uint32_t i = 0; i < lane->seen_count; i++)
        if (lane->seen[i] == prim) return false;
    if (lane->seen_count >= EW_SEEN_MAX) {
        lane->state.decided = true;
        return false;
    }
    lane->seen[lane->seen_count++] = prim;
    return true;
}

static void add_pending(ew_lane *lane, float t, uint32_t prim)
{
    if (!first_sighting(lane, prim)) return;
    if (lane->count == EW_PENDING_MAX) {
        if (lane->head == 0) {
            lane->state.decided = true;
            return;
        }
        memmove(lane->pending, lane->pending + lane->head, (lane->count - lane->head) * sizeof(ew_hit));
        lane->count -= lane->head;
        lane->head = 0;
    }
    uint32_t i = lane->count++;
    while (i > lane->head && (lane->pending[i - 1].t > t || (lane->pending[i - 1].t == t && lane->pending[i - 1].prim > prim))) {
        lane->pending[i] = lane->pending[i - 1];
        i--;
    }
    lane->pending[i] = (ew_hit){t, prim};
}

/* Feeds the pending hits with t <= limit. */
static void release(const rtt_edge_width_model *m, ew_lane *lane, float limit)
{
    while (lane->head < lane->count && !lane->state.decided && lane->pending[lane->head].t <= limit) {
        ew_hit h = lane->pending[lane->head++];
        rtt_edge_width_feed(m, &lane->state, h.t, h.prim);
    }
    if (lane->head == lane->count) lane->head = lane->count = 0;
}

/* A triangle's crossings into the pending lists of the lanes that cross it. */
static void queue_crossings(uint32_t prim, int hit, __m128 t, void *context)
{
    ew_lane *lanes = context;
    float tl[4];
    _mm_storeu_ps(tl, t);
    for (int l = 0; l < 4; l++)
        if (hit >> l & 1) add_pending(&lanes[l], tl[l], prim);
}

/* Intersects the leaf with the lanes in `mask`, queues their hits and
 * feeds each lane up to its far end; returns the lanes decided. */
static int visit_leaf(const kd_tree *tree, const rtt_edge_width_model *m, const kd_leaf *leaf, const ray_packet4 *r,
                      ew_lane lanes[4], int mask, __m128 far, kd_counters *counters)
{
    const __m128i bits = _mm_set_epi32(8, 4, 2, 1);
    const __m128 live = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(mask), bits), bits));
    crossings4_leaf(tree, leaf, r, live, queue_crossings, lanes);
    if (counters) counters->isects += leaf->count;
    float limit[4];
    _mm_storeu_ps(limit, _mm_mul_ps(far, _mm_set1_ps(1.0f + EW_WIDEN)));
    int decided = 0;
    for (int l = 0; l < 4; l++) {
        if (!(mask >> l & 1)) continue;
        release(m, &lanes[l], limit[l]);
        if (lanes[l].state.decided) decided |= 1 << l;
    }
    return decided;
}

/* Per-lane [entry, exit] of the packet in the root box (grown by the
 * kernels' margin), widened. */
static void root_interval(const kd_tree *tree, const ray_packet4 *r, __m128 *entry, __m128 *exit)
{
    const rtt_bounds *b = &tree->bounds;
    const float margin = kd_tree_margin(tree);
    const float lo[3] = {b->lo.x - margin, b->lo.y - margin, b->lo.z - margin};
    const float hi[3] = {b->hi.x + margin, b->hi.y + margin, b->hi.z + margin};
    __m128 t0, t1;
    ray_packet4_slab(r, lo, hi, r->tnear, r->tfar, &t0, &t1);
    /* t0 >= tnear >= 0: scaling widens */
    *entry = _mm_mul_ps(t0, _mm_set1_ps(1.0f - EW_WIDEN));
    *exit = _mm_mul_ps(t1, _mm_set1_ps(1.0f + EW_WIDEN));
}

/* Children of an inner node for the lanes in `alive` (see the header
 * comment): intervals of the child to visit now and of the one to push. */
typedef struct ew_split {
    uint32_t first, second;
    __m128 fnear, ffar, snear, sfar;
} ew_split;

static void split_node(const kd_node *n, float origin, const ray_packet4 *r, __m128 near, __m128 far, ew_split *s)
{
    const uint32_t axis = kd_node_axis(n), left = kd_node_child(n);
    const float dist = n->split - origin;
    const __m128 pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY), zero = _mm_setzero_ps();
    if (dist == 0.0f) { /* origin in the plane: each lane goes where its direction points */
        __m128 d = r->dir[axis];
        __m128 to_left = _mm_cmple_ps(d, zero), to_right = _mm_cmpge_ps(d, zero);
        s->first = left, s->second = left + 1;
        s->fnear = _mm_blendv_ps(pinf, near, to_left), s->ffar = _mm_blendv_ps(ninf, far, to_left);
        s->snear = _mm_blendv_ps(pinf, near, to_right), s->sfar = _mm_blendv_ps(ninf, far, to_right);
        return;
    }
    __m128 t = _mm_mul_ps(_mm_set1_ps(dist), r->inv_dir[axis]);
    t = _mm_blendv_ps(t, pinf, _mm_cmplt_ps(t, zero)); /* moving away: never crosses */
    s->first = dist > 0.0f ? left : left + 1;
    s->second = dist > 0.0f ? left + 1 : left;
    s->fnear = near;
    s->ffar = _mm_min_ps(far, _mm_mul_ps(t, _mm_set1_ps(1.0f + EW_WIDEN)));
    s->snear = _mm_max_ps(near, _mm_mul_ps(t, _mm_set1_ps(1.0f - EW_WIDEN)));
    s->sfar = far;
}

static inline int nonempty(__m128 near, __m128 far) { return _mm_movemask_ps(_mm_cmple_ps(near, far)); }

/* Front-to-back traversal of the packet; returns with every lane either
 * decided or past its last leaf. */
static void traverse(const kd_tree *tree, const rtt_edge_width_model *m, const ray_packet4 *r, float origin[3],
                     ew_lane lanes[4], int alive, kd_counters *counters)
{
    const kd_node *nodes = tree->nodes;
    ew_entry stack[KD_TRAVERSAL_STACK];
    uint32_t sp = 0, node = 0;
    uint64_t steps = 0;
    __m128 near, far;
    root_interval(tree, r, &near, &far);
    alive &= nonempty(near, far);
    while (alive) {
        if (nonempty(near, far) & alive) {
            const kd_node *n = &nodes[node];
            while (!kd_node_is_leaf(n)) {
                steps++;
                ew_split s;
                split_node(n, origin[kd_node_axis(n)], r, near, far, &s);
                int fmask = nonempty(s.fnear, s.ffar) & alive, smask = nonempty(s.snear, s.sfar) & alive;
                if (!fmask && !smask) goto pop;
                if (!fmask) {
                    n = &nodes[s.second], near = s.snear, far = s.sfar;
                    continue;
                }
                if (smask && sp < KD_TRAVERSAL_STACK) stack[sp++] = (ew_entry){s.snear, s.sfar, s.second};
                n = &nodes[s.first], near = s.fnear, far = s.ffar;
            }
            steps++;
            const kd_leaf *leaf = &tree->leaves[n->leaf];
            if (leaf->count) alive &= ~visit_leaf(tree, m, leaf, r, lanes, nonempty(near, far) & alive, far, counters);
        }
    pop:
        if (sp == 0) break;
        ew_entry e = stack[--sp];
        node = e.node, near = e.near, far = e.far;
    }
    if (counters) counters->steps += steps;
}

/* Thesis chapter 5, Listing 5.1, four rays from a light's centre.  Trades:
 * no stop at the first hit (the ray walks to its point or past R) and both
 * faces tested, for a penumbra from one ray. */
void ew_occlusion4(const kd_tree *tree, const rtt_edge_width_model *m, const rtt_ray *rays, uint32_t count,
                   float occlusion[4], kd_counters *counters)
{
    if (count > 4) count = 4;
    ew_lane lanes[4];
    ray_packet4 r;
    ray_packet4_load(&r, rays, count);
    int alive = 0;
    for (uint32_t l = 0; l < 4; l++) {
        occlusion[l] = 0.0f;
        if (l >= count) continue;
        lanes[l].head = lanes[l].count = lanes[l].seen_count = 0;
        rtt_edge_width_start(&lanes[l].state, rays[l].dir);
        alive |= 1 << l;
    }
    if (!count) return;
    if (counters) counters->packets++;
    float origin[3] = {rays[0].org[0], rays[0].org[1], rays[0].org[2]};
    if (tree->node_count) traverse(tree, m, &r, origin, lanes, alive, counters);
    for (uint32_t l = 0; l < count; l++) {
        release(m, &lanes[l], INFINITY);
        occlusion[l] = rtt_edge_width_finish(m, &lanes[l].state);
    }
}

static bool same_origin(const rtt_ray *a, const rtt_ray *b)
{
    return a->org[0] == b->org[0] && a->org[1] == b->org[1] && a->org[2] == b->org[2];
}

void ew_occlusion_stream(const kd_tree *tree, const rtt_edge_width_model *m, const rtt_ray *rays,
                         const uint32_t *order, uint32_t n, float *occlusion, kd_counters *counters)
{
    for (uint32_t i = 0; i < n;) {
        rtt_ray packet[4];
        uint32_t count = 0, first = i;
        while (i < n && count < 4 && (count == 0 || same_origin(&rays[order[i]], &packet[0])))
            packet[count++] = rays[order[i++]];
        float result[4];
        ew_occlusion4(tree, m, packet, count, result, counters);
        for (uint32_t l = 0; l < count; l++) occlusion[order[first + l]] = result[l];
    }
}


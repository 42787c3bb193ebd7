/* Thesis 4.1.9 and Figure 4.5: soft shadows with a cone frustum.  The N
 * shadow samples of a shading point all start at the point and end on the
 * disk of the sphere light facing it, so they fill a cone: apex at the
 * point, axis towards the light, half angle the light's angular radius.
 * kd_cone_build (cone.c) finds exactly that cone from the rays (their
 * origins coincide, so the apex is the point itself), and the cone interval
 * traversal of Listing 4.5 (traverse_cone.c) walks the tree once for all N
 * rays, intersecting the surviving packets at each leaf.  pyramid:N bounds
 * the same rays by the interval frustum of Listing 4.2 (traverse_frustum.c)
 * for Table 4.6's comparison: the pyramid needs the min/max reciprocal
 * directions per axis, the cone one multiply per plane.  The cone is built
 * here in one SSE pass over the rays (apex the shared origin, so no box
 * of origins and no double precision), which is what makes it cheaper
 * per group than the generic kd_cone_build; groups without a common origin
 * use the generic cone kernel.
 *
 * Exactness: both proxies are conservative and the leaf test is the same
 * projected test as the other occlusion kernels, so each ray's answer is
 * that of multi:N's ray; only the order of work differs.  A group too wide
 * for a cone (beyond ~80 degrees) or a frustum is traced packet by packet
 * inside the frustum kernel.  Trades: one block set-up per shading point,
 * and no early stop of the whole group until every ray is blocked. */
#include <math.h>

#include "kernel_isa.h"

#include "cone.h"
#include "shadow_kernels.h"
#include "simd4.h"
#include "traverse_interval.h"

#define SC_MIN_COS 0.17f /* ~80 degrees, as cone.c: wider cones do not pay */

/* The cone of Figure 4.5 for a group whose rays share their origin (the
 * shading point): apex at the point, axis the mean direction, half angle
 * the widest ray's, all in SSE over the live lanes in two passes (what
 * cone.c does in double for arbitrary origins).  tau = t (d . v) since the
 * apex is every ray's origin.  Returns 0 when the group has no common
 * origin or the cone would be too wide (then the generic cone kernel). */
static int shared_apex_cone(kd_block *b, kd_cone *c)
{
    const ray_packet4 *r0 = &b->packets[0];
    const float apex[3] = {_mm_cvtss_f32(r0->org[0]), _mm_cvtss_f32(r0->org[1]), _mm_cvtss_f32(r0->org[2])};
    __m128 sum[3] = {_mm_setzero_ps(), _mm_setzero_ps(), _mm_setzero_ps()};
    int any = 0;
    for (uint32_t p = 0; p < b->packet_count; p++) {
        __m128 live = b->live[p];
        const ray_packet4 *r = &b->packets[p];
        int mask = _mm_movemask_ps(live);
        for (int a = 0; a < 3; a++) {
            if (_mm_movemask_ps(_mm_and_ps(_mm_cmpneq_ps(r->org[a], _mm_set1_ps(apex[a])), live))) return 0;
            sum[a] = _mm_add_ps(sum[a], _mm_and_ps(r->dir[a], live));
        }
        any |= mask;
    }
    if (!any) return 0;
    float v[3] = {kd_hsum4(sum[0]), kd_hsum4(sum[1]), kd_hsum4(sum[2])};
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0f)) return 0;
    for (int a = 0; a < 3; a++) v[a] /= len;
    __m128 cos_min = _mm_set1_ps(1.0f), near = _mm_set1_ps(INFINITY), far = _mm_set1_ps(-INFINITY);
    for (uint32_t p = 0; p < b->packet_count; p++) {
        __m128 live = b->live[p];
        if (!_mm_movemask_ps(live)) continue;
        const ray_packet4 *r = &b->packets[p];
        __m128 dot = _mm_setzero_ps(), len2 = _mm_setzero_ps();
        for (int a = 0; a < 3; a++) {
            dot = _mm_add_ps(dot, _mm_mul_ps(r->dir[a], _mm_set1_ps(v[a])));
            len2 = _mm_add_ps(len2, _mm_mul_ps(r->dir[a], r->dir[a]));
        }
        __m128 cosine = _mm_div_ps(dot, _mm_sqrt_ps(len2));
        cos_min = _mm_min_ps(cos_min, _mm_blendv_ps(_mm_set1_ps(1.0f), cosine, live));
        __m128 entry, exit; /* clipped to the scene's box, as cone.c */
        kd_block_root_interval(b, p, &entry, &exit);
        entry = _mm_max_ps(entry, _mm_setzero_ps());
        near = _mm_min_ps(near, _mm_blendv_ps(near, _mm_mul_ps(entry, dot), live));
        far = _mm_max_ps(far, _mm_blendv_ps(far, _mm_mul_ps(exit, dot), live));
    }
    float cmin = kd_hmin4(cos_min);
    if (!(cmin >= SC_MIN_COS)) return 0;
    /* widened: the rounding of the cosines, and never a zero angle */
    float sin_b = kd_fmin1(sqrtf(kd_fmax1(0.0f, 1.0f - cmin * cmin)) * (1.0f + 1e-3f) + 1e-5f, 0.985f);
    float tan_b = sin_b / sqrtf(1.0f - sin_b * sin_b);
    for (int a = 0; a < 3; a++) {
        c->apex[a] = apex[a];
        c->axis[a] = v[a];
        b->cone_apex[0][a] = apex[a];
        b->cone_axis[0][a] = v[a];
        float beta = tan_b * sqrtf(kd_fmax1(0.0f, 1.0f - v[a] * v[a])); /* Listing 4.4 */
        c->pre[0][a] = 1.0f / (v[a] + beta);
        c->pre[1][a] = 1.0f / (v[a] - beta);
    }
    c->tan_angle = tan_b;
    c->near = kd_fmax1(0.0f, kd_widen_lo(kd_hmin4(near), KD_WIDEN));
    c->far = kd_widen_hi(kd_hmax4(far), KD_WIDEN);
    b->units = KD_UNITS_CONE_AXIS;
    return c->near <= c->far;
}

/* One group under its cone: Listing 4.5's interval traversal, packets
 * culled and intersected at leaves (block.c). */
static void trace_group_cone(const kd_tree *tree, const ray_packet4 *packets, uint32_t count, uint8_t *lane_masks,
                             int leaf_culling, kd_counters *counters)
{
    kd_block b;
    if (!kd_block_init(&b, tree, packets, count, NULL, lane_masks, leaf_culling, counters)) return;
    kd_cone c;
    if (shared_apex_cone(&b, &c))
        kd_traverse1(&b, &c, kd_cone_split, c.near, c.far);
    else
        kd_block_trace_cone(&b);
}

/* Thesis 4.1.9, Figure 4.5 (cone:N) and Table 4.6's pyramid (pyramid:N):
 * each group under one proxy.  Trades: one block set-up per shading point
 * and light, for one walk of the tree for its N samples. */
void sc_trace_groups(const kd_tree *tree, const kd_kernel *pyramid, const rtt_ray *rays, const uint32_t *group_first,
                     uint32_t groups, ray_packet4 *packets, uint8_t *lane_masks, uint8_t *occluded, int leaf_culling,
                     kd_counters *counters)
{
    uint32_t packet = 0;
    for (uint32_t g = 0; g < groups; g++) {
        uint32_t first = group_first[g], n = group_first[g + 1] - first, count = (n + 3u) / 4u;
        for (uint32_t p = 0; p < count; p++) {
            uint32_t lanes = n - 4u * p < 4u ? n - 4u * p : 4u;
            ray_packet4_load(&packets[packet + p], &rays[first + 4u * p], lanes);
        }
        if (count && !pyramid) {
            trace_group_cone(tree, packets + packet, count, lane_masks + packet, leaf_culling, counters);
        } else if (count) {
            const kd_query q = {.packets = packets + packet, .packet_count = count, .occluded = lane_masks + packet,
                                .leaf_culling = leaf_culling, .counters = counters};
            pyramid->trace(tree, &q);
        }
        for (uint32_t i = 0; i < n; i++) occluded[first + i] = lane_masks[packet + i / 4u] >> (i % 4u) & 1u;
        packet += count;
    }
}

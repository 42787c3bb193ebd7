/* Thesis Listings 4.3 - 4.5: cone proxy traversal, one cone per block
 * (cone) or four cones in the SSE lanes (mft-cone, 4.1.9).
 *
 * At a plane the cone's disk starts to cross into the back child at axis
 * parameter t1 and has left the front child at t2 (Equation 4.8: the
 * distance to the plane times the two precomputed reciprocals, negative
 * distances compensated to +inf); front is the side of the apex.  Beyond
 * the listing: an apex exactly on the plane (dist == 0) gives 0 * pre = 0
 * for both, which would send the whole cone to the back; such a cone visits
 * both children with its full interval.  t1, t2 are widened relatively.
 * The intervals are in tau units (cone.c); leaf visits convert each ray's
 * best hit to tau for early termination.  Trades: looser than a pyramid for
 * square tiles (Table 4.5), no per-node horizontal min/max. */
#include <math.h>

#include "cone.h"
#include "traverse_interval.h"

static void cone_split(const void *proxy, uint32_t axis, float split, float near, int *front_left, float *dmin,
                       float *dmax)
{
    (void)near;
    const kd_cone *c = proxy;
    float dist = split - c->apex[axis];
    if (dist == 0.0f) {
        *front_left = 1, *dmin = -INFINITY, *dmax = INFINITY;
        return;
    }
    /* Listing 4.5 */
    float t_a = dist * c->pre[0][axis], t_b = dist * c->pre[1][axis];
    t_a = t_a < 0.0f ? INFINITY : t_a;
    t_b = t_b < 0.0f ? INFINITY : t_b;
    *front_left = dist > 0.0f;
    *dmin = fminf(t_a, t_b) * (1.0f - KD_WIDEN);
    *dmax = fmaxf(t_a, t_b) * (1.0f + KD_WIDEN);
}

static void cones_split(const void *proxy, uint32_t axis, float split, __m128 near, __m128 *front_left, __m128 *dmin,
                        __m128 *dmax)
{
    (void)near;
    const kd_cone4 *c = proxy;
    const __m128 zero = _mm_setzero_ps(), pinf = _mm_set1_ps(INFINITY);
    __m128 dist = _mm_sub_ps(_mm_set1_ps(split), c->apex[axis]);
    __m128 t_a = _mm_mul_ps(dist, c->pre0[axis]), t_b = _mm_mul_ps(dist, c->pre1[axis]);
    t_a = _mm_blendv_ps(t_a, pinf, _mm_cmplt_ps(t_a, zero));
    t_b = _mm_blendv_ps(t_b, pinf, _mm_cmplt_ps(t_b, zero));
    __m128 on_plane = _mm_cmpeq_ps(dist, zero);
    __m128 lo = _mm_blendv_ps(_mm_min_ps(t_a, t_b), _mm_set1_ps(-INFINITY), on_plane);
    __m128 hi = _mm_blendv_ps(_mm_max_ps(t_a, t_b), pinf, on_plane);
    *dmin = _mm_mul_ps(lo, _mm_set1_ps(1.0f - KD_WIDEN));
    *dmax = _mm_mul_ps(hi, _mm_set1_ps(1.0f + KD_WIDEN));
    *front_left = _mm_cmpge_ps(dist, zero);
}

void kd_block_trace_cone(kd_block *b)
{
    kd_cone c;
    int built = kd_cone_build(b, 0, &c);
    if (built < 0)
        kd_block_trace_packets(b);
    else if (built > 0)
        kd_traverse1(b, &c, cone_split, c.near, c.far);
}

void kd_block_trace_mft_cone(kd_block *b)
{
    kd_block_group_quadrants(b);
    kd_cone c[4];
    int present[4], any = 0;
    for (uint32_t g = 0; g < 4; g++) {
        int built = kd_cone_build(b, g, &c[g]);
        if (built < 0) {
            kd_block_trace_packets(b);
            return;
        }
        present[g] = built;
        any |= built;
    }
    if (!any) return;
    kd_cone4 c4;
    kd_cone4_pack(c, present, &c4);
    kd_traverse4(b, &c4, cones_split, c4.near, c4.far);
}

/* Thesis Listings 4.3 - 4.5: one cone per block. */
void kd_kernel_cone(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_cone);
}

/* Thesis 4.1.9: four quadrant cones per block. */
void kd_kernel_mft_cone(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_mft_cone);
}

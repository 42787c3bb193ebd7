/* Thesis 4.1.5: Multiple Frustum Traversal.  The block is split into four
 * quadrant frusta traced together in the SSE lanes, each with its own
 * interval; a frustum is masked where its interval is empty or when all its
 * rays have their closest hit (the active mask travels on the stack with
 * the intervals), and at a leaf only the packets of active frusta are culled
 * and intersected.  Trades: four intervals per node (a 2x2 packet's worth of
 * SSE work) for fewer node visits and far fewer intersection tests than one
 * frustum (Table 4.3).
 *
 * The per-lane split is the interval-arithmetic frustum of
 * traverse_frustum.c in SSE; it also serves as the omni-directional per-ray
 * traversal for blocks too incoherent for any proxy (each lane one ray). */
#include <math.h>

#include "frustum.h"
#include "traverse_interval.h"

static void frusta_split(const void *proxy, uint32_t axis, float split, __m128 near, __m128 *front_left,
                         __m128 *dmin, __m128 *dmax)
{
    const kd_frustum4 *f = proxy;
    const __m128 zero = _mm_setzero_ps(), pinf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
    __m128 s = _mm_set1_ps(split);
    __m128 a_lo = _mm_sub_ps(s, f->org_hi[axis]), a_hi = _mm_sub_ps(s, f->org_lo[axis]);
    __m128 ahead = _mm_cmpge_ps(near, zero);
    __m128 left = _mm_and_ps(_mm_cmpgt_ps(a_lo, zero), ahead);
    __m128 right = _mm_and_ps(_mm_cmplt_ps(a_hi, zero), ahead);
    __m128 dmin_left = _mm_mul_ps(a_lo, f->pos_lo[axis]);
    __m128 dmax_left = _mm_blendv_ps(_mm_mul_ps(a_hi, f->pos_hi[axis]), pinf, f->has_neg[axis]);
    __m128 dmin_right = _mm_mul_ps(_mm_sub_ps(zero, a_hi), f->neg_lo[axis]);
    __m128 dmax_right = _mm_blendv_ps(_mm_mul_ps(_mm_sub_ps(zero, a_lo), f->neg_hi[axis]), pinf, f->has_pos[axis]);
    __m128 lo = _mm_blendv_ps(_mm_blendv_ps(ninf, dmin_right, right), dmin_left, left);
    __m128 hi = _mm_blendv_ps(_mm_blendv_ps(pinf, dmax_right, right), dmax_left, left);
    *dmin = _mm_mul_ps(lo, _mm_set1_ps(1.0f - KD_WIDEN));
    *dmax = _mm_mul_ps(hi, _mm_set1_ps(1.0f + KD_WIDEN));
    *front_left = _mm_andnot_ps(right, _mm_castsi128_ps(_mm_set1_epi32(-1)));
}

void kd_traverse4_frusta(kd_block *b, const kd_frustum4 *frusta)
{
    kd_traverse4(b, frusta, frusta_split, frusta->near, frusta->far);
}

void kd_block_trace_mft(kd_block *b)
{
    kd_block_group_quadrants(b);
    kd_frustum f[4];
    int present[4], any = 0;
    for (uint32_t g = 0; g < 4; g++) {
        present[g] = kd_frustum_build(b, g, &f[g]);
        any |= present[g];
        if (present[g] && kd_frustum_is_incoherent(b, &f[g])) {
            kd_block_trace_packets(b);
            return;
        }
    }
    if (!any) return;
    kd_frustum4 f4;
    kd_frustum4_pack(f, present, &f4);
    b->leaf_frusta = &f4;
    kd_traverse4_frusta(b, &f4);
    b->leaf_frusta = NULL;
}

/* Thesis 4.1.5: the block's four quadrant frusta in the SSE lanes. */
void kd_kernel_mft(const kd_tree *tree, const kd_query *q)
{
    kd_blocks_trace(tree, q, kd_block_trace_mft);
}

/* A leaf's triangles against a packet or one ray, with the test the tree
 * names: Wald's projected test on the records (isect_projected_bary.h) when
 * tree->corners is NULL, Woop's watertight test on the corners
 * (isect_woop_watertight.h) when it is set.  Every kd kernel reaches the
 * triangles through these functions and nothing else, so the choice is made
 * once per leaf visit (one predictable branch) and a kernel needs no copy per
 * test.  Counts one intersection test (I) per record per packet. */
#ifndef RTT_ISECT_LEAF_H
#define RTT_ISECT_LEAF_H

#include "isect_projected_bary.h"
#include "isect_woop_watertight.h"

static inline void isect4_leaf(const kd_tree *tree, const kd_leaf *leaf, const ray_packet4 *rays, hit_packet4 *hits,
                               __m128 active, kd_counters *counters)
{
    if (counters) counters->isects += leaf->count;
    if (!tree->corners) {
        const kd_triangle *tri = tree->triangles + leaf->first;
        for (uint32_t i = 0; i < leaf->count; i++) isect4_projected_bary(&tri[i], rays, hits, active);
        return;
    }
    const kd_corners *tri = tree->corners + leaf->first;
    __m128 lanes[3];
    wt_shear4 shears[3];
    for (uint32_t g = 0, groups = wt_groups4(rays, active, lanes, shears); g < groups; g++)
        for (uint32_t i = 0; i < leaf->count; i++) isect4_watertight(&tri[i], rays, &shears[g], hits, lanes[g]);
}

/* The lanes under `active` occluded by a triangle of the leaf; stops as soon
 * as every active lane is.  Counts the records actually tested. */
static inline __m128 occluded4_leaf(const kd_tree *tree, const kd_leaf *leaf, const ray_packet4 *rays,
                                    __m128 active, kd_counters *counters)
{
    const int want = _mm_movemask_ps(active);
    __m128 hit = _mm_setzero_ps();
    uint32_t tested = 0;
    if (!tree->corners) {
        const kd_triangle *tri = tree->triangles + leaf->first;
        while (tested < leaf->count && _mm_movemask_ps(hit) != want) {
            hit = _mm_or_ps(hit, occluded4_projected_bary(&tri[tested], rays, _mm_andnot_ps(hit, active)));
            tested++;
        }
    } else {
        const kd_corners *tri = tree->corners + leaf->first;
        const __m128 inf = _mm_set1_ps(INFINITY);
        __m128 lanes[3];
        wt_shear4 shears[3];
        for (uint32_t g = 0, groups = wt_groups4(rays, active, lanes, shears); g < groups; g++) {
            const int group_want = _mm_movemask_ps(lanes[g]);
            uint32_t i = 0;
            while (i < leaf->count && (_mm_movemask_ps(hit) & group_want) != group_want) {
                __m128 t, u, v;
                const __m128 open = _mm_andnot_ps(hit, lanes[g]);
                hit = _mm_or_ps(hit, isect4_watertight_mask(&tri[i], rays, &shears[g], open, inf, false, &t, &u, &v));
                i++;
            }
            tested = i > tested ? i : tested;
        }
    }
    if (counters) counters->isects += tested;
    return hit;
}

/* Per lane the t of every triangle of the leaf the lane crosses (any t in
 * (tnear, tfar)): `visit(tri_index, hit_mask, t, context)` is called once per
 * triangle with the lanes of `active` that cross it.  For the kernels that
 * need every crossing, not only the closest (edge width). */
typedef void (*kd_crossing_visit)(uint32_t prim, int lanes, __m128 t, void *context);

static inline void crossings4_leaf(const kd_tree *tree, const kd_leaf *leaf, const ray_packet4 *rays, __m128 active,
                                   kd_crossing_visit visit, void *context)
{
    const __m128 inf = _mm_set1_ps(INFINITY);
    if (!tree->corners) {
        const kd_triangle *tri = tree->triangles + leaf->first;
        for (uint32_t i = 0; i < leaf->count; i++) {
            __m128 t, beta, gamma;
            const int lanes = _mm_movemask_ps(_mm_and_ps(active, isect4_projected_bary_mask(&tri[i], rays, inf, &t,
                                                                                            &beta, &gamma)));
            if (lanes) visit(tri[i].prim, lanes, t, context);
        }
        return;
    }
    const kd_corners *tri = tree->corners + leaf->first;
    __m128 lanes[3];
    wt_shear4 shears[3];
    for (uint32_t g = 0, groups = wt_groups4(rays, active, lanes, shears); g < groups; g++)
        for (uint32_t i = 0; i < leaf->count; i++) {
            __m128 t, u, v;
            const int hit = _mm_movemask_ps(isect4_watertight_mask(&tri[i], rays, &shears[g], lanes[g], inf, false,
                                                                   &t, &u, &v));
            if (hit) visit(tri[i].prim, hit, t, context);
        }
}

/* One ray against a leaf: the closest hit into `hit`, or (occlusion) true
 * at the first crossing.  Returns the records tested. */
static inline uint32_t isect1_leaf(const kd_tree *tree, const kd_leaf *leaf, const kd_ray1 *ray, kd_hit1 *hit,
                                   bool occlusion, bool *occluded)
{
    *occluded = false;
    if (!tree->corners) {
        const kd_triangle *tri = tree->triangles + leaf->first;
        for (uint32_t i = 0; i < leaf->count; i++) {
            if (!occlusion) {
                isect1_projected_bary(&tri[i], ray, hit);
            } else if (occluded1_projected_bary(&tri[i], ray)) {
                *occluded = true;
                return i + 1;
            }
        }
        return leaf->count;
    }
    const kd_corners *tri = tree->corners + leaf->first;
    wt_ray1 shear;
    wt_ray1_setup(&shear, ray);
    for (uint32_t i = 0; i < leaf->count; i++) {
        float t, u, v;
        if (!isect1_watertight_test(&tri[i], ray, &shear, &t, &u, &v)) continue;
        if (occlusion) {
            *occluded = true;
            return i + 1;
        }
        if (t < hit->t || (t == hit->t && tri[i].prim < hit->prim)) *hit = (kd_hit1){t, u, v, tri[i].prim};
    }
    return leaf->count;
}

#endif

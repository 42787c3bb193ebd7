/* The watertight test's lane predicates (optimized/bvh/bvh_wt_lanes.h),
 * which let the BVH leaves and the light grid's shadow kernel skip the
 * double path: every lane they call settled must be one the reference's
 * own decision (wt_decide1) answers "no" for, at any scale.  Compiled at the
 * baseline width (4 lanes); the kernels' wider copies are the same code and
 * are checked against the reference in test_optimized_bvh and
 * test_optimized_pgrid_shadows. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "bvh_wt_lanes.h"
#include "isect_woop_watertight.h"
#include "test_random.h"

/* One word of lanes: the sheared corners (ax .. cz) and tnear. */
typedef struct lanes_word {
    float p[9][BVH_W]; /* ax, ay, az, bx, by, bz, cx, cy, cz */
    float tnear[BVH_W];
} lanes_word;

/* The kernels' arithmetic on the word: which lanes the float path cannot
 * decide (a value not normal), and of those the ones bvh_wt_short_lanes
 * settles. */
static void predicates(const lanes_word *w, uint32_t *slow, uint32_t *settled)
{
    vf x[9];
    for (int i = 0; i < 9; i++) x[i] = vf_load(w->p[i]);
    const vf ax = x[0], ay = x[1], az = x[2], bx = x[3], by = x[4], bz = x[5], cx = x[6], cy = x[7], cz = x[8];
    const vf u = vf_sub(vf_mul(cx, by), vf_mul(cy, bx));
    const vf v = vf_sub(vf_mul(ax, cy), vf_mul(ay, cx));
    const vf ww = vf_sub(vf_mul(bx, ay), vf_mul(by, ax));
    const vf det = vf_add(vf_add(u, v), ww);
    const vf t_scaled = vf_add(vf_add(vf_mul(u, az), vf_mul(v, bz)), vf_mul(ww, cz));
    const vm normal = vm_and(vm_and(vm_and(bvh_wt_normal(u), bvh_wt_normal(v)), bvh_wt_normal(ww)),
                             vm_and(bvh_wt_normal(det), bvh_wt_normal(t_scaled)));
    *slow = BVH_LANES_ALL & ~vm_bits(normal);
    *settled = bvh_wt_short_lanes(ax, ay, az, bx, by, bz, cx, cy, cz, det, t_scaled, vf_load(w->tnear));
}

/* Lane l of the word through the reference's decision: a hit? */
static bool reference_hits(const lanes_word *w, uint32_t l)
{
    const wt_lane one = {w->p[0][l], w->p[1][l], w->p[2][l], w->p[3][l], w->p[4][l],
                         w->p[5][l], w->p[6][l], w->p[7][l], w->p[8][l]};
    float t, u, v;
    return wt_decide1(&one, w->tnear[l], INFINITY, &t, &u, &v);
}

/* A lane near the plane case the predicate is for: small integer corners
 * (an origin in the triangle's plane gives T = 0 exactly when cz balances
 * az and bz), or float corners with cz chosen to cancel T up to rounding,
 * or anything; all scaled by a power of two from 2^-70 to 2^70 (exact), with
 * tnear from 2^-100 to 1 of the corners' scale, zero or negative. */
static void random_lane(rng *r, lanes_word *w, uint32_t l, int family)
{
    float c[9];
    for (int i = 0; i < 9; i++)
        c[i] = family == 0 ? (float)((int)(rng_float(r) * 17.0f) - 8) : rng_range(r, -1.0f, 1.0f);
    if (family < 2) { /* cz so that u az + v bz + w cz is (nearly) zero */
        const float u = c[6] * c[4] - c[7] * c[3], v = c[0] * c[7] - c[1] * c[6], ww = c[3] * c[1] - c[4] * c[0];
        if (ww != 0.0f) {
            const float cz = -(u * c[2] + v * c[5]) / ww;
            c[8] = family == 0 ? roundf(cz) : cz;
        }
    }
    const float scale = ldexpf(1.0f, (int)(rng_float(r) * 141.0f) - 70);
    for (int i = 0; i < 9; i++) w->p[i][l] = c[i] * scale;
    const float pick = rng_float(r);
    w->tnear[l] = pick < 0.05f ? 0.0f
                  : pick < 0.1f ? -1e-3f
                                : ldexpf(1.0f, -(int)(rng_float(r) * 101.0f)) * (rng_float(r) < 0.5f ? 1.0f : 3.0f);
}

static void test_short_lanes_are_lanes_the_reference_misses(void **state)
{
    (void)state;
    rng r = {0x5eedf00dULL};
    uint64_t slow_lanes = 0, settled_slow = 0, settled = 0;
    for (int word = 0; word < 200000; word++) {
        lanes_word w;
        for (uint32_t l = 0; l < BVH_W; l++) random_lane(&r, &w, l, (int)(word % 3));
        uint32_t slow, short_lanes;
        predicates(&w, &slow, &short_lanes);
        for (uint32_t l = 0; l < BVH_W; l++) {
            if (!(short_lanes >> l & 1u)) continue;
            settled++;
            if (reference_hits(&w, l))
                fail_msg("word %d lane %u: settled as a miss, but the reference hits (tnear %g, corners %g %g %g / %g %g "
                         "%g / %g %g %g)",
                         word, l, (double)w.tnear[l], (double)w.p[0][l], (double)w.p[1][l], (double)w.p[2][l],
                         (double)w.p[3][l], (double)w.p[4][l], (double)w.p[5][l], (double)w.p[6][l],
                         (double)w.p[7][l], (double)w.p[8][l]);
        }
        slow_lanes += (uint64_t)__builtin_popcount(slow);
        settled_slow += (uint64_t)__builtin_popcount(slow & short_lanes);
    }
    /* not vacuous: many lanes the float path cannot take are settled (the
     * integer family gives T = 0 whenever cz balances; the rest of the slow
     * lanes have a zero edge function, tnear <= 0 or a tnear below T's
     * rounding: 60971 of 510205 with this seed) */
    print_message("lanes settled %llu, of the float path's slow lanes %llu of %llu\n", (unsigned long long)settled,
                  (unsigned long long)settled_slow, (unsigned long long)slow_lanes);
    assert_true(settled_slow > 30000);
}

/* Lanes the reference hits just above tnear (t = T / det a little over
 * it, T of normal size or tiny): never settled, at any scale. */
static void test_short_lanes_leave_hits_above_tnear_alone(void **state)
{
    (void)state;
    rng r = {0xabcdef12ULL};
    uint64_t hits = 0;
    for (int word = 0; word < 50000; word++) {
        lanes_word w;
        for (uint32_t l = 0; l < BVH_W; l++) {
            /* a triangle around the origin's projection: a = (1, 0), b = (-1, 1), c = (-1, -1) shapes, jittered */
            const float scale = ldexpf(1.0f, (int)(rng_float(&r) * 101.0f) - 50);
            const float a[2] = {1.0f + rng_range(&r, -0.1f, 0.1f), rng_range(&r, -0.1f, 0.1f)};
            const float b[2] = {-1.0f + rng_range(&r, -0.1f, 0.1f), 1.0f + rng_range(&r, -0.1f, 0.1f)};
            const float c[2] = {-1.0f + rng_range(&r, -0.1f, 0.1f), -1.0f + rng_range(&r, -0.1f, 0.1f)};
            const float depth = ldexpf(1.0f, -(int)(rng_float(&r) * 100.0f)); /* the plane's distance along the ray */
            const float corners[9] = {a[0], a[1], depth, b[0], b[1], depth, c[0], c[1], depth};
            for (int i = 0; i < 9; i++) w.p[i][l] = corners[i] * scale;
            /* t = depth * scale: tnear a little below it */
            w.tnear[l] = depth * scale * (1.0f - ldexpf(1.0f, -(int)(rng_float(&r) * 20.0f) - 2));
        }
        uint32_t slow, short_lanes;
        predicates(&w, &slow, &short_lanes);
        for (uint32_t l = 0; l < BVH_W; l++) {
            if (!reference_hits(&w, l)) continue;
            hits++;
            assert_false(short_lanes >> l & 1u);
        }
    }
    assert_true(hits > 100000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_short_lanes_are_lanes_the_reference_misses),
        cmocka_unit_test(test_short_lanes_leave_hits_above_tnear_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The judgement of one ray (conformance/conform_classify.c), on the cases
 * that once went wrong, and the double-precision referee that decides
 * disagreements (conform_referee.c, conform_judge.c): where it must side
 * with the engine, where with Embree or the reference, a shared edge, a ray
 * from 1e18, watertightness.
 *
 * Regression: `rtt conform --extremes` (8192 rays), check "aimed at
 * vertices, edges", ray 4957, reported one t-mismatch for every optimized
 * traversal mode.  The ray is aimed at a vertex of the base scene's sphere
 * (prims 442 and 443 there, two of the six around it) and runs almost inside
 * their planes (cos 8.0e-4 to the normals).  The reference hits 442 at
 * t = 1; the projected barycentric test hits 443 at t = 0.99992424, because
 * its numerator n_d - o_k - n_u o_u - n_v o_v cancels to 2 float ulps of
 * error (7.6e-5 of t).  In exact arithmetic both planes are crossed at
 * t = 1.0000094719 and 1.0000094717: a tie at a vertex whose crossing is
 * ill-conditioned, which the tie rule now measures on the crossings. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "conform.h"
#include "extremes_internal.h"
#include "rtt/engine.h"
#include "rtt/scene.h"

/* Prims 442 and 443 of rtt_ext_base_soup (they share the corners
 * (0x1.bb67aep-2, ..) and (0x1p-2, 0x1.8p-2, -0x1.76cf5ep-2), the vertex the
 * ray is aimed at), then prim 764, the floor cell the exact ray reaches
 * after passing 3e-8 outside that vertex. */
static const float triangles[3][9] = {
    {0x1.bb67aep-2f, 0x1.1db3d8p-1f, -0x1.a8279ap-3f, 0x1.8483eep-2f, 0x1.6e8dd4p-2f, -0x1.76cf5ep-2f, 0x1p-2f,
     0x1.8p-2f, -0x1.76cf5ep-2f},
    {0x1.bb67aep-2f, 0x1.1db3d8p-1f, -0x1.a8279ap-3f, 0x1p-2f, 0x1.8p-2f, -0x1.76cf5ep-2f, 0x1p-2f,
     0x1.2a09e6p-1f, -0x1.a8279ap-3f},
    {-0x1p+0f, -0x1p+0f, -0x1.8p+0f, -0x1p-1f, -0x1p+0f, -0x1.8p+0f, -0x1p-1f, -0x1p-1f, -0x1.8p+0f},
};
static const uint32_t base_prims[3] = {442, 443, 764};

/* Ray 4957 of rtt_ext_rays_vertex_aimed(base scene, seed 0xE7E7E5EED + 3). */
static const rtt_ray vertex_ray = {{0x1.d34684p+0f, 0x1.36b09ep+1f, 0x1.5d5e84p+0f},
                                   {-0x1.934684p+0f, -0x1.06b09ep+1f, -0x1.bb125cp+0f},
                                   0.0f,
                                   INFINITY};

/* The hits the two engines reported (prims renumbered 0, 1 here). */
static const rtt_hit reference_hit = {1.0f, 0.0f, 1.0f, 0};
static const rtt_hit projected_hit = {0x1.fff612p-1f, 0.999173522f, 0.000174462795f, 1};

static rtt_scene *scene_of(const float *soup, uint32_t count)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(soup, count, &err);
    if (!scene) fail_msg("rtt_scene_from_triangles: %s", err.message);
    return scene;
}

static rtt_scene *regression_scene(void) { return scene_of(&triangles[0][0], 3); }

static rtt_conform_category classify(const rtt_scene *scene, const rtt_ray *r, const rtt_hit *test,
                                     const rtt_hit *oracle)
{
    return rtt_conform_classify(scene, rtt_conform_scene_magnitude(scene), r, test, oracle);
}

/* The literals above are the suite's own triangles, bit for bit. */
static void test_regression_triangles_are_those_of_the_base_scene(void **state)
{
    (void)state;
    uint32_t count = 0;
    float *soup = rtt_ext_base_soup(&count);
    assert_non_null(soup);
    assert_true(count > base_prims[2]);
    for (int i = 0; i < 3; i++) assert_memory_equal(&soup[9 * base_prims[i]], triangles[i], sizeof triangles[i]);
    free(soup);
}

/* Both hits, in either role, are a tie, on the small scene and on the
 * suite's base scene (whose larger magnitude widens the tolerance). */
static void test_grazing_vertex_hit_on_neighbours_is_a_tie(void **state)
{
    (void)state;
    rtt_scene *scene = regression_scene();
    assert_int_equal(classify(scene, &vertex_ray, &projected_hit, &reference_hit), RTT_CONFORM_TIE);
    assert_int_equal(classify(scene, &vertex_ray, &reference_hit, &projected_hit), RTT_CONFORM_TIE);
    rtt_scene_free(scene);

    uint32_t count = 0;
    float *soup = rtt_ext_base_soup(&count);
    assert_non_null(soup);
    scene = scene_of(soup, count);
    free(soup);
    rtt_hit test = projected_hit, oracle = reference_hit;
    test.prim = base_prims[1];
    oracle.prim = base_prims[0];
    assert_int_equal(classify(scene, &vertex_ray, &test, &oracle), RTT_CONFORM_TIE);
    rtt_scene_free(scene);
}

/* Every engine on the ray: none is a t-mismatch against the reference. */
static void test_engines_on_the_regression_ray_do_not_mismatch(void **state)
{
    (void)state;
    rtt_scene *scene = regression_scene();
    rtt_error err = {{0}};
    rtt_engine *reference = rtt_engine_create("reference", scene, NULL, &err);
    if (!reference) fail_msg("reference: %s", err.message);
    rtt_hit oracle;
    rtt_engine_intersect(reference, &vertex_ray, &oracle, 1);
    assert_int_not_equal(oracle.prim, RTT_MISS);
    assert_true(oracle.prim < 2); /* the vertex, not the floor behind it */
    const char *kernel;
    for (uint32_t t = 0; (kernel = rtt_engine_find("optimized")->kernel(RTT_ACCEL_KD, t)); t++) {
        rtt_engine_options opt;
        rtt_engine_options_default(&opt);
        snprintf(opt.traversal, sizeof opt.traversal, "%s", kernel);
        opt.tile = 8;
        rtt_engine *engine = rtt_engine_create("optimized", scene, &opt, &err);
        if (!engine) fail_msg("optimized/%s: %s", kernel, err.message);
        rtt_hit hit;
        rtt_engine_intersect(engine, &vertex_ray, &hit, 1);
        rtt_conform_category c = classify(scene, &vertex_ray, &hit, &oracle);
        if (c != RTT_CONFORM_AGREE && c != RTT_CONFORM_TIE && c != RTT_CONFORM_GRAZING)
            fail_msg("optimized/%s: prim %u t %a against the reference's prim %u t %a: %s",
                     kernel, hit.prim, (double)hit.t, oracle.prim, (double)oracle.t,
                     rtt_conform_category_name(c));
        rtt_engine_destroy(engine);
    }
    rtt_engine_destroy(reference);
    rtt_scene_free(scene);
}

/* What the tie at one crossing does not accept. */
static void test_tie_at_one_crossing_stays_strict(void **state)
{
    (void)state;
    rtt_scene *scene = regression_scene();
    /* The same grazing ray, the neighbour's t far beyond its crossing's
     * allowance (tolerance / cos is about 0.03 here). */
    rtt_hit far = projected_hit;
    far.t = 0.9f;
    assert_int_equal(classify(scene, &vertex_ray, &far, &reference_hit), RTT_CONFORM_T_MISMATCH);

    /* A steep ray through the same vertex: both planes are crossed at
     * t = 1, cos is near 1, so a t off by 1e-4 (several tolerances) is
     * not a tie. */
    const float v[3] = {0x1p-2f, 0x1.8p-2f, -0x1.76cf5ep-2f};
    rtt_ray steep = {{v[0], v[1] + 1.0f, v[2] - 1.5f}, {0.0f, -1.0f, 1.5f}, 0.0f, INFINITY};
    rtt_hit a = {1.0f, 0.0f, 1.0f, 0}, b = {1.0f - 1e-4f, 1.0f, 0.0f, 1};
    assert_int_equal(classify(scene, &steep, &b, &a), RTT_CONFORM_T_MISMATCH);
    b.t = 1.0f;
    assert_int_equal(classify(scene, &steep, &b, &a), RTT_CONFORM_TIE);

    /* A hit on a triangle crossed elsewhere along the ray (the floor at
     * t = 1.655) is no tie with the vertex at t = 1: the exact ray passes
     * the vertex and reaches the floor, so it is a pass-through (grazing). */
    rtt_hit floor = {1.6551930f, 0.375f, 0.06f, 2};
    assert_int_equal(classify(scene, &vertex_ray, &floor, &reference_hit), RTT_CONFORM_GRAZING);
    rtt_scene_free(scene);
}

/* ---- the double-precision referee (conformance/conform_referee.c) ---- */

/* A unit quad in z = 0 split along its diagonal (prims 0, 1 share the edge
 * (-1, -1) .. (1, 1)) and a second quad in z = -1 (prims 2, 3). */
static const float two_quads[4][9] = {
    {-1, -1, 0, 1, -1, 0, 1, 1, 0},
    {-1, -1, 0, 1, 1, 0, -1, 1, 0},
    {-1, -1, -1, 1, -1, -1, 1, 1, -1},
    {-1, -1, -1, 1, 1, -1, -1, 1, -1},
};

static rtt_scene *quads_scene(void) { return scene_of(&two_quads[0][0], 4); }

/* A ray given in the scene's own coordinates, moved into its stored ones. */
static rtt_ray stored_ray(const rtt_scene *scene, float ox, float oy, float oz, float dx, float dy, float dz)
{
    rtt_ray r = {{ox, oy, oz}, {dx, dy, dz}, 0.0f, INFINITY};
    rtt_rays_to_stored(scene, &r, 1);
    return r;
}

/* One ray through compare_judged on a row that allows no error at all. */
static rtt_conform_row judge_one(const rtt_scene *scene, const rtt_ray *r, const rtt_hit *engine, const rtt_hit *oracle,
                                 bool engine_is_embree)
{
    rtt_conform_row row;
    memset(&row, 0, sizeof row);
    uint64_t budget = RTT_CONFORM_REFEREE_BUDGET;
    rtt_conform_referee_cache cache = {.n = 1, .budget = &budget};
    rtt_conform_judging judging = {.referee = &cache, .engine_is_embree = engine_is_embree, .collect = true};
    assert_true(rtt_conform_compare_judged(scene, r, engine, NULL, oracle, 1, &row, &judging));
    rtt_conform_row_judge(&row);
    rtt_conform_referee_cache_free(&cache);
    rtt_conform_row_free(&row);
    return row;
}

static const rtt_hit miss = {INFINITY, 0.0f, 0.0f, RTT_MISS};

/* Exactly on the shared edge: the referee (edges inclusive) hits at t = 1,
 * and accepts either neighbour: a tie, never a disagreement. */
static void test_referee_on_a_shared_edge(void **state)
{
    (void)state;
    rtt_scene *scene = quads_scene();
    rtt_ray r = stored_ray(scene, 0.25f, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_conform_referee_hit h;
    assert_true(rtt_conform_referee(scene, &r, &h));
    assert_true(h.prim == 0 || h.prim == 1);
    assert_true(h.t == 1.0);
    double magnitude = rtt_conform_scene_magnitude(scene);
    rtt_hit on0 = {1.0f, 0.0f, 0.0f, 0}, on1 = {1.0f, 0.0f, 0.0f, 1}, far = {2.0f, 0.0f, 0.0f, 2};
    assert_true(rtt_conform_referee_accepts(scene, magnitude, &r, &on0, &h));
    assert_true(rtt_conform_referee_accepts(scene, magnitude, &r, &on1, &h));
    assert_false(rtt_conform_referee_accepts(scene, magnitude, &r, &far, &h));
    assert_false(rtt_conform_referee_accepts(scene, magnitude, &r, &miss, &h));
    assert_int_equal(classify(scene, &r, &on0, &on1), RTT_CONFORM_TIE);
    rtt_conform_row row = judge_one(scene, &r, &on0, &on1, false);
    assert_int_equal(row.refereed, 0); /* a tie is not a disagreement */
    assert_true(row.pass);
    rtt_scene_free(scene);
}

/* Embree slips through the shared edge to the far quad while the reference
 * hits it: the referee sides with the reference, "Embree wrong", which is
 * counted apart and never fails the row.  The same answers with rtt's
 * optimized engine in Embree's place are that engine's error. */
static void test_referee_sides_with_the_reference_against_embree(void **state)
{
    (void)state;
    rtt_scene *scene = quads_scene();
    rtt_ray r = stored_ray(scene, 0.25f, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_hit slipped = {2.0f, 0.0f, 0.0f, 2}, on1 = {1.0f, 0.0f, 0.0f, 1};
    rtt_conform_row row = judge_one(scene, &r, &slipped, &on1, true);
    assert_int_equal(row.refereed, 1);
    assert_int_equal(row.embree_wrong, 1);
    assert_int_equal(row.errors[RTT_CONFORM_GRAZING] + row.errors[RTT_CONFORM_T_MISMATCH], 0);
    assert_int_equal(row.wrong_oracle_count, 1);
    assert_int_equal(row.wrong_oracle[0].verdict, RTT_VERDICT_EMBREE_WRONG);
    assert_true(row.pass);

    row = judge_one(scene, &r, &slipped, &on1, false);
    assert_int_equal(row.embree_wrong, 0);
    assert_int_equal(row.errors[RTT_CONFORM_GRAZING], 1); /* a pass-through: grazing */
    assert_false(row.pass);
    assert_int_equal(row.failing_count, 1);
    assert_int_equal(row.failing[0].verdict, RTT_VERDICT_ENGINE_WRONG);
    assert_true(row.failing[0].referee.t == 1.0);
    assert_true(row.failing[0].referee.prim == 0 || row.failing[0].referee.prim == 1);
    assert_true(row.failing[0].ray.org[0] == 0.25f && row.failing[0].ray.org[2] == 1.0f); /* the scene's own */
    rtt_scene_free(scene);
}

/* The reference is the one that is wrong (it reports the far quad, away
 * from any edge): an optimized row that answers right passes and counts
 * "reference wrong"; on the embree row, where the reference is the rtt side
 * judged, it is an error and the row fails. */
static void test_referee_sides_with_the_engine_and_with_embree(void **state)
{
    (void)state;
    rtt_scene *scene = quads_scene();
    rtt_ray r = stored_ray(scene, 0.5f, -0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_hit near = {1.0f, 0.0f, 0.0f, 0}, far = {2.0f, 0.0f, 0.0f, 2};
    assert_int_equal(classify(scene, &r, &near, &far), RTT_CONFORM_T_MISMATCH);
    rtt_conform_row row = judge_one(scene, &r, &near, &far, false);
    assert_int_equal(row.count[RTT_CONFORM_T_MISMATCH], 1);
    assert_int_equal(row.errors[RTT_CONFORM_T_MISMATCH], 0);
    assert_int_equal(row.reference_wrong, 1);
    assert_true(row.pass);

    row = judge_one(scene, &r, &near, &far, true);
    assert_int_equal(row.errors[RTT_CONFORM_T_MISMATCH], 1);
    assert_int_equal(row.embree_wrong, 0);
    assert_false(row.pass);
    assert_int_equal(row.failing[0].verdict, RTT_VERDICT_REFERENCE_WRONG);
    assert_int_equal(row.failing[0].referee.prim, 0);

    /* and a miss where both quads lie ahead is nobody's right answer but the referee's */
    row = judge_one(scene, &r, &miss, &far, false);
    assert_int_equal(row.errors[RTT_CONFORM_HITMISS_OTHER], 1);
    assert_false(row.pass);
    rtt_scene_free(scene);
}

/* A ray from 1e18 away: the referee's t is the exact distance (to double
 * rounding), and an answer lost to float range is judged wrong, not a tie. */
static void test_referee_at_1e18(void **state)
{
    (void)state;
    rtt_scene *scene = quads_scene();
    rtt_ray r = stored_ray(scene, 0.5f, -0.25f, 1e18f, 0.0f, 0.0f, -1.0f);
    rtt_conform_referee_hit h;
    assert_true(rtt_conform_referee(scene, &r, &h));
    assert_int_equal(h.prim, 0);
    assert_true(fabs(h.t - (double)1e18f) <= 1e-12 * 1e18);
    rtt_hit right = {(float)h.t, 0.0f, 0.0f, 0};
    rtt_conform_row row = judge_one(scene, &r, &miss, &right, true);
    assert_int_equal(row.embree_wrong, 1);
    assert_true(row.pass);
    row = judge_one(scene, &r, &miss, &right, false);
    assert_false(row.pass);
    /* beyond Embree's range the adapter does not trace: unspecified, apart */
    rtt_ray beyond = stored_ray(scene, 0.5f, -0.25f, 2e18f, 0.0f, 0.0f, -1.0f);
    assert_true(rtt_conform_referee(scene, &beyond, &h) && h.prim == 0);
#ifdef RTT_HAVE_EMBREE
    right.t = (float)h.t;
    row = judge_one(scene, &beyond, &miss, &right, true);
    assert_int_equal(row.count[RTT_CONFORM_UNSPECIFIED], 1);
    assert_int_equal(row.refereed, 0);
    assert_true(row.pass);
#endif
    rtt_scene_free(scene);
}

/* The referee is watertight: from the centre of a closed UV sphere, rays at
 * every vertex and edge midpoint all hit. */
static void test_referee_is_watertight(void **state)
{
    (void)state;
    const float centre[3] = {0.0f, 0.0f, 0.0f};
    uint32_t count = 0;
    float *soup = rtt_extremes_sphere(48, 24, 1.0f, centre, &count);
    assert_non_null(soup);
    rtt_scene *scene = scene_of(soup, count);
    free(soup);
    float inside[3] = {0.125f, -0.0625f, 0.03125f};
    size_t n = 0;
    rtt_ray *rays = rtt_extremes_watertight_rays(scene, inside, 4096, &n);
    assert_non_null(rays);
    assert_true(n > 1000);
    size_t escapes = 0;
    for (size_t i = 0; i < n; i++) {
        rtt_conform_referee_hit h;
        assert_true(rtt_conform_referee(scene, &rays[i], &h));
        escapes += h.prim == RTT_MISS;
    }
    assert_int_equal(escapes, 0);
    free(rays);
    rtt_scene_free(scene);
}

int main(void)
{
    if (!rtt_conform_register_engines(NULL)) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regression_triangles_are_those_of_the_base_scene),
        cmocka_unit_test(test_grazing_vertex_hit_on_neighbours_is_a_tie),
        cmocka_unit_test(test_engines_on_the_regression_ray_do_not_mismatch),
        cmocka_unit_test(test_tie_at_one_crossing_stays_strict),
        cmocka_unit_test(test_referee_on_a_shared_edge),
        cmocka_unit_test(test_referee_sides_with_the_reference_against_embree),
        cmocka_unit_test(test_referee_sides_with_the_engine_and_with_embree),
        cmocka_unit_test(test_referee_at_1e18),
        cmocka_unit_test(test_referee_is_watertight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

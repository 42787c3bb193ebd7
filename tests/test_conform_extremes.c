/* The numerical-extremes suite (conformance/extremes.c): its scenes and ray
 * patterns, and what it must find per engine — the reference holds every
 * check, Embree is bounded, the optimized engine's leak rate is reported
 * and never hidden.  Small ray counts keep it to seconds; the benchmark
 * meshes are left to `rtt conform --extremes`. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "extremes.h"
#include "extremes_internal.h"
#include "rtt/engine.h"
#include "rtt/scene.h"

#define TEST_RAYS 2048u

typedef struct corner_key {
    float p[6];
} corner_key;

static int corner_order(const void *a, const void *b) { return memcmp(a, b, sizeof(corner_key)); }

/* Every edge of the soup, compared bit for bit, is used by exactly two
 * triangles: the sphere is closed and its shared corners identical. */
static void test_sphere_is_closed_with_bit_identical_shared_corners(void **state)
{
    (void)state;
    const float centre[3] = {1.5f, -2.0f, 0.25f};
    uint32_t count = 0;
    float *soup = rtt_extremes_sphere(17, 9, 3.0f, centre, &count);
    assert_non_null(soup);
    assert_int_equal(count, 2 * 17 * (9 - 1));
    corner_key *edges = malloc(3 * count * sizeof *edges);
    assert_non_null(edges);
    for (uint32_t t = 0; t < count; t++)
        for (int k = 0; k < 3; k++) {
            const float *a = &soup[9 * t + 3 * k], *b = &soup[9 * t + 3 * ((k + 1) % 3)];
            if (memcmp(a, b, 3 * sizeof *a) > 0) {
                const float *swap = a;
                a = b;
                b = swap;
            }
            memcpy(edges[3 * t + k].p, a, 3 * sizeof *a);
            memcpy(edges[3 * t + k].p + 3, b, 3 * sizeof *b);
        }
    qsort(edges, 3 * count, sizeof *edges, corner_order);
    for (uint32_t i = 0; i < 3 * count; i += 2) {
        assert_memory_equal(&edges[i], &edges[i + 1], sizeof *edges);
        if (i + 2 < 3 * count) assert_true(memcmp(&edges[i + 1], &edges[i + 2], sizeof *edges) != 0);
    }
    free(edges);
    free(soup);
}

static rtt_scene *sphere_scene(float radius, const float centre[3])
{
    uint32_t count = 0;
    float *soup = rtt_extremes_sphere(24, 12, radius, centre, &count);
    assert_non_null(soup);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(soup, count, &err);
    if (!scene) fail_msg("rtt_scene_from_triangles: %s", err.message);
    free(soup);
    return scene;
}

static void test_watertight_rays_aim_at_every_vertex_and_edge_midpoint(void **state)
{
    (void)state;
    const float centre[3] = {0, 0, 0}, inside[3] = {0.1f, 0.2f, -0.1f};
    rtt_scene *scene = sphere_scene(2.0f, centre);
    size_t all = 0, some = 0;
    rtt_ray *rays = rtt_extremes_watertight_rays(scene, inside, 1u << 20, &all);
    assert_non_null(rays);
    assert_int_equal(all, scene->vertex_count + 3 * scene->triangle_count);
    for (size_t i = 0; i < all; i++) {
        assert_true(rays[i].org[0] == inside[0] && rays[i].org[1] == inside[1] && rays[i].org[2] == inside[2]);
        /* t = 1 at the target, which lies on the sphere of radius 2 */
        float x = rays[i].org[0] + rays[i].dir[0], y = rays[i].org[1] + rays[i].dir[1],
              z = rays[i].org[2] + rays[i].dir[2];
        assert_true(fabsf(sqrtf(x * x + y * y + z * z) - 2.0f) < 0.05f);
    }
    free(rays);
    rays = rtt_extremes_watertight_rays(scene, inside, 100, &some);
    assert_non_null(rays);
    assert_int_equal(some, 100);
    free(rays);
    rtt_scene_free(scene);
}

static void test_reference_never_leaks_from_inside_a_sphere(void **state)
{
    (void)state;
    const float centres[3][3] = {{0, 0, 0}, {1e4f, -3e4f, 3e3f}, {0, 0, 0}};
    const float radii[3] = {1.0f, 7.0f, 1e18f};
    for (int s = 0; s < 3; s++) {
        rtt_scene *scene = sphere_scene(radii[s], centres[s]);
        rtt_error err = {{0}};
        rtt_engine *reference = rtt_engine_create("reference", scene, NULL, &err);
        if (!reference) fail_msg("reference: %s", err.message);
        size_t n = 0;
        const double centre[3] = {centres[s][0], centres[s][1], centres[s][2]};
        const rtt_vec3 stored = rtt_scene_point_to_stored(scene, centre);
        rtt_ray *rays = rtt_extremes_watertight_rays(scene, (const float[3]){stored.x, stored.y, stored.z}, 1u << 20, &n);
        rtt_hit *hits = malloc(n * sizeof *hits);
        assert_non_null(rays);
        assert_non_null(hits);
        rtt_engine_intersect(reference, rays, hits, n);
        size_t escapes = 0;
        for (size_t i = 0; i < n; i++) escapes += hits[i].prim == RTT_MISS;
        if (escapes) fail_msg("sphere %d: %zu of %zu rays escaped the reference", s, escapes, n);
        free(rays);
        free(hits);
        rtt_engine_destroy(reference);
        rtt_scene_free(scene);
    }
}

static void test_deep_scene_drives_the_reference_to_its_maximum_depth(void **state)
{
    (void)state;
    float *soup = rtt_ext_deep_soup(200);
    assert_non_null(soup);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(soup, 200, &err);
    free(soup);
    if (!scene) fail_msg("%s", err.message);
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.max_tree_depth = 64;
    rtt_engine *reference = rtt_engine_create("reference", scene, &opt, &err);
    if (!reference) fail_msg("%s", err.message);
    rtt_tree_info info;
    assert_true(rtt_engine_tree_info(reference, &info));
    assert_int_equal(info.max_depth, 64);
    assert_int_equal(info.depth, 64);
    rtt_engine_destroy(reference);
    rtt_scene_free(scene);
}

static void test_nan_and_inf_coordinates_are_refused_with_a_message(void **state)
{
    (void)state;
    const float centre[3] = {0, 0, 0};
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++) {
        uint32_t count = 0;
        float *soup = rtt_extremes_sphere(6, 3, 1.0f, centre, &count);
        assert_non_null(soup);
        soup[9 * 5 + 4] = bad[b];
        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_from_triangles(soup, count, &err);
        free(soup);
        assert_null(scene);
        assert_true(strlen(err.message) > 0);
        assert_null(strchr(err.message, '\n'));
    }
}

static void test_invalid_rays_miss_in_every_pattern(void **state)
{
    (void)state;
    const float centre[3] = {0, 0, 0};
    rtt_scene *scene = sphere_scene(1.0f, centre);
    size_t n = 4 * rtt_ext_invalid_pattern_count();
    rtt_ray *rays = malloc(n * sizeof *rays);
    rtt_hit *hits = malloc(n * sizeof *hits);
    uint8_t *occluded = malloc(n);
    assert_non_null(rays);
    assert_non_null(hits);
    assert_non_null(occluded);
    assert_int_equal(rtt_ext_rays_invalid(rtt_v3(0, 0, 0), n, rays), n);
    rtt_error err = {{0}};
    rtt_engine *reference = rtt_engine_create("reference", scene, NULL, &err);
    if (!reference) fail_msg("%s", err.message);
    rtt_engine_intersect(reference, rays, hits, n);
    rtt_engine_occluded(reference, rays, occluded, n);
    for (size_t i = 0; i < n; i++) {
        if (hits[i].prim != RTT_MISS || occluded[i]) fail_msg("invalid ray %zu hit", i % rtt_ext_invalid_pattern_count());
        assert_true(isinf(hits[i].t) && hits[i].t > 0);
    }
    rtt_engine_destroy(reference);
    free(rays);
    free(hits);
    free(occluded);
    rtt_scene_free(scene);
}

/* Runs the suite on `engines` (benchmark meshes off) and fails on every
 * asserted check that did not pass, naming it. */
static rtt_extremes_report run_suite_with(const char *engines, rtt_isect isect)
{
    rtt_extremes_config config;
    rtt_extremes_config_default(&config);
    config.engines = engines;
    config.isect = isect;
    config.mesh_dir = "";
    config.max_rays = TEST_RAYS;
    rtt_extremes_report report;
    rtt_error err = {{0}};
    if (!rtt_extremes_run(&config, &report, &err)) fail_msg("rtt_extremes_run: %s", err.message);
    return report;
}

static rtt_extremes_report run_suite(const char *engines) { return run_suite_with(engines, RTT_ISECT_DEFAULT); }

static void expect_asserted_checks_pass(const rtt_extremes_report *report)
{
    int failed = 0;
    for (size_t i = 0; i < report->count; i++) {
        const rtt_extreme_result *r = &report->items[i];
        if (r->asserted && !r->pass) {
            print_error("FAIL %s / %s: %llu failures, %s\n", r->check, r->engine, (unsigned long long)r->failures,
                        r->note);
            failed++;
        }
    }
    assert_int_equal(failed, 0);
    assert_true(report->pass);
}

static void test_reference_and_oracle_hold_every_asserted_check(void **state)
{
    (void)state;
#ifdef RTT_HAVE_EMBREE
    rtt_extremes_report report = run_suite("embree");
#else
    rtt_extremes_report report = run_suite("reference");
#endif
    expect_asserted_checks_pass(&report);
    /* the reference is asserted everywhere, watertightness included */
    size_t reference_rows = 0;
    for (size_t i = 0; i < report.count; i++)
        if (strcmp(report.items[i].engine, "reference") == 0) {
            reference_rows++;
            assert_true(report.items[i].asserted);
        }
    assert_true(reference_rows >= 20);
    rtt_extremes_report_free(&report);
}

/* The optimized engine's watertight rows (the watertight spheres, every
 * traversal mode, kd and BVH), asserted when `asserted`; returns how many. */
static size_t watertight_rows(const rtt_extremes_report *report, bool asserted)
{
    size_t rows = 0;
    for (size_t i = 0; i < report->count; i++) {
        const rtt_extreme_result *r = &report->items[i];
        if (strncmp(r->engine, "optimized/", 10) == 0 && strncmp(r->check, "watertight", 10) == 0) {
            rows++;
            assert_int_equal(r->asserted, asserted);
            assert_true(r->rays > 0);
            assert_non_null(strstr(r->note, "escape"));
            if (r->asserted) assert_int_equal(r->failures, 0);
        }
    }
    return rows;
}

static uint32_t optimized_kernel_count(void)
{
    uint32_t kernels = 0;
    const rtt_accel accels[] = {RTT_ACCEL_KD, RTT_ACCEL_BVH, RTT_ACCEL_PGRID};
    for (size_t a = 0; a < sizeof accels / sizeof accels[0]; a++)
        for (uint32_t k = 0; rtt_engine_find("optimized")->kernel(accels[a], k); k++) kernels++;
    return kernels;
}

static void test_optimized_with_the_projected_test_holds_every_asserted_check_and_reports_its_leaks(void **state)
{
    (void)state;
    rtt_extremes_report report = run_suite_with("optimized", RTT_ISECT_PROJECTED);
    expect_asserted_checks_pass(&report);
    /* four spheres, every traversal mode of every structure (pgrid: its streams go through the kd-tree) */
    assert_int_equal(watertight_rows(&report, false), 4 * optimized_kernel_count());
    char *table = rtt_extremes_report_table(&report), *json = rtt_extremes_report_json(&report);
    assert_non_null(table);
    assert_non_null(json);
    assert_non_null(strstr(table, "watertight sphere r=1 "));
    assert_non_null(strstr(table, "optimized/mft-cone"));
    assert_non_null(strstr(json, "\"asserted\":\tfalse"));
    free(table);
    free(json);
    rtt_extremes_report_free(&report);
}

/* The default, watertight test: no escape from any sphere in any mode, and
 * that is asserted, as for the reference. */
static void test_optimized_with_the_watertight_test_lets_no_ray_out_in_any_mode(void **state)
{
    (void)state;
    rtt_extremes_report report = run_suite("optimized");
    expect_asserted_checks_pass(&report);
    assert_int_equal(watertight_rows(&report, true), 4 * optimized_kernel_count());
    rtt_extremes_report_free(&report);
}

int main(void)
{
    if (!rtt_conform_register_engines(NULL)) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_is_closed_with_bit_identical_shared_corners),
        cmocka_unit_test(test_watertight_rays_aim_at_every_vertex_and_edge_midpoint),
        cmocka_unit_test(test_reference_never_leaks_from_inside_a_sphere),
        cmocka_unit_test(test_deep_scene_drives_the_reference_to_its_maximum_depth),
        cmocka_unit_test(test_nan_and_inf_coordinates_are_refused_with_a_message),
        cmocka_unit_test(test_invalid_rays_miss_in_every_pattern),
        cmocka_unit_test(test_reference_and_oracle_hold_every_asserted_check),
        cmocka_unit_test(test_optimized_with_the_projected_test_holds_every_asserted_check_and_reports_its_leaks),
        cmocka_unit_test(test_optimized_with_the_watertight_test_lets_no_ray_out_in_any_mode),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

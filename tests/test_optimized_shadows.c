/* Soft shadows of the optimized renderer, each kernel at every instruction
 * set this CPU runs (rows of kd/shadows/shadow_kernels.h): the SSE packet
 * Edge Width (optimized/kd/shadows/edge_width.c) against hand-computed
 * widths and against the scalar reference (reference/edge_width_reference.c)
 * on random closed meshes, pairing across leaves of a tree built by hand,
 * the early exit, and cone:N / pyramid:N (optimized/kd/shadows/
 * shadow_cone.c) against multi:N with the same samples: identical
 * visibility per sample and identical images. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "edge_width_reference.h"
#include "engine_optimized.h"
#include "isect_projected_bary.h"
#include "kd_reference.h"
#include "kernels.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "rtt/shade.h"
#include "scene_build.h"
#include "shadow_kernels.h"
#include "shapes.h"
#include "test_isa.h"

#define LIGHT rtt_v3(0, 10, 0)

/* ---- scenes ---- */

static rtt_scene *scene_begin(void)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("shadow_test", &err);
    assert_non_null(scene);
    rtt_material m = rtt_material_default();
    assert_int_equal(rtt_scene_add_material(scene, &m), 0);
    return scene;
}

static void add_shape(rtt_scene *scene, rtt_shape_mesh *mesh)
{
    rtt_error err = {{0}};
    if (!rtt_scene_add_mesh(scene, "test", "shape", mesh->positions, NULL, mesh->vertex_count, mesh->indices,
                            mesh->triangle_count, NULL, 0, NULL, &err))
        fail_msg("add_mesh: %s", err.message);
    rtt_shape_mesh_free(mesh);
}

static void add_box(rtt_scene *scene, rtt_vec3 lo, rtt_vec3 hi)
{
    rtt_shape_mesh mesh;
    assert_true(rtt_shape_box(lo, hi, &mesh));
    add_shape(scene, &mesh);
}

static void add_sphere(rtt_scene *scene, rtt_vec3 c, float r, uint32_t subdivisions)
{
    rtt_shape_mesh mesh;
    assert_true(rtt_shape_sphere(c, r, subdivisions, &mesh));
    add_shape(scene, &mesh);
}

static void scene_end(rtt_scene *scene, float light_radius)
{
    rtt_error err = {{0}};
    rtt_light light = {RTT_LIGHT_SPHERE, LIGHT, rtt_v3(1, 1, 1), 1.0f, {1, 0, 0}, light_radius, {0, 0, 0}, {0, 0, 0}, 0.0f};
    assert_true(rtt_scene_add_light(scene, &light, &err));
    if (!rtt_scene_finish(scene, &err)) fail_msg("finish: %s", err.message);
}

static rtt_engine *optimized_engine(const rtt_scene *scene)
{
    rtt_error err = {{0}};
    rtt_engine *engine = rtt_optimized_engine_create(scene, NULL, &err);
    if (!engine) fail_msg("optimized engine: %s", err.message);
    return engine;
}

static rtt_ray ray_to(rtt_vec3 p)
{
    rtt_ray ray;
    assert_true(rtt_edge_width_ray(LIGHT, p, 1e-4f, &ray));
    return ray;
}

/* The shadow kernels of exactly that instruction set. */
static const kd_shadow_kernels *shadow_row(rtt_isa isa)
{
    const kd_shadow_kernels *row = kd_shadow_kernels_find(isa);
    assert_int_equal(row->isa, isa);
    return row;
}

static float sse_occlusion(rtt_isa isa, const kd_tree *tree, const rtt_edge_width_model *m, rtt_vec3 p,
                           kd_counters *counters)
{
    rtt_ray ray = ray_to(p);
    float occ[4];
    shadow_row(isa)->edge_width4(tree, m, &ray, 1, occ, counters);
    return occ[0];
}

static uint32_t next_random(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static float uniform(uint32_t *state, float lo, float hi) { return lo + (hi - lo) * (float)next_random(state) / 16777216.0f; }

/* ---- edge width, SSE ---- */

/* The cube of test_reference_edge_width.c: widths 2/15 (top to bottom) and
 * 1/px - 0.6 (top to the side x = 1); R = 1 makes occlusion = width. */
static void test_sse_cube_widths_along_known_rays(void **state)
{
    (void)state;
    rtt_scene *scene = scene_begin();
    add_box(scene, rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1));
    scene_end(scene, 1.0f);
    rtt_engine *engine = optimized_engine(scene);
    const kd_tree *tree = kd_engine_tree(engine);
    rtt_edge_width_model m = rtt_edge_width_model_make(scene, 1.0f, false);
    rtt_ray rays[4] = {ray_to(rtt_v3(1.2f, -5, 0.1f)), ray_to(rtt_v3(1.5f, -5, 0.1f)), ray_to(rtt_v3(2.0f, -5, 0.1f)),
                       ray_to(rtt_v3(0.2f, 0.1f, 0.3f))};
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        float occ[4];
        m.leak_fix = false;
        shadow_row(isa)->edge_width4(tree, &m, rays, 4, occ, NULL);
        assert_float_equal(occ[0], 2.0f / 15.0f, 1e-5f);
        assert_float_equal(occ[1], 1.0f / 1.5f - 0.6f, 1e-5f);
        assert_float_equal(occ[2], 0.0f, 0.0f);
        assert_float_equal(occ[3], 1.0f, 0.0f); /* ends inside the cube */
        m.leak_fix = true;
        shadow_row(isa)->edge_width4(tree, &m, rays, 4, occ, NULL);
        assert_float_equal(occ[0], 1.0f, 0.0f); /* top and bottom share no vertex */
        assert_float_equal(occ[1], 1.0f / 1.5f - 0.6f, 1e-5f);
    }
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

/* A tree made by hand: the root splits the cube at y = 0, so a ray's entry
 * (the top, y = 1) and exit (the bottom, y = -1) lie in different leaves,
 * and the side triangles are in both (duplicates). */
static void test_sse_pairs_entry_and_exit_across_leaves(void **state)
{
    (void)state;
    rtt_scene *scene = scene_begin();
    add_box(scene, rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1));
    scene_end(scene, 1.0f);
    kd_triangle records[24];
    uint32_t below = 0, above = 0;
    kd_triangle lower[12], upper[12];
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 p[3];
        rtt_scene_triangle(scene, i, p);
        kd_triangle rec;
        assert_true(kd_triangle_record(&rec, p, i));
        if (fminf(p[0].y, fminf(p[1].y, p[2].y)) < 0.0f) lower[below++] = rec;
        if (fmaxf(p[0].y, fmaxf(p[1].y, p[2].y)) > 0.0f) upper[above++] = rec;
    }
    memcpy(records, lower, below * sizeof *records);
    memcpy(records + below, upper, above * sizeof *records);
    kd_node nodes[3];
    nodes[0].split = 0.0f, nodes[0].bits = (1u << 2) | 1u;
    nodes[1].leaf = 0, nodes[1].bits = KD_AXIS_LEAF;
    nodes[2].leaf = 1, nodes[2].bits = KD_AXIS_LEAF;
    kd_leaf leaves[2] = {{0, below, {-1, -1, -1}, {1, 0, 1}}, {below, above, {-1, 0, -1}, {1, 1, 1}}};
    kd_tree tree = {nodes, leaves, records, 3, 2, below + above, {rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1)}, {0}, NULL};
    assert_true(below < 12 && above < 12);

    rtt_edge_width_model m = rtt_edge_width_model_make(scene, 1.0f, false);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        kd_counters c = {0, 0, 0};
        assert_float_equal(sse_occlusion(isa, &tree, &m, rtt_v3(1.2f, -5, 0.1f), &c), 2.0f / 15.0f, 1e-5f);
        assert_int_equal(c.steps, 3); /* root and both leaves */
        assert_float_equal(sse_occlusion(isa, &tree, &m, rtt_v3(-1.6f, -5, -0.1f), NULL), 1.0f / 1.6f - 0.6f,
                           1e-5f);
    }
    rtt_scene_free(scene);
}

/* Listing 5.1's early exit: once a width exceeds R, the rest of the ray
 * (here a stack of slabs) is not intersected. */
static void test_sse_early_exit_stops_at_the_first_width_beyond_r(void **state)
{
    (void)state;
    rtt_scene *scene = scene_begin();
    for (int i = 0; i < 8; i++) add_box(scene, rtt_v3(-3, 8.0f - i, -3), rtt_v3(3, 8.5f - i, 3));
    scene_end(scene, 1.0f);
    rtt_engine *engine = optimized_engine(scene);
    const kd_tree *tree = kd_engine_tree(engine);
    rtt_edge_width_model wide = rtt_edge_width_model_make(scene, 10.0f, false);
    rtt_edge_width_model narrow = rtt_edge_width_model_make(scene, 0.01f, false);
    rtt_vec3 p = rtt_v3(0.3f, -5, 0.2f);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        kd_counters full = {0, 0, 0}, early = {0, 0, 0};
        float occ_wide = sse_occlusion(isa, tree, &wide, p, &full);
        assert_float_equal(occ_wide, (0.5f / 15.0f) / 10.0f, 1e-5f);
        assert_float_equal(sse_occlusion(isa, tree, &narrow, p, &early), 1.0f, 0.0f);
        assert_true(early.isects < full.isects);
        assert_true(early.steps < full.steps);
    }
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

/* Random closed meshes (spheres and boxes), random points below them: the
 * SSE version agrees with the scalar reference except, rarely, for a ray
 * that meets a mesh on an edge (the projected test is not watertight). */
static void test_sse_matches_the_scalar_reference_on_random_closed_meshes(void **state)
{
    (void)state;
    uint32_t seed = 12345u;
    uint32_t mismatches[RTT_ISA_COUNT] = {0}, total = 0, partial = 0;
    for (int trial = 0; trial < 4; trial++) {
        rtt_scene *scene = scene_begin();
        for (int i = 0; i < 10; i++) {
            rtt_vec3 c = rtt_v3(uniform(&seed, -4, 4), uniform(&seed, -1, 7), uniform(&seed, -4, 4));
            if (i % 2)
                add_sphere(scene, c, uniform(&seed, 0.2f, 1.2f), 2);
            else
                add_box(scene, rtt_v3_sub(c, rtt_v3(0.6f, 0.3f, 0.5f)), rtt_v3_add(c, rtt_v3(0.4f, 0.2f, 0.7f)));
        }
        scene_end(scene, 1.0f);
        rtt_error err = {{0}};
        rtt_kd_tree ref;
        assert_true(rtt_kd_reference_build(scene, NULL, &ref, &err));
        rtt_engine *engine = optimized_engine(scene);
        const kd_tree *tree = kd_engine_tree(engine);
        for (int variant = 0; variant < 3; variant++) {
            rtt_edge_width_model m = rtt_edge_width_model_make(scene, variant == 0 ? 0.05f : 0.3f, variant == 2);
            for (int i = 0; i < 500; i += 4) {
                rtt_ray rays[4];
                for (int l = 0; l < 4; l++)
                    rays[l] = ray_to(rtt_v3(uniform(&seed, -6, 6), -2.0f, uniform(&seed, -6, 6)));
                float expected[4];
                for (int l = 0; l < 4; l++) {
                    expected[l] = rtt_edge_width_reference(&ref, &m, &rays[l], NULL);
                    total++;
                    if (expected[l] > 0.0f && expected[l] < 1.0f) partial++;
                }
                for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
                    if (!rtt_isa_supported(isa)) continue;
                    float occ[4];
                    shadow_row(isa)->edge_width4(tree, &m, rays, 4, occ, NULL);
                    for (int l = 0; l < 4; l++) mismatches[isa] += fabsf(expected[l] - occ[l]) > 1e-3f;
                }
            }
        }
        rtt_engine_destroy(engine);
        rtt_kd_reference_free(&ref);
        rtt_scene_free(scene);
    }
    assert_true(partial > total / 50); /* the test sees penumbrae, not only 0 and 1 */
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        print_message("edge width %s vs scalar: %u of %u rays differ, %u in a penumbra\n", rtt_isa_name(isa),
                      mismatches[isa], total, partial);
        assert_true(mismatches[isa] * 1000u <= total * 2u);
    }
}

/* ---- cone and pyramid ---- */

static rtt_scene *cone_scene(float light_radius)
{
    rtt_scene *scene = scene_begin();
    add_box(scene, rtt_v3(-6, -1, -6), rtt_v3(6, 0, 6));
    add_sphere(scene, rtt_v3(0, 2.5f, 0), 1.0f, 3);
    add_box(scene, rtt_v3(1.5f, 0, -0.5f), rtt_v3(2.5f, 3, 0.5f));
    add_box(scene, rtt_v3(-3, 4, -1), rtt_v3(-1.8f, 4.1f, 2));
    scene->camera = (rtt_camera){rtt_v3(0, 12, 9), rtt_v3(0, 0, 0), rtt_v3(0, 1, 0), 50.0f};
    scene->width = scene->height = 64;
    scene_end(scene, light_radius);
    return scene;
}

/* Every sample ray of cone:N and pyramid:N has the visibility the plain
 * occlusion kernel gives the same ray (multi:N). */
static void test_cone_and_pyramid_see_each_sample_as_multi_does(void **state)
{
    (void)state;
    rtt_scene *scene = cone_scene(1.5f);
    rtt_engine *engine = optimized_engine(scene);
    const kd_tree *tree = kd_engine_tree(engine);
    const uint32_t n = 16, points = 300;
    rtt_ray *rays = malloc(sizeof(rtt_ray) * n * points);
    uint32_t *group_first = malloc(sizeof(uint32_t) * (points + 1));
    uint8_t *cone = malloc(n * points), *pyramid = malloc(n * points), *multi = malloc(n * points);
    ray_packet4 *packets = aligned_alloc(16, sizeof(ray_packet4) * n * points / 4);
    uint8_t *masks = malloc(n * points / 4);
    uint32_t seed = 99u;
    float eps = rtt_scene_ray_epsilon(scene);
    for (uint32_t g = 0; g < points; g++) {
        rtt_vec3 p = rtt_v3(uniform(&seed, -5, 5), 0.0f, uniform(&seed, -5, 5));
        group_first[g] = g * n;
        for (uint32_t k = 0; k < n; k++) {
            rtt_vec3 target = rtt_light_sample(&scene->lights[0], p, k, n, g);
            rtt_vec3 d = rtt_v3_sub(target, p);
            float dist = rtt_v3_length(d);
            d = rtt_v3_scale(d, 1.0f / dist);
            rays[g * n + k] = (rtt_ray){{p.x, p.y, p.z}, {d.x, d.y, d.z}, eps, dist - eps};
        }
    }
    group_first[points] = points * n;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const kd_shadow_kernels *row = shadow_row(isa);
        row->trace_groups(tree, NULL, rays, group_first, points, packets, masks, cone, 1, NULL);
        row->trace_groups(tree, kd_kernel_find("frustum", isa), rays, group_first, points, packets, masks, pyramid, 0,
                          NULL);
        for (uint32_t p = 0; p < n * points / 4; p++) ray_packet4_load(&packets[p], &rays[4 * p], 4);
        const kd_query multi_query = {.packets = packets, .packet_count = n * points / 4, .occluded = masks,
                                      .leaf_culling = 1};
        kd_kernel_find("mono", isa)->trace(tree, &multi_query);
        uint32_t blocked = 0;
        for (uint32_t i = 0; i < n * points; i++) {
            multi[i] = masks[i / 4] >> (i % 4) & 1u;
            blocked += multi[i];
        }
        assert_true(blocked > n * points / 20 && blocked < n * points * 19 / 20);
        assert_memory_equal(cone, multi, n * points);
        assert_memory_equal(pyramid, multi, n * points);
    }
    free(rays), free(group_first), free(cone), free(pyramid), free(multi), free(packets), free(masks);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static rtt_image *render(rtt_engine *engine, rtt_shadow_method method, uint32_t samples, uint32_t threads,
                         rtt_isa isa)
{
    rtt_error err = {{0}};
    rtt_image *image = rtt_image_create(64, 64, 0, &err);
    assert_non_null(image);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.shadows = method;
    opt.shadow_samples = samples;
    opt.threads = threads;
    opt.engine.isa = isa;
    snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", "mft");
    if (!rtt_optimized_render(engine, &opt, image, NULL, &err)) fail_msg("render: %s", err.message);
    return image;
}

static void test_cone_and_pyramid_images_equal_multi_images(void **state)
{
    (void)state;
    const float radii[2] = {1.0f, 2.0f};
    for (int r = 0; r < 2; r++) {
        rtt_scene *scene = cone_scene(radii[r]);
        rtt_engine *engine = optimized_engine(scene);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            rtt_image *multi = render(engine, RTT_SHADOWS_MULTI, 16, 2, isa);
            rtt_image *cone = render(engine, RTT_SHADOWS_CONE, 16, 1, isa);
            rtt_image *pyramid = render(engine, RTT_SHADOWS_PYRAMID, 16, 2, isa);
            rtt_image *hard = render(engine, RTT_SHADOWS_HARD, 16, 2, isa);
            assert_memory_equal(cone->rgb, multi->rgb, sizeof(float) * 3 * 64 * 64);
            assert_memory_equal(pyramid->rgb, multi->rgb, sizeof(float) * 3 * 64 * 64);
            assert_memory_not_equal(hard->rgb, multi->rgb, sizeof(float) * 3 * 64 * 64);
            rtt_image_free(multi), rtt_image_free(cone), rtt_image_free(pyramid), rtt_image_free(hard);
        }
        rtt_engine_destroy(engine);
        rtt_scene_free(scene);
    }
}

/* The optimized edgewidth image against the reference renderer's. */
static void test_edgewidth_render_matches_the_reference_renderer(void **state)
{
    (void)state;
    rtt_scene *scene = cone_scene(1.0f);
    rtt_engine *engine = optimized_engine(scene);
    rtt_error err = {{0}};
    rtt_engine *ref_engine = rtt_reference_engine_create(scene, NULL, &err);
    assert_non_null(ref_engine);
    for (int fix = 0; fix < 2; fix++) {
        rtt_render_options opt;
        rtt_render_options_default(&opt);
        opt.shadows = RTT_SHADOWS_EDGEWIDTH;
        opt.edge_radius = 0.08f;
        opt.edge_leak_fix = fix;
        opt.threads = 2;
        snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", "mft");
        rtt_image *b = rtt_image_create(64, 64, 0, &err);
        if (!rtt_reference_render(scene, ref_engine, &opt, b, NULL, &err)) fail_msg("reference: %s", err.message);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            opt.engine.isa = isa;
            rtt_image *a = rtt_image_create(64, 64, 0, &err);
            if (!rtt_optimized_render(engine, &opt, a, NULL, &err)) fail_msg("optimized: %s", err.message);
            rtt_image_metrics metrics;
            assert_true(rtt_image_compare(a, b, &metrics, &err));
            print_message("edgewidth %s leak fix %d: rmse %g, over 1/255 %g\n", rtt_isa_name(isa), fix, metrics.rmse,
                          metrics.share_over_1_255);
            assert_true(metrics.share_over_1_255 <= 0.005);
            rtt_image *hard = render(engine, RTT_SHADOWS_HARD, 1, 2, isa);
            assert_memory_not_equal(hard->rgb, a->rgb, sizeof(float) * 3 * 64 * 64);
            rtt_image_free(hard), rtt_image_free(a);
        }
        rtt_image_free(b);
    }
    rtt_engine_destroy(ref_engine);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void test_hard_and_multi_stay_as_they_were(void **state)
{
    (void)state;
    /* The dispatch change must not touch hard and multi: both still match
     * the reference renderer as tightly as test_optimized_render demands. */
    rtt_scene *scene = cone_scene(1.0f);
    rtt_engine *engine = optimized_engine(scene);
    rtt_error err = {{0}};
    rtt_engine *ref_engine = rtt_reference_engine_create(scene, NULL, &err);
    const rtt_shadow_method methods[2] = {RTT_SHADOWS_HARD, RTT_SHADOWS_MULTI};
    for (int i = 0; i < 2; i++) {
        rtt_render_options opt;
        rtt_render_options_default(&opt);
        opt.shadows = methods[i];
        opt.shadow_samples = 8;
        opt.threads = 2;
        rtt_image *b = rtt_image_create(64, 64, 0, &err);
        assert_true(rtt_reference_render(scene, ref_engine, &opt, b, NULL, &err));
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            rtt_image *a = render(engine, methods[i], 8, 2, isa);
            rtt_image_metrics metrics;
            assert_true(rtt_image_compare(a, b, &metrics, &err));
            assert_true(metrics.rmse <= 2e-3 && metrics.share_over_1_255 <= 0.005);
            rtt_image_free(a);
        }
        rtt_image_free(b);
    }
    rtt_engine_destroy(ref_engine);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sse_cube_widths_along_known_rays),
        cmocka_unit_test(test_sse_pairs_entry_and_exit_across_leaves),
        cmocka_unit_test(test_sse_early_exit_stops_at_the_first_width_beyond_r),
        cmocka_unit_test(test_sse_matches_the_scalar_reference_on_random_closed_meshes),
        cmocka_unit_test(test_cone_and_pyramid_see_each_sample_as_multi_does),
        cmocka_unit_test(test_cone_and_pyramid_images_equal_multi_images),
        cmocka_unit_test(test_edgewidth_render_matches_the_reference_renderer),
        cmocka_unit_test(test_hard_and_multi_stay_as_they_were),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

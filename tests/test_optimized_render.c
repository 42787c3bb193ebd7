/* The optimized renderer (optimized/render/) against the reference renderer
 * on a small scene built here with every material type (diffuse, specular,
 * mirror, glass slab, glass mirror), a point light and a sphere light, at
 * every instruction set this CPU runs; and each instruction set's images
 * against the SSE4 ones, bit for bit (what makes golden images independent
 * of the CPU).
 *
 * Thresholds: both renderers evaluate the same formulas in the same order,
 * so pixels differ only where the engines pick different (tied) hits, on
 * shared edges.  Accepted: RMSE <= 2e-3 and at most 0.5% of pixels off by
 * more than 1/255 (rtt_image_compare, colours clamped to [0, 1]). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "kernels.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "rtt/shade.h"
#include "test_isa.h"

#define MAX_RMSE 2e-3
#define MAX_SHARE_OVER 0.005

static void quad_append(float *xyz, uint32_t *count, rtt_vec3 a, rtt_vec3 b, rtt_vec3 c, rtt_vec3 d)
{
    const rtt_vec3 corners[6] = {a, b, c, a, c, d};
    for (int k = 0; k < 6; k++) {
        float *p = &xyz[9 * *count + 3 * (k % 3)];
        p[0] = corners[k].x, p[1] = corners[k].y, p[2] = corners[k].z;
        if (k % 3 == 2) ++*count;
    }
}

/* Axis-aligned box as 12 triangles. */
static void box_append(float *xyz, uint32_t *count, rtt_vec3 lo, rtt_vec3 hi)
{
    rtt_vec3 p[8];
    for (int i = 0; i < 8; i++) p[i] = rtt_v3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    quad_append(xyz, count, p[0], p[1], p[3], p[2]);
    quad_append(xyz, count, p[4], p[6], p[7], p[5]);
    quad_append(xyz, count, p[0], p[4], p[5], p[1]);
    quad_append(xyz, count, p[2], p[3], p[7], p[6]);
    quad_append(xyz, count, p[0], p[2], p[6], p[4]);
    quad_append(xyz, count, p[1], p[5], p[7], p[3]);
}

typedef struct fixture {
    rtt_scene *scene;
    rtt_engine *optimized, *reference;
} fixture;

/* Floor (diffuse), back wall (specular), mirror, glass box, glass-mirror
 * box, a small diffuse box casting shadows; lights: point + sphere.  The
 * boxes float 0.01 above the floor: a bottom face coplanar with the floor
 * would be a tie the two triangle tests may break either way (a documented
 * conformance tie), which is not what this test is about. */
static int setup_scene(void **state)
{
    float xyz[9 * 128];
    uint32_t count = 0, first[7];
    first[0] = count;
    quad_append(xyz, &count, rtt_v3(-4, 0, -4), rtt_v3(-4, 0, 4), rtt_v3(4, 0, 4), rtt_v3(4, 0, -4));
    first[1] = count;
    quad_append(xyz, &count, rtt_v3(-4, 0, -3), rtt_v3(4, 0, -3), rtt_v3(4, 4, -3), rtt_v3(-4, 4, -3));
    first[2] = count;
    quad_append(xyz, &count, rtt_v3(-3, 0.2f, -1), rtt_v3(-2, 0.2f, 0.5f), rtt_v3(-2, 2.5f, 0.5f),
                rtt_v3(-3, 2.5f, -1));
    first[3] = count;
    box_append(xyz, &count, rtt_v3(-0.6f, 0.01f, 0.2f), rtt_v3(0.4f, 1.2f, 0.9f));
    first[4] = count;
    box_append(xyz, &count, rtt_v3(1.0f, 0.01f, -1.0f), rtt_v3(2.0f, 1.5f, 0.0f));
    first[5] = count;
    box_append(xyz, &count, rtt_v3(-1.5f, 0.01f, -2.0f), rtt_v3(-0.8f, 0.7f, -1.3f));
    first[6] = count;
    rtt_error err = {{0}};
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    f->scene = rtt_scene_from_triangles(xyz, count, &err);
    if (!f->scene) fail_msg("scene: %s", err.message);
    rtt_scene *s = f->scene;
    rtt_material base = s->materials[0];
    s->materials = realloc(s->materials, 6 * sizeof *s->materials);
    assert_non_null(s->materials);
    for (int i = 0; i < 6; i++) s->materials[i] = base;
    s->material_count = 6;
    s->materials[1].type = RTT_MATERIAL_SPECULAR;
    s->materials[1].diffuse = rtt_v3(0.3f, 0.5f, 0.8f);
    s->materials[2].type = RTT_MATERIAL_REFLECTIVE;
    s->materials[2].reflection = 0.8f;
    s->materials[3].type = RTT_MATERIAL_TRANSPARENT;
    s->materials[3].diffuse = rtt_v3(0.9f, 0.9f, 1.0f);
    s->materials[4].type = RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
    s->materials[4].diffuse = rtt_v3(1.0f, 0.8f, 0.6f);
    s->materials[4].reflection = 0.3f;
    s->materials[4].transparency = 0.6f;
    s->materials[4].ior = 1.33f;
    s->materials[5].diffuse = rtt_v3(0.8f, 0.2f, 0.2f);
    for (uint32_t m = 0; m < 6; m++)
        for (uint32_t t = first[m]; t < first[m + 1]; t++) s->triangle_material[t] = m;
    s->lights = realloc(s->lights, 2 * sizeof *s->lights);
    assert_non_null(s->lights);
    s->lights[0] = (rtt_light){RTT_LIGHT_POINT, rtt_v3(2.0f, 5.0f, 3.0f), rtt_v3(1, 1, 1), 30.0f, {1, 0, 0.2f}, 0, {0, 0, 0}, {0, 0, 0}, 0.0f};
    s->lights[1] = (rtt_light){RTT_LIGHT_SPHERE, rtt_v3(-2.0f, 4.0f, 2.0f), rtt_v3(1, 0.9f, 0.7f), 20.0f,
                               {1, 0, 0.2f}, 0.6f, {0, 0, 0}, {0, 0, 0}, 0.0f};
    s->light_count = 2;
    s->camera = (rtt_camera){rtt_v3(0.5f, 2.2f, 5.5f), rtt_v3(0, 0.8f, -0.5f), rtt_v3(0, 1, 0), 55.0f};
    s->width = s->height = 64;
    s->max_bounces = 3;
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    f->optimized = rtt_optimized_engine_create(s, &opt, &err);
    if (!f->optimized) fail_msg("optimized engine: %s", err.message);
    f->reference = rtt_reference_engine_create(s, &opt, &err);
    if (!f->reference) fail_msg("reference engine: %s", err.message);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rtt_engine_destroy(f->optimized);
    rtt_engine_destroy(f->reference);
    rtt_scene_free(f->scene);
    free(f);
    return 0;
}

static rtt_image *render_optimized(const fixture *f, const rtt_render_options *opt, rtt_render_stats *stats)
{
    rtt_error err = {{0}};
    rtt_image *image = rtt_image_create(64, 64, opt->aovs, &err);
    if (!image) fail_msg("image: %s", err.message);
    if (!rtt_optimized_render(f->optimized, opt, image, stats, &err)) fail_msg("optimized render: %s", err.message);
    return image;
}

static rtt_image *render_reference(const fixture *f, const rtt_render_options *opt)
{
    rtt_error err = {{0}};
    rtt_image *image = rtt_image_create(64, 64, opt->aovs, &err);
    if (!image) fail_msg("image: %s", err.message);
    if (!rtt_reference_render(f->scene, f->reference, opt, image, NULL, &err))
        fail_msg("reference render: %s", err.message);
    return image;
}

static void assert_close_to_reference(const fixture *f, const rtt_render_options *opt, const char *what)
{
    rtt_image *a = render_optimized(f, opt, NULL), *b = render_reference(f, opt);
    rtt_image_metrics m;
    rtt_error err = {{0}};
    assert_true(rtt_image_compare(a, b, &m, &err));
    if (m.rmse > MAX_RMSE || m.share_over_1_255 > MAX_SHARE_OVER)
        fail_msg("%s: RMSE %g, max error %g, %.3f%% pixels over 1/255", what, m.rmse, m.max_error,
                 100.0 * m.share_over_1_255);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void options(rtt_render_options *opt, const char *traversal, uint32_t tile)
{
    rtt_render_options_default(opt);
    opt->width = opt->height = 64;
    opt->threads = 2;
    snprintf(opt->engine.traversal, sizeof opt->engine.traversal, "%s", traversal);
    opt->engine.tile = tile;
}

static void test_every_traversal_renders_the_reference_image_with_hard_shadows(void **state)
{
    const fixture *f = *state;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        for (uint32_t t = 0; kd_kernel_name_at(t); t++) {
            rtt_render_options opt;
            options(&opt, kd_kernel_name_at(t), 8);
            opt.shadows = RTT_SHADOWS_HARD;
            opt.engine.isa = isa;
            assert_close_to_reference(f, &opt, kd_kernel_name_at(t));
        }
    }
}

static void test_frustum_tiles_of_every_size_with_and_without_culling_match_the_reference(void **state)
{
    const fixture *f = *state;
    const uint32_t tiles[] = {4, 8, 16, 32};
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        for (int i = 0; i < 4; i++)
            for (int culling = 0; culling <= 1; culling++) {
                rtt_render_options opt;
                options(&opt, i % 2 ? "mft" : "frustum", tiles[i]);
                opt.engine.leaf_culling = culling;
                opt.engine.isa = isa;
                assert_close_to_reference(f, &opt, "frustum/mft tile");
            }
    }
}

static void test_multi_sample_and_no_shadows_match_the_reference(void **state)
{
    const fixture *f = *state;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        rtt_render_options opt;
        options(&opt, "mft", 16);
        opt.engine.isa = isa;
        opt.shadows = RTT_SHADOWS_MULTI;
        opt.shadow_samples = 8;
        assert_close_to_reference(f, &opt, "multi:8");
        opt.shadows = RTT_SHADOWS_NONE;
        snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", "cone");
        assert_close_to_reference(f, &opt, "none");
    }
}

/* Every traversal and shadow method renders, at each instruction set past
 * SSE4, the SSE4 image bit for bit: colours and every AOV. */
static void test_every_instruction_set_renders_the_sse4_image_bit_for_bit(void **state)
{
    const fixture *f = *state;
    const rtt_shadow_method methods[] = {RTT_SHADOWS_HARD, RTT_SHADOWS_MULTI, RTT_SHADOWS_CONE, RTT_SHADOWS_PYRAMID,
                                         RTT_SHADOWS_EDGEWIDTH};
    const size_t pixels = 64 * 64;
    uint32_t compared = 0;
    for (uint32_t t = 0; kd_kernel_name_at(t); t++)
        for (size_t m = 0; m < sizeof methods / sizeof methods[0]; m++) {
            rtt_render_options opt;
            options(&opt, kd_kernel_name_at(t), 8);
            opt.shadows = methods[m];
            opt.shadow_samples = 4;
            opt.aovs = RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL;
            opt.engine.isa = RTT_ISA_SSE4;
            rtt_image *sse4 = render_optimized(f, &opt, NULL);
            for (rtt_isa isa = isa_next(RTT_ISA_SSE4); isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
                if (!rtt_isa_supported(isa)) continue;
                opt.engine.isa = isa;
                rtt_image *wide = render_optimized(f, &opt, NULL);
                assert_memory_equal(wide->rgb, sse4->rgb, pixels * 3 * sizeof(float));
                assert_memory_equal(wide->depth, sse4->depth, pixels * sizeof(float));
                assert_memory_equal(wide->prim, sse4->prim, pixels * sizeof(uint32_t));
                assert_memory_equal(wide->normal, sse4->normal, pixels * 3 * sizeof(float));
                rtt_image_free(wide);
                compared++;
            }
            rtt_image_free(sse4);
        }
    for (rtt_isa isa = isa_next(RTT_ISA_SSE4); isa < RTT_ISA_COUNT; isa = isa_next(isa)) isa_runs(isa);
    print_message("%u images compared with their SSE4 twins\n", compared);
}

static void test_one_and_three_threads_give_identical_images(void **state)
{
    const fixture *f = *state;
    rtt_render_options opt;
    options(&opt, "frustum", 8);
    opt.shadows = RTT_SHADOWS_MULTI;
    opt.shadow_samples = 4;
    opt.aovs = RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL;
    opt.threads = 1;
    rtt_image *one = render_optimized(f, &opt, NULL);
    opt.threads = 3;
    rtt_image *three = render_optimized(f, &opt, NULL);
    assert_memory_equal(one->rgb, three->rgb, 64 * 64 * 3 * sizeof(float));
    assert_memory_equal(one->depth, three->depth, 64 * 64 * sizeof(float));
    assert_memory_equal(one->prim, three->prim, 64 * 64 * sizeof(uint32_t));
    assert_memory_equal(one->normal, three->normal, 64 * 64 * 3 * sizeof(float));
    rtt_image_free(one);
    rtt_image_free(three);
}

static void test_aovs_match_the_reference(void **state)
{
    const fixture *f = *state;
    rtt_render_options opt;
    options(&opt, "mft-cone", 8);
    opt.aovs = RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL;
    rtt_image *a = render_optimized(f, &opt, NULL), *b = render_reference(f, &opt);
    uint32_t prim_differs = 0;
    for (uint32_t i = 0; i < 64 * 64; i++) {
        if (a->prim[i] != b->prim[i]) {
            prim_differs++;
            continue; /* a tie on a shared edge: either neighbour is right */
        }
        if (b->prim[i] == RTT_MISS) {
            assert_true(isinf(a->depth[i]));
            continue;
        }
        assert_float_equal(a->depth[i], b->depth[i], 1e-5 * fmax(1.0, b->depth[i]));
        for (int c = 0; c < 3; c++) assert_float_equal(a->normal[3 * i + c], b->normal[3 * i + c], 1e-5);
    }
    assert_true(prim_differs <= 64 * 64 / 200);
    rtt_image_free(a);
    rtt_image_free(b);
}

static void test_stats_count_rays_packets_and_never_change_the_image(void **state)
{
    const fixture *f = *state;
    rtt_render_options opt;
    options(&opt, "mft", 16);
    opt.stats = true;
    rtt_render_stats stats;
    rtt_image *with = render_optimized(f, &opt, &stats);
    opt.stats = false;
    rtt_image *without = render_optimized(f, &opt, NULL);
    assert_memory_equal(with->rgb, without->rgb, 64 * 64 * 3 * sizeof(float));
    assert_int_equal(stats.primary_rays, 64 * 64);
    assert_int_equal(stats.packets, 64 * 64 / 4);
    assert_true(stats.traversal_steps >= stats.packets / 64); /* at least one node per 16x16 tile */
    assert_true(stats.intersection_tests > 0);
    assert_true(stats.shadow_rays > 0);
    assert_true(stats.secondary_rays > 0);
    assert_true(stats.seconds_total > 0.0);
    assert_true(stats.seconds_primary_traversal >= 0.0 && stats.seconds_primary_intersection > 0.0);
    assert_true(stats.seconds_shading > 0.0 && stats.seconds_secondary > 0.0);
    /* the reference traces the same rays */
    rtt_render_stats ref;
    rtt_error err = {{0}};
    rtt_image *image = rtt_image_create(64, 64, 0, &err);
    assert_true(rtt_reference_render(f->scene, f->reference, &opt, image, &ref, &err));
    assert_int_equal(stats.primary_rays, ref.primary_rays);
    assert_true(llabs((long long)stats.secondary_rays - (long long)ref.secondary_rays) <= 64);
    assert_true(llabs((long long)stats.shadow_rays - (long long)ref.shadow_rays) <= 64);
    rtt_image_free(image);
    rtt_image_free(with);
    rtt_image_free(without);
}

static void test_wrong_tile_and_image_size_are_refused(void **state)
{
    const fixture *f = *state;
    rtt_render_options opt;
    options(&opt, "frustum", 12);
    rtt_error err = {{0}};
    rtt_image *image = rtt_image_create(64, 64, 0, &err);
    assert_false(rtt_optimized_render(f->optimized, &opt, image, NULL, &err));
    assert_non_null(strstr(err.message, "tile"));
    opt.engine.tile = 8;
    opt.width = 32;
    assert_false(rtt_optimized_render(f->optimized, &opt, image, NULL, &err));
    rtt_image_free(image);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_traversal_renders_the_reference_image_with_hard_shadows),
        cmocka_unit_test(test_frustum_tiles_of_every_size_with_and_without_culling_match_the_reference),
        cmocka_unit_test(test_multi_sample_and_no_shadows_match_the_reference),
        cmocka_unit_test(test_every_instruction_set_renders_the_sse4_image_bit_for_bit),
        cmocka_unit_test(test_one_and_three_threads_give_identical_images),
        cmocka_unit_test(test_aovs_match_the_reference),
        cmocka_unit_test(test_stats_count_rays_packets_and_never_change_the_image),
        cmocka_unit_test(test_wrong_tile_and_image_size_are_refused),
    };
    return cmocka_run_group_tests(tests, setup_scene, teardown);
}

/* The reference Whitted renderer (shade.h's model) on scenes built here:
 * a lit quad against the formula worked by hand, a mirror, thread-count
 * independence, soft-shadow penumbrae, AOVs, stats and the refusals. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rtt/reference.h"
#include "rtt/shade.h"

/* Appends the two triangles of the quad (a, b, c, d in order) to xyz. */
static void quad_append(float *xyz, uint32_t *count, rtt_vec3 a, rtt_vec3 b, rtt_vec3 c, rtt_vec3 d)
{
    const rtt_vec3 corners[6] = {a, b, c, a, c, d};
    for (int k = 0; k < 6; k++) {
        float *p = &xyz[9 * *count + 3 * (k % 3)];
        p[0] = corners[k].x;
        p[1] = corners[k].y;
        p[2] = corners[k].z;
        if (k % 3 == 2) ++*count;
    }
}

/* Square in the plane z = height, side 2*half, centred on (cx, cy). */
static void square_append(float *xyz, uint32_t *count, float cx, float cy, float half, float height)
{
    quad_append(xyz, count, rtt_v3(cx - half, cy - half, height), rtt_v3(cx + half, cy - half, height),
                rtt_v3(cx + half, cy + half, height), rtt_v3(cx - half, cy + half, height));
}

static rtt_scene *scene_from(const float *xyz, uint32_t count)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, count, &err);
    if (!scene) fail_msg("rtt_scene_from_triangles: %s", err.message);
    return scene;
}

/* Gives the scene `count` materials, all grey diffuse, triangles on material 0. */
static void materials_resize(rtt_scene *scene, uint32_t count)
{
    rtt_material base = scene->materials[0];
    scene->materials = realloc(scene->materials, count * sizeof *scene->materials);
    assert_non_null(scene->materials);
    for (uint32_t i = 0; i < count; i++) scene->materials[i] = base;
    scene->material_count = count;
}

static void camera_set(rtt_scene *scene, rtt_vec3 eye, rtt_vec3 look_at, float fov, uint32_t width, uint32_t height)
{
    scene->camera = (rtt_camera){eye, look_at, rtt_v3(0, 1, 0), fov};
    scene->width = width;
    scene->height = height;
}

static rtt_engine *engine_for(const rtt_scene *scene)
{
    rtt_error err = {{0}};
    rtt_engine *engine = rtt_reference_engine_create(scene, NULL, &err);
    if (!engine) fail_msg("engine: %s", err.message);
    return engine;
}

static rtt_image *render(const rtt_scene *scene, rtt_engine *engine, const rtt_render_options *opt,
                         rtt_render_stats *stats)
{
    rtt_error err = {{0}};
    uint32_t width = opt->width ? opt->width : scene->width, height = opt->height ? opt->height : scene->height;
    rtt_image *image = rtt_image_create(width, height, opt->aovs, &err);
    if (!image) fail_msg("image: %s", err.message);
    if (!rtt_reference_render(scene, engine, opt, image, stats, &err)) fail_msg("render: %s", err.message);
    return image;
}

static rtt_vec3 pixel_rgb(const rtt_image *image, uint32_t x, uint32_t y)
{
    const float *p = &image->rgb[3 * ((size_t)y * image->width + x)];
    return rtt_v3(p[0], p[1], p[2]);
}

static void assert_rgb_near(rtt_vec3 got, rtt_vec3 want, float tolerance)
{
    if (fabsf(got.x - want.x) > tolerance || fabsf(got.y - want.y) > tolerance || fabsf(got.z - want.z) > tolerance)
        fail_msg("colour (%g, %g, %g), expected (%g, %g, %g)", got.x, got.y, got.z, want.x, want.y, want.z);
}

/* One diffuse quad facing the camera, one point light: the centre pixel is
 *   diffuse * ambient + colour * intensity / (c + l d + q d^2) * diffuse * n.l */
static void test_lit_quad_centre_pixel_matches_the_shade_formula(void **state)
{
    (void)state;
    float xyz[2 * 9];
    uint32_t count = 0;
    square_append(xyz, &count, 0.0f, 0.0f, 1.0f, 0.0f);
    rtt_scene *scene = scene_from(xyz, count);
    camera_set(scene, rtt_v3(0, 0, 5), rtt_v3(0, 0, 0), 40.0f, 33, 33);
    scene->ambient = 0.05f;
    scene->materials[0].type = RTT_MATERIAL_DIFFUSE;
    scene->materials[0].diffuse = rtt_v3(0.8f, 0.6f, 0.4f);
    scene->lights[0] = (rtt_light){RTT_LIGHT_POINT, rtt_v3(0.5f, 0.5f, 3.0f), rtt_v3(1.0f, 0.9f, 0.8f), 10.0f,
                                   {1.0f, 0.0f, 0.1f}, 0.0f, {0, 0, 0}, {0, 0, 0}, 0.0f};
    scene->light_count = 1;
    rtt_engine *engine = engine_for(scene);

    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.aovs = RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL;
    rtt_image *image = render(scene, engine, &opt, NULL);

    /* by hand: the centre ray hits (0, 0, 0), normal +z */
    const double d2 = 0.25 + 0.25 + 9.0, d = sqrt(d2), n_dot_l = 3.0 / d;
    const double falloff = 10.0 / (1.0 + 0.1 * d2);
    rtt_vec3 want = rtt_v3((float)(0.8 * 0.05 + 1.0 * falloff * 0.8 * n_dot_l),
                           (float)(0.6 * 0.05 + 0.9 * falloff * 0.6 * n_dot_l),
                           (float)(0.4 * 0.05 + 0.8 * falloff * 0.4 * n_dot_l));
    assert_rgb_near(pixel_rgb(image, 16, 16), want, 1e-4f);

    const size_t centre = 16 * 33 + 16;
    assert_float_equal(image->depth[centre], 5.0f, 1e-4f);
    assert_true(image->prim[centre] == 0 || image->prim[centre] == 1);
    assert_float_equal(image->normal[3 * centre + 2], 1.0f, 1e-6f);
    /* the corner pixel sees past the quad: background, and the AOVs say so */
    assert_rgb_near(pixel_rgb(image, 0, 0), scene->background, 0.0f);
    assert_true(isinf(image->depth[0]));
    assert_int_equal(image->prim[0], RTT_MISS);
    assert_true(image->normal[0] == 0.0f && image->normal[1] == 0.0f && image->normal[2] == 0.0f);

    rtt_image_free(image);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

/* A perfect mirror (reflection 1) shows exactly what its reflected rays see:
 * a red square behind the camera in the middle, the background elsewhere. */
static void test_mirror_shows_the_background_and_what_it_reflects(void **state)
{
    (void)state;
    float xyz[4 * 9];
    uint32_t count = 0;
    square_append(xyz, &count, 0.0f, 0.0f, 2.0f, 0.0f); /* mirror, triangles 0-1 */
    square_append(xyz, &count, 0.0f, 0.0f, 0.5f, 8.0f); /* red square behind the camera, 2-3 */
    rtt_scene *scene = scene_from(xyz, count);
    camera_set(scene, rtt_v3(0, 0, 5), rtt_v3(0, 0, 0), 40.0f, 33, 33);
    materials_resize(scene, 2);
    scene->materials[0].type = RTT_MATERIAL_REFLECTIVE;
    scene->materials[0].reflection = 1.0f;
    scene->materials[1].type = RTT_MATERIAL_DIFFUSE;
    scene->materials[1].diffuse = rtt_v3(1.0f, 0.0f, 0.0f);
    for (uint32_t i = 0; i < 4; i++) scene->triangle_material[i] = i < 2 ? 0 : 1;
    scene->ambient = 1.0f;
    scene->lights[0].intensity = 0.0f; /* the red square shows its ambient colour only */
    scene->background = rtt_v3(0.1f, 0.2f, 0.3f);
    rtt_engine *engine = engine_for(scene);

    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_image *image = render(scene, engine, &opt, NULL);
    assert_rgb_near(pixel_rgb(image, 16, 16), rtt_v3(1.0f, 0.0f, 0.0f), 1e-6f);
    assert_rgb_near(pixel_rgb(image, 0, 0), scene->background, 1e-6f);
    assert_rgb_near(pixel_rgb(image, 32, 32), scene->background, 1e-6f);
    rtt_image_free(image);

    /* with no bounces allowed the mirror shows its own local colour: its
     * diffuse colour times the ambient 1 (the light is off) */
    scene->max_bounces = 0;
    opt.max_bounces = 0;
    image = render(scene, engine, &opt, NULL);
    assert_rgb_near(pixel_rgb(image, 16, 16), scene->materials[0].diffuse, 1e-6f);
    rtt_image_free(image);

    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

/* Ground, an occluder and a large sphere light: the shared scene of the
 * shadow and threading tests. */
static rtt_scene *shadow_scene(void)
{
    float xyz[4 * 9];
    uint32_t count = 0;
    square_append(xyz, &count, 0.0f, 0.0f, 3.0f, 0.0f);  /* ground */
    square_append(xyz, &count, 0.0f, 0.0f, 0.6f, 1.0f);  /* occluder */
    rtt_scene *scene = scene_from(xyz, count);
    camera_set(scene, rtt_v3(0, -0.5f, 6), rtt_v3(0, 0, 0), 50.0f, 40, 40);
    scene->ambient = 0.0f;
    scene->lights[0] = (rtt_light){RTT_LIGHT_SPHERE, rtt_v3(0.3f, 0.2f, 3.0f), rtt_v3(1, 1, 1), 8.0f,
                                   {1.0f, 0.0f, 0.0f}, 0.8f, {0, 0, 0}, {0, 0, 0}, 0.0f};
    scene->light_count = 1;
    return scene;
}

/* Visibility = shadowed / unshadowed colour, per pixel (ambient is 0). */
static void visibility_range(const rtt_image *shadowed, const rtt_image *lit, uint32_t *penumbra, uint32_t *other)
{
    *penumbra = *other = 0;
    for (size_t i = 0; i < (size_t)lit->width * lit->height; i++) {
        float unshadowed = lit->rgb[3 * i];
        if (!(unshadowed > 1e-4f)) continue;
        float vis = shadowed->rgb[3 * i] / unshadowed;
        if (vis > 0.02f && vis < 0.98f) ++*penumbra;
        else if (vis < 1e-5f || fabsf(vis - 1.0f) < 1e-5f) ++*other;
    }
}

static void test_multi_sample_soft_shadow_has_a_penumbra(void **state)
{
    (void)state;
    rtt_scene *scene = shadow_scene();
    rtt_engine *engine = engine_for(scene);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.shadows = RTT_SHADOWS_NONE;
    rtt_image *lit = render(scene, engine, &opt, NULL);
    opt.shadows = RTT_SHADOWS_MULTI;
    opt.shadow_samples = 16;
    rtt_image *soft = render(scene, engine, &opt, NULL);
    opt.shadows = RTT_SHADOWS_HARD;
    rtt_image *hard = render(scene, engine, &opt, NULL);

    uint32_t penumbra, other;
    visibility_range(soft, lit, &penumbra, &other);
    assert_true(penumbra > 0);
    visibility_range(hard, lit, &penumbra, &other);
    assert_int_equal(penumbra, 0); /* hard shadows are all or nothing */
    assert_true(other > 0);

    rtt_image_free(lit);
    rtt_image_free(soft);
    rtt_image_free(hard);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void test_one_and_three_threads_give_identical_images(void **state)
{
    (void)state;
    rtt_scene *scene = shadow_scene();
    materials_resize(scene, 2);
    scene->materials[1].type = RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
    scene->materials[1].reflection = 0.3f;
    scene->materials[1].transparency = 0.5f;
    for (uint32_t i = 2; i < 4; i++) scene->triangle_material[i] = 1;
    rtt_engine *engine = engine_for(scene);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.shadows = RTT_SHADOWS_MULTI;
    opt.shadow_samples = 8;
    opt.width = 37; /* tiles that do not divide the image */
    opt.height = 29;
    opt.aovs = RTT_AOV_DEPTH | RTT_AOV_PRIM | RTT_AOV_NORMAL;
    opt.threads = 1;
    rtt_image *one = render(scene, engine, &opt, NULL);
    opt.threads = 3;
    rtt_image *three = render(scene, engine, &opt, NULL);
    const size_t pixels = 37 * 29;
    assert_memory_equal(one->rgb, three->rgb, 3 * pixels * sizeof(float));
    assert_memory_equal(one->depth, three->depth, pixels * sizeof(float));
    assert_memory_equal(one->prim, three->prim, pixels * sizeof(uint32_t));
    assert_memory_equal(one->normal, three->normal, 3 * pixels * sizeof(float));
    rtt_image_free(one);
    rtt_image_free(three);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void test_stats_count_every_kind_of_ray(void **state)
{
    (void)state;
    rtt_scene *scene = shadow_scene();
    rtt_engine *engine = engine_for(scene);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.shadows = RTT_SHADOWS_MULTI;
    opt.shadow_samples = 4;
    rtt_render_stats stats;
    rtt_image *image = render(scene, engine, &opt, &stats);
    assert_int_equal(stats.primary_rays, 40 * 40);
    assert_true(stats.shadow_rays > 0 && stats.shadow_rays <= 4u * 40 * 40);
    assert_true(stats.shadow_rays % 4 == 0); /* four rays per lit point, one sphere light */
    assert_int_equal(stats.secondary_rays, 0); /* nothing reflects */
    assert_true(stats.seconds_total >= 0.0);
    rtt_image_free(image);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void test_cone_and_pyramid_shadows_are_refused(void **state)
{
    (void)state;
    rtt_scene *scene = shadow_scene();
    rtt_engine *engine = engine_for(scene);
    rtt_image *image = rtt_image_create(40, 40, 0, NULL);
    assert_non_null(image);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_error err = {{0}};
    opt.shadows = RTT_SHADOWS_CONE;
    opt.shadow_samples = 16;
    assert_false(rtt_reference_render(scene, engine, &opt, image, NULL, &err));
    assert_string_equal(err.message,
                        "shadow method cone:16 is not drawn by the reference renderer (the optimized one draws it)");
    opt.shadows = RTT_SHADOWS_PYRAMID;
    assert_false(rtt_reference_render(scene, engine, &opt, image, NULL, &err));
    assert_non_null(strstr(err.message, "pyramid:16"));
    rtt_image_free(image);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void test_output_image_of_the_wrong_size_or_planes_is_refused(void **state)
{
    (void)state;
    rtt_scene *scene = shadow_scene();
    rtt_engine *engine = engine_for(scene);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_error err = {{0}};
    rtt_image *small = rtt_image_create(20, 40, 0, NULL);
    assert_false(rtt_reference_render(scene, engine, &opt, small, NULL, &err));
    assert_non_null(strstr(err.message, "20x40"));
    opt.width = 20; /* now the option asks for that size */
    assert_true(rtt_reference_render(scene, engine, &opt, small, NULL, &err));
    opt.aovs = RTT_AOV_DEPTH;
    assert_false(rtt_reference_render(scene, engine, &opt, small, NULL, &err));
    assert_non_null(strstr(err.message, "AOV"));
    rtt_image_free(small);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lit_quad_centre_pixel_matches_the_shade_formula),
        cmocka_unit_test(test_mirror_shows_the_background_and_what_it_reflects),
        cmocka_unit_test(test_multi_sample_soft_shadow_has_a_penumbra),
        cmocka_unit_test(test_one_and_three_threads_give_identical_images),
        cmocka_unit_test(test_stats_count_every_kind_of_ray),
        cmocka_unit_test(test_cone_and_pyramid_shadows_are_refused),
        cmocka_unit_test(test_output_image_of_the_wrong_size_or_planes_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

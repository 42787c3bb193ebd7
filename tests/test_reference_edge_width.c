/* Edge Width Soft Shadows, the scalar reference (reference/
 * edge_width_reference.c) and the shared pairing (scene/edge_width_model.c):
 * exact widths through a cube worked by hand, Equation 5.1, the early exit
 * R, the inside-at-end rule, the leak fix, the width scale, open meshes,
 * rays through shared edges, and the reference renderer's edgewidth. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "edge_width_reference.h"
#include "kd_reference.h"
#include "rtt/reference.h"
#include "rtt/shade.h"
#include "scene_build.h"
#include "shapes.h"

/* ---- scenes built here ---- */

static rtt_scene *scene_begin(void)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("edge_width_test", &err);
    assert_non_null(scene);
    rtt_material m = rtt_material_default();
    assert_int_equal(rtt_scene_add_material(scene, &m), 0);
    return scene;
}

static uint32_t material_with_scale(rtt_scene *scene, float scale)
{
    rtt_material m = rtt_material_default();
    m.edge_width_scale = scale;
    return rtt_scene_add_material(scene, &m);
}

static void add_shape(rtt_scene *scene, rtt_shape_mesh *mesh, uint32_t material)
{
    rtt_error err = {{0}};
    if (!rtt_scene_add_mesh(scene, "test", "shape", mesh->positions, NULL, mesh->vertex_count, mesh->indices,
                            mesh->triangle_count, NULL, material, NULL, &err))
        fail_msg("add_mesh: %s", err.message);
    rtt_shape_mesh_free(mesh);
}

static void add_box(rtt_scene *scene, rtt_vec3 lo, rtt_vec3 hi, uint32_t material)
{
    rtt_shape_mesh mesh;
    assert_true(rtt_shape_box(lo, hi, &mesh));
    add_shape(scene, &mesh, material);
}

static void add_quad(rtt_scene *scene, rtt_vec3 a, rtt_vec3 b, rtt_vec3 c, rtt_vec3 d)
{
    rtt_vec3 corners[4] = {a, b, c, d};
    rtt_shape_mesh mesh;
    assert_true(rtt_shape_quad(corners, &mesh));
    add_shape(scene, &mesh, 0);
}

static void scene_end(rtt_scene *scene)
{
    rtt_error err = {{0}};
    rtt_light light = {RTT_LIGHT_SPHERE, rtt_v3(0, 10, 0), rtt_v3(1, 1, 1), 1.0f, {1, 0, 0}, 1.0f, {0, 0, 0}, {0, 0, 0}, 0.0f};
    if (scene->light_count == 0) assert_true(rtt_scene_add_light(scene, &light, &err));
    if (!rtt_scene_finish(scene, &err)) fail_msg("finish: %s", err.message);
}

typedef struct fixture {
    rtt_scene *scene;
    rtt_kd_tree tree;
} fixture;

static void fixture_build(fixture *f)
{
    rtt_error err = {{0}};
    scene_end(f->scene);
    if (!rtt_kd_reference_build(f->scene, NULL, &f->tree, &err)) fail_msg("build: %s", err.message);
}

static void fixture_free(fixture *f)
{
    rtt_kd_reference_free(&f->tree);
    rtt_scene_free(f->scene);
}

/* The ray from the light (0, 10, 0) to p: t is the fraction of the way. */
static rtt_ray ray_to(rtt_vec3 p)
{
    rtt_ray ray;
    assert_true(rtt_edge_width_ray(rtt_v3(0, 10, 0), p, 1e-4f, &ray));
    return ray;
}

static float width_along(const fixture *f, rtt_vec3 p, float *occlusion)
{
    rtt_edge_width_model m = rtt_edge_width_model_make(f->scene, 1e30f, false);
    rtt_ray ray = ray_to(p);
    float width;
    float occ = rtt_edge_width_reference(&f->tree, &m, &ray, &width);
    if (occlusion) *occlusion = occ;
    return width;
}

/* ---- the model ---- */

static void test_equation_5_1_maps_width_to_occlusion(void **state)
{
    (void)state;
    assert_float_equal(rtt_edge_width_occlusion(-1.0f, 0.2f), 0.0f, 0.0f);
    assert_float_equal(rtt_edge_width_occlusion(0.0f, 0.2f), 0.0f, 0.0f);
    assert_float_equal(rtt_edge_width_occlusion(0.05f, 0.2f), 0.25f, 1e-7f);
    assert_float_equal(rtt_edge_width_occlusion(0.2f, 0.2f), 1.0f, 0.0f);
    assert_float_equal(rtt_edge_width_occlusion(INFINITY, 0.2f), 1.0f, 0.0f);
    rtt_edge_width_model m = rtt_edge_width_model_make(NULL, 0.0f, false);
    assert_float_equal(m.radius, RTT_EDGE_WIDTH_DEFAULT_RADIUS, 0.0f);
}

static void test_edge_width_ray_runs_from_the_light_centre_as_a_fraction(void **state)
{
    (void)state;
    rtt_ray ray;
    assert_true(rtt_edge_width_ray(rtt_v3(0, 10, 0), rtt_v3(3, -5, 0), 0.15f, &ray));
    assert_float_equal(ray.org[1], 10.0f, 0.0f);
    assert_float_equal(ray.dir[0], 3.0f, 0.0f);
    assert_float_equal(ray.dir[1], -15.0f, 0.0f);
    float d = sqrtf(9.0f + 225.0f);
    assert_float_equal(ray.tnear, 0.15f / d, 1e-7f);
    assert_float_equal(ray.tfar, 1.0f - 0.15f / d, 1e-7f);
    assert_false(rtt_edge_width_ray(rtt_v3(0, 0, 0), rtt_v3(0.1f, 0, 0), 0.1f, &ray));
}

/* ---- a cube between the light (0,10,0) and points on y = -5 ----
 * ray to (px, -5, z): x = px t, y = 10 - 15 t.  It enters the top y = 1 at
 * t = 0.6 (x = 0.6 px) and leaves the bottom y = -1 at t = 11/15 when
 * |11/15 px| <= 1, else the side x = 1 at t = 1/px. */

static void cube_fixture(fixture *f)
{
    f->scene = scene_begin();
    add_box(f->scene, rtt_v3(-1, -1, -1), rtt_v3(1, 1, 1), 0);
    fixture_build(f);
}

static void test_cube_widths_along_known_rays(void **state)
{
    (void)state;
    fixture f;
    cube_fixture(&f);
    float occ;
    /* through top and bottom: 2/15 */
    assert_float_equal(width_along(&f, rtt_v3(1.2f, -5, 0.1f), &occ), 2.0f / 15.0f, 1e-5f);
    assert_float_equal(occ, 0.0f, 1e-6f); /* R = 1e30 */
    assert_float_equal(width_along(&f, rtt_v3(-0.5f, -5, 0.3f), NULL), 2.0f / 15.0f, 1e-5f);
    /* through the top and the side x = 1: 1/1.5 - 0.6 */
    assert_float_equal(width_along(&f, rtt_v3(1.5f, -5, 0.1f), NULL), 1.0f / 1.5f - 0.6f, 1e-5f);
    assert_float_equal(width_along(&f, rtt_v3(1.6f, -5, -0.2f), NULL), 1.0f / 1.6f - 0.6f, 1e-5f);
    /* past the cube: nothing */
    assert_float_equal(width_along(&f, rtt_v3(2.0f, -5, 0.1f), &occ), 0.0f, 0.0f);
    assert_float_equal(occ, 0.0f, 0.0f);
    fixture_free(&f);
}

static void test_occlusion_is_width_over_r_and_one_beyond_r(void **state)
{
    (void)state;
    fixture f;
    cube_fixture(&f);
    rtt_ray ray = ray_to(rtt_v3(1.5f, -5, 0.1f)); /* width 1/15 */
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 0.2f, false);
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), (1.0f / 15.0f) / 0.2f, 1e-4f);
    m.radius = 0.05f; /* exceeded: the early exit's answer */
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 1.0f, 0.0f);
    fixture_free(&f);
}

static void test_ray_ending_inside_an_object_is_fully_occluded(void **state)
{
    (void)state;
    fixture f;
    cube_fixture(&f);
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 1e30f, false);
    rtt_ray ray;
    assert_true(rtt_edge_width_ray(rtt_v3(0, 10, 0), rtt_v3(0.2f, 0.1f, 0.3f), 1e-4f, &ray));
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 1.0f, 0.0f);
    fixture_free(&f);
}

static void test_widths_of_two_occluders_take_the_maximum(void **state)
{
    (void)state;
    fixture f;
    f.scene = scene_begin();
    add_box(f.scene, rtt_v3(-3, 4, -3), rtt_v3(3, 4.3f, 3), 0);   /* crossed over 0.3 / 15 */
    add_box(f.scene, rtt_v3(-3, -2, -3), rtt_v3(3, -1, 3), 0);    /* crossed over 1 / 15 */
    fixture_build(&f);
    assert_float_equal(width_along(&f, rtt_v3(0.3f, -5, 0.2f), NULL), 1.0f / 15.0f, 1e-5f);
    fixture_free(&f);
}

/* ---- light leaks (thesis 5 "Light Leaks") ---- */

static void thin_plate_fixture(fixture *f, float scale)
{
    f->scene = scene_begin();
    uint32_t m = material_with_scale(f->scene, scale);
    add_box(f->scene, rtt_v3(-2, 0, -2), rtt_v3(2, 0.03f, 2), m); /* width 0.03 / 15 = 0.002 */
    fixture_build(f);
}

static void test_thin_plate_leaks_and_the_leak_fix_closes_it(void **state)
{
    (void)state;
    fixture f;
    thin_plate_fixture(&f, 1.0f);
    rtt_ray ray = ray_to(rtt_v3(0.3f, -5, 0.2f));
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 0.05f, false);
    float leak = rtt_edge_width_reference(&f.tree, &m, &ray, NULL);
    assert_float_equal(leak, 0.002f / 0.05f, 1e-3f); /* mostly lit under the plate: the leak */
    m.leak_fix = true; /* top and bottom faces share no vertex: infinite width */
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 1.0f, 0.0f);
    fixture_free(&f);
}

static void test_leak_fix_keeps_widths_of_faces_that_share_a_vertex(void **state)
{
    (void)state;
    fixture f;
    cube_fixture(&f);
    /* top then side x = 1: the faces meet along an edge */
    rtt_ray ray = ray_to(rtt_v3(1.6f, -5, 0.1f));
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 0.5f, true);
    float expected = (1.0f / 1.6f - 0.6f) / 0.5f;
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), expected, 1e-4f);
    /* top then bottom: no shared vertex */
    ray = ray_to(rtt_v3(0.5f, -5, 0.1f));
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 1.0f, 0.0f);
    fixture_free(&f);
}

static void test_material_width_scale_widens_thin_occluders(void **state)
{
    (void)state;
    fixture f;
    thin_plate_fixture(&f, 20.0f);
    rtt_ray ray = ray_to(rtt_v3(0.3f, -5, 0.2f));
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 0.05f, false);
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 0.8f, 1e-3f);
    fixture_free(&f);
}

static void test_open_mesh_casts_a_hard_shadow(void **state)
{
    (void)state;
    fixture f;
    f.scene = scene_begin();
    add_quad(f.scene, rtt_v3(-2, 0, -2), rtt_v3(2, 0, -2), rtt_v3(2, 0, 2), rtt_v3(-2, 0, 2));
    fixture_build(&f);
    assert_false(f.scene->meshes[0].closed);
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 1e30f, false);
    rtt_ray ray = ray_to(rtt_v3(0.3f, -5, 0.2f));
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 1.0f, 0.0f);
    ray = ray_to(rtt_v3(7.0f, -5, 0.2f)); /* misses the quad */
    assert_float_equal(rtt_edge_width_reference(&f.tree, &m, &ray, NULL), 0.0f, 0.0f);
    fixture_free(&f);
}

/* A ray through the diagonal shared by the top face's two triangles enters
 * once, not twice (the cluster rule). */
static void test_ray_through_a_shared_edge_enters_once(void **state)
{
    (void)state;
    fixture f;
    cube_fixture(&f);
    /* the top face's diagonal runs through its centre; aim at the centre */
    float occ;
    float w = width_along(&f, rtt_v3(0.0f, -5, 0.0f), &occ);
    assert_float_equal(w, 2.0f / 15.0f, 1e-5f);
    assert_float_equal(occ, 0.0f, 1e-6f);
    fixture_free(&f);
}

/* The shared pairing fed by hand: entries and exits in several batches
 * (leaves) give the same widths as one sorted list. */
static void test_pairing_carries_the_open_entry_across_batches(void **state)
{
    (void)state;
    fixture f;
    f.scene = scene_begin();
    for (int i = 0; i < 3; i++) add_box(f.scene, rtt_v3(10.0f * i, 0, 0), rtt_v3(10.0f * i + 1, 1, 1), 0);
    scene_end(f.scene);
    rtt_edge_width_model m = rtt_edge_width_model_make(f.scene, 0.5f, false);
    rtt_edge_width_state s;
    const float dir[3] = {1, 0, 0};
    rtt_edge_width_start(&s, dir);
    /* crossings of prims of boxes 0, 1 (12 triangles each); leaf A: entry
     * only; leaf B: exit, entry; leaf C: exit */
    assert_false(rtt_edge_width_feed(&m, &s, 0.10f, 0));
    assert_true(s.inside);
    assert_false(rtt_edge_width_feed(&m, &s, 0.15f, 5));
    assert_false(rtt_edge_width_feed(&m, &s, 0.30f, 12));
    assert_false(rtt_edge_width_feed(&m, &s, 0.42f, 17));
    assert_false(s.inside);
    assert_float_equal(s.max_width, 0.12f, 1e-6f);
    assert_float_equal(rtt_edge_width_finish(&m, &s), 0.24f, 1e-5f);
    /* a third pair wider than R decides the occlusion */
    assert_false(rtt_edge_width_feed(&m, &s, 0.5f, 24));
    assert_true(rtt_edge_width_feed(&m, &s, 1.2f, 30));
    assert_float_equal(rtt_edge_width_finish(&m, &s), 1.0f, 0.0f);
    rtt_scene_free(f.scene);
}

/* ---- the reference renderer ---- */

static void test_reference_renderer_draws_an_edge_width_penumbra(void **state)
{
    (void)state;
    fixture f;
    f.scene = scene_begin();
    add_box(f.scene, rtt_v3(-1, 2, -1), rtt_v3(1, 4, 1), 0);
    add_box(f.scene, rtt_v3(-6, -1, -6), rtt_v3(6, 0, 6), 0); /* the floor, closed */
    f.scene->camera = (rtt_camera){rtt_v3(0, 15, 0.01f), rtt_v3(0, 0, 0), rtt_v3(0, 0, -1), 60.0f};
    f.scene->width = f.scene->height = 48;
    fixture_build(&f);
    rtt_error err = {{0}};
    rtt_engine *engine = rtt_reference_engine_create(f.scene, NULL, &err);
    assert_non_null(engine);
    rtt_image *hard = rtt_image_create(48, 48, 0, &err), *soft = rtt_image_create(48, 48, 0, &err);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.threads = 2;
    opt.shadows = RTT_SHADOWS_HARD;
    assert_true(rtt_reference_render(f.scene, engine, &opt, hard, NULL, &err));
    opt.shadows = RTT_SHADOWS_EDGEWIDTH;
    opt.edge_radius = 0.1f;
    if (!rtt_reference_render(f.scene, engine, &opt, soft, NULL, &err)) fail_msg("%s", err.message);
    /* edge widths only brighten nothing and darken nothing outside the hard
     * shadow; inside it some pixels are partly lit (the penumbra) */
    uint32_t partial = 0;
    for (uint32_t i = 0; i < 48u * 48u * 3u; i++) {
        assert_true(soft->rgb[i] >= hard->rgb[i] - 1e-6f);
        if (soft->rgb[i] > hard->rgb[i] + 1e-3f) partial++;
    }
    assert_true(partial > 0);
    rtt_image_free(hard);
    rtt_image_free(soft);
    rtt_engine_destroy(engine);
    fixture_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equation_5_1_maps_width_to_occlusion),
        cmocka_unit_test(test_edge_width_ray_runs_from_the_light_centre_as_a_fraction),
        cmocka_unit_test(test_cube_widths_along_known_rays),
        cmocka_unit_test(test_occlusion_is_width_over_r_and_one_beyond_r),
        cmocka_unit_test(test_ray_ending_inside_an_object_is_fully_occluded),
        cmocka_unit_test(test_widths_of_two_occluders_take_the_maximum),
        cmocka_unit_test(test_thin_plate_leaks_and_the_leak_fix_closes_it),
        cmocka_unit_test(test_leak_fix_keeps_widths_of_faces_that_share_a_vertex),
        cmocka_unit_test(test_material_width_scale_widens_thin_occluders),
        cmocka_unit_test(test_open_mesh_casts_a_hard_shadow),
        cmocka_unit_test(test_ray_through_a_shared_edge_enters_once),
        cmocka_unit_test(test_pairing_carries_the_open_entry_across_batches),
        cmocka_unit_test(test_reference_renderer_draws_an_edge_width_penumbra),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The scene model (scene/scene.c, scene/transform.c) and the shading model
 * (scene/shade.c): vector maths, mesh validation, defaults, closedness,
 * degenerate counts, camera rays, light samples, weights and refraction. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rtt/scene.h"
#include "rtt/shade.h"
#include "scene_build.h"

static void assert_near(float a, float b, float tolerance)
{
    if (!(fabsf(a - b) <= tolerance)) fail_msg("%.9g is not within %g of %.9g", a, tolerance, b);
}

static void test_vector_maths(void **state)
{
    (void)state;
    rtt_vec3 a = rtt_v3(1, 2, 3), b = rtt_v3(-4, 5, 0.5f);
    assert_near(rtt_v3_dot(a, b), -4 + 10 + 1.5f, 0);
    rtt_vec3 c = rtt_v3_cross(rtt_v3(1, 0, 0), rtt_v3(0, 1, 0));
    assert_near(c.x, 0, 0), assert_near(c.y, 0, 0), assert_near(c.z, 1, 0);
    assert_near(rtt_v3_length(rtt_v3_normalize(b)), 1, 1e-6f);
    rtt_vec3 zero = rtt_v3_normalize(rtt_v3(0, 0, 0));
    assert_true(zero.x == 0 && zero.y == 0 && zero.z == 0);
    rtt_vec3 r = rtt_v3_reflect(rtt_v3(1, -1, 0), rtt_v3(0, 1, 0));
    assert_near(r.x, 1, 0), assert_near(r.y, 1, 0);
    rtt_bounds box = rtt_bounds_grow(rtt_bounds_grow(rtt_bounds_empty(), a), b);
    assert_false(rtt_bounds_is_empty(box));
    assert_near(rtt_bounds_area(box), 2.0f * (5 * 3 + 3 * 2.5f + 2.5f * 5), 1e-5f);
    assert_near(rtt_bounds_area(rtt_bounds_empty()), 0, 0);
    assert_false(rtt_v3_is_finite(rtt_v3(NAN, 0, 0)));
}

/* A unit cube: 8 shared vertices, 12 triangles. */
static const rtt_vec3 cube_positions[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                           {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const uint32_t cube_indices[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                          3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static rtt_scene *cube_scene(uint32_t triangles)
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("cube", &err);
    assert_non_null(scene);
    rtt_material m = rtt_material_default();
    assert_int_equal(rtt_scene_add_material(scene, &m), 0);
    if (!rtt_scene_add_mesh(scene, "cube", "cube", cube_positions, NULL, 8, cube_indices, triangles, NULL, 0, NULL,
                            &err))
        fail_msg("%s", err.message);
    if (!rtt_scene_finish(scene, &err)) fail_msg("%s", err.message);
    return scene;
}

static void test_finish_fills_every_default(void **state)
{
    (void)state;
    rtt_scene *scene = cube_scene(12);
    assert_int_equal(scene->width, RTT_DEFAULT_WIDTH);
    assert_int_equal(scene->height, RTT_DEFAULT_HEIGHT);
    assert_int_equal(scene->light_count, 1);
    assert_int_equal(scene->lights[0].type, RTT_LIGHT_POINT);
    assert_near(scene->camera.fov_deg, RTT_DEFAULT_FOV_DEG, 0);
    assert_near(scene->camera.look_at.x, 0.5f, 1e-6f);
    /* the camera frames the bounds: every corner is in front of it and inside the view */
    rtt_camera_frame frame = rtt_camera_frame_make(&scene->camera, 64, 64);
    rtt_vec3 forward = rtt_v3_normalize(rtt_v3_sub(scene->camera.look_at, scene->camera.eye));
    for (int i = 0; i < 8; i++) {
        rtt_vec3 to = rtt_v3_normalize(rtt_v3_sub(cube_positions[i], frame.eye));
        assert_true(rtt_v3_dot(to, forward) > cosf(0.5f * RTT_DEFAULT_FOV_DEG * 3.14159265f / 180.0f));
    }
    assert_near(scene->lights[0].position.z, scene->camera.eye.z, 0);
    assert_int_equal(scene->material_count, 1);
    assert_int_equal(scene->materials[0].type, RTT_MATERIAL_DIFFUSE);
    assert_near(scene->bounds.hi.x, 1, 0);
    rtt_scene_free(scene);
}

static void test_closed_and_open_meshes_are_told_apart(void **state)
{
    (void)state;
    rtt_scene *closed = cube_scene(12), *open = cube_scene(10);
    assert_true(closed->meshes[0].closed);
    assert_false(open->meshes[0].closed);
    rtt_scene_free(closed);
    rtt_scene_free(open);
}

static void test_split_vertices_at_seams_still_close_a_mesh(void **state)
{
    (void)state;
    /* the cube with every triangle on its own three vertices (as importers split at normal seams) */
    float xyz[12 * 9];
    for (int t = 0; t < 12; t++)
        for (int k = 0; k < 3; k++) memcpy(&xyz[9 * t + 3 * k], &cube_positions[cube_indices[3 * t + k]], 12);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, 12, &err);
    assert_non_null(scene);
    assert_true(scene->meshes[0].closed);
    rtt_scene_free(scene);
}

static void test_degenerate_triangles_are_kept_and_counted(void **state)
{
    (void)state;
    const float xyz[27] = {0, 0, 0, 1, 0, 0, 0, 1, 0, /* fine */
                           0, 0, 0, 1, 1, 1, 2, 2, 2, /* collinear */
                           3, 3, 3, 3, 3, 3, 3, 3, 3 /* a point */};
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, 3, &err);
    assert_non_null(scene);
    assert_int_equal(scene->triangle_count, 3);
    assert_int_equal(scene->degenerate_count, 2);
    rtt_scene_free(scene);
}

static void test_non_finite_coordinates_are_refused_with_the_vertex(void **state)
{
    (void)state;
    float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    xyz[4] = NAN;
    rtt_error err = {{0}};
    assert_null(rtt_scene_from_triangles(xyz, 1, &err));
    assert_string_equal(err.message, "triangles: vertex 1 has a NaN or infinite coordinate");
    xyz[4] = INFINITY;
    assert_null(rtt_scene_from_triangles(xyz, 1, &err));
    assert_string_equal(err.message, "triangles: vertex 1 has a NaN or infinite coordinate");
}

static void test_out_of_range_index_is_refused_with_the_face(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("bad.obj", &err);
    rtt_material m = rtt_material_default();
    rtt_scene_add_material(scene, &m);
    const uint32_t indices[6] = {0, 1, 2, 0, 2, 8};
    assert_false(
        rtt_scene_add_mesh(scene, "bad.obj", "m", cube_positions, NULL, 8, indices, 2, NULL, 0, NULL, &err));
    assert_string_equal(err.message, "bad.obj: face 1: vertex index 8 is out of range (8 vertices)");
    rtt_scene_free(scene);
}

static void test_empty_scene_is_refused(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("empty.obj", &err);
    assert_false(rtt_scene_finish(scene, &err));
    assert_string_equal(err.message, "empty.obj: the scene has no triangles");
    rtt_scene_free(scene);
}

static void test_transform_moves_points_and_turns_normals(void **state)
{
    (void)state;
    const double scale_x2_move_z[16] = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 5, 0, 0, 0, 1};
    const rtt_vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const rtt_vec3 n[3] = {{0, 0, 1}, {0.70710678f, 0, 0.70710678f}, {0, 0, 1}};
    const uint32_t idx[3] = {0, 1, 2};
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("t", &err);
    rtt_material m = rtt_material_default();
    rtt_scene_add_material(scene, &m);
    assert_true(rtt_scene_add_mesh(scene, "t", "t", p, n, 3, idx, 1, NULL, 0, scale_x2_move_z, &err));
    assert_true(rtt_scene_finish(scene, &err));
    double moved[3];
    rtt_scene_point_from_stored(scene, scene->vertices[1], moved);
    assert_near((float)moved[0], 2, 0);
    assert_near((float)moved[2], 5, 0);
    /* a normal (1,0,1)/sqrt2 under x scaled by 2 becomes (1,0,2)/sqrt5 */
    assert_near(scene->normals[1].x, 1 / sqrtf(5), 1e-6f);
    assert_near(scene->normals[1].z, 2 / sqrtf(5), 1e-6f);
    rtt_scene_free(scene);
}

static void test_missing_file_is_one_line(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    assert_null(rtt_scene_load("/nonexistent/scene.json", NULL, &err));
    assert_string_equal(err.message, "/nonexistent/scene.json: cannot open: No such file or directory");
}

static void test_camera_rays_go_through_pixel_centres(void **state)
{
    (void)state;
    rtt_camera cam = {rtt_v3(0, 0, 5), rtt_v3(0, 0, 0), rtt_v3(0, 1, 0), 90.0f};
    rtt_camera_frame f = rtt_camera_frame_make(&cam, 2, 2);
    rtt_ray top_left = rtt_camera_ray(&f, 0, 0);
    /* 90 degrees: the image plane at distance 1 spans [-1, 1]; pixel centre (-0.5, 0.5) */
    rtt_vec3 expect = rtt_v3_normalize(rtt_v3(-0.5f, 0.5f, -1));
    assert_near(top_left.dir[0], expect.x, 1e-6f);
    assert_near(top_left.dir[1], expect.y, 1e-6f);
    assert_near(top_left.dir[2], expect.z, 1e-6f);
    assert_near(top_left.tnear, 0, 0);
    assert_true(isinf(top_left.tfar));
}

static void test_light_samples_lie_on_the_disk_facing_the_point(void **state)
{
    (void)state;
    rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = {0, 10, 0}, .radius = 2, .color = {1, 1, 1},
                       .intensity = 1, .attenuation = {1, 0, 0}};
    rtt_vec3 p = rtt_v3(0, 0, 0), mean = rtt_v3(0, 0, 0);
    for (uint32_t i = 0; i < 64; i++) {
        rtt_vec3 s = rtt_light_sample(&light, p, i, 64, 17);
        assert_near(s.y, 10, 1e-5f);                        /* the disk faces p: perpendicular to y */
        assert_true(hypotf(s.x, s.z) <= 2.0f + 1e-5f);
        mean = rtt_v3_add(mean, rtt_v3_scale(s, 1.0f / 64));
        rtt_vec3 again = rtt_light_sample(&light, p, i, 64, 17);
        assert_true(memcmp(&s, &again, sizeof s) == 0);     /* deterministic */
    }
    assert_near(mean.x, 0, 0.25f);
    assert_near(mean.z, 0, 0.25f);
    rtt_light point = light;
    point.type = RTT_LIGHT_POINT;
    rtt_vec3 c = rtt_light_sample(&point, p, 3, 16, 5);
    assert_near(c.y, 10, 0), assert_near(c.x, 0, 0);
    float h[2];
    rtt_hammersley(4, 8, h);
    assert_near(h[0], 0.5f, 0), assert_near(h[1], 0.125f, 0);
}

static void test_weights_and_refraction(void **state)
{
    (void)state;
    rtt_material m = rtt_material_default();
    float wr, wt;
    m.type = RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
    m.reflection = 0.6f, m.transparency = 0.6f;
    rtt_shade_weights(&m, 0, 3, &wr, &wt);
    assert_near(wr + wt, 1, 1e-6f);
    rtt_shade_weights(&m, 3, 3, &wr, &wt);
    assert_true(wr == 0 && wt == 0);
    m.type = RTT_MATERIAL_DIFFUSE;
    rtt_shade_weights(&m, 0, 3, &wr, &wt);
    assert_true(wr == 0 && wt == 0);
    /* straight through at normal incidence; total internal reflection at a grazing exit */
    rtt_vec3 d = rtt_refract(rtt_v3(0, -1, 0), rtt_v3(0, 1, 0), 1.0f, 1.5f);
    assert_near(d.y, -1, 1e-6f);
    rtt_vec3 in = rtt_v3_normalize(rtt_v3(1, -0.2f, 0));
    rtt_vec3 tir = rtt_refract(in, rtt_v3(0, 1, 0), 1.5f, 1.0f);
    assert_near(tir.y, 0.2f / rtt_v3_length(rtt_v3(1, -0.2f, 0)), 1e-6f);
    /* Snell: sin(out) = 1/1.5 sin(in) */
    rtt_vec3 d45 = rtt_v3_normalize(rtt_v3(1, -1, 0));
    rtt_vec3 out = rtt_refract(d45, rtt_v3(0, 1, 0), 1.0f, 1.5f);
    assert_near(out.x, sinf(3.14159265f / 4) / 1.5f, 1e-6f);
}

static void test_light_behind_the_surface_contributes_nothing(void **state)
{
    (void)state;
    rtt_material m = rtt_material_default();
    rtt_light light = {.type = RTT_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 2, .attenuation = {1, 0, 0.25f}};
    rtt_surface surface = {.normal = rtt_v3(0, 1, 0), .dir = rtt_v3(0, -1, 0), .diffuse = m.diffuse, .material = &m};
    rtt_vec3 c = rtt_shade_light(&surface, rtt_v3(0, -1, 0), &light, 2);
    assert_true(c.x == 0 && c.y == 0 && c.z == 0);
    c = rtt_shade_light(&surface, rtt_v3(0, 1, 0), &light, 2);
    assert_near(c.x, 0.7f * 2 / (1 + 0.25f * 4), 1e-6f);
}

static void test_ray_epsilon_scales_with_the_scene(void **state)
{
    (void)state;
    const float small[9] = {0, 0, 0, 1e-10f, 0, 0, 0, 1e-10f, 0};
    const float far[9] = {1e6f, 0, 0, 1e6f + 1, 0, 0, 1e6f, 1, 0};
    rtt_error err = {{0}};
    rtt_scene *a = rtt_scene_from_triangles(small, 1, &err), *b = rtt_scene_from_triangles(far, 1, &err);
    assert_true(rtt_scene_ray_epsilon(a) < 1e-14f);
    /* the far triangle is stored relative to its centre: its epsilon
     * follows its size (1), not its distance from the origin (1e6) */
    assert_true(b->origin[0] == 1e6 + 0.5);
    assert_true(rtt_scene_ray_epsilon(b) < 1e-3f);
    rtt_scene_free(a);
    rtt_scene_free(b);
}

/* A 1e-3 triangle 1e5 from the origin: at 1e5 a float's spacing is 8e-3, so
 * stored in absolute float it would collapse; read in double and stored
 * relative to its centre it keeps its shape.  A scene that is large as
 * well as far away is not centred, and its tiny triangle still collapses:
 * counted apart. */
static void test_a_small_mesh_far_from_the_origin_keeps_its_shape_and_collapses_are_counted(void **state)
{
    (void)state;
    const rtt_vec3 tiny[3] = {{0, 0, 0}, {1e-3f, 0, 0}, {0, 1e-3f, 0}};
    const uint32_t idx[3] = {0, 1, 2};
    const double move_1e5[16] = {1, 0, 0, 1e5, 0, 1, 0, 1e5, 0, 0, 1, 1e5, 0, 0, 0, 1};
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("far", &err);
    rtt_material m = rtt_material_default();
    rtt_scene_add_material(scene, &m);
    assert_true(rtt_scene_add_mesh(scene, "far", "tiny", tiny, NULL, 3, idx, 1, NULL, 0, move_1e5, &err));
    assert_true(rtt_scene_finish(scene, &err));
    assert_int_equal(scene->degenerate_count, 0);
    assert_int_equal(scene->collapsed_count, 0);
    assert_near(scene->vertices[1].x - scene->vertices[0].x, 1e-3f, 1e-9f);
    double p[3];
    rtt_scene_point_from_stored(scene, scene->vertices[1], p);
    assert_true(fabs(p[0] - (1e5 + 1e-3)) < 1e-9);
    rtt_scene_free(scene);

    const rtt_vec3 big[3] = {{-1e5f, -1e5f, 0}, {1e5f, -1e5f, 0}, {0, 1e5f, 0}};
    scene = rtt_scene_new("far and large", &err);
    rtt_scene_add_material(scene, &m);
    assert_true(rtt_scene_add_mesh(scene, "far", "big", big, NULL, 3, idx, 1, NULL, 0, NULL, &err));
    assert_true(rtt_scene_add_mesh(scene, "far", "tiny", tiny, NULL, 3, idx, 1, NULL, 0, move_1e5, &err));
    assert_true(rtt_scene_finish(scene, &err));
    assert_int_equal(scene->collapsed_count, 1);
    assert_int_equal(scene->degenerate_count, 1);
    rtt_scene_free(scene);
}

/* The builders' default depth bound: round(2 + log2 N), never below 8 nor
 * above 64, the same for both engines (include/rtt/engine.h). */
static void test_default_tree_depth_follows_log2_of_the_triangles(void **state)
{
    (void)state;
    assert_int_equal(rtt_kd_default_max_depth(0), 8);
    assert_int_equal(rtt_kd_default_max_depth(1), 8);
    assert_int_equal(rtt_kd_default_max_depth(64), 8);
    assert_int_equal(rtt_kd_default_max_depth(128), 9);
    assert_int_equal(rtt_kd_default_max_depth(43288), 17);    /* the demo */
    assert_int_equal(rtt_kd_default_max_depth(75408), 18);    /* bunny00 */
    assert_int_equal(rtt_kd_default_max_depth(1u << 20), 22);
    assert_int_equal(rtt_kd_default_max_depth(UINT32_MAX), 34);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vector_maths),
        cmocka_unit_test(test_finish_fills_every_default),
        cmocka_unit_test(test_closed_and_open_meshes_are_told_apart),
        cmocka_unit_test(test_split_vertices_at_seams_still_close_a_mesh),
        cmocka_unit_test(test_degenerate_triangles_are_kept_and_counted),
        cmocka_unit_test(test_non_finite_coordinates_are_refused_with_the_vertex),
        cmocka_unit_test(test_out_of_range_index_is_refused_with_the_face),
        cmocka_unit_test(test_empty_scene_is_refused),
        cmocka_unit_test(test_transform_moves_points_and_turns_normals),
        cmocka_unit_test(test_a_small_mesh_far_from_the_origin_keeps_its_shape_and_collapses_are_counted),
        cmocka_unit_test(test_missing_file_is_one_line),
        cmocka_unit_test(test_camera_rays_go_through_pixel_centres),
        cmocka_unit_test(test_light_samples_lie_on_the_disk_facing_the_point),
        cmocka_unit_test(test_weights_and_refraction),
        cmocka_unit_test(test_light_behind_the_surface_contributes_nothing),
        cmocka_unit_test(test_ray_epsilon_scales_with_the_scene),
        cmocka_unit_test(test_default_tree_depth_follows_log2_of_the_triangles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

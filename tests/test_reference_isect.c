/* The watertight ray/triangle test (Woop, Benthin, Wald 2013) on hand-made
 * cases: interior, edge and vertex hits, back faces, parallel rays, det 0,
 * the open interval (tnear, tfar), degenerate triangles, NaN rays, scales. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "rtt/reference.h"

static const rtt_vec3 unit_tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

static rtt_ray ray_make(float ox, float oy, float oz, float dx, float dy, float dz)
{
    return (rtt_ray){{ox, oy, oz}, {dx, dy, dz}, 0.0f, INFINITY};
}

static bool hits(const rtt_ray *ray, const rtt_vec3 tri[3])
{
    float t, u, v;
    return rtt_reference_intersect_triangle(ray, tri, &t, &u, &v);
}

static void test_interior_hit_gives_distance_and_barycentrics(void **state)
{
    (void)state;
    rtt_ray ray = ray_make(0.25f, 0.5f, 2.0f, 0.0f, 0.0f, -1.0f);
    float t = 0, u = 0, v = 0;
    assert_true(rtt_reference_intersect_triangle(&ray, unit_tri, &t, &u, &v));
    assert_float_equal(t, 2.0f, 1e-6f);
    assert_float_equal(u, 0.25f, 1e-6f); /* weight of vertex 1 = x */
    assert_float_equal(v, 0.5f, 1e-6f);  /* weight of vertex 2 = y */
}

static void test_barycentrics_reconstruct_the_hit_point_for_oblique_rays(void **state)
{
    (void)state;
    const rtt_vec3 tri[3] = {{1, 2, 3}, {4, -1, 2}, {0, 5, -2}};
    rtt_vec3 target = rtt_v3_add(rtt_v3_add(rtt_v3_scale(tri[0], 0.2f), rtt_v3_scale(tri[1], 0.3f)),
                                 rtt_v3_scale(tri[2], 0.5f));
    rtt_vec3 org = {-3, 7, 9};
    rtt_vec3 dir = rtt_v3_sub(target, org);
    rtt_ray ray = ray_make(org.x, org.y, org.z, dir.x, dir.y, dir.z);
    float t, u, v;
    assert_true(rtt_reference_intersect_triangle(&ray, tri, &t, &u, &v));
    assert_float_equal(t, 1.0f, 1e-5f);
    assert_float_equal(u, 0.3f, 1e-5f);
    assert_float_equal(v, 0.5f, 1e-5f);
}

static void test_back_face_is_hit_too(void **state)
{
    (void)state;
    rtt_ray front = ray_make(0.25f, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray back = ray_make(0.25f, 0.25f, -1.0f, 0.0f, 0.0f, 1.0f);
    float t, u, v;
    assert_true(rtt_reference_intersect_triangle(&back, unit_tri, &t, &u, &v));
    assert_float_equal(t, 1.0f, 1e-6f);
    assert_true(hits(&front, unit_tri));
}

static void test_rays_through_edges_and_vertices_hit(void **state)
{
    (void)state;
    const float points[][2] = {{0.5f, 0.0f}, {0.0f, 0.5f}, {0.5f, 0.5f}, {0, 0}, {1, 0}, {0, 1}};
    for (size_t i = 0; i < sizeof points / sizeof points[0]; i++) {
        rtt_ray down = ray_make(points[i][0], points[i][1], 1.0f, 0.0f, 0.0f, -1.0f);
        rtt_ray up = ray_make(points[i][0], points[i][1], -1.0f, 0.0f, 0.0f, 1.0f);
        assert_true(hits(&down, unit_tri));
        assert_true(hits(&up, unit_tri));
    }
}

static void test_rays_just_outside_an_edge_miss(void **state)
{
    (void)state;
    rtt_ray left = ray_make(-1e-7f, 0.5f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray below = ray_make(0.5f, -1e-7f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray beyond = ray_make(0.5f, nextafterf(0.5f, 1.0f), 1.0f, 0.0f, 0.0f, -1.0f);
    assert_false(hits(&left, unit_tri));
    assert_false(hits(&below, unit_tri));
    assert_false(hits(&beyond, unit_tri));
}

/* Watertightness on a shared edge: every ray through the diagonal of a
 * planar quad made of two triangles hits at least one of them, from any
 * direction.  (The quad is planar, with exact dyadic corners, because at a
 * fold seen edge-on a ray passing just beside the edge rightly misses both.) */
static void test_shared_edge_never_lets_a_ray_through(void **state)
{
    (void)state;
    /* in the plane z = 0.25 + 0.125 x + 0.25 y */
    const rtt_vec3 p00 = {0.0f, 0.0f, 0.25f}, p10 = {2.0f, 0.0f, 0.5f}, p01 = {0.0f, 2.0f, 0.75f},
                   p11 = {2.0f, 2.0f, 1.0f};
    const rtt_vec3 first[3] = {p00, p10, p11}, second[3] = {p00, p11, p01};
    uint32_t seed = 12345u;
    for (int i = 0; i < 20000; i++) {
        seed = seed * 1664525u + 1013904223u;
        float s = (float)(seed >> 8) / 16777216.0f;
        seed = seed * 1664525u + 1013904223u;
        float theta = (float)(seed >> 8) / 16777216.0f * 6.2831853f;
        seed = seed * 1664525u + 1013904223u;
        float z = 0.2f + (float)(seed >> 8) / 16777216.0f;
        rtt_vec3 target = rtt_v3_add(p00, rtt_v3_scale(rtt_v3_sub(p11, p00), s));
        rtt_vec3 org = rtt_v3_add(target, rtt_v3(cosf(theta), sinf(theta), (i & 1) ? z : -z));
        rtt_vec3 dir = rtt_v3_sub(target, org);
        rtt_ray ray = ray_make(org.x, org.y, org.z, dir.x, dir.y, dir.z);
        assert_true(hits(&ray, first) || hits(&ray, second));
    }
}

static void test_ray_parallel_to_the_plane_misses(void **state)
{
    (void)state;
    rtt_ray in_plane = ray_make(-1.0f, 0.25f, 0.0f, 1.0f, 0.0f, 0.0f);  /* det 0 */
    rtt_ray above = ray_make(-1.0f, 0.25f, 0.5f, 1.0f, 0.0f, 0.0f);
    rtt_ray diagonal_in_plane = ray_make(-1.0f, -1.0f, 0.0f, 1.0f, 1.0f, 0.0f);
    assert_false(hits(&in_plane, unit_tri));
    assert_false(hits(&above, unit_tri));
    assert_false(hits(&diagonal_in_plane, unit_tri));
}

static void test_hit_counts_only_strictly_between_tnear_and_tfar(void **state)
{
    (void)state;
    rtt_ray ray = ray_make(0.25f, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    ray.tnear = 1.0f; /* exactly at t */
    assert_false(hits(&ray, unit_tri));
    ray.tnear = 0.0f;
    ray.tfar = 1.0f;
    assert_false(hits(&ray, unit_tri));
    ray.tnear = nextafterf(1.0f, 0.0f);
    ray.tfar = nextafterf(1.0f, 2.0f);
    assert_true(hits(&ray, unit_tri));
    ray.tnear = 0.0f;
    ray.tfar = INFINITY;
    ray.org[2] = -1.0f; /* triangle behind the origin */
    assert_false(hits(&ray, unit_tri));
}

static void test_degenerate_triangles_never_hit(void **state)
{
    (void)state;
    const rtt_vec3 collinear[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    const rtt_vec3 repeated[3] = {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}};
    const rtt_vec3 point[3] = {{0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}};
    rtt_ray at_line = ray_make(1.0f, 1.0f, 5.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray at_edge = ray_make(0.0f, 0.5f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray at_point = ray_make(0.5f, 0.5f, 1.0f, 0.0f, 0.0f, -1.0f);
    assert_false(hits(&at_line, collinear));
    assert_false(hits(&at_edge, repeated));
    assert_false(hits(&at_point, point));
}

static void test_nan_and_zero_rays_miss(void **state)
{
    (void)state;
    rtt_ray nan_dir = ray_make(0.25f, 0.25f, 1.0f, NAN, 0.0f, -1.0f);
    rtt_ray nan_org = ray_make(NAN, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    rtt_ray zero_dir = ray_make(0.25f, 0.25f, 1.0f, 0.0f, 0.0f, 0.0f);
    rtt_ray nan_interval = ray_make(0.25f, 0.25f, 1.0f, 0.0f, 0.0f, -1.0f);
    nan_interval.tfar = NAN;
    assert_false(hits(&nan_dir, unit_tri));
    assert_false(hits(&nan_org, unit_tri));
    assert_false(hits(&zero_dir, unit_tri));
    assert_false(hits(&nan_interval, unit_tri));
}

static void test_negative_zero_direction_components_are_handled(void **state)
{
    (void)state;
    rtt_ray ray = ray_make(0.25f, 0.25f, 1.0f, -0.0f, -0.0f, -1.0f);
    float t, u, v;
    assert_true(rtt_reference_intersect_triangle(&ray, unit_tri, &t, &u, &v));
    assert_float_equal(t, 1.0f, 1e-6f);
}

/* Float edge functions overflow at 1e20 (scale^2) and underflow at 1e-20;
 * the double fallback keeps the test exact there. */
static void test_tiny_and_huge_scales_hit_like_unit_scale(void **state)
{
    (void)state;
    const float scales[] = {1e-20f, 1e-13f, 1e13f, 1e20f};
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        float s = scales[i];
        rtt_vec3 tri[3] = {{0, 0, 0}, {s, 0, 0}, {0, s, 0}};
        rtt_ray ray = ray_make(0.25f * s, 0.5f * s, 2.0f * s, -0.1f, -0.05f, -1.0f);
        float t, u, v;
        assert_true(rtt_reference_intersect_triangle(&ray, tri, &t, &u, &v));
        assert_float_equal(t / s, 2.0f, 1e-5f);
        assert_float_equal(u, 0.25f - 0.2f, 1e-5f);
        assert_float_equal(v, 0.5f - 0.1f, 1e-5f);
        rtt_ray outside = ray_make(0.75f * s, 0.5f * s, 2.0f * s, 0.0f, 0.0f, -1.0f);
        assert_false(hits(&outside, tri));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_interior_hit_gives_distance_and_barycentrics),
        cmocka_unit_test(test_barycentrics_reconstruct_the_hit_point_for_oblique_rays),
        cmocka_unit_test(test_back_face_is_hit_too),
        cmocka_unit_test(test_rays_through_edges_and_vertices_hit),
        cmocka_unit_test(test_rays_just_outside_an_edge_miss),
        cmocka_unit_test(test_shared_edge_never_lets_a_ray_through),
        cmocka_unit_test(test_ray_parallel_to_the_plane_misses),
        cmocka_unit_test(test_hit_counts_only_strictly_between_tnear_and_tfar),
        cmocka_unit_test(test_degenerate_triangles_never_hit),
        cmocka_unit_test(test_nan_and_zero_rays_miss),
        cmocka_unit_test(test_negative_zero_direction_components_are_handled),
        cmocka_unit_test(test_tiny_and_huge_scales_hit_like_unit_scale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

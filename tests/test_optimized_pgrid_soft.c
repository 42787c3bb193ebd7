/* --shadows pgrid:N (optimized/pgrid/pgrid_soft.h): the 3D light grids'
 * slice traverser per ray against the reference engine and a brute force
 * over every triangle (the reference's watertight test), at every
 * instruction set this CPU runs and at several resolutions and slice counts.
 * The rays: multi:N's (each origin's N samples of a sphere or quad light,
 * rtt_light_sample, the shader proxy's segment), rays to the light's centre,
 * and arbitrary rays (random origins, directions and lengths, some
 * unbounded) that start nowhere near the light; origins at the eye rays'
 * hits and all over the scene's box; lights at the scenes' places, inside
 * the geometry and on a triangle's corner (the near list).  Then the
 * renderer: pgrid:N's image is multi:N's bit for bit (the optimized
 * renderer's under every --accel, the reference's under kd and bvh), and
 * the method's parse and refusals. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "engine_optimized.h"
#include "pgrid_eye.h"
#include "pgrid_soft.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "test_fixtures_pgrid.h"
#include "test_isa.h"
#include "test_scale.h"

enum { SAMPLES = 8 };

/* The rays of one light: multi:N's samples from every point (packets of one
 * origin), one to the centre from every fourth, then `arbitrary` random rays. */
static rtt_ray *light_rays(const rtt_scene *s, const rtt_light *light, const rtt_vec3 *points, uint32_t count,
                           uint32_t arbitrary, uint32_t *seed, uint32_t *n_out)
{
    rtt_ray *rays = malloc(((size_t)count * (SAMPLES + 1) + arbitrary + 1) * sizeof *rays);
    assert_non_null(rays);
    uint32_t n = 0;
    for (uint32_t i = 0; i < count; i++) {
        for (uint32_t k = 0; k < SAMPLES; k++)
            if (shadow_ray(s, points[i], rtt_light_sample(light, points[i], k, SAMPLES, i), &rays[n])) n++;
        if (i % 4 == 0 && shadow_ray(s, points[i], light->position, &rays[n])) n++;
    }
    const rtt_vec3 lo = s->bounds.lo, hi = s->bounds.hi, grow = rtt_v3_scale(rtt_v3_sub(hi, lo), 0.25f);
    const float size = rtt_v3_length(rtt_v3_sub(hi, lo));
    for (uint32_t i = 0; i < arbitrary; i++) {
        rtt_vec3 d = {random_in(seed, -1, 1), random_in(seed, -1, 1), random_in(seed, -1, 1)};
        if (!(rtt_v3_length(d) > 1e-3f)) d = rtt_v3(0, 0, 1);
        d = rtt_v3_normalize(d);
        const rtt_vec3 o = {random_in(seed, lo.x - grow.x, hi.x + grow.x), random_in(seed, lo.y - grow.y, hi.y + grow.y),
                            random_in(seed, lo.z - grow.z, hi.z + grow.z)};
        const float tfar = i % 5 == 0 ? INFINITY : random_in(seed, 0.0f, 1.5f * size);
        rays[n++] = (rtt_ray){{o.x, o.y, o.z}, {d.x, d.y, d.z}, rtt_scene_ray_epsilon(s), tfar};
    }
    *n_out = n;
    return rays;
}

typedef struct {
    uint32_t res, slices; /* 0: the defaults */
} grid_shape;

/* One light's grid of `shape` at every instruction set this CPU runs, on
 * `rays`, against `expected` (the brute force's answers). */
static void check_grid_shape(const pgrid_soft *grids, const rtt_light *light, const rtt_ray *rays, uint32_t n,
                             const uint8_t *expected, uint8_t *ours, grid_shape shape, const char *what)
{
    pgrid_soft one = *grids;
    pgrid_soft_light grid;
    const float position[3] = {light->position.x, light->position.y, light->position.z};
    assert_true(pgrid_soft_light_build(&grid, grids, position, pgrid_soft_light_extent(light), shape.res,
                                       shape.slices));
    one.lights = &grid, one.light_count = 1;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        assert_non_null(k);
        assert_int_equal(k->isa, isa);
        pgrid_soft_counts counts = {0};
        memset(ours, 7, n);
        k->soft_occluded(&one, 0, rays, n, ours, &counts);
        for (uint32_t i = 0; i < n; i++)
            if (ours[i] != expected[i])
                fail_msg("%s (%s, res %u, %u slices): ray %u from (%g %g %g) dir (%g %g %g) t (%g, %g): grid %u, "
                         "reference %u",
                         what, rtt_isa_name(isa), grid.res, grid.slices, i, (double)rays[i].org[0],
                         (double)rays[i].org[1], (double)rays[i].org[2], (double)rays[i].dir[0],
                         (double)rays[i].dir[1], (double)rays[i].dir[2], (double)rays[i].tnear,
                         (double)rays[i].tfar, ours[i], expected[i]);
        assert_true(counts.rays > 0 && counts.rays <= n);
        /* in small batches: packets cut elsewhere */
        for (uint32_t first = 0; first < n; first += 13) {
            const uint32_t m = n - first < 13 ? n - first : 13;
            k->soft_occluded(&one, 0, rays + first, m, ours + first, NULL);
        }
        for (uint32_t i = 0; i < n; i++) assert_int_equal(ours[i], expected[i]);
    }
    print_message("%s: res %u x %u slices, %u rays, %u near, %zu refs\n", what, grid.res, grid.slices, n,
                  grid.near_count, grid.ref_count);
    pgrid_soft_light_free(&grid);
}

/* Every ray of `light` (at `position`, samples on `light`) through grids of
 * each of `shapes`, against the reference engine and the brute force (once
 * per light: the rays do not depend on the grid). */
static void check_soft_light(const rtt_scene *s, rtt_engine *ref, const pgrid_soft *grids, const rtt_vec3 *points,
                             uint32_t point_count, const grid_shape *shapes, size_t shape_count,
                             const rtt_light *light, uint32_t seed, const char *what)
{
    uint32_t n;
    rtt_ray *rays = light_rays(s, light, points, point_count, test_sweep(600), &seed, &n);
    uint8_t *expected = malloc(n + 1), *engine = malloc(n + 1), *ours = malloc(n + 1);
    assert_true(expected && engine && ours);
    const uint32_t blocked = expected_occlusion(s, ref, rays, n, expected, engine, what);
    for (size_t g = 0; g < shape_count; g++) check_grid_shape(grids, light, rays, n, expected, ours, shapes[g], what);
    print_message("%s: %u rays, %u occluded\n", what, n, blocked);
    if (n > 200) assert_true(blocked > 0 && blocked < n); /* both answers were checked */
    free(rays);
    free(expected);
    free(engine);
    free(ours);
}

static void test_soft_grid_rays_match_reference_and_brute_force(void **state)
{
    (void)state;
    /* demo.json (the largest) is checked through the renderer below */
    static const char *const scenes[] = {"light_quad.json", "light_sphere.json", "shadow_on_shadow.json",
                                         "shadow_occluder_sizes.json", "shadow_thin_plate.json", "mesh_obj.json"};
    /* 600 cells a side: past the column scan's 512, the rectangles' path (pgrid_soft_trace.c) */
    static const grid_shape shapes[] = {{0, 0}, {7, 1}, {64, 9}, {600, 2}};
    const size_t shape_count = sizeof shapes / sizeof shapes[0];
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_non_null(ref);
        pgrid_soft grids;
        assert_true(pgrid_soft_build(&grids, s, NULL, 0, 0, &err));
        assert_int_equal(grids.light_count, s->light_count);
        assert_int_equal(grids.lights[0].res, PGRID_SOFT_RES_DEFAULT);
        assert_int_equal(grids.lights[0].slices, PGRID_SOFT_SLICES_DEFAULT);
        uint32_t count, *prims;
        rtt_vec3 *points = shadow_origins(s, ref, 16, test_sweep(12), test_sweep(120), &count, 7u + (uint32_t)sc, &prims);
        uint32_t seed = 99u + (uint32_t)sc;
        char what[96];
        for (uint32_t l = 0; l < s->light_count; l++) {
            snprintf(what, sizeof what, "%s light %u", scenes[sc], l);
            check_soft_light(s, ref, &grids, points, count, shapes, shape_count, &s->lights[l], seed + l, what);
        }
        /* sphere lights inside the scene's box: near triangles, rays from every side */
        for (int k = 0; k < 2; k++) {
            const rtt_vec3 lo = s->bounds.lo, hi = s->bounds.hi;
            rtt_light inside = s->lights[0];
            inside.type = RTT_LIGHT_SPHERE;
            inside.radius = 0.05f * rtt_v3_length(rtt_v3_sub(hi, lo));
            inside.position = (rtt_vec3){random_in(&seed, lo.x, hi.x), random_in(&seed, lo.y, hi.y),
                                         random_in(&seed, lo.z, hi.z)};
            snprintf(what, sizeof what, "%s light inside %d", scenes[sc], k);
            check_soft_light(s, ref, &grids, points, count, shapes, shape_count, &inside, seed, what);
        }
        free(points);
        free(prims);
        pgrid_soft_free(&grids);
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

/* A soup of random triangles, some huge, some tiny, lights among them. */
static void test_soft_grid_on_a_triangle_soup(void **state)
{
    (void)state;
    uint32_t seed = 4242u;
    rtt_scene *s = triangle_soup(&seed);
    rtt_error err = {{0}};
    rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
    assert_non_null(ref);
    pgrid_soft grids;
    assert_true(pgrid_soft_build(&grids, s, NULL, 0, 0, &err));
    uint32_t count, *prims;
    rtt_vec3 *points = shadow_origins(s, ref, 16, test_sweep(16), test_sweep(400), &count, 5u, &prims);
    for (int l = 0; l < 5; l++) {
        rtt_light light = {0};
        light.type = l % 2 ? RTT_LIGHT_QUAD : RTT_LIGHT_SPHERE;
        light.position = l == 4 ? s->vertices[s->triangles[3].v[1]] /* on a corner: a near triangle */
                                : (rtt_vec3){random_in(&seed, -1.2f, 1.2f), random_in(&seed, -1.2f, 1.2f),
                                             random_in(&seed, -1.2f, 1.2f)};
        light.radius = light.type == RTT_LIGHT_SPHERE ? 0.1f : 0.0f;
        light.edge_u = light.type == RTT_LIGHT_QUAD ? rtt_v3(0.3f, 0.0f, 0.05f) : rtt_v3(0, 0, 0);
        light.edge_v = light.type == RTT_LIGHT_QUAD ? rtt_v3(0.0f, 0.2f, 0.0f) : rtt_v3(0, 0, 0);
        light.intensity = 1.0f;
        const grid_shape shape = {l % 2 ? 200 : 16, l == 2 ? 4 : 3};
        check_soft_light(s, ref, &grids, points, count, &shape, 1, &light, seed, "soup");
    }
    free(points);
    free(prims);
    pgrid_soft_free(&grids);
    rtt_engine_destroy(ref);
    rtt_scene_free(s);
}

static bool render(rtt_engine *engine, const rtt_scene *s, rtt_engine *ref, rtt_shadow_method m, rtt_accel accel,
                   rtt_isa isa, rtt_image *out)
{
    rtt_render_options ro;
    rtt_render_options_default(&ro);
    ro.width = 80, ro.height = 60, ro.threads = 2;
    ro.shadows = m, ro.shadow_samples = SAMPLES;
    ro.engine.accel = accel, ro.engine.isa = isa;
    rtt_error err = {{0}};
    const bool ok = engine ? rtt_optimized_render(engine, &ro, out, NULL, &err)
                           : rtt_reference_render(s, ref, &ro, out, NULL, &err);
    if (!ok) fail_msg("%s: %s", rtt_shadow_method_name(m), err.message);
    return ok;
}

/* The renderer: pgrid:N's image is multi:N's, bit for bit. */
static void test_render_pgrid_soft_equals_multi(void **state)
{
    (void)state;
    static const char *const scenes[] = {"demo.json", "shadow_transparent.json", "light_quad.json", "light_point.json",
                                         "shadow_on_shadow.json"};
    static const rtt_accel accels[] = {RTT_ACCEL_KD, RTT_ACCEL_BVH, RTT_ACCEL_PGRID};
    const size_t bytes = (size_t)80 * 60 * 3 * sizeof(float);
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine *engine = rtt_optimized_engine_create(s, NULL, &err);
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_true(engine && ref);
        rtt_image *reference = rtt_image_create(80, 60, 0, &err);
        assert_non_null(reference);
        render(NULL, s, ref, RTT_SHADOWS_MULTI, RTT_ACCEL_DEFAULT, RTT_ISA_AUTO, reference);
        /* under TSan (test_scale.h) at the CPU's instruction set only */
        const rtt_isa first = TEST_TSAN ? rtt_isa_resolve(RTT_ISA_AUTO) : TEST_ISA_FIRST;
        for (rtt_isa isa = first; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            for (size_t a = 0; a < 3; a++) {
                rtt_image *multi = rtt_image_create(80, 60, 0, &err), *grid = rtt_image_create(80, 60, 0, &err);
                assert_true(multi && grid);
                render(engine, s, ref, RTT_SHADOWS_MULTI, accels[a], isa, multi);
                render(engine, s, ref, RTT_SHADOWS_PGRID_SOFT, accels[a], isa, grid);
                if (memcmp(multi->rgb, grid->rgb, bytes) != 0)
                    fail_msg("%s %s accel %d: pgrid:%d differs from multi:%d", scenes[sc], rtt_isa_name(isa),
                             (int)accels[a], SAMPLES, SAMPLES);
                /* kd and bvh shade the reference's hit points: the reference's image itself */
                if (accels[a] != RTT_ACCEL_PGRID && memcmp(reference->rgb, grid->rgb, bytes) != 0)
                    fail_msg("%s %s accel %d: pgrid:%d differs from the reference's multi:%d", scenes[sc],
                             rtt_isa_name(isa), (int)accels[a], SAMPLES, SAMPLES);
                rtt_image_free(multi);
                rtt_image_free(grid);
            }
        }
        rtt_image_free(reference);
        rtt_engine_destroy(engine);
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

static void test_pgrid_soft_parse_and_refusals(void **state)
{
    (void)state;
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_error err = {{0}};
    rtt_engine_register(&rtt_optimized_engine_class, NULL);
    rtt_engine_register(&rtt_reference_engine_class, NULL);
    assert_true(rtt_shadow_method_parse("pgrid:8", &opt, &err));
    assert_int_equal(opt.shadows, RTT_SHADOWS_PGRID_SOFT);
    assert_int_equal(opt.shadow_samples, 8);
    assert_true(rtt_shadow_method_parse("pgrid:256", &opt, &err));
    assert_int_equal(opt.shadow_samples, 256);
    assert_string_equal(rtt_shadow_method_name(RTT_SHADOWS_PGRID_SOFT), "pgrid");
    static const char *const bad[] = {"pgrid:0", "pgrid:257", "pgrid:", "pgrid:8x", "pgrid:-1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) assert_false(rtt_shadow_method_parse(bad[i], &opt, &err));
    assert_true(rtt_shadow_method_parse("pgrid:16", &opt, &err));
    if (!rtt_render_options_check("optimized", &opt, &err)) fail_msg("%s", err.message);
    assert_false(rtt_render_options_check("reference", &opt, &err));
    assert_non_null(strstr(err.message, "pgrid"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_soft_grid_rays_match_reference_and_brute_force),
        cmocka_unit_test(test_soft_grid_on_a_triangle_soup),
        cmocka_unit_test(test_render_pgrid_soft_equals_multi),
        cmocka_unit_test(test_pgrid_soft_parse_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

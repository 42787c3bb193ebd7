/* --shadows pgrid (optimized/pgrid/pgrid_light.h): the light grids' shadow
 * rays against the reference engine and a brute force over every triangle
 * (the reference's watertight test, rtt_reference_intersect_triangle), per
 * ray, at every instruction set this CPU runs and at several grid
 * resolutions; the shadow rays are the shader proxy's (from a point towards
 * a light's centre over (epsilon, distance - epsilon)), from the eye rays'
 * hit points and from points all over the scene's box, lights at the
 * scene's and at random places (inside the geometry too, which fills the
 * near list); each of those grids rebuilt on 2 and 3 threads equals its
 * one-thread build; the culling on a real closed mesh (the bunny, when cached).
 * Then the renderer: --shadows pgrid gives hard's image bit for
 * bit (same rays, same visibility), with --accel pgrid and kd; and the
 * method's name, parse and refusal by the reference renderer. */
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
#include "pgrid_light.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "rtt/shade.h"
#include "test_fixtures_pgrid.h"
#include "test_isa.h"
#include "test_scale.h"

/* The grids a and b hold the same cells, lists, bounds and flags. */
static void assert_same_grid(const pgrid_light *a, const pgrid_light *b, const rtt_scene *s, uint32_t records)
{
    assert_int_equal(a->res, b->res);
    assert_int_equal(a->ref_count, b->ref_count);
    assert_int_equal(a->near_count, b->near_count);
    assert_int_equal(a->faces, b->faces);
    const size_t cells = PGRID_LIGHT_FACES * (size_t)a->res * a->res;
    assert_int_equal(a->cell_first[cells], b->cell_first[cells]);
    assert_memory_equal(a->kept_cells, b->kept_cells, sizeof a->kept_cells);
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
        /* the kept rows' cells; the others hold stale words */
        const size_t first = a->kept_cells[face][0], kept = a->kept_cells[face][1] - first;
        assert_int_equal(a->faces >> face & 1u, kept > 0);
        if (!kept) continue;
        assert_memory_equal(a->cell_first + first, b->cell_first + first, (kept + 1) * sizeof *a->cell_first);
        assert_memory_equal(a->cell_front + first, b->cell_front + first, kept * sizeof *a->cell_front);
        assert_memory_equal(a->cell_min + first, b->cell_min + first, kept * sizeof *a->cell_min);
    }
    if (a->ref_count) assert_memory_equal(a->refs, b->refs, a->ref_count * sizeof *a->refs);
    if (a->near_count) assert_memory_equal(a->near, b->near, a->near_count * sizeof *a->near);
    if (records) assert_memory_equal(a->bound, b->bound, records * sizeof *a->bound);
    assert_memory_equal(a->front, b->front, s->triangle_count);
}

/* pgrid_light_rebuild on 2 and 3 threads, into a light built before at
 * another place and resolution (its arrays kept), gives the one-thread
 * build's grid. */
static void check_rebuild(const rtt_scene *s, const pgrid_shadows *grids, const pgrid_light *built,
                          const float position[3], uint32_t res)
{
    const float elsewhere[3] = {position[0] + 1.0f, position[1] - 2.0f, position[2] + 0.5f};
    const uint32_t other[2] = {res > 8 ? res / 4 : 2 * res, res + 3};
    pgrid_light again;
    memset(&again, 0, sizeof again);
    for (uint32_t threads = 2; threads <= 3; threads++) {
        assert_true(pgrid_light_rebuild(&again, grids, s, elsewhere, other[threads - 2], threads));
        assert_true(pgrid_light_rebuild(&again, grids, s, position, res, threads));
        assert_same_grid(built, &again, s, grids->corner_count);
    }
    pgrid_light_free(&again);
}

/* Every ray from `points` to `light` through the grid at every instruction
 * set, against the reference engine and the brute force. */
static void check_light(const rtt_scene *s, rtt_engine *ref, const pgrid_shadows *grids, const rtt_vec3 *points,
                        const uint32_t *point_prims, uint32_t point_count, uint32_t res, rtt_vec3 light,
                        const char *what)
{
    pgrid_shadows one = *grids;
    pgrid_light grid;
    const float position[3] = {light.x, light.y, light.z};
    assert_true(pgrid_light_build(&grid, grids, s, position, res));
    one.lights = &grid, one.light_count = 1;
    rtt_ray *rays = malloc((size_t)point_count * sizeof *rays);
    uint32_t *prims = malloc(((size_t)point_count + 1) * sizeof *prims);
    uint8_t *expected = malloc(point_count + 1), *engine = malloc(point_count + 1), *ours = malloc(point_count + 1);
    assert_true(rays && prims && expected && engine && ours);
    uint32_t n = 0;
    for (uint32_t i = 0; i < point_count; i++)
        if (shadow_ray(s, points[i], light, &rays[n])) prims[n++] = point_prims[i];
    const uint32_t blocked = expected_occlusion(s, ref, rays, n, expected, engine, what);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        assert_non_null(k);
        assert_int_equal(k->isa, isa);
        /* whole, and in small batches (partial packets, other sort runs) */
        assert_true(k->shadow_occluded(&one, 0, rays, prims, n, ours));
        for (uint32_t i = 0; i < n; i++)
            if (ours[i] != expected[i])
                fail_msg("%s (%s, res %u): ray %u from (%g %g %g): grid %u, reference %u", what, rtt_isa_name(isa), res,
                         i, (double)rays[i].org[0], (double)rays[i].org[1], (double)rays[i].org[2], ours[i],
                         expected[i]);
        for (uint32_t first = 0; first < n; first += 37) {
            const uint32_t m = n - first < 37 ? n - first : 37;
            assert_true(k->shadow_occluded(&one, 0, rays + first, NULL, m, ours + first));
        }
        for (uint32_t i = 0; i < n; i++) assert_int_equal(ours[i], expected[i]);
    }
    size_t front = 0;
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++)
        for (size_t c = grid.kept_cells[face][0]; c < grid.kept_cells[face][1]; c++) front += grid.cell_first[c + 1] - grid.cell_front[c];
    print_message("%s: res %u, %u rays, %u occluded, %u near, %zu refs (%zu facing the light, of %u culled meshes)\n",
                  what, grid.res, n, blocked, grid.near_count, grid.ref_count, front, grids->culled_count);
    if (n > 100) assert_true(blocked > 0 && blocked < n); /* both answers were checked */
    free(rays);
    free(prims);
    free(expected);
    free(engine);
    free(ours);
    pgrid_light_free(&grid);
}

/* One light check: the grid of `light` at resolution `res` (0: the
 * default) over scene s, with the points the rays start from (none for a
 * check that traces no rays). */
typedef void light_check(const rtt_scene *s, rtt_engine *ref, const pgrid_shadows *grids, const rtt_vec3 *points,
                         const uint32_t *point_prims, uint32_t point_count, uint32_t res, rtt_vec3 light,
                         const char *what);

/* `check` on every light of the light grids' scenes, and on a light at a
 * random place in each scene's box (near triangles, rays from every side),
 * at several resolutions; with the rays' origins when `with_points`. */
static void sweep_lights(light_check *check, int with_points)
{
    static const char *const scenes[] = {"demo.json", "mesh_obj.json", "shadow_thin_plate.json",
                                         "shadow_on_shadow.json", "light_sphere.json", "shadow_occluder_sizes.json"};
    static const uint32_t resolutions[] = {0, 7, 64};
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_non_null(ref);
        pgrid_shadows grids;
        assert_true(pgrid_shadows_build(&grids, s, NULL, 0, &err));
        assert_int_equal(grids.light_count, s->light_count);
        uint32_t count = 0, *prims = NULL;
        rtt_vec3 *points = NULL;
        if (with_points)
            points = shadow_origins(s, ref, 48, test_sweep(36), test_sweep(800), &count, 7u + (uint32_t)sc, &prims);
        uint32_t seed = 99u + (uint32_t)sc;
        for (size_t r = 0; r < sizeof resolutions / sizeof resolutions[0]; r++) {
            char what[96];
            for (uint32_t l = 0; l < s->light_count; l++) {
                snprintf(what, sizeof what, "%s light %u", scenes[sc], l);
                check(s, ref, &grids, points, prims, count, resolutions[r], s->lights[l].position, what);
            }
            const rtt_vec3 lo = s->bounds.lo, hi = s->bounds.hi;
            const rtt_vec3 inside = {random_in(&seed, lo.x, hi.x), random_in(&seed, lo.y, hi.y),
                                     random_in(&seed, lo.z, hi.z)};
            snprintf(what, sizeof what, "%s light inside", scenes[sc]);
            check(s, ref, &grids, points, prims, count, resolutions[r], inside, what);
        }
        free(points);
        free(prims);
        pgrid_shadows_free(&grids);
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

static void test_light_grid_rays_match_reference_and_brute_force(void **state)
{
    (void)state;
    sweep_lights(check_light, 1);
}

/* The footprint stage of every instruction set (pgrid_light_prints.c, its
 * vectors of doubles) against the scalar one (pgrid_light_print_record):
 * the same footprints, bounds, flags and so the same grid, bit for bit.
 * Returns how many records the vectors took (not near, one face, unclipped). */
static uint32_t check_prints(const rtt_scene *s, const pgrid_shadows *grids, const pgrid_light *scalar,
                             const float position[3], uint32_t res)
{
    const uint32_t n = grids->corner_count;
    uint32_t one_face = 0;
    for (uint32_t i = 0; i < n; i++) one_face += scalar->face_mask[i] && !(scalar->face_mask[i] & (scalar->face_mask[i] - 1u));
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        assert_non_null(k);
        pgrid_shadows vector = *grids;
        vector.prints = k->light_prints;
        pgrid_light grid;
        assert_true(pgrid_light_build(&grid, &vector, s, position, res));
        assert_same_grid(scalar, &grid, s, n);
        assert_true(pgrid_light_prints_equal(scalar, &grid, n));
        pgrid_light_free(&grid);
    }
    return one_face;
}

/* The grid of one light built on one thread, then rebuilt on 2 and 3, and
 * with each instruction set's footprint stage. */
static void check_light_rebuild(const rtt_scene *s, rtt_engine *ref, const pgrid_shadows *grids,
                                const rtt_vec3 *points, const uint32_t *point_prims, uint32_t point_count,
                                uint32_t res, rtt_vec3 light, const char *what)
{
    (void)ref, (void)points, (void)point_prims, (void)point_count, (void)what;
    pgrid_light grid;
    const float position[3] = {light.x, light.y, light.z};
    assert_true(pgrid_light_build(&grid, grids, s, position, res));
    check_rebuild(s, grids, &grid, position, res);
    check_prints(s, grids, &grid, position, res);
    pgrid_light_free(&grid);
}

/* The vector footprint stage on triangle soups scaled by 2^-60 .. 2^60,
 * lights among them, on corners and far away: the scalar stage's grid. */
static void test_light_grid_footprints_in_vectors_equal_scalar(void **state)
{
    (void)state;
    uint32_t seed = 777u, vector_records = 0, records = 0;
    for (int e = -60; e <= 60; e += 15) {
        const float scale = ldexpf(1.0f, e);
        rtt_scene *s = triangle_soup_scaled(&seed, scale);
        rtt_error err = {{0}};
        pgrid_shadows grids;
        assert_true(pgrid_shadows_build(&grids, s, NULL, 0, &err));
        for (int l = 0; l < 6; l++) {
            rtt_vec3 light = {random_in(&seed, -1.2f, 1.2f), random_in(&seed, -1.2f, 1.2f), random_in(&seed, -1.2f, 1.2f)};
            if (l == 4) light = rtt_v3_scale(light, 1e4f); /* far: every triangle on one or two faces */
            light = rtt_v3_scale(light, scale);
            if (l == 5) light = s->vertices[s->triangles[l].v[0]]; /* on a corner: near ones */
            const float position[3] = {light.x, light.y, light.z};
            const uint32_t res = l % 2 ? 200 : 13;
            pgrid_light grid;
            assert_true(pgrid_light_build(&grid, &grids, s, position, res));
            vector_records += check_prints(s, &grids, &grid, position, res);
            records += grids.corner_count;
            pgrid_light_free(&grid);
        }
        pgrid_shadows_free(&grids);
        rtt_scene_free(s);
    }
    print_message("%u of %u records on one face\n", vector_records, records);
    assert_true(vector_records > records / 4); /* the vectors' case was exercised */
}

static void test_light_grid_rebuilt_on_threads_equals_one_thread(void **state)
{
    (void)state;
    sweep_lights(check_light_rebuild, 0);
}

/* Large slanted triangles around a light, whose footprints of many cells
 * the build cuts to the cells their cone from the light meets
 * (pgrid_light_build.c, cone_cut): shadow rays aimed past their edges and
 * corners by a hair on either side, from beyond them, answer as the
 * reference and the brute force at every instruction set, and the cut
 * dropped cells (fewer references than the footprints' rectangles hold). */
static void test_light_grid_cuts_large_footprints_to_their_cones(void **state)
{
    (void)state;
    enum { TRIANGLES = 24, ALONG = 9, OFFSETS = 6 };
    uint32_t seed = 777u;
    float xyz[TRIANGLES * 9];
    for (uint32_t i = 0; i < TRIANGLES; i++) {
        /* a long thin triangle 1.5 to 3 from the light at the origin, slanted every way */
        const float c[3] = {random_in(&seed, -3, 3), random_in(&seed, -3, 3), random_in(&seed, -3, 3)};
        const float along[3] = {random_in(&seed, -2, 2), random_in(&seed, -2, 2), random_in(&seed, -2, 2)};
        const float across[3] = {random_in(&seed, -0.4f, 0.4f), random_in(&seed, -0.4f, 0.4f), random_in(&seed, -0.4f, 0.4f)};
        for (int k = 0; k < 3; k++) {
            xyz[9 * i + k] = c[k] - along[k];
            xyz[9 * i + 3 + k] = c[k] + along[k];
            xyz[9 * i + 6 + k] = c[k] + across[k];
        }
    }
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_from_triangles(xyz, TRIANGLES, &err);
    assert_non_null(s);
    rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
    assert_non_null(ref);
    pgrid_shadows grids;
    assert_true(pgrid_shadows_prepare(&grids, s, NULL, &err));
    const rtt_vec3 light = {0.01f, -0.02f, 0.03f};
    /* points beyond each triangle's edges and corners as seen from the light, off them by 1e-7 .. 1e-2 of
     * the distance, on both sides */
    const uint32_t count = TRIANGLES * 3 * ALONG * OFFSETS * 2;
    rtt_vec3 *points = malloc(count * sizeof *points);
    uint32_t *prims = malloc(count * sizeof *prims);
    assert_true(points && prims);
    uint32_t n = 0;
    for (uint32_t i = 0; i < TRIANGLES; i++) {
        rtt_vec3 v[3];
        rtt_scene_triangle(s, i, v);
        const rtt_vec3 centre = rtt_v3_scale(rtt_v3_add(rtt_v3_add(v[0], v[1]), v[2]), 1.0f / 3.0f);
        for (int e = 0; e < 3; e++)
            for (int a = 0; a < ALONG; a++) {
                const float t = (float)a / (ALONG - 1); /* 0 and 1: the corners */
                const rtt_vec3 on = rtt_v3_add(v[e], rtt_v3_scale(rtt_v3_sub(v[(e + 1) % 3], v[e]), t));
                const rtt_vec3 out = rtt_v3_normalize(rtt_v3_sub(on, centre));
                for (int o = 0; o < OFFSETS; o++)
                    for (int side = -1; side <= 1; side += 2) {
                        const float off = (float)side * powf(10.0f, -7.0f + (float)o) * rtt_v3_length(rtt_v3_sub(on, light));
                        const rtt_vec3 aim = rtt_v3_add(on, rtt_v3_scale(out, off));
                        points[n] = rtt_v3_add(light, rtt_v3_scale(rtt_v3_sub(aim, light), 1.6f));
                        prims[n++] = RTT_MISS;
                    }
            }
    }
    /* the cut drops cells: fewer references than the rectangles' cells */
    pgrid_light grid;
    const float position[3] = {light.x, light.y, light.z};
    for (uint32_t res = 16; res <= 256; res *= 4) {
        assert_true(pgrid_light_build(&grid, &grids, s, position, res));
        size_t rectangles = 0;
        for (uint32_t i = 0; i < grids.corner_count; i++)
            for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
                if (!(grid.face_mask[i] >> face & 1u)) continue;
                const pgrid_footprint f = grid.prints[(size_t)face * grids.corner_count + i];
                rectangles += (size_t)(f.x1 - f.x0 + 1) * (f.y1 - f.y0 + 1);
            }
        print_message("cone cut, res %u: %zu references of %zu rectangle cells\n", res, grid.ref_count, rectangles);
        assert_true(grid.ref_count < rectangles);
        pgrid_light_free(&grid);
        check_light(s, ref, &grids, points, prims, n, res, light, "large slanted triangles");
    }
    free(points);
    free(prims);
    pgrid_shadows_free(&grids);
    rtt_engine_destroy(ref);
    rtt_scene_free(s);
}

/* A soup of random triangles, some huge, some tiny, lights among them. */
static void test_light_grid_on_a_triangle_soup(void **state)
{
    (void)state;
    uint32_t seed = 12345u;
    rtt_scene *s = triangle_soup(&seed);
    rtt_error err = {{0}};
    rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
    assert_non_null(ref);
    pgrid_shadows grids;
    assert_true(pgrid_shadows_build(&grids, s, NULL, 0, &err));
    uint32_t count, *prims;
    rtt_vec3 *points = shadow_origins(s, ref, 32, 32, 2000, &count, 5u, &prims);
    for (int l = 0; l < 4; l++) {
        const rtt_vec3 light = {random_in(&seed, -1.2f, 1.2f), random_in(&seed, -1.2f, 1.2f),
                                random_in(&seed, -1.2f, 1.2f)};
        check_light(s, ref, &grids, points, prims, count, l % 2 ? 200 : 16, light, "soup");
    }
    /* on a corner of a triangle: that triangle is a near one */
    check_light(s, ref, &grids, points, prims, count, 0, s->vertices[s->triangles[3].v[1]],
                "soup, light on a corner");
    /* origins far beyond the scene (1e3 to 1e20 times its size): the
     * reference's rounding follows the origin, so the grid tests them
     * against every triangle (pgrid_light.h) */
    enum { FAR = 96 };
    rtt_vec3 far[FAR];
    uint32_t far_prims[FAR];
    for (uint32_t i = 0; i < FAR; i++) {
        rtt_vec3 d = {random_in(&seed, -1, 1), random_in(&seed, -1, 1), random_in(&seed, -1, 1)};
        if (!(rtt_v3_length(d) > 1e-3f)) d = rtt_v3(1, 0, 0);
        far[i] = rtt_v3_scale(rtt_v3_normalize(d), powf(10.0f, 3.0f + (float)(i % 18)));
        far_prims[i] = RTT_MISS;
    }
    for (int l = 0; l < 3; l++) {
        const rtt_vec3 light = {random_in(&seed, -0.5f, 0.5f), random_in(&seed, -0.5f, 0.5f),
                                random_in(&seed, -0.5f, 0.5f)};
        check_light(s, ref, &grids, far, far_prims, FAR, l ? 200 : 16, light, "soup, far origins");
    }
    free(points);
    free(prims);
    pgrid_shadows_free(&grids);
    rtt_engine_destroy(ref);
    rtt_scene_free(s);
}

/* The renderer: pgrid's image is hard's, bit for bit, and near the reference's. */
static void test_render_pgrid_shadows_equal_hard(void **state)
{
    (void)state;
    static const char *const scenes[] = {"demo.json", "shadow_transparent.json", "light_quad.json"};
    static const rtt_accel accels[] = {RTT_ACCEL_PGRID, RTT_ACCEL_KD};
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine *engine = rtt_optimized_engine_create(s, NULL, &err);
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_non_null(engine);
        assert_non_null(ref);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            for (size_t a = 0; a < 2; a++) {
                rtt_render_options ro;
                rtt_render_options_default(&ro);
                ro.width = 80, ro.height = 60, ro.threads = 2;
                ro.engine.accel = accels[a];
                ro.engine.isa = isa;
                rtt_image *hard = rtt_image_create(80, 60, 0, &err), *grid = rtt_image_create(80, 60, 0, &err),
                          *reference = rtt_image_create(80, 60, 0, &err);
                assert_true(hard && grid && reference);
                ro.shadows = RTT_SHADOWS_HARD;
                if (!rtt_optimized_render(engine, &ro, hard, NULL, &err)) fail_msg("hard: %s", err.message);
                ro.shadows = RTT_SHADOWS_PGRID;
                if (!rtt_optimized_render(engine, &ro, grid, NULL, &err)) fail_msg("pgrid: %s", err.message);
                if (memcmp(hard->rgb, grid->rgb, (size_t)80 * 60 * 3 * sizeof *hard->rgb) != 0)
                    fail_msg("%s %s accel %d: --shadows pgrid differs from hard", scenes[sc], rtt_isa_name(isa),
                             (int)accels[a]);
                rtt_render_options rr;
                rtt_render_options_default(&rr);
                rr.width = 80, rr.height = 60, rr.threads = 2;
                if (!rtt_reference_render(s, ref, &rr, reference, NULL, &err)) fail_msg("reference: %s", err.message);
                rtt_image_metrics mt;
                assert_true(rtt_image_compare(grid, reference, &mt, &err));
                if (mt.rmse > 2e-3 || mt.share_over_1_255 > 0.005)
                    fail_msg("%s: RMSE %g against the reference", scenes[sc], mt.rmse);
                rtt_image_free(hard);
                rtt_image_free(grid);
                rtt_image_free(reference);
            }
        }
        rtt_engine_destroy(engine);
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

static rtt_image *render_pgrid_shadows(rtt_engine *engine, uint32_t threads)
{
    rtt_error err = {{0}};
    rtt_render_options ro;
    rtt_render_options_default(&ro);
    ro.width = 80, ro.height = 60, ro.threads = threads;
    ro.engine.accel = RTT_ACCEL_PGRID;
    ro.shadows = RTT_SHADOWS_PGRID;
    rtt_image *image = rtt_image_create(80, 60, 0, &err);
    assert_non_null(image);
    if (!rtt_optimized_render(engine, &ro, image, NULL, &err)) fail_msg("pgrid: %s", err.message);
    return image;
}

static void assert_same_image(const rtt_image *a, const rtt_image *b, const char *what)
{
    if (memcmp(a->rgb, b->rgb, (size_t)a->width * a->height * 3 * sizeof *a->rgb) != 0) fail_msg("%s", what);
}

/* The engine keeps the light grids between frames (their scene half made
 * once, the lights' arrays regrown): lent to one frame at a time, the same
 * grids again after their return; a frame while they are lent makes its
 * own and draws the same picture; a light moved between frames is drawn
 * as a fresh engine draws it (the lights' grids are every frame's own). */
static void test_engine_keeps_the_light_grids_between_frames(void **state)
{
    (void)state;
    rtt_scene *s = load_scene("demo.json");
    rtt_error err = {{0}};
    rtt_engine *engine = rtt_optimized_engine_create(s, NULL, &err);
    assert_non_null(engine);
    rtt_image *first = render_pgrid_shadows(engine, 2);
    bool failed = true;
    pgrid_shadows *kept = optimized_engine_light_grids_lend(engine, s, &err, &failed);
    assert_false(failed);
    assert_non_null(kept);
    assert_true(kept->corner_count > 0);
    const kd_corners *corners = kept->corners;
    /* lent: another frame gets none, and draws with its own */
    assert_null(optimized_engine_light_grids_lend(engine, s, &err, &failed));
    assert_false(failed);
    rtt_image *own = render_pgrid_shadows(engine, 1);
    assert_same_image(first, own, "a frame with its own light grids differs from the engine's");
    optimized_engine_light_grids_return(engine);
    pgrid_shadows *again = optimized_engine_light_grids_lend(engine, s, &err, &failed);
    assert_ptr_equal(again, kept);
    assert_ptr_equal(again->corners, corners); /* the scene half kept, not made again */
    optimized_engine_light_grids_return(engine);
    rtt_image *second = render_pgrid_shadows(engine, 2);
    assert_same_image(first, second, "the second frame on the kept light grids differs from the first");
    /* a light moved: the kept engine draws what a fresh one draws */
    assert_true(s->light_count > 0);
    s->lights[0].position.x += 0.75f, s->lights[0].position.y += 0.5f;
    rtt_image *moved = render_pgrid_shadows(engine, 2);
    rtt_engine *fresh = rtt_optimized_engine_create(s, NULL, &err);
    assert_non_null(fresh);
    rtt_image *fresh_moved = render_pgrid_shadows(fresh, 2);
    assert_same_image(moved, fresh_moved, "a moved light on the kept light grids differs from a fresh engine's");
    if (memcmp(moved->rgb, first->rgb, (size_t)80 * 60 * 3 * sizeof *first->rgb) == 0)
        fail_msg("moving the light changed nothing: the test proves nothing");
    rtt_image_free(first), rtt_image_free(own), rtt_image_free(second), rtt_image_free(moved);
    rtt_image_free(fresh_moved);
    rtt_engine_destroy(fresh);
    rtt_engine_destroy(engine);
    rtt_scene_free(s);
}

/* Culling at a real scale: the Stanford bunny (one closed mesh of 75k
 * triangles, from bench/fetch-scenes.sh's cache; skipped without it), its
 * eye hits at 384x384 through the eye grid, each hit's shadow ray (the
 * shader proxy's: from rtt_surface_at's point, its prim known) through the
 * light grid at every instruction set against the reference engine.  The
 * grazing rays at the shadow terminator are the ones the culling rules must
 * catch (pgrid README, "Hard shadows"). */
static void test_light_grid_culling_on_the_bunny(void **state)
{
    (void)state;
    const char *home = getenv("HOME");
    char path[600];
    snprintf(path, sizeof path, "%s/.cache/rtt-data/meshes/bunny00.off", home ? home : "");
    FILE *probe = fopen(path, "rb");
    if (!probe) {
        print_message("note: %s not cached (bash bench/fetch-scenes.sh): skipped\n", path);
        skip();
    }
    fclose(probe);
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    if (!s) fail_msg("%s: %s", path, err.message);
    rtt_engine *opt = rtt_optimized_engine_create(s, NULL, &err), *ref = rtt_reference_engine_create(s, NULL, &err);
    assert_true(opt && ref);
    const uint32_t SIDE = TEST_SANITIZED ? 192 : 384;
    rtt_hit *hits = malloc((size_t)SIDE * SIDE * sizeof *hits);
    rtt_ray *rays = malloc((size_t)SIDE * SIDE * sizeof *rays);
    uint32_t *prims = malloc((size_t)SIDE * SIDE * sizeof *prims);
    uint8_t *expected = malloc((size_t)SIDE * SIDE), *ours = malloc((size_t)SIDE * SIDE);
    assert_true(hits && rays && prims && expected && ours);
    const rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, SIDE, SIDE);
    pgrid_eye eye = {0};
    assert_true(pgrid_eye_trace_frame(&eye, pgrid_kernel_find("", RTT_ISA_SSE4), s, optimized_engine_degenerate(opt),
                                      &frame, SIDE, SIDE, 0, 2, hits, NULL, &err));
    pgrid_eye_free(&eye);
    pgrid_shadows grids;
    assert_true(pgrid_shadows_build(&grids, s, optimized_engine_degenerate(opt), 0, &err));
    assert_int_equal(grids.culled_count, 1);
    /* the default light sits at the eye, which sees no shadow: one above and to the side */
    const rtt_vec3 size = rtt_v3_sub(s->bounds.hi, s->bounds.lo);
    const rtt_vec3 light = rtt_v3_add(s->camera.eye, rtt_v3(0.8f * size.x, 0.9f * size.y, 0.1f * size.z));
    const float position[3] = {light.x, light.y, light.z};
    pgrid_light_free(&grids.lights[0]);
    assert_true(pgrid_light_build(&grids.lights[0], &grids, s, position, 0));
    /* res 0: the rule's (the bunny's 75k triangles: 400; a map's 4k: 64) */
    assert_int_equal(grids.lights[0].res, pgrid_light_res_rule(grids.corner_count));
    assert_int_equal(pgrid_light_res_rule(grids.corner_count), PGRID_LIGHT_RES_MESHES);
    assert_int_equal(pgrid_light_res_rule(4093), PGRID_LIGHT_RES_MAPS);
    /* the vector footprint stage on a culled mesh (front flags): the scalar's grid */
    const uint32_t one_face = check_prints(s, &grids, &grids.lights[0], position, 0);
    assert_true(one_face > grids.corner_count / 2);
    uint32_t n = 0, blocked = 0;
    for (uint32_t i = 0; i < SIDE * SIDE; i++) {
        if (hits[i].prim == RTT_MISS) continue;
        const rtt_ray eye_ray = rtt_camera_ray(&frame, i % SIDE, i / SIDE);
        const rtt_surface surf = rtt_surface_at(s, &eye_ray, &hits[i]);
        if (shadow_ray(s, surf.point, light, &rays[n])) prims[n++] = hits[i].prim;
    }
    rtt_engine_occluded(ref, rays, expected, n);
    for (uint32_t i = 0; i < n; i++) expected[i] = expected[i] != 0, blocked += expected[i];
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        assert_true(k->shadow_occluded(&grids, 0, rays, prims, n, ours));
        for (uint32_t i = 0; i < n; i++)
            if (ours[i] != expected[i])
                fail_msg("bunny (%s): ray %u from prim %u: grid %u, reference %u", rtt_isa_name(isa), i, prims[i], ours[i],
                         expected[i]);
    }
    print_message("bunny: %u shadow rays, %u occluded\n", n, blocked);
    assert_true(blocked > 0 && blocked < n);
    pgrid_shadows_free(&grids);
    free(hits), free(rays), free(prims), free(expected), free(ours);
    rtt_engine_destroy(opt);
    rtt_engine_destroy(ref);
    rtt_scene_free(s);
}

static void test_pgrid_shadow_method_name_and_refusals(void **state)
{
    (void)state;
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_error err = {{0}};
    rtt_engine_register(&rtt_optimized_engine_class, NULL);
    rtt_engine_register(&rtt_reference_engine_class, NULL);
    assert_true(rtt_shadow_method_parse("pgrid", &opt, &err));
    assert_int_equal(opt.shadows, RTT_SHADOWS_PGRID);
    assert_string_equal(rtt_shadow_method_name(RTT_SHADOWS_PGRID), "pgrid");
    assert_true(rtt_shadow_method_parse("pgrid:8", &opt, &err)); /* soft light grids: test_optimized_pgrid_soft.c */
    assert_int_equal(opt.shadows, RTT_SHADOWS_PGRID_SOFT);
    assert_true(rtt_shadow_method_parse("pgrid", &opt, &err));
    if (!rtt_render_options_check("optimized", &opt, &err)) fail_msg("%s", err.message);
    opt.shadows = RTT_SHADOWS_PGRID;
    assert_false(rtt_render_options_check("reference", &opt, &err));
    assert_non_null(strstr(err.message, "pgrid"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_light_grid_rays_match_reference_and_brute_force),
        cmocka_unit_test(test_light_grid_rebuilt_on_threads_equals_one_thread),
        cmocka_unit_test(test_light_grid_on_a_triangle_soup),
        cmocka_unit_test(test_light_grid_cuts_large_footprints_to_their_cones),
        cmocka_unit_test(test_light_grid_footprints_in_vectors_equal_scalar),
        cmocka_unit_test(test_light_grid_culling_on_the_bunny),
        cmocka_unit_test(test_render_pgrid_shadows_equal_hard),
        cmocka_unit_test(test_engine_keeps_the_light_grids_between_frames),
        cmocka_unit_test(test_pgrid_shadow_method_name_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

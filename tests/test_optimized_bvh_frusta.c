/* The BVH's multi-frusta shadow kernels (optimized/bvh/): hard shadows
 * through bvh-mft with the light as the frusta's apex (bvh_query.toward),
 * and the soft-shadow frusta of --shadows frusta:N (bvh_shadow_kernel), at
 * every instruction set this CPU runs, under both triangle tests (the
 * default, watertight, and --isect projected), against two oracles: a
 * brute force over every triangle record with the scalar form of the same
 * test (per ray, bit for bit: the frusta may cull nothing a ray hits), and
 * the reference engine (under the watertight test every ray alike; under
 * the projected test a flip next to an occluder's edge counted apart, as
 * that test is not watertight).  Then the renderer: frusta:N draws
 * interleaved:N's image of the same BVH bit for bit, with and without the
 * filter, and hard shadows through bvh-mft draw bvh-packet's, at every ISA;
 * frusta is refused without --accel bvh and by the reference engine. */
#include <float.h>
#include <stdio.h>

#include "bvh_build.h"
#include "bvh_kernels.h"
#include "rtt/image.h"
#include "rtt/interleaved.h"
#include "rtt/render.h"
#include "test_fixtures_bvh.h"
#include "test_scale.h"

static int setup_bvh(void **state) { return setup_bvh_seeded(state, 0x2545f4914f6cdd1dull); }

/* Against the reference engine: a disagreement whose ray passes within
 * 1e-4 (barycentric) of an edge of a triangle the other side hit is an edge
 * flip; returns the others. */
static uint32_t reference_disagreements(const bvh_fixture *f, const bvh_tree *tree, const rtt_ray *rays,
                                        const uint8_t *got, uint32_t n, uint32_t *edge)
{
    uint8_t *want = malloc(n);
    rtt_hit *hits = malloc(n * sizeof *hits);
    assert_non_null(want), assert_non_null(hits);
    rtt_engine_occluded(f->base.reference, rays, want, n);
    rtt_engine_intersect(f->base.reference, rays, hits, n);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (!got[i] == !want[i]) continue;
        rtt_hit h;
        const rtt_ray *r = &rays[i];
        if (want[i]) {
            h = hits[i];
        } else { /* ours hit: find what with the record brute force */
            h = bvh_records_closest(tree, r);
        }
        /* a flip at an edge only for the projected test: the watertight one is the reference's */
        if (!tree->watertight && h.prim != RTT_MISS &&
            (near_interval_end(r, h.t) || h.u < 1e-4f || h.v < 1e-4f || h.u + h.v > 1.0f - 1e-4f)) {
            (*edge)++;
            continue;
        }
        if (bad++ < 5) print_message("ray %u: occluded %d, reference %d\n", i, got[i], want[i]);
    }
    free(want), free(hits);
    return bad;
}

/* Rays of 16 neighbouring points each (a 4x4 block's hit points) to one light. */
static void check_hard_shadows_on(const bvh_fixture *f, const bvh_tree *tree, rtt_vec3 light, uint64_t seed)
{
    const uint32_t n = test_sweep(4096);
    rtt_ray *rays = shadow_rays(n, light, seed);
    uint8_t *want = malloc(n), *got = malloc(n);
    assert_non_null(want), assert_non_null(got);
    uint32_t occluded = 0;
    for (uint32_t i = 0; i < n; i++) occluded += want[i] = (uint8_t)bvh_records_occlude(tree, &rays[i]);
    const float toward[3] = {light.x, light.y, light.z};
    const bvh_kernel *row;
    for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
        if (strcmp(row->name, "bvh-mft") != 0 || !isa_runs(row->isa)) continue;
        bvh_counters with = {0}, without = {0};
        row->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = got, .counters = &with, .toward = toward});
        uint32_t lost = 0, edge = 0;
        for (uint32_t i = 0; i < n; i++)
            if (got[i] != want[i] && lost++ < 5) print_message("%s ray %u: %d, records %d\n", rtt_isa_name(row->isa), i, got[i], want[i]);
        const uint32_t bad = reference_disagreements(f, tree, rays, got, n, &edge);
        row->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = got, .counters = &without});
        print_message("hard bvh-mft %-7s %-10s %u rays (%u occluded): %u wrong against the records, %u off the reference, "
                      "%u edge flips; AABB tests %llu with the apex, %llu without\n",
                      rtt_isa_name(row->isa), bvh_tree_test_name(tree), n, occluded, lost, bad, edge,
                      (unsigned long long)with.aabb_tests,
                      (unsigned long long)without.aabb_tests);
        assert_int_equal(lost, 0);
        assert_int_equal(bad, 0);
        assert_true(edge <= n / 1000 + 1);
        assert_true(with.aabb_tests < without.aabb_tests); /* the apex frusta cull: fewer box tests than packets */
    }
    assert_true(occluded > n / 20 && occluded < n - n / 20); /* both answers are exercised */
    free(rays), free(want), free(got);
}

/* Under both triangle tests. */
static void check_hard_shadows(const bvh_fixture *f, rtt_vec3 light, uint64_t seed)
{
    for (uint32_t t = 0; t < BVH_FIXTURE_TESTS; t++) check_hard_shadows_on(f, f->trees[t], light, seed);
}

static void test_hard_shadows_through_the_apex_frusta(void **state)
{
    const bvh_fixture *f = *state;
    check_hard_shadows(f, rtt_v3(0.5f, 3.0f, 0.7f), 61);
    check_hard_shadows(f, rtt_v3(0.0f, 0.1f, 0.0f), 67);   /* a light among the triangles */
    check_hard_shadows(f, rtt_v3(-4.0f, 0.0f, 0.05f), 71); /* rays nearly along an axis plane */
}

/* ---- soft-shadow frusta ---- */

/* The 16 interleaved sets of `samples` samples of the light (4x4 pixels),
 * each with its 2D bounds, as the renderer's frusta:N path makes them. */
static bvh_shadow_sets *interleaved_sets(const rtt_light *light, uint32_t samples)
{
    bvh_shadow_sets *sets = calloc(1, sizeof *sets);
    assert_non_null(sets);
    sets->samples = samples;
    float xy[BVH_SHADOW_MAX_SAMPLES][2];
    for (uint32_t s = 0; s < 16; s++) {
        rtt_interleaved_coords(light, s, samples, xy);
        for (uint32_t k = 0; k < samples; k++) sets->x[s][k] = xy[k][0], sets->y[s][k] = xy[k][1];
        rtt_interleaved_bounds(light, s, samples, sets->lo[s], sets->hi[s]);
    }
    return sets;
}

/* n points on patches of 16 (a 4x4 block each: sets 0..15), the light's
 * frame from each. */
static bvh_shadow_point *shadow_points(const rtt_light *light, uint32_t n, uint64_t seed)
{
    rng r = {seed};
    bvh_shadow_point *pts = malloc(n * sizeof *pts);
    assert_non_null(pts);
    rtt_vec3 patch = rtt_v3(0, 0, 0);
    for (uint32_t i = 0; i < n; i++) {
        if (i % 16 == 0)
            patch = rtt_v3(rng_range(&r, -1.2f, 1.2f), rng_range(&r, -1.2f, 1.2f), rng_range(&r, -1.2f, 1.2f));
        const rtt_vec3 p = rtt_v3_add(patch, rtt_v3(rng_range(&r, -0.04f, 0.04f), rng_range(&r, -0.04f, 0.04f),
                                                    rng_range(&r, -0.04f, 0.04f)));
        const rtt_light_frame fr = rtt_light_sample_frame(light, p);
        pts[i] = (bvh_shadow_point){{p.x, p.y, p.z}, {fr.base.x, fr.base.y, fr.base.z}, {fr.du.x, fr.du.y, fr.du.z},
                                    {fr.dv.x, fr.dv.y, fr.dv.z}, i % 16};
    }
    return pts;
}

/* Sample k's ray from point pt as the optimized renderer's interleaved path
 * builds it (shader_proxy.c shadow_segment); false when none (clear). */
static bool sample_ray(const bvh_shadow_point *pt, const bvh_shadow_sets *sets, uint32_t k, float eps, rtt_ray *ray)
{
    const rtt_light_frame fr = {rtt_v3(pt->base[0], pt->base[1], pt->base[2]), rtt_v3(pt->du[0], pt->du[1], pt->du[2]),
                                rtt_v3(pt->dv[0], pt->dv[1], pt->dv[2])};
    const rtt_vec3 p = rtt_v3(pt->org[0], pt->org[1], pt->org[2]);
    const rtt_vec3 to = rtt_v3_sub(rtt_light_frame_point(&fr, sets->x[pt->set][k], sets->y[pt->set][k]), p);
    const float d = rtt_v3_length(to);
    if (!(d > 2.0f * eps)) return false;
    const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / d);
    *ray = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, eps, d - eps};
    return true;
}

static void check_soft_shadows_on(const bvh_fixture *f, const bvh_tree *tree, const rtt_light *light,
                                  uint32_t samples, uint64_t seed)
{
    const uint32_t n = test_sweep(1024);
    const float eps = 1e-4f;
    bvh_shadow_sets *sets = interleaved_sets(light, samples);
    bvh_shadow_point *pts = shadow_points(light, n, seed);
    uint32_t *want = calloc(n, sizeof *want), *got = malloc(n * sizeof *got);
    rtt_ray *rays = malloc((size_t)n * samples * sizeof *rays);
    uint8_t *ours = malloc((size_t)n * samples);
    assert_non_null(want), assert_non_null(got), assert_non_null(rays), assert_non_null(ours);
    uint32_t traced = 0, occluded = 0, partial = 0;
    for (uint32_t i = 0; i < n; i++) {
        for (uint32_t k = 0; k < samples; k++) {
            rtt_ray ray;
            if (!sample_ray(&pts[i], sets, k, eps, &ray)) continue;
            if (bvh_records_occlude(tree, &ray)) want[i] |= 1u << k, occluded++;
            rays[traced++] = ray;
        }
        partial += want[i] != 0 && want[i] != (samples == 32 ? ~0u : (1u << samples) - 1u);
    }
    const bvh_shadow_kernel *row;
    for (uint32_t r = 0; (row = bvh_shadow_kernel_row_at(r)); r++) {
        if (!isa_runs(row->isa)) continue;
        bvh_counters counters = {0};
        row->trace(tree, &(bvh_shadow_query){.points = pts, .count = n, .sets = sets, .epsilon = eps,
                                                .occluded = got, .counters = &counters});
        uint32_t lost = 0;
        for (uint32_t i = 0; i < n; i++)
            if (got[i] != want[i] && lost++ < 5)
                print_message("%s point %u: mask %08x, records %08x\n", rtt_isa_name(row->isa), i, got[i], want[i]);
        /* the same rays' occlusion bits, in ray order, against the reference */
        for (uint32_t i = 0, at = 0; i < n; i++)
            for (uint32_t k = 0; k < samples; k++) {
                rtt_ray ray;
                if (sample_ray(&pts[i], sets, k, eps, &ray)) ours[at++] = got[i] >> k & 1u;
            }
        uint32_t edge = 0;
        const uint32_t bad = reference_disagreements(f, tree, rays, ours, traced, &edge);
        print_message("frusta:%-2u %s light %-7s %-10s %u points, %u rays (%u occluded, %u points partly): %u wrong against "
                      "the records, %u off the reference, %u edge flips; %llu AABB tests, %llu frusta at triangles, "
                      "%llu ray-packet tests\n",
                      samples, light->type == RTT_LIGHT_QUAD ? "quad" : "sphere", rtt_isa_name(row->isa),
                      bvh_tree_test_name(tree), n, traced,
                      occluded, partial, lost, bad, edge, (unsigned long long)counters.aabb_tests,
                      (unsigned long long)counters.triangles, (unsigned long long)counters.isect_tests);
        assert_int_equal(lost, 0);
        assert_int_equal(bad, 0);
        assert_true(edge <= traced / 1000 + 1);
        assert_int_equal(counters.packets, n);
    }
    assert_true(occluded > traced / 20 && occluded < traced - traced / 20);
    assert_true(partial > 0); /* penumbrae: frusta partly occluded */
    free(sets), free(pts), free(want), free(got), free(rays), free(ours);
}

/* Under both triangle tests. */
static void check_soft_shadows(const bvh_fixture *f, const rtt_light *light, uint32_t samples, uint64_t seed)
{
    for (uint32_t t = 0; t < BVH_FIXTURE_TESTS; t++) check_soft_shadows_on(f, f->trees[t], light, samples, seed);
}

static void test_soft_shadow_frusta_every_sample_count_and_light(void **state)
{
    const bvh_fixture *f = *state;
    const rtt_light sphere = {.type = RTT_LIGHT_SPHERE, .position = {0.4f, 2.5f, 0.6f}, .radius = 0.5f};
    const rtt_light quad = {.type = RTT_LIGHT_QUAD, .position = {-0.3f, 2.2f, 0.2f}, .edge_u = {0.9f, 0.0f, 0.1f},
                            .edge_v = {0.0f, 0.2f, 0.8f}};
    const rtt_light near = {.type = RTT_LIGHT_SPHERE, .position = {0.0f, 0.05f, 0.0f}, .radius = 0.3f};
    const uint32_t counts[] = {4, 7, 16, 32};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        check_soft_shadows(f, &sphere, counts[i], 100 + i);
        check_soft_shadows(f, &quad, counts[i], 200 + i);
    }
    check_soft_shadows(f, &near, 16, 300); /* a light among the triangles */
}

/* Soft shadows from points on a floor (a map's common case): a tiled
 * floor, axis-aligned (z = 0, points exactly on it) or tilted (points
 * where vertical rays meet it, off its plane by their rounding, or 1e-6
 * above or below), a sphere light above, and every eighth point 2e-3 under
 * the floor.  Without occluders only those points' frusta may reach a
 * ray-triangle test: the floor's triangles hold the other points in their
 * plane, so only beside_plane (shadow_frusta.c) culls them.  With
 * occluders every sample's answer must be the records' brute force's, at
 * every ISA under both triangle tests. */
static bvh_shadow_point *floor_points(const rtt_light *light, float slope, uint32_t n, uint64_t seed)
{
    rng r = {seed};
    bvh_shadow_point *pts = malloc(n * sizeof *pts);
    assert_non_null(pts);
    for (uint32_t i = 0; i < n; i++) {
        const float x = rng_range(&r, -3.5f, 3.5f), y = rng_range(&r, -3.5f, 3.5f);
        /* the floor z = slope x: a vertical ray from z = 10 meets it at t = 10 - slope x */
        float z = slope == 0.0f ? 0.0f : 10.0f + -1.0f * (10.0f - slope * x);
        if (slope != 0.0f && i % 3) z += i % 3 == 1 ? 1e-6f : -1e-6f;
        if (i % 8 == 7) z -= 2e-3f; /* under the floor: it shadows every sample */
        const rtt_vec3 p = rtt_v3(x, y, z);
        const rtt_light_frame fr = rtt_light_sample_frame(light, p);
        pts[i] = (bvh_shadow_point){{p.x, p.y, p.z}, {fr.base.x, fr.base.y, fr.base.z}, {fr.du.x, fr.du.y, fr.du.z},
                                    {fr.dv.x, fr.dv.y, fr.dv.z}, i % 16};
    }
    return pts;
}

static rtt_scene *floor_scene(float slope, uint32_t occluders, uint64_t seed)
{
    enum { TILES = 8 };
    const uint32_t count = 2 * TILES * TILES + occluders;
    float *xyz = malloc(9 * (size_t)count * sizeof *xyz);
    assert_non_null(xyz);
    uint32_t t = tiled_floor(xyz, TILES, slope);
    rng r = {seed};
    for (; t < count; t++) {
        const float c[3] = {rng_range(&r, -3, 3), rng_range(&r, -3, 3), rng_range(&r, 0.3f, 1.5f)};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) xyz[9 * t + 3 * v + a] = c[a] + rng_range(&r, -0.4f, 0.4f);
        for (int v = 0; v < 3; v++) xyz[9 * t + 3 * v + 2] += slope * xyz[9 * t + 3 * v];
    }
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, count, &err);
    free(xyz);
    if (!scene) fail_msg("scene: %s", err.message);
    return scene;
}

static void test_soft_shadow_frusta_from_points_on_a_floor(void **state)
{
    (void)state;
    const rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = {0.5f, -0.3f, 6.0f}, .radius = 1.0f};
    const uint32_t n = 1024, samples = 16;
    const float eps = 1e-4f;
    bvh_shadow_sets *sets = interleaved_sets(&light, samples);
    uint32_t *want = malloc(n * sizeof *want), *got = malloc(n * sizeof *got);
    assert_non_null(want), assert_non_null(got);
    const float slopes[2] = {0.0f, 0.37f};
    for (int sl = 0; sl < 2; sl++)
        for (uint32_t occluders = 0; occluders <= 30; occluders += 30) {
            rtt_scene *scene = floor_scene(slopes[sl], occluders, 0xF100Dull + occluders);
            bvh_shadow_point *pts = floor_points(&light, slopes[sl], n, 0xF1002ull + (uint64_t)sl);
            bvh_build_options bo = {.leaf_size = 4, .max_depth = 0, .threads = 1};
            rtt_error err = {{0}};
            bvh_tree tree;
            if (!bvh_build_sah(scene, &bo, &tree, &err)) fail_msg("build: %s", err.message);
            for (int wt = 0; wt < 2; wt++) {
                tree.watertight = wt == 0;
                uint32_t occluded = 0;
                for (uint32_t i = 0; i < n; i++) {
                    want[i] = 0;
                    for (uint32_t k = 0; k < samples; k++) {
                        rtt_ray ray;
                        if (sample_ray(&pts[i], sets, k, eps, &ray) && bvh_records_occlude(&tree, &ray))
                            want[i] |= 1u << k, occluded++;
                    }
                }
                const bvh_shadow_kernel *row;
                for (uint32_t r = 0; (row = bvh_shadow_kernel_row_at(r)); r++) {
                    if (!isa_runs(row->isa)) continue;
                    bvh_counters counters = {0};
                    row->trace(&tree, &(bvh_shadow_query){.points = pts, .count = n, .sets = sets, .epsilon = eps,
                                                            .occluded = got, .counters = &counters});
                    uint32_t lost = 0;
                    for (uint32_t i = 0; i < n; i++)
                        if (got[i] != want[i] && lost++ < 5)
                            print_message("point %u: mask %08x, records %08x\n", i, got[i], want[i]);
                    print_message("frusta:16 %-7s %-10s floor slope %.2f, %2u occluders: %u of %u samples occluded, "
                                  "%u points wrong; %llu frusta at triangles, %llu ray-packet tests\n",
                                  rtt_isa_name(row->isa), bvh_tree_test_name(&tree), (double)slopes[sl], occluders,
                                  occluded, n * samples, lost, (unsigned long long)counters.triangles,
                                  (unsigned long long)counters.isect_tests);
                    assert_int_equal(lost, 0);
                    assert_true(counters.triangles > 0);
                    if (occluders == 0) assert_true(counters.isect_tests <= 2 * (n / 8)); /* the points under it */
                }
                if (occluders) assert_true(occluded > n * samples / 8 && occluded < n * samples / 2);
                else assert_int_equal(occluded, n / 8 * samples);
            }
            bvh_tree_free(&tree);
            rtt_scene_free(scene);
            free(pts);
        }
    free(sets), free(want), free(got);
}

/* ---- the renderer ---- */

static rtt_image *render_scene(rtt_engine *engine, const rtt_render_options *opt)
{
    rtt_error err = {{0}};
    rtt_image *img = rtt_image_create(96, 96, 0, &err);
    assert_non_null(img);
    if (!rtt_render(engine, opt, img, NULL, &err)) fail_msg("render: %s", err.message);
    return img;
}

static rtt_scene *load(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", RTT_SOURCE_DIR, name);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(path, NULL, &err);
    if (!scene) fail_msg("%s: %s", path, err.message);
    return scene;
}

static void test_renders_equal_interleaved_and_packet_hard_shadows(void **state)
{
    (void)state;
    const char *scenes[] = {"light_quad.json", "light_sphere.json", "shadow_on_shadow.json", "demo.json"};
    const rtt_isect tests[] = {RTT_ISECT_DEFAULT, RTT_ISECT_PROJECTED}; /* watertight, then projected */
    for (size_t s = 0; s < 2 * sizeof scenes / sizeof scenes[0]; s++) {
        rtt_scene *scene = load(scenes[s / 2]);
        rtt_engine_options eo;
        rtt_engine_options_default(&eo);
        eo.accel = RTT_ACCEL_BVH;
        eo.isect = tests[s % 2];
        rtt_error err = {{0}};
        rtt_engine *engine = rtt_optimized_engine_create(scene, &eo, &err);
        if (!engine) fail_msg("%s", err.message);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            rtt_render_options opt;
            rtt_render_options_default(&opt);
            opt.engine = eo;
            opt.engine.isa = isa;
            opt.width = opt.height = 96;
            opt.threads = 2;
            for (int filter = 0; filter < 3; filter++) { /* :nofilter, filtered, :refine */
                const uint32_t n = filter ? 16 : 8;
                opt.shadow_filter = filter > 0;
                opt.shadow_refine = filter == 2;
                opt.shadow_samples = n;
                opt.shadows = RTT_SHADOWS_INTERLEAVED;
                rtt_image *want = render_scene(engine, &opt);
                opt.shadows = RTT_SHADOWS_FRUSTA;
                rtt_image *got = render_scene(engine, &opt);
                const char *mode = filter == 0 ? ":nofilter" : filter == 2 ? ":refine" : "";
                print_message("%s %s %s frusta:%u%s against interleaved:%u%s\n", scenes[s / 2],
                              rtt_engine_isect_name(engine), rtt_isa_name(isa), n, mode, n, mode);
                assert_memory_equal(got->rgb, want->rgb, sizeof(float) * 3 * 96 * 96);
                rtt_image_free(want), rtt_image_free(got);
            }
            opt.shadows = RTT_SHADOWS_HARD;
            snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", "bvh-packet");
            rtt_image *want = render_scene(engine, &opt);
            snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", "bvh-mft");
            rtt_image *got = render_scene(engine, &opt);
            print_message("%s %s %s hard: bvh-mft against bvh-packet\n", scenes[s / 2], rtt_engine_isect_name(engine),
                          rtt_isa_name(isa));
            assert_memory_equal(got->rgb, want->rgb, sizeof(float) * 3 * 96 * 96);
            rtt_image_free(want), rtt_image_free(got);
        }
        rtt_engine_destroy(engine);
        rtt_scene_free(scene);
    }
}

static void test_frusta_is_refused_without_the_bvh(void **state)
{
    (void)state;
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    rtt_error err = {{0}};
    assert_true(rtt_shadow_method_parse("frusta", &opt, &err));
    assert_int_equal(opt.shadows, RTT_SHADOWS_FRUSTA);
    assert_int_equal(opt.shadow_samples, 16);
    assert_true(opt.shadow_filter);
    assert_true(rtt_shadow_method_parse("frusta:32:nofilter", &opt, &err));
    assert_int_equal(opt.shadow_samples, 32);
    assert_false(opt.shadow_filter);
    assert_true(rtt_shadow_method_parse("frusta:4", &opt, &err));
    assert_int_equal(opt.shadow_samples, 4);
    const char *bad[] = {"frusta:3", "frusta:33", "frusta:x", "frusta:16:filter", "frusta:", "frustum"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_false(rtt_shadow_method_parse(bad[i], &opt, &err));
        assert_non_null(strstr(err.message, bad[i]));
    }
    assert_string_equal(rtt_shadow_method_name(RTT_SHADOWS_FRUSTA), "frusta");
    rtt_render_options_default(&opt);
    opt.shadows = RTT_SHADOWS_FRUSTA;
    assert_false(rtt_render_options_check("optimized", &opt, &err)); /* kd by default */
    assert_non_null(strstr(err.message, "--accel bvh"));
    opt.engine.accel = RTT_ACCEL_BVH;
    assert_true(rtt_render_options_check("optimized", &opt, &err));
    assert_false(rtt_render_options_check("reference", &opt, &err));
    assert_non_null(strstr(err.message, "frusta"));
}

int main(void)
{
    rtt_error err = {{0}};
    if (!rtt_engine_register(&rtt_optimized_engine_class, &err) || !rtt_engine_register(&rtt_reference_engine_class, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_hard_shadows_through_the_apex_frusta, setup_bvh, teardown_bvh),
        cmocka_unit_test_setup_teardown(test_soft_shadow_frusta_every_sample_count_and_light, setup_bvh, teardown_bvh),
        cmocka_unit_test(test_soft_shadow_frusta_from_points_on_a_floor),
        cmocka_unit_test(test_renders_equal_interleaved_and_packet_hard_shadows),
        cmocka_unit_test(test_frusta_is_refused_without_the_bvh),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

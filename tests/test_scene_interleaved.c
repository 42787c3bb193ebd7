/* Interleaved sampling, light frames, quad lights and the discontinuity
 * filter (scene/interleaved.c, scene/shade.c; rtt/interleaved.h): the sets'
 * stratification checked point by point, frames against the light's
 * geometry, the filter on constructed buffers whose answers are known. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rtt/interleaved.h"
#include "rtt/shade.h"

static void assert_near(float a, float b, float tolerance)
{
    if (!(fabsf(a - b) <= tolerance)) fail_msg("%.9g is not within %g of %.9g", a, tolerance, b);
}

static void assert_v3_near(rtt_vec3 a, rtt_vec3 b, float tolerance)
{
    assert_near(a.x, b.x, tolerance), assert_near(a.y, b.y, tolerance), assert_near(a.z, b.z, tolerance);
}

static const rtt_light quad_light = {.type = RTT_LIGHT_QUAD,
                                     .position = {1, 4, -2},
                                     .color = {1, 1, 1},
                                     .intensity = 1,
                                     .attenuation = {1, 0, 0},
                                     .edge_u = {2, 0, 0},
                                     .edge_v = {0, 0, 1}};
/* edge_u x edge_v = (0, -2, 0): this quad shines downwards */

static const rtt_light sphere_light = {.type = RTT_LIGHT_SPHERE,
                                       .position = {0, 5, 0},
                                       .color = {1, 1, 1},
                                       .intensity = 1,
                                       .attenuation = {1, 0, 0},
                                       .radius = 0.75f};

/* Do the points cover every elementary box of (1/2^a) x (1/2^(m-a)), for
 * every a = 0..m, exactly once?  (A (0, m, 2)-net in base 2.) */
static void assert_net(const float (*pts)[2], uint32_t count, uint32_t m)
{
    assert_int_equal(count, 1u << m);
    uint8_t *seen = calloc(count, 1);
    assert_non_null(seen);
    for (uint32_t a = 0; a <= m; a++) {
        memset(seen, 0, count);
        for (uint32_t i = 0; i < count; i++) {
            uint32_t bx = (uint32_t)(pts[i][0] * (float)(1u << a)), by = (uint32_t)(pts[i][1] * (float)(1u << (m - a)));
            uint32_t box = (bx << (m - a)) | by;
            if (seen[box]) fail_msg("box %u of the %u x %u split holds two points", box, 1u << a, 1u << (m - a));
            seen[box] = 1;
        }
    }
    free(seen);
}

static void test_each_set_and_their_union_are_nets(void **state)
{
    (void)state;
    static float set[32][2], all[16 * 32][2];
    for (uint32_t m = 2; m <= 5; m++) {
        const uint32_t n = 1u << m;
        for (uint32_t j = 0; j < RTT_INTERLEAVED_SETS; j++) {
            for (uint32_t i = 0; i < n; i++) {
                rtt_interleaved_sample(j, i, n, set[i]);
                assert_true(set[i][0] >= 0.0f && set[i][0] < 1.0f && set[i][1] >= 0.0f && set[i][1] < 1.0f);
                all[j * n + i][0] = set[i][0], all[j * n + i][1] = set[i][1];
            }
            assert_net((const float (*)[2])set, n, m);
        }
        assert_net((const float (*)[2])all, 16 * n, m + 4);
    }
}

static void test_sets_partition_the_hammersley_set_for_any_count(void **state)
{
    (void)state;
    for (uint32_t n = RTT_INTERLEAVED_MIN_SAMPLES; n <= RTT_INTERLEAVED_MAX_SAMPLES; n++) {
        uint8_t seen[16 * 32] = {0};
        for (uint32_t j = 0; j < 16; j++)
            for (uint32_t i = 0; i < n; i++) {
                float s[2], h[2];
                rtt_interleaved_sample(j, i, n, s);
                uint32_t k = (uint32_t)lroundf(s[0] * (float)(16 * n));
                assert_true(k < 16 * n);
                assert_false(seen[k]);
                seen[k] = 1;
                rtt_hammersley(k, 16 * n, h);
                assert_near(s[0], h[0], 0), assert_near(s[1], h[1], 0);
                float again[2];
                rtt_interleaved_sample(j, i, n, again); /* fixed: the same every call */
                assert_near(again[0], s[0], 0), assert_near(again[1], s[1], 0);
            }
    }
    assert_int_equal(rtt_interleaved_set(0, 0), 0);
    assert_int_equal(rtt_interleaved_set(3, 0), 3);
    assert_int_equal(rtt_interleaved_set(5, 2), 9);
    assert_int_equal(rtt_interleaved_set(7, 7), 15);
}

static void test_quad_frame_spans_the_quad_whatever_the_point(void **state)
{
    (void)state;
    rtt_light_frame f = rtt_light_sample_frame(&quad_light, rtt_v3(3, -1, 2));
    assert_v3_near(f.base, quad_light.position, 0);
    assert_v3_near(f.du, quad_light.edge_u, 0);
    assert_v3_near(f.dv, quad_light.edge_v, 0);
    assert_v3_near(rtt_light_frame_point(&f, -0.5f, -0.5f), rtt_v3(0, 4, -2.5f), 0);
    assert_v3_near(rtt_light_frame_point(&f, 0.5f, 0.5f), rtt_v3(2, 4, -1.5f), 0);
    float lo[2], hi[2];
    for (uint32_t set = 0; set < 16; set++) {
        float xy[32][2];
        rtt_interleaved_coords(&quad_light, set, 32, xy);
        rtt_interleaved_bounds(&quad_light, set, 32, lo, hi);
        bool touched[4] = {false, false, false, false};
        for (uint32_t i = 0; i < 32; i++)
            for (int k = 0; k < 2; k++) {
                assert_true(xy[i][k] >= -0.5f && xy[i][k] < 0.5f);
                assert_true(xy[i][k] >= lo[k] && xy[i][k] <= hi[k]);
                touched[2 * k] |= xy[i][k] == lo[k], touched[2 * k + 1] |= xy[i][k] == hi[k];
            }
        for (int k = 0; k < 4; k++) assert_true(touched[k]); /* the bounds are tight */
    }
    /* multi:N's samples lie on the quad too */
    for (uint32_t i = 0; i < 16; i++) {
        rtt_vec3 q = rtt_light_sample(&quad_light, rtt_v3(0, 0, 0), i, 16, 77);
        assert_near(q.y, 4, 0);
        assert_true(q.x >= 0 && q.x <= 2 && q.z >= -2.5f && q.z <= -1.5f);
    }
}

static void test_sphere_frame_is_the_disc_facing_the_point(void **state)
{
    (void)state;
    rtt_vec3 p = rtt_v3(1, 1, 2);
    rtt_light_frame f = rtt_light_sample_frame(&sphere_light, p);
    rtt_vec3 w = rtt_v3_normalize(rtt_v3_sub(p, sphere_light.position));
    assert_v3_near(f.base, sphere_light.position, 0);
    assert_near(rtt_v3_length(f.du), 0.75f, 1e-6f), assert_near(rtt_v3_length(f.dv), 0.75f, 1e-6f);
    assert_near(rtt_v3_dot(f.du, f.dv), 0, 1e-6f);
    assert_near(rtt_v3_dot(f.du, w), 0, 1e-6f), assert_near(rtt_v3_dot(f.dv, w), 0, 1e-6f);
    for (uint32_t set = 0; set < 16; set++) {
        float xy[16][2];
        rtt_interleaved_coords(&sphere_light, set, 16, xy);
        for (uint32_t i = 0; i < 16; i++) {
            assert_true(xy[i][0] * xy[i][0] + xy[i][1] * xy[i][1] <= 1.0f + 1e-6f);
            rtt_vec3 q = rtt_light_frame_point(&f, xy[i][0], xy[i][1]);
            /* affine: the point is base + x du + y dv, on the disc */
            assert_v3_near(q, rtt_v3_add(f.base, rtt_v3_add(rtt_v3_scale(f.du, xy[i][0]), rtt_v3_scale(f.dv, xy[i][1]))),
                           1e-6f);
            assert_near(rtt_v3_dot(rtt_v3_sub(q, f.base), w), 0, 1e-5f);
            assert_true(rtt_v3_length(rtt_v3_sub(q, f.base)) <= 0.75f + 1e-5f);
        }
    }
    /* the same disc basis as rtt_light_sample: its samples lie in the frame's plane */
    for (uint32_t i = 0; i < 8; i++)
        assert_near(rtt_v3_dot(rtt_v3_sub(rtt_light_sample(&sphere_light, p, i, 8, 3), f.base), w), 0, 1e-5f);
    rtt_light point = sphere_light;
    point.type = RTT_LIGHT_POINT;
    point.radius = 0;
    f = rtt_light_sample_frame(&point, p);
    assert_v3_near(rtt_light_frame_point(&f, 0.3f, -0.2f), point.position, 0);
    assert_false(rtt_light_has_area(&point));
    assert_true(rtt_light_has_area(&sphere_light) && rtt_light_has_area(&quad_light));
    rtt_light flat = quad_light;
    flat.edge_v = rtt_v3(-4, 0, 0);
    assert_false(rtt_light_has_area(&flat));
}

/* rtt_shade_light of material m at a surface with normal n seen from to_viewer. */
static rtt_vec3 shade(const rtt_material *m, rtt_vec3 n, rtt_vec3 to_viewer, rtt_vec3 to_light, const rtt_light *light,
                      float distance)
{
    rtt_surface surf = {.dir = rtt_v3_scale(to_viewer, -1.0f), .normal = n, .material = m, .diffuse = m->diffuse};
    return rtt_shade_light(&surf, to_light, light, distance);
}

static void test_quad_light_is_one_sided_and_lambertian(void **state)
{
    (void)state;
    rtt_material m = {.type = RTT_MATERIAL_DIFFUSE, .diffuse = {1, 1, 1}};
    rtt_vec3 up = rtt_v3(0, 1, 0);
    /* straight below the centre: the emitter's cosine is 1 */
    rtt_vec3 below = shade(&m, up, up, up, &quad_light, 4);
    assert_near(below.x, 1, 1e-6f);
    /* from the side at 60 degrees off the quad's normal: half */
    rtt_vec3 l = rtt_v3_normalize(rtt_v3(0, 1, sqrtf(3)));
    rtt_vec3 side = shade(&m, l, up, l, &quad_light, 2);
    assert_near(side.x, 0.5f, 1e-6f);
    /* above the quad's plane, facing it: nothing (one-sided) */
    rtt_vec3 down = rtt_v3(0, -1, 0);
    rtt_vec3 above = shade(&m, down, down, down, &quad_light, 1);
    assert_near(above.x, 0, 0);
    rtt_vec3 sphere = shade(&m, up, up, l, &sphere_light, 2); /* spheres: no emitter cosine */
    assert_near(sphere.x, rtt_v3_dot(up, l), 1e-6f);
}

/* ---- the filter ---- */

enum { W = 12, H = 8 };

static void flat_buffers(float *depth, float *normals, float d)
{
    for (int p = 0; p < W * H; p++) {
        depth[p] = d;
        normals[3 * p] = 0, normals[3 * p + 1] = 0, normals[3 * p + 2] = 1;
    }
}

static void test_filter_averages_a_flat_region_over_all_sixteen_sets(void **state)
{
    (void)state;
    float vis[W * H], depth[W * H], normals[3 * W * H], out[W * H];
    flat_buffers(depth, normals, 3.0f);
    float per_set[16], mean = 0;
    for (int j = 0; j < 16; j++) mean += (per_set[j] = (float)((j * 7) % 16) / 16.0f);
    mean /= 16.0f;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) vis[y * W + x] = per_set[rtt_interleaved_set((uint32_t)x, (uint32_t)y)];
    rtt_discontinuity_filter(vis, depth, normals, W, H, NULL, out);
    for (int y = 2; y + 2 < H; y++)
        for (int x = 2; x + 2 < W; x++) assert_near(out[y * W + x], mean, 1e-6f);
    /* the corner's window is clipped to its 3x3, the far row and column at half weight */
    const float w[3] = {1.0f, 1.0f, 0.5f};
    float corner = 0, weight = 0;
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++) corner += w[x] * w[y] * vis[y * W + x], weight += w[x] * w[y];
    assert_near(out[0], corner / weight, 1e-6f);
}

static void test_filter_keeps_depth_and_normal_edges(void **state)
{
    (void)state;
    float vis[W * H], depth[W * H], normals[3 * W * H], out[W * H];
    flat_buffers(depth, normals, 3.0f);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int p = y * W + x;
            vis[p] = x < 6 ? 0.0f : 1.0f;
            if (x >= 6) depth[p] = 3.0f * (1.0f + 1.5f * RTT_DISCONTINUITY_DEPTH_RELATIVE); /* a step in depth */
        }
    rtt_discontinuity_filter(vis, depth, normals, W, H, NULL, out);
    for (int p = 0; p < W * H; p++) assert_near(out[p], vis[p], 0);
    /* the same step in normals only: 30 degrees apart */
    flat_buffers(depth, normals, 3.0f);
    for (int y = 0; y < H; y++)
        for (int x = 6; x < W; x++) {
            float *n = &normals[3 * (y * W + x)];
            n[0] = 0.5f, n[1] = 0, n[2] = sqrtf(3) / 2;
        }
    rtt_discontinuity_filter(vis, depth, normals, W, H, NULL, out);
    for (int p = 0; p < W * H; p++) assert_near(out[p], vis[p], 0);
    /* within the thresholds the edge is smoothed: 20 degrees, 5% deeper */
    for (int y = 0; y < H; y++)
        for (int x = 6; x < W; x++) {
            float *n = &normals[3 * (y * W + x)];
            n[0] = sinf(0.349f), n[1] = 0, n[2] = cosf(0.349f);
            depth[y * W + x] = 3.15f;
        }
    rtt_discontinuity_filter(vis, depth, normals, W, H, NULL, out);
    assert_near(out[3 * W + 5], 1.5f / 4.0f, 1e-6f); /* columns 3..7 weighted 1/2, 1, 1, 1, 1/2: 1.5 of 4 lit */
    /* stricter thresholds given: the edge holds again */
    rtt_discontinuity_thresholds strict = {0.01f, 0.99f};
    rtt_discontinuity_filter(vis, depth, normals, W, H, &strict, out);
    assert_near(out[3 * W + 5], 0, 0);
}

static void test_filter_skips_pixels_without_visibility_or_depth(void **state)
{
    (void)state;
    float vis[W * H], depth[W * H], normals[3 * W * H], out[W * H];
    flat_buffers(depth, normals, 3.0f);
    for (int p = 0; p < W * H; p++) vis[p] = 1.0f;
    vis[3 * W + 4] = NAN;        /* the light cast no rays here */
    depth[3 * W + 6] = INFINITY; /* a miss */
    vis[3 * W + 6] = 0.0f;
    vis[3 * W + 5] = 0.5f;
    rtt_discontinuity_filter(vis, depth, normals, W, H, NULL, out);
    assert_true(isnan(out[3 * W + 4]));
    assert_near(out[3 * W + 6], 0.0f, 0);
    /* pixel (5, 3): weight 16 in its window, minus the NaN's 1 and the miss's 1 */
    assert_near(out[3 * W + 5], (13.0f + 0.5f) / 14.0f, 1e-6f);
}

static void test_planes_compose_rest_plus_filtered_light_terms(void **state)
{
    (void)state;
    rtt_light lights[2] = {quad_light, sphere_light};
    lights[1].type = RTT_LIGHT_POINT;
    lights[1].radius = 0;
    rtt_shadow_planes planes;
    assert_true(rtt_shadow_planes_init(&planes, W, H, lights, 2));
    assert_true(planes.soft[0] && !planes.soft[1]);
    const size_t n = (size_t)W * H;
    for (size_t p = 0; p < n; p++) {
        assert_true(isnan(planes.visibility[p]) && isinf(planes.depth[p]));
        planes.depth[p] = 2.0f;
        planes.normal[3 * p + 2] = 1.0f;
        planes.rest[3 * p] = 0.25f;
        planes.visibility[p] = (p % W) % 2 ? 1.0f : 0.0f;     /* stripes: the filter halves them */
        planes.visibility[n + p] = (p % W) % 2 ? 1.0f : 0.0f; /* a point light: left alone */
        for (int c = 0; c < 3; c++) planes.contribution[3 * p + c] = 1.0f, planes.contribution[3 * (n + p) + c] = 2.0f;
    }
    planes.visibility[n + 5] = NAN; /* light 1 left out at pixel 5 */
    float rgb[3 * W * H];
    assert_true(rtt_shadow_planes_resolve(&planes, false, NULL, rgb));
    assert_near(rgb[3 * 5], 0.25f + 1.0f, 0);
    assert_near(rgb[3 * (W + 3)], 0.25f + 1.0f + 2.0f, 0);
    assert_near(rgb[3 * (W + 4)], 0.25f, 0);
    assert_true(rtt_shadow_planes_resolve(&planes, true, NULL, rgb));
    assert_near(rgb[3 * (2 * W + 4)], 0.25f + 0.5f, 1e-6f);
    assert_near(rgb[3 * (2 * W + 5)], 0.25f + 0.5f + 2.0f, 1e-6f);
    rtt_shadow_planes_free(&planes);
    assert_null(planes.visibility);
}

static void test_refine_picks_what_the_filter_moved_past_the_noise(void **state)
{
    (void)state;
    /* a lit pixel beside a contact shadow, the filter's 0.7 three standard deviations of 16 samples away */
    assert_true(rtt_refine_needed(1.0f, 0.7f, 16));
    assert_true(rtt_refine_needed(0.0f, 0.3f, 16));
    /* a smooth penumbra: within one deviation (0.125) plus the margin */
    assert_false(rtt_refine_needed(0.5625f, 0.5f, 16));
    assert_false(rtt_refine_needed(0.375f, 0.5f, 16));
    /* the tail of a penumbra: all 16 samples clear where 95% are, no refining */
    assert_false(rtt_refine_needed(1.0f, 0.95f, 16));
    /* fewer samples, more noise: what 16 refine, 4 leave */
    assert_true(rtt_refine_needed(0.25f, 0.5f, 16));
    assert_false(rtt_refine_needed(0.25f, 0.5f, 4));
    /* flat regions never */
    assert_false(rtt_refine_needed(1.0f, 1.0f, 16));
    assert_false(rtt_refine_needed(0.0f, 0.0f, 32));
}

typedef struct refine_calls {
    uint32_t light;
    size_t count;
    uint32_t pixel[W * H];
    const rtt_shadow_planes *planes;
} refine_calls;

/* The test's second pass: records what it is asked and answers 0.5, or
 * fails when asked to (count SIZE_MAX on entry). */
static bool refine_record(void *context, uint32_t light, const uint32_t *pixel, size_t count, float *vis)
{
    refine_calls *calls = context;
    if (calls->count == SIZE_MAX) return false;
    calls->light = light;
    for (size_t i = 0; i < count; i++) {
        calls->pixel[calls->count++] = pixel[i];
        const float *p = &calls->planes->point[3 * (size_t)pixel[i]];
        assert_near(p[0], (float)(pixel[i] % W), 0); /* the planes' point reaches the pass */
        vis[i] = 0.5f;
    }
    return true;
}

static void test_refine_retraces_the_pixels_the_filter_smeared(void **state)
{
    (void)state;
    rtt_light lights[2] = {sphere_light, quad_light};
    lights[0].type = RTT_LIGHT_POINT; /* light 0 hard: never refined */
    lights[0].radius = 0;
    rtt_shadow_planes planes;
    assert_true(rtt_shadow_planes_init(&planes, W, H, lights, 2));
    const size_t n = (size_t)W * H;
    /* one surface; light 1: a sharp shadow edge between columns 3 and 4, as at a contact shadow */
    for (size_t p = 0; p < n; p++) {
        planes.depth[p] = 2.0f;
        planes.normal[3 * p + 2] = 1.0f;
        planes.point[3 * p] = (float)(p % W);
        planes.rest[3 * p] = 0.25f;
        planes.visibility[p] = (p % W) < 4 ? 0.0f : 1.0f;
        planes.visibility[n + p] = (p % W) < 4 ? 0.0f : 1.0f;
        for (int c = 0; c < 3; c++) planes.contribution[3 * (n + p) + c] = 1.0f;
    }
    float filtered[W * H], rgb[3 * W * H];
    rtt_discontinuity_filter(&planes.visibility[n], planes.depth, planes.normal, W, H, NULL, filtered);
    refine_calls calls = {.planes = &planes};
    uint64_t refined = 0;
    assert_true(rtt_shadow_planes_resolve_refined(&planes, 16, NULL, refine_record, &calls, rgb, &refined));
    assert_int_equal(calls.light, 1);
    assert_int_equal(refined, calls.count);
    /* exactly the pixels the rule picks, in pixel order: the two columns each side of the edge */
    size_t want = 0;
    for (size_t p = 0; p < n; p++) {
        const bool pick = rtt_refine_needed(planes.visibility[n + p], filtered[p], 16);
        assert_int_equal(pick, (p % W) >= 2 && (p % W) <= 5);
        if (!pick) {
            assert_near(rgb[3 * p], 0.25f + filtered[p], 1e-6f);
            continue;
        }
        assert_int_equal(calls.pixel[want++], p);
        assert_near(rgb[3 * p], 0.25f + 0.5f, 0);
    }
    assert_int_equal(want, calls.count);
    /* a failing pass fails the resolve */
    calls.count = SIZE_MAX;
    assert_false(rtt_shadow_planes_resolve_refined(&planes, 16, NULL, refine_record, &calls, rgb, NULL));
    rtt_shadow_planes_free(&planes);
}

static void test_planes_too_large_are_refused_with_the_figures(void **state)
{
    (void)state;
    assert_int_equal(rtt_shadow_planes_bytes(10, 10, 2), 100u * 40u + 100u * 2u * 16u + 2u);
    assert_int_equal(rtt_shadow_planes_bytes(UINT32_MAX, UINT32_MAX, UINT32_MAX), UINT64_MAX);
    static rtt_light lights[300];
    rtt_scene scene;
    memset(&scene, 0, sizeof scene);
    strcpy(scene.path, "map.bsp");
    scene.lights = lights;
    scene.light_count = 300;
    rtt_shadow_planes planes;
    rtt_error err = {{0}};
    assert_false(rtt_shadow_planes_create(&planes, &scene, 4096, 4096, &err));
    assert_string_equal(err.message, "map.bsp: interleaved shadows keep 75.6 GiB of planes for 4096x4096 pixels and "
                                     "300 lights, more than 4 GiB: render smaller or with fewer lights");
    assert_null(planes.visibility);
    assert_true(rtt_shadow_planes_create(&planes, &scene, 16, 8, &err));
    assert_int_equal(planes.lights, 300);
    rtt_shadow_planes_free(&planes);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_set_and_their_union_are_nets),
        cmocka_unit_test(test_sets_partition_the_hammersley_set_for_any_count),
        cmocka_unit_test(test_quad_frame_spans_the_quad_whatever_the_point),
        cmocka_unit_test(test_sphere_frame_is_the_disc_facing_the_point),
        cmocka_unit_test(test_quad_light_is_one_sided_and_lambertian),
        cmocka_unit_test(test_filter_averages_a_flat_region_over_all_sixteen_sets),
        cmocka_unit_test(test_filter_keeps_depth_and_normal_edges),
        cmocka_unit_test(test_filter_skips_pixels_without_visibility_or_depth),
        cmocka_unit_test(test_planes_compose_rest_plus_filtered_light_terms),
        cmocka_unit_test(test_refine_picks_what_the_filter_moved_past_the_noise),
        cmocka_unit_test(test_refine_retraces_the_pixels_the_filter_smeared),
        cmocka_unit_test(test_planes_too_large_are_refused_with_the_figures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The per-ray-interval kernels (mono, packet, omni; optimized/kd/traverse_*.c),
 * each at every instruction set this CPU runs, against the reference engine,
 * ray by ray, on random triangle soups with a large floor: primary-like camera rays, arbitrary random rays (NaN, Inf,
 * zero, axis-parallel with +-0.0 parts, tnear > tfar, negative tnear mixed
 * in), shadow-like rays toward one point, and rays lying in the tree's split
 * planes.  Also: degenerate trees, hits only lowered, counters.
 *
 * Agreement: both miss, or both hit with |t - t_ref| <= 1e-5 * max(1, |t_ref|).
 * A different prim is a tie only when both triangles are hit by the ray
 * within that tolerance (checked with rtt_reference_intersect_triangle).  A
 * hit within tolerance of tnear or tfar is unspecified (docs/ARCHITECTURE.md) and not
 * counted.  Every kernel must show zero disagreements. */
#include <float.h>
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
#include "test_fixtures_optimized.h"

#define BLOCK_PACKETS 16u  /* packets per kernel call */

/* ---- scenes (the soup, setup_triangles, teardown: test_fixtures_optimized.h) ---- */

static int setup_large_triangles(void **state) { return setup_soup(state, 300, 0.6f, 0x1234567ull); }

#define TINY_FAR_TRIANGLES 256u
#define TINY_FAR_SEED 0x71A7ull
static int setup_tiny_far_triangles(void **state)
{
    float *xyz = tiny_far_triangles(TINY_FAR_TRIANGLES, TINY_FAR_SEED);
    const int rc = setup_triangles(state, xyz, TINY_FAR_TRIANGLES);
    free(xyz);
    return rc;
}

/* One triangle: the tree is a single leaf. */
static int setup_one_triangle(void **state)
{
    const float tri[9] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    return setup_triangles(state, tri, 1);
}

/* Only degenerate triangles: the optimized tree holds no record at all. */
static int setup_degenerate_only(void **state)
{
    const float tris[27] = {0, 0, 0, 1, 1, 1, 2, 2, 2, /* collinear */
                            1, 0, 0, 1, 0, 0, 1, 0, 0, /* a point */
                            0, 0, 1, 0, 1, 1, 0, 2, 1};
    return setup_triangles(state, tris, 3);
}

/* setup_octahedron: test_fixtures_optimized.h (the BVH tests use it too). */

/* ---- ray sets (camera, random, shadow: test_fixtures_optimized.h) ---- */

/* Rays lying in the tree's split planes: for each of the first inner nodes,
 * origins on its plane with a direction inside the plane (a +-0.0 component
 * on the split axis), axis-parallel or not; and rays crossing the plane with
 * their origin on it.  Exercises the NaN split distance (0 * inf). */
static rtt_ray *plane_rays(const kd_tree *tree, uint32_t *count, uint64_t seed)
{
    rng r = {seed};
    const uint32_t max = 4096;
    rtt_ray *rays = malloc(max * sizeof *rays);
    assert_non_null(rays);
    uint32_t n = 0;
    for (uint32_t node = 0; node < tree->node_count && n + 8 <= max; node++) {
        const kd_node *nd = &tree->nodes[node];
        if (kd_node_is_leaf(nd)) continue;
        uint32_t axis = kd_node_axis(nd);
        for (int k = 0; k < 8; k++) {
            rtt_ray *ray = &rays[n++];
            for (int a = 0; a < 3; a++) ray->org[a] = rng_range(&r, -1.5f, 1.5f), ray->dir[a] = rng_range(&r, -1, 1);
            ray->org[axis] = nd->split;
            if (k < 6) ray->dir[axis] = k % 2 ? -0.0f : 0.0f;
            if (k == 2 || k == 3) ray->dir[(axis + 1) % 3] = 0.0f;
            ray->tnear = k == 5 ? -2.0f : 0.0f;
            ray->tfar = INFINITY;
        }
    }
    *count = n;
    return rays;
}

/* ---- comparison ---- */

/* The same triangle at a t beyond tolerance is not a traversal error (the
 * kernels compute t with the same test, whatever cells they visit): it is
 * the projected barycentric test's precision at grazing angles.  Its t =
 * num / den takes coefficients rounded to float in the record, so its
 * absolute error grows like eps * S / (|d| |cos|) (S the coordinate scale,
 * cos between ray and normal); the reference is more accurate there.  Such
 * hits are accepted within 16 times that bound and counted apart. */
static uint32_t grazing_count;

static float grazing_tolerance(const fixture *f, const rtt_ray *ray, uint32_t prim)
{
    rtt_vec3 p[3];
    rtt_scene_triangle(f->scene, prim, p);
    rtt_vec3 n = rtt_v3_cross(rtt_v3_sub(p[1], p[0]), rtt_v3_sub(p[2], p[0]));
    rtt_vec3 d = rtt_v3(ray->dir[0], ray->dir[1], ray->dir[2]);
    float scale = 1.0f;
    for (int a = 0; a < 3; a++) {
        scale = fmaxf(scale, fabsf(ray->org[a]));
        for (int v = 0; v < 3; v++) scale = fmaxf(scale, fabsf(rtt_v3_get(p[v], a)));
    }
    float cos_nd = fabsf(rtt_v3_dot(n, d)) / (rtt_v3_length(n) * rtt_v3_length(d));
    return 16.0f * FLT_EPSILON * scale / (rtt_v3_length(d) * cos_nd);
}

/* 1 when the hits disagree beyond tolerance (and are not a documented tie).
 * A hit within tolerance of tnear or tfar is unspecified: when one side has
 * such a hit and the other does not, the one that skipped it must agree with
 * the reference on the rest of the ray (tnear moved past the unspecified
 * hit). */
static int hits_disagree(const fixture *f, const rtt_ray *ray, const rtt_hit *got, const rtt_hit *want)
{
    int got_hit = got->prim != RTT_MISS, want_hit = want->prim != RTT_MISS;
    if (!got_hit && !want_hit) return 0;
    if (got_hit != want_hit) return !near_interval_end(ray, got_hit ? got->t : want->t);
    if (fabsf(got->t - want->t) <= t_tolerance(want->t)) {
        if (got->prim == want->prim) return 0;
        return !(prim_hit_at(f, ray, got->prim, want->t) && prim_hit_at(f, ray, want->prim, got->t));
    }
    if (got->prim == want->prim && fabsf(got->t - want->t) <= grazing_tolerance(f, ray, got->prim)) {
        grazing_count++;
        return 0;
    }
    if (near_interval_end(ray, got->t)) return 0;
    if (!near_interval_end(ray, want->t) || got->t < want->t) return 1;
    rtt_ray rest = *ray;
    rest.tnear = want->t + 2 * t_tolerance(want->t);
    rtt_hit rest_want;
    rtt_engine_intersect(f->reference, &rest, &rest_want, 1);
    if (got->t <= rest.tnear) return 0;
    return hits_disagree(f, &rest, got, &rest_want);
}

/* mono, packet and omni at every instruction set the CPU runs (main). */
static const char *const kernel_names[] = {"mono", "packet", "omni"};
#define KERNEL_NAMES (sizeof kernel_names / sizeof kernel_names[0])
static kernel_case kernels[KERNEL_NAMES * 3];
static size_t kernel_count;

/* Every ray through `k` in calls of BLOCK_PACKETS packets: hits (cleared
 * first) and occlusion masks, one entry per ray. */
static void trace_with(const fixture *f, const kernel_case *k, const rtt_ray *rays, uint32_t count, rtt_hit *hits,
                       uint8_t *occluded, kd_counters *counters)
{
    ray_packet4 *packets = aligned_alloc(16, BLOCK_PACKETS * sizeof *packets);
    hit_packet4 *packet_hits = aligned_alloc(16, BLOCK_PACKETS * sizeof *packet_hits);
    uint8_t masks[BLOCK_PACKETS];
    assert_non_null(packets);
    assert_non_null(packet_hits);
    for (uint32_t first = 0; first < count; first += 4 * BLOCK_PACKETS) {
        uint32_t n = count - first < 4 * BLOCK_PACKETS ? count - first : 4 * BLOCK_PACKETS, np = (n + 3) / 4;
        for (uint32_t p = 0; p < np; p++) {
            ray_packet4_load(&packets[p], &rays[first + 4 * p], n - 4 * p < 4 ? n - 4 * p : 4);
            hit_packet4_clear(&packet_hits[p]);
        }
        kernel_closest(k, f->tree, packets, packet_hits, np, 1, counters);
        kernel_occluded(k, f->tree, packets, masks, np, 1, counters);
        for (uint32_t p = 0; p < np; p++) {
            uint32_t lanes = n - 4 * p < 4 ? n - 4 * p : 4;
            hit_packet4_store(&packet_hits[p], &hits[first + 4 * p], lanes);
            for (uint32_t l = 0; l < lanes; l++) occluded[first + 4 * p + l] = masks[p] >> l & 1;
        }
    }
    free(packets);
    free(packet_hits);
}

/* Disagreements of kernel `k` with the reference on `rays`, closest hit and
 * occlusion. */
static uint32_t disagreements(const fixture *f, const kernel_case *k, const rtt_ray *rays, uint32_t count,
                              kd_counters *counters)
{
    rtt_hit *want = malloc((size_t)count * sizeof *want), *got = malloc((size_t)count * sizeof *got);
    uint8_t *want_occ = malloc(count), *got_occ = malloc(count);
    assert_non_null(want);
    assert_non_null(got);
    assert_non_null(want_occ);
    assert_non_null(got_occ);
    rtt_engine_intersect(f->reference, rays, want, count);
    rtt_engine_occluded(f->reference, rays, want_occ, count);
    trace_with(f, k, rays, count, got, got_occ, counters);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < count; i++) {
        const rtt_ray *ray = &rays[i];
        if (hits_disagree(f, ray, &got[i], &want[i])) {
            if (bad < 5)
                print_message("%s/%s: ray %u got prim %u t %.9g, reference prim %u t %.9g\n", k->name,
                              rtt_isa_name(k->isa), i, got[i].prim, (double)got[i].t, want[i].prim,
                              (double)want[i].t);
            bad++;
        }
        int unspecified = (want[i].prim != RTT_MISS && near_interval_end(ray, want[i].t)) ||
                          (got[i].prim != RTT_MISS && near_interval_end(ray, got[i].t));
        if (got_occ[i] != want_occ[i] && !unspecified) {
            if (bad < 5)
                print_message("%s/%s: ray %u occluded %d, reference %d\n", k->name, rtt_isa_name(k->isa), i,
                              got_occ[i], want_occ[i]);
            bad++;
        }
    }
    if (grazing_count)
        print_message("%s/%s: %u grazing same-triangle hits beyond 1e-5 (isect precision)\n", k->name,
                      rtt_isa_name(k->isa), grazing_count);
    grazing_count = 0;
    free(want);
    free(got);
    free(want_occ);
    free(got_occ);
    return bad;
}

static void check_all_kernels(const fixture *f, const rtt_ray *rays, uint32_t count)
{
    for (size_t k = 0; k < kernel_count; k++) assert_int_equal(disagreements(f, &kernels[k], rays, count, NULL), 0);
}

/* Rays that differ from the reference's answer in any bit of t, u, v, prim
 * or occlusion. */
static uint32_t bit_differences(const fixture *f, const kernel_case *k, const rtt_ray *rays, uint32_t count)
{
    rtt_hit *want = malloc((size_t)count * sizeof *want), *got = malloc((size_t)count * sizeof *got);
    uint8_t *want_occ = malloc(count), *got_occ = malloc(count);
    assert_true(want && got && want_occ && got_occ);
    rtt_engine_intersect(f->reference, rays, want, count);
    rtt_engine_occluded(f->reference, rays, want_occ, count);
    trace_with(f, k, rays, count, got, got_occ, NULL);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (memcmp(&got[i], &want[i], sizeof got[i]) == 0 && got_occ[i] == want_occ[i]) continue;
        if (bad++ < 5)
            print_message("%s/%s: ray %u got prim %u t %a u %a v %a occ %d, reference prim %u t %a u %a v %a occ %d\n",
                          k->name, rtt_isa_name(k->isa), i, got[i].prim, (double)got[i].t, (double)got[i].u,
                          (double)got[i].v, got_occ[i], want[i].prim, (double)want[i].t, (double)want[i].u,
                          (double)want[i].v, want_occ[i]);
    }
    free(want), free(got), free(want_occ), free(got_occ);
    return bad;
}

/* ---- tests ---- */

/* The watertight test is the reference's arithmetic in the same order, and
 * every kernel keeps the closest hit with ties to the smaller prim: so
 * every answer is the reference's, to the bit, at every instruction set. */
static void test_watertight_kernels_answer_every_ray_bit_for_bit_as_the_reference(void **state)
{
    const fixture *f = *state;
    assert_string_equal(rtt_engine_isect_name(f->optimized), "watertight");
    uint32_t camera_count, plane_count;
    rtt_ray *camera = primary_rays(64, 64, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &camera_count);
    rtt_ray *random = random_rays(8192, 4242, ALL_SPECIALS);
    rtt_ray *shadow = shadow_rays(8192, rtt_v3(0.2f, 2.5f, 0.4f), 31);
    rtt_ray *plane = plane_rays(f->tree, &plane_count, 7);
    for (size_t k = 0; k < kernel_count; k++) {
        assert_int_equal(bit_differences(f, &kernels[k], camera, camera_count), 0);
        assert_int_equal(bit_differences(f, &kernels[k], random, 8192), 0);
        assert_int_equal(bit_differences(f, &kernels[k], shadow, 8192), 0);
        assert_int_equal(bit_differences(f, &kernels[k], plane, plane_count), 0);
    }
    free(camera), free(random), free(shadow), free(plane);
}

/* Tiny triangles far from the rays' origins (test_fixtures_optimized.h):
 * the reference's answers are the brute force's over every triangle with
 * its own test, and every kernel's are the reference's, to the bit. */
static void test_rays_at_tiny_far_triangles_match_the_brute_force_and_the_reference(void **state)
{
    const fixture *f = *state;
    enum { RAYS = 4096 };
    float *xyz = tiny_far_triangles(TINY_FAR_TRIANGLES, TINY_FAR_SEED); /* the fixture's scene */
    rtt_ray *rays = rays_at_tiny_far_triangles(xyz, TINY_FAR_TRIANGLES, RAYS, TINY_FAR_SEED + 1u);
    free(xyz);
    rtt_hit *want = malloc(RAYS * sizeof *want);
    assert_non_null(want);
    rtt_engine_intersect(f->reference, rays, want, RAYS);
    uint32_t hits = 0, lost = 0;
    for (uint32_t i = 0; i < RAYS; i++) {
        rtt_hit truth = {INFINITY, 0.0f, 0.0f, RTT_MISS};
        for (uint32_t prim = 0; prim < f->scene->triangle_count; prim++) {
            rtt_vec3 tri[3];
            rtt_scene_triangle(f->scene, prim, tri);
            float t, u, v;
            if (rtt_reference_intersect_triangle(&rays[i], tri, &t, &u, &v) && t < truth.t)
                truth = (rtt_hit){t, u, v, prim};
        }
        hits += truth.prim != RTT_MISS;
        if (memcmp(&truth, &want[i], sizeof truth) != 0 && lost++ < 5)
            print_message("ray %u: reference prim %u t %a, brute force prim %u t %a\n", i, want[i].prim,
                          (double)want[i].t, truth.prim, (double)truth.t);
    }
    print_message("%u rays at tiny far triangles, %u hits: the reference answers %u otherwise than the brute force\n",
                  RAYS, hits, lost);
    assert_int_equal(lost, 0);
    assert_true(hits > RAYS / 2);
    for (size_t k = 0; k < kernel_count; k++) assert_int_equal(bit_differences(f, &kernels[k], rays, RAYS), 0);
    free(rays), free(want);
}

/* From inside a closed mesh, rays aimed exactly at its corners, at its
 * edges' midpoints and at other points of its edges must hit it: none slips
 * between two faces. */
static void test_watertight_kernels_let_no_ray_aimed_at_corners_or_edges_out_of_a_closed_mesh(void **state)
{
    const fixture *f = *state;
    enum { RAYS = 2048 };
    rtt_ray *rays = octahedron_corner_and_edge_rays(f->scene, RAYS, 1, 0xC0FFEEull);
    rtt_hit *hits = malloc(RAYS * sizeof *hits);
    uint8_t *occluded = malloc(RAYS);
    assert_true(hits && occluded);
    for (size_t k = 0; k < kernel_count; k++) {
        trace_with(f, &kernels[k], rays, RAYS, hits, occluded, NULL);
        uint32_t escapes = 0;
        for (uint32_t i = 0; i < RAYS; i++) escapes += hits[i].prim == RTT_MISS || !occluded[i];
        if (escapes) print_message("%s/%s: %u of %u rays escaped\n", kernels[k].name, rtt_isa_name(kernels[k].isa),
                                   escapes, (unsigned)RAYS);
        assert_int_equal(escapes, 0);
    }
    free(rays), free(hits), free(occluded);
}

static void test_camera_rays_match_reference(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *rays = primary_rays(64, 64, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
    check_all_kernels(f, rays, count);
    free(rays);
}

static void test_camera_inside_the_soup_with_mixed_direction_signs_matches_reference(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    /* a wide view from inside: the lanes of a quad straddle the axes */
    rtt_ray *rays = primary_rays(48, 48, rtt_v3(0.05f, 0.02f, 0.3f), 2.5f, &count);
    check_all_kernels(f, rays, count);
    free(rays);
}

static void test_random_rays_with_nan_inf_zero_and_empty_intervals_match_reference(void **state)
{
    const fixture *f = *state;
    rtt_ray *rays = random_rays(8192, 12345, ALL_SPECIALS);
    check_all_kernels(f, rays, 8192);
    free(rays);
}

static void test_shadow_rays_toward_one_point_match_reference(void **state)
{
    const fixture *f = *state;
    rtt_ray *rays = shadow_rays(8192, rtt_v3(0.2f, 2.5f, 0.4f), 777);
    check_all_kernels(f, rays, 8192);
    free(rays);
}

static void test_rays_lying_in_split_planes_match_reference(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *rays = plane_rays(f->tree, &count, 99);
    assert_true(count > 0);
    check_all_kernels(f, rays, count);
    free(rays);
}

static void test_axis_parallel_rays_onto_the_floor_match_reference(void **state)
{
    const fixture *f = *state;
    /* straight down (+-0.0 in x and z) onto the floor, the box's bottom face,
     * from a grid over and beyond its edges */
    enum { SIDE = 40 };
    rtt_ray rays[SIDE * SIDE];
    for (int i = 0; i < SIDE * SIDE; i++) {
        float x = -2.5f + 5.0f * (float)(i % SIDE) / (SIDE - 1), z = -2.5f + 5.0f * (float)(i / SIDE) / (SIDE - 1);
        float zero = (i % 3) ? 0.0f : -0.0f;
        rays[i] = (rtt_ray){{x, 2.0f, z}, {zero, -1.0f, (i % 2) ? -0.0f : 0.0f}, 0.0f, INFINITY};
    }
    check_all_kernels(f, rays, SIDE * SIDE);
}

static void test_nan_and_inf_lanes_miss_and_are_not_occluded_without_the_loader(void **state)
{
    const fixture *f = *state;
    /* packets built by hand (not by ray_packet4_load, which already turns
     * such rays into empty lanes): lane 0 is a good ray straight down */
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int field = 0; field < 4; field++)
        for (int which = 0; which < 3; which++) {
            ray_packet4 packet;
            rtt_ray good = {{0.1f, 3, 0.2f}, {0, -1, 0}, 0.0f, INFINITY};
            ray_packet4_load(&packet, (const rtt_ray[4]){good, good, good, good}, 4);
            _Alignas(16) float v[4] = {0, 0, 0, 0};
            __m128 *target = field == 0 ? &packet.org[1] : field == 1 ? &packet.dir[1] : field == 2 ? &packet.tnear
                                                                                                   : &packet.tfar;
            _mm_store_ps(v, *target);
            for (int l = 1; l < 4; l++) v[l] = bad[which];
            *target = _mm_load_ps(v);
            for (int a = 0; a < 3; a++) packet.inv_dir[a] = _mm_div_ps(_mm_set1_ps(1.0f), packet.dir[a]);
            for (size_t k = 0; k < kernel_count; k++) {
                hit_packet4 hits;
                uint8_t occ = 0xFF;
                hit_packet4_clear(&hits);
                kernel_closest(&kernels[k], f->tree, &packet, &hits, 1, 1, NULL);
                kernel_occluded(&kernels[k], f->tree, &packet, &occ, 1, 1, NULL);
                rtt_hit out[4];
                hit_packet4_store(&hits, out, 4);
                assert_int_not_equal(out[0].prim, RTT_MISS); /* the good lane hits the floor or the soup */
                assert_true(occ & 1);
                /* a -inf tnear or +inf tfar is a legal interval, not a bad lane */
                int legal = (field == 2 && which == 2) || (field == 3 && which == 1);
                for (int l = 1; l < 4 && !legal; l++) {
                    assert_int_equal(out[l].prim, RTT_MISS);
                    assert_false(occ >> l & 1);
                }
            }
        }
}

static void test_closest_hit_kernels_only_lower_the_hits_they_are_given(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *rays = primary_rays(16, 16, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
    rtt_hit *want = malloc(count * sizeof *want);
    assert_non_null(want);
    rtt_engine_intersect(f->reference, rays, want, count);
    for (size_t k = 0; k < kernel_count; k++)
        for (uint32_t p = 0; p < count / 4; p++) {
            ray_packet4 packet;
            ray_packet4_load(&packet, &rays[4 * p], 4);
            /* lanes 0, 1 hold a closer fake hit; lanes 2, 3 a farther one */
            hit_packet4 hits;
            _Alignas(16) float t[4];
            for (int l = 0; l < 4; l++) {
                float ref = want[4 * p + l].t;
                t[l] = l < 2 ? (isfinite(ref) ? 0.5f * ref : 1.0f) : (isfinite(ref) ? 2.0f * ref + 1.0f : 1e30f);
            }
            hits.t = _mm_load_ps(t);
            hits.u = hits.v = _mm_setzero_ps();
            hits.prim = _mm_set1_epi32(123456);
            kernel_closest(&kernels[k], f->tree, &packet, &hits, 1, 1, NULL);
            rtt_hit out[4];
            hit_packet4_store(&hits, out, 4);
            for (int l = 0; l < 4; l++) {
                const rtt_hit *ref = &want[4 * p + l];
                if (l < 2 || ref->prim == RTT_MISS) {
                    assert_int_equal(out[l].prim, 123456);
                    assert_true(out[l].t == t[l]);
                } else {
                    assert_false(hits_disagree(f, &rays[4 * p + l], &out[l], ref));
                }
            }
        }
    free(want);
    free(rays);
}

static void test_single_leaf_tree_matches_reference(void **state)
{
    const fixture *f = *state;
    assert_true(kd_node_is_leaf(&f->tree->nodes[0]));
    rtt_ray *rays = random_rays(2048, 4242, ALL_SPECIALS);
    for (uint32_t i = 0; i < 2048; i++) rays[i].org[2] = rays[i].org[2] > 0 ? 1.0f : -1.0f; /* face the triangle */
    check_all_kernels(f, rays, 2048);
    uint32_t count;
    free(rays);
    rays = primary_rays(32, 32, rtt_v3(0.1f, 0.2f, 3.0f), 0.5f, &count);
    check_all_kernels(f, rays, count);
    free(rays);
}

static void test_tree_of_degenerate_triangles_never_hits(void **state)
{
    const fixture *f = *state;
    assert_int_equal(f->tree->triangle_count, 0);
    rtt_ray *rays = random_rays(1024, 7, ALL_SPECIALS);
    check_all_kernels(f, rays, 1024);
    free(rays);
}

static void test_empty_and_leaf_only_trees_built_by_hand_never_hit(void **state)
{
    (void)state;
    kd_node root = {.leaf = 0, .bits = KD_AXIS_LEAF};
    kd_leaf leaf = {0, 0, {0, 0, 0}, {1, 1, 1}};
    kd_tree zeroed, empty_leaf;
    memset(&zeroed, 0, sizeof zeroed);
    memset(&empty_leaf, 0, sizeof empty_leaf);
    empty_leaf.nodes = &root;
    empty_leaf.leaves = &leaf;
    empty_leaf.node_count = 1;
    empty_leaf.leaf_count = 1;
    empty_leaf.bounds = (rtt_bounds){{0, 0, 0}, {1, 1, 1}};
    const kd_tree *trees[2] = {&zeroed, &empty_leaf};
    rtt_ray rays[4] = {{{0.5f, 0.5f, -1}, {0, 0, 1}, 0, INFINITY},
                       {{0.5f, 0.5f, 0.5f}, {1, 1, 1}, 0, INFINITY},
                       {{-1, -1, -1}, {1, 1, 1}, 0, INFINITY},
                       {{0.5f, 0.5f, 0.5f}, {-0.0f, 0, 1}, -1, 1}};
    ray_packet4 packet;
    ray_packet4_load(&packet, rays, 4);
    for (int t = 0; t < 2; t++)
        for (size_t k = 0; k < kernel_count; k++) {
            hit_packet4 hits;
            uint8_t occ = 0xFF;
            hit_packet4_clear(&hits);
            kd_counters counters = {0, 0, 0};
            kernel_closest(&kernels[k], trees[t], &packet, &hits, 1, 1, &counters);
            kernel_occluded(&kernels[k], trees[t], &packet, &occ, 1, 1, &counters);
            rtt_hit out[4];
            hit_packet4_store(&hits, out, 4);
            for (int l = 0; l < 4; l++) assert_int_equal(out[l].prim, RTT_MISS);
            assert_int_equal(occ, 0);
        }
}

/* Hits are kept wherever they lie and ties go to the smaller prim, so the
 * order cells are visited in cannot change a result: the three kernels, at
 * every instruction set, return the bits of mono at SSE4 (kernels[0]). */
static void test_mono_packet_and_omni_return_identical_hits(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *sets[2] = {random_rays(8192, 2024, ALL_SPECIALS),
                        primary_rays(64, 64, rtt_v3(0.05f, 0.02f, 0.3f), 2.5f, &count)};
    const uint32_t counts[2] = {8192, count};
    for (int s = 0; s < 2; s++) {
        rtt_hit *hits[KERNEL_NAMES * 3];
        uint8_t *occluded[KERNEL_NAMES * 3];
        for (size_t k = 0; k < kernel_count; k++) {
            hits[k] = malloc(counts[s] * sizeof *hits[k]);
            occluded[k] = malloc(counts[s]);
            assert_non_null(hits[k]);
            assert_non_null(occluded[k]);
            trace_with(f, &kernels[k], sets[s], counts[s], hits[k], occluded[k], NULL);
        }
        for (size_t k = 1; k < kernel_count; k++) {
            assert_memory_equal(hits[0], hits[k], counts[s] * sizeof *hits[k]);
            assert_memory_equal(occluded[0], occluded[k], counts[s]);
        }
        for (size_t k = 0; k < kernel_count; k++) {
            free(hits[k]);
            free(occluded[k]);
        }
        free(sets[s]);
    }
}

static void test_counters_count_and_never_change_results(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *rays = primary_rays(64, 64, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
    rtt_ray *random = random_rays(4096, 555, ALL_SPECIALS);
    rtt_hit *with = malloc(count * sizeof *with), *without = malloc(count * sizeof *without);
    uint8_t *occ_with = malloc(count), *occ_without = malloc(count);
    assert_non_null(with);
    assert_non_null(without);
    assert_non_null(occ_with);
    assert_non_null(occ_without);
    for (size_t k = 0; k < kernel_count; k++) {
        const rtt_ray *sets[2] = {rays, random};
        const uint32_t counts[2] = {count, 4096};
        for (int s = 0; s < 2; s++) {
            kd_counters counters = {0, 0, 0};
            trace_with(f, &kernels[k], sets[s], counts[s], with, occ_with, &counters);
            trace_with(f, &kernels[k], sets[s], counts[s], without, occ_without, NULL);
            assert_memory_equal(with, without, counts[s] * sizeof *with);
            assert_memory_equal(occ_with, occ_without, counts[s]);
            assert_true(counters.packets > 0);
            assert_true(counters.steps > 0);
            assert_true(counters.isects > 0);
            if (s == 0) /* every primary packet is traced twice (closest, occlusion) */
                assert_int_equal(counters.packets, 2 * (count / 4));
            print_message("%-6s %-6s %s: N %.2f I %.2f per 2x2 packet (closest + occlusion)\n", kernels[k].name,
                          rtt_isa_name(kernels[k].isa), s ? "random " : "primary",
                          (double)counters.steps / (double)counters.packets,
                          (double)counters.isects / (double)counters.packets);
        }
    }
    free(with);
    free(without);
    free(occ_with);
    free(occ_without);
    free(rays);
    free(random);
}

int main(void)
{
    kernel_count = kernel_cases_every_isa(kernel_names, KERNEL_NAMES, kernels);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_camera_rays_match_reference, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_camera_inside_the_soup_with_mixed_direction_signs_matches_reference,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_random_rays_with_nan_inf_zero_and_empty_intervals_match_reference,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_random_rays_with_nan_inf_zero_and_empty_intervals_match_reference,
                                        setup_large_triangles, teardown),
        cmocka_unit_test_setup_teardown(test_shadow_rays_toward_one_point_match_reference, setup_small_soup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_rays_lying_in_split_planes_match_reference, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_rays_lying_in_split_planes_match_reference, setup_large_triangles,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_axis_parallel_rays_onto_the_floor_match_reference, setup_small_soup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_nan_and_inf_lanes_miss_and_are_not_occluded_without_the_loader,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_closest_hit_kernels_only_lower_the_hits_they_are_given,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_single_leaf_tree_matches_reference, setup_one_triangle, teardown),
        cmocka_unit_test_setup_teardown(test_tree_of_degenerate_triangles_never_hits, setup_degenerate_only,
                                        teardown),
        cmocka_unit_test(test_empty_and_leaf_only_trees_built_by_hand_never_hit),
        cmocka_unit_test_setup_teardown(test_mono_packet_and_omni_return_identical_hits, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_mono_packet_and_omni_return_identical_hits, setup_large_triangles,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_counters_count_and_never_change_results, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_watertight_kernels_answer_every_ray_bit_for_bit_as_the_reference,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_watertight_kernels_answer_every_ray_bit_for_bit_as_the_reference,
                                        setup_large_triangles, teardown),
        cmocka_unit_test_setup_teardown(
            test_watertight_kernels_let_no_ray_aimed_at_corners_or_edges_out_of_a_closed_mesh, setup_octahedron,
            teardown),
        cmocka_unit_test_setup_teardown(test_rays_at_tiny_far_triangles_match_the_brute_force_and_the_reference,
                                        setup_tiny_far_triangles, teardown),
        /* the projected test, against the reference within tolerance */
        cmocka_unit_test_setup_teardown(test_camera_rays_match_reference, setup_small_soup_projected, teardown),
        cmocka_unit_test_setup_teardown(test_random_rays_with_nan_inf_zero_and_empty_intervals_match_reference,
                                        setup_small_soup_projected, teardown),
        cmocka_unit_test_setup_teardown(test_shadow_rays_toward_one_point_match_reference, setup_small_soup_projected,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_rays_lying_in_split_planes_match_reference, setup_small_soup_projected,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_mono_packet_and_omni_return_identical_hits, setup_small_soup_projected,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

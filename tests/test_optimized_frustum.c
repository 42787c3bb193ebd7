/* The proxy kernels (frustum, MFT, cone, MFT-cone; optimized/kd/traverse_*.c),
 * each at every instruction set this CPU runs, against the reference engine,
 * ray by ray, on random triangle soups: primary-like camera tiles,
 * arbitrary random rays (with NaN, zero and axis-parallel ones mixed in) and
 * shadow-like rays toward one point.
 *
 * Agreement: both miss, or both hit with |t - t_ref| <= 1e-5 * max(1, |t_ref|).
 * A different prim is a tie only when both triangles are hit by the ray
 * within that tolerance (checked with rtt_reference_intersect_triangle).  A
 * hit within tolerance of tnear or tfar is unspecified (docs/ARCHITECTURE.md) and not
 * counted.  Every kernel must show zero disagreements. */
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

/* ---- comparison ---- */

/* 1 when the hits disagree beyond tolerance (and are not a documented tie). */
static int hits_disagree(const fixture *f, const rtt_ray *ray, const rtt_hit *got, const rtt_hit *want)
{
    int got_hit = got->prim != RTT_MISS, want_hit = want->prim != RTT_MISS;
    if (!got_hit && !want_hit) return 0;
    if (got_hit != want_hit) return !near_interval_end(ray, got_hit ? got->t : want->t);
    if (fabsf(got->t - want->t) > t_tolerance(want->t)) return 1;
    if (got->prim == want->prim) return 0;
    return !(prim_hit_at(f, ray, got->prim, want->t) && prim_hit_at(f, ray, want->prim, got->t));
}

/* The proxy kernels at every instruction set the CPU runs (main). */
static const char *const kernel_names[] = {"frustum", "mft", "cone", "mft-cone"};
#define KERNEL_NAMES (sizeof kernel_names / sizeof kernel_names[0])
static kernel_case kernels[KERNEL_NAMES * 3];
static size_t kernel_count;

/* Traces `rays` in blocks of tile*tile rays with `k` and counts
 * disagreements with the reference, closest hit and occlusion. */
static uint32_t disagreements(const fixture *f, const kernel_case *k, const rtt_ray *rays, uint32_t count,
                              uint32_t tile, int leaf_culling, kd_counters *counters)
{
    rtt_hit *want = malloc((size_t)count * sizeof *want);
    uint8_t *want_occ = malloc(count);
    assert_non_null(want);
    assert_non_null(want_occ);
    rtt_engine_intersect(f->reference, rays, want, count);
    rtt_engine_occluded(f->reference, rays, want_occ, count);
    uint32_t per_block = tile * tile, bad = 0;
    ray_packet4 *packets = aligned_alloc(16, (per_block / 4) * sizeof *packets);
    hit_packet4 *hits = aligned_alloc(16, (per_block / 4) * sizeof *hits);
    uint8_t occ[KD_BLOCK_MAX_PACKETS];
    assert_non_null(packets);
    assert_non_null(hits);
    for (uint32_t first = 0; first < count; first += per_block) {
        uint32_t n = count - first < per_block ? count - first : per_block, np = (n + 3) / 4;
        for (uint32_t p = 0; p < np; p++)
            ray_packet4_load(&packets[p], &rays[first + 4 * p], n - 4 * p < 4 ? n - 4 * p : 4);
        for (uint32_t p = 0; p < np; p++) hit_packet4_clear(&hits[p]);
        kernel_closest(k, f->tree, packets, hits, np, leaf_culling, counters);
        kernel_occluded(k, f->tree, packets, occ, np, leaf_culling, NULL);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t p = i / 4, l = i % 4;
            rtt_hit lanes[4];
            hit_packet4_store(&hits[p], lanes, 4);
            rtt_hit got = lanes[l];
            const rtt_ray *ray = &rays[first + i];
            if (hits_disagree(f, ray, &got, &want[first + i])) {
                if (bad < 5)
                    print_message("%s/%s tile %u culling %d: ray %u got prim %u t %g, reference prim %u t %g\n",
                                  k->name, rtt_isa_name(k->isa), tile, leaf_culling, first + i, got.prim,
                                  (double)got.t, want[first + i].prim, (double)want[first + i].t);
                bad++;
            }
            int got_occ = occ[p] >> l & 1;
            if (got_occ != want_occ[first + i] && !(want[first + i].prim != RTT_MISS &&
                                                    near_interval_end(ray, want[first + i].t))) {
                if (bad < 5)
                    print_message("%s/%s tile %u: ray %u occluded %d, reference %d\n", k->name,
                                  rtt_isa_name(k->isa), tile, first + i, got_occ, want_occ[first + i]);
                bad++;
            }
        }
    }
    free(packets);
    free(hits);
    free(want);
    free(want_occ);
    return bad;
}

static void check_all_kernels(const fixture *f, const rtt_ray *rays, uint32_t count, uint32_t tile)
{
    for (size_t k = 0; k < kernel_count; k++)
        for (int culling = 0; culling <= 1; culling++)
            assert_int_equal(disagreements(f, &kernels[k], rays, count, tile, culling, NULL), 0);
}

static void test_frustum_kernels_match_reference_on_camera_tiles_of_every_size(void **state)
{
    const fixture *f = *state;
    const uint32_t tiles[] = {4, 8, 16, 32};
    for (size_t i = 0; i < 4; i++) {
        uint32_t count;
        rtt_ray *rays = primary_rays(64, tiles[i], rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
        check_all_kernels(f, rays, count, tiles[i]);
        free(rays);
    }
}

static void test_camera_inside_the_soup_with_mixed_direction_signs_matches_reference(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    /* eye inside the geometry, a wide view: rays of a tile go in all directions of the split planes */
    rtt_ray *rays = primary_rays(32, 8, rtt_v3(0.05f, 0.02f, 0.3f), 0.7f, &count);
    for (uint32_t i = 0; i < count; i++) {
        rtt_vec3 d = rtt_v3_normalize(rtt_v3(rays[i].dir[0] * 3.0f, rays[i].dir[1] * 3.0f, rays[i].dir[2]));
        rays[i].dir[0] = d.x, rays[i].dir[1] = d.y, rays[i].dir[2] = d.z;
    }
    check_all_kernels(f, rays, count, 8);
    free(rays);
}

static void test_random_rays_with_nan_and_zero_directions_match_reference(void **state)
{
    const fixture *f = *state;
    rtt_ray *rays = random_rays(4096, 12345, NAN_AND_ZERO_SPECIALS);
    check_all_kernels(f, rays, 4096, 8);
    check_all_kernels(f, rays, 1024, 32);
    free(rays);
}

static void test_shadow_rays_toward_one_point_match_reference(void **state)
{
    const fixture *f = *state;
    rtt_ray *rays = shadow_rays(4096, rtt_v3(0.2f, 2.5f, 0.4f), 777);
    check_all_kernels(f, rays, 4096, 8);
    check_all_kernels(f, rays, 4096, 16);
    free(rays);
}

static void test_nan_rays_miss_and_are_not_occluded(void **state)
{
    const fixture *f = *state;
    rtt_ray rays[16];
    for (int i = 0; i < 16; i++)
        rays[i] = (rtt_ray){{0.1f, 3, 0.1f}, {0, -1, 0}, 0.0f, INFINITY}; /* down onto the floor at least */
    rays[1].org[0] = NAN;
    rays[6].dir[2] = NAN;
    rays[9].tnear = NAN;
    rays[12].tfar = NAN;
    ray_packet4 packets[4];
    hit_packet4 hits[4];
    uint8_t occ[4];
    for (int p = 0; p < 4; p++) ray_packet4_load(&packets[p], &rays[4 * p], 4);
    for (size_t k = 0; k < kernel_count; k++) {
        for (int p = 0; p < 4; p++) hit_packet4_clear(&hits[p]);
        kernel_closest(&kernels[k], f->tree, packets, hits, 4, 1, NULL);
        kernel_occluded(&kernels[k], f->tree, packets, occ, 4, 1, NULL);
        rtt_hit out[16];
        for (int p = 0; p < 4; p++) hit_packet4_store(&hits[p], &out[4 * p], 4);
        const int nan_rays[4] = {1, 6, 9, 12};
        for (int i = 0; i < 4; i++) {
            assert_int_equal(out[nan_rays[i]].prim, RTT_MISS);
            assert_false(occ[nan_rays[i] / 4] >> (nan_rays[i] % 4) & 1);
        }
        assert_int_not_equal(out[0].prim, RTT_MISS); /* the good rays hit the floor or the soup */
    }
}

static void test_counters_give_steps_and_tests_per_packet(void **state)
{
    const fixture *f = *state;
    uint32_t count;
    rtt_ray *rays = primary_rays(64, 8, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
    for (size_t k = 0; k < kernel_count; k++) {
        kd_counters with = {0, 0, 0}, without = {0, 0, 0};
        assert_int_equal(disagreements(f, &kernels[k], rays, count, 8, 1, &with), 0);
        assert_int_equal(disagreements(f, &kernels[k], rays, count, 8, 0, &without), 0);
        assert_int_equal(with.packets, count / 4);
        assert_true(with.steps > 0);
        assert_true(with.isects > 0);
        assert_true(without.isects > 0);
        print_message("%-8s %-6s 8x8: N %.2f I %.2f (I without culling %.2f)\n", kernels[k].name,
                      rtt_isa_name(kernels[k].isa),
                      (double)with.steps / (double)with.packets, (double)with.isects / (double)with.packets,
                      (double)without.isects / (double)without.packets);
    }
    free(rays);
}

int main(void)
{
    kernel_count = kernel_cases_every_isa(kernel_names, KERNEL_NAMES, kernels);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_frustum_kernels_match_reference_on_camera_tiles_of_every_size,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_camera_inside_the_soup_with_mixed_direction_signs_matches_reference,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_random_rays_with_nan_and_zero_directions_match_reference,
                                        setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_shadow_rays_toward_one_point_match_reference, setup_small_soup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_nan_rays_miss_and_are_not_occluded, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_counters_give_steps_and_tests_per_packet, setup_small_soup, teardown),
        /* the projected test */
        cmocka_unit_test_setup_teardown(test_frustum_kernels_match_reference_on_camera_tiles_of_every_size,
                                        setup_small_soup_projected, teardown),
        cmocka_unit_test_setup_teardown(test_random_rays_with_nan_and_zero_directions_match_reference,
                                        setup_small_soup_projected, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The instruction-set copies of the optimized kernels (optimized/kd/
 * kernel_isa.h, kernel_table.c, shadows/shadow_table.c): every kernel has
 * one row per instruction set; kd_kernel_find hands out the widest copy the
 * request and the CPU allow; the engine names the copy it traces with; and
 * every copy this CPU runs returns the SSE4 copy's results bit for bit (t,
 * u, v, prim, occlusion masks, counters, edge-width occlusion) on the same
 * rays.  That last claim is what makes golden images independent of the
 * CPU: the copies come from the same sources with -ffp-contract=off, so
 * only the encoding (VEX, EVEX) differs, never an operation. */
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
#include "rtt/edge_width.h"
#include "shadow_kernels.h"
#include "test_fixtures_optimized.h"

#define ISA_COUNT_TESTED 3u /* SSE4, AVX2, AVX-512 */

/* ---- the tables ---- */

static void test_every_kernel_has_one_row_per_instruction_set(void **state)
{
    (void)state;
    uint32_t names = 0, rows = 0;
    while (kd_kernel_name_at(names)) names++;
    while (kd_kernel_row_at(rows)) rows++;
    assert_int_equal(names, 7);
    assert_int_equal(rows, names * ISA_COUNT_TESTED);
    for (uint32_t n = 0; n < names; n++)
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            uint32_t found = 0;
            for (uint32_t r = 0; r < rows; r++) {
                const kd_kernel *row = kd_kernel_row_at(r);
                found += strcmp(row->name, kd_kernel_name_at(n)) == 0 && row->isa == isa;
            }
            if (found != 1) fail_msg("%s has %u rows for %s", kd_kernel_name_at(n), found, rtt_isa_name(isa));
        }
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        const kd_shadow_kernels *row = kd_shadow_kernels_row_at((uint32_t)(isa - TEST_ISA_FIRST));
        assert_non_null(row);
        assert_int_equal(row->isa, isa);
    }
    assert_null(kd_shadow_kernels_row_at(ISA_COUNT_TESTED));
}

/* The widest instruction set not wider than `requested` that the CPU runs. */
static rtt_isa widest_runnable(rtt_isa requested)
{
    rtt_isa best = RTT_ISA_SSE4;
    for (rtt_isa isa = TEST_ISA_FIRST; isa <= requested && isa < RTT_ISA_COUNT; isa = isa_next(isa))
        if (rtt_isa_supported(isa)) best = isa;
    return best;
}

static void test_find_falls_back_to_the_widest_row_the_cpu_runs(void **state)
{
    (void)state;
    for (rtt_isa requested = TEST_ISA_FIRST; requested < RTT_ISA_COUNT; requested = isa_next(requested)) {
        const rtt_isa want = widest_runnable(requested);
        for (uint32_t n = 0; kd_kernel_name_at(n); n++) {
            const kd_kernel *row = kd_kernel_find(kd_kernel_name_at(n), requested);
            assert_non_null(row);
            assert_string_equal(row->name, kd_kernel_name_at(n));
            assert_int_equal(row->isa, want);
            assert_true(rtt_isa_supported(row->isa));
        }
        assert_string_equal(kd_kernel_find("", requested)->name, "mft");
        assert_null(kd_kernel_find("no-such-kernel", requested));
        assert_int_equal(kd_shadow_kernels_find(requested)->isa, want);
        print_message("asked for %s: %s rows\n", rtt_isa_name(requested), rtt_isa_name(want));
    }
}

static void test_the_engine_names_the_copy_it_traces_with(void **state)
{
    const fixture *f = *state;
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        rtt_engine_options opt;
        rtt_engine_options_default(&opt);
        snprintf(opt.traversal, sizeof opt.traversal, "%s", "mft");
        opt.isa = isa;
        rtt_error err = {{0}};
        rtt_engine *engine = rtt_optimized_engine_create(f->scene, &opt, &err);
        if (!engine) fail_msg("%s", err.message);
        char want[32];
        snprintf(want, sizeof want, "mft/%s", rtt_isa_name(isa));
        assert_string_equal(rtt_engine_kernel_name(engine), want);
        assert_int_equal(kd_engine_kernel(engine)->isa, isa);
        rtt_engine_destroy(engine);
    }
}

/* ---- the copies against the SSE4 copy ---- */

typedef struct traced {
    hit_packet4 *hits;     /* every lane as the kernel left it */
    uint8_t *occluded;
    kd_counters counters;
} traced;

/* `count` rays through one copy in the blocks its kernel reads at tile 8. */
static traced trace_copy(const kd_tree *tree, const kd_kernel *row, const rtt_ray *rays, uint32_t count)
{
    const uint32_t packets = (count + 3) / 4, block = kd_kernel_block_packets(row, 8);
    ray_packet4 *loaded = aligned_alloc(16, packets * sizeof *loaded);
    traced out = {aligned_alloc(16, packets * sizeof *out.hits), malloc(packets), {0, 0, 0}};
    assert_non_null(loaded);
    assert_non_null(out.hits);
    assert_non_null(out.occluded);
    for (uint32_t p = 0; p < packets; p++) {
        ray_packet4_load(&loaded[p], &rays[4 * p], count - 4 * p < 4 ? count - 4 * p : 4);
        hit_packet4_clear(&out.hits[p]);
    }
    for (uint32_t first = 0; first < packets; first += block) {
        const uint32_t n = packets - first < block ? packets - first : block;
        const kd_query closest = {.packets = loaded + first, .packet_count = n, .hits = out.hits + first,
                                  .leaf_culling = 1, .counters = &out.counters};
        const kd_query occlusion = {.packets = loaded + first, .packet_count = n, .occluded = out.occluded + first,
                                    .leaf_culling = 1, .counters = &out.counters};
        row->trace(tree, &closest);
        row->trace(tree, &occlusion);
    }
    free(loaded);
    return out;
}

static void traced_free(traced *t)
{
    free(t->hits);
    free(t->occluded);
}

static void assert_same_as_sse4(const kd_tree *tree, const rtt_ray *rays, uint32_t count, const char *set)
{
    uint32_t compared = 0;
    for (uint32_t n = 0; kd_kernel_name_at(n); n++) {
        const char *name = kd_kernel_name_at(n);
        const kd_kernel *base = kd_kernel_find(name, RTT_ISA_SSE4);
        assert_int_equal(base->isa, RTT_ISA_SSE4);
        traced want = trace_copy(tree, base, rays, count);
        for (rtt_isa isa = isa_next(RTT_ISA_SSE4); isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!rtt_isa_supported(isa)) continue;
            const kd_kernel *row = kd_kernel_find(name, isa);
            assert_int_equal(row->isa, isa);
            traced got = trace_copy(tree, row, rays, count);
            const uint32_t packets = (count + 3) / 4;
            for (uint32_t p = 0; p < packets; p++)
                if (memcmp(&got.hits[p], &want.hits[p], sizeof got.hits[p]) != 0 ||
                    got.occluded[p] != want.occluded[p])
                    fail_msg("%s/%s, %s rays: packet %u differs from sse4", name, rtt_isa_name(isa), set, p);
            assert_memory_equal(&got.counters, &want.counters, sizeof got.counters);
            traced_free(&got);
            compared++;
        }
        traced_free(&want);
    }
    print_message("%s rays: %u kernel copies equal their sse4 copy\n", set, compared);
}

static void test_every_copy_returns_the_sse4_hits_bit_for_bit(void **state)
{
    const fixture *f = *state;
    for (rtt_isa isa = isa_next(RTT_ISA_SSE4); isa < RTT_ISA_COUNT; isa = isa_next(isa)) isa_runs(isa);
    uint32_t count;
    rtt_ray *rays = random_rays(8192, 31337, ALL_SPECIALS);
    assert_same_as_sse4(f->tree, rays, 8192, "random");
    free(rays);
    rays = primary_rays(64, 8, rtt_v3(0.3f, 0.8f, 3.5f), 0.7f, &count);
    assert_same_as_sse4(f->tree, rays, count, "camera");
    free(rays);
    rays = primary_rays(48, 8, rtt_v3(0.05f, 0.02f, 0.3f), 2.5f, &count);
    assert_same_as_sse4(f->tree, rays, count, "inside camera");
    free(rays);
    rays = shadow_rays(8192, rtt_v3(0.2f, 2.5f, 0.4f), 4711);
    assert_same_as_sse4(f->tree, rays, 8192, "shadow");
    free(rays);
}

/* Sample groups as the renderer makes them: N rays from one point to a disk
 * around the light (a common origin: the shared-apex cone), and every
 * third group with its origins jittered (the generic cone). */
static rtt_ray *sample_groups(uint32_t groups, uint32_t n, uint32_t *group_first, uint64_t seed)
{
    rng r = {seed};
    rtt_ray *rays = malloc((size_t)groups * n * sizeof *rays);
    assert_non_null(rays);
    const rtt_vec3 light = rtt_v3(0.2f, 2.5f, 0.4f);
    for (uint32_t g = 0; g < groups; g++) {
        rtt_vec3 p = rtt_v3(rng_range(&r, -1.2f, 1.2f), rng_range(&r, -1.2f, 1.0f), rng_range(&r, -1.2f, 1.2f));
        group_first[g] = g * n;
        for (uint32_t k = 0; k < n; k++) {
            rtt_vec3 o = g % 3 == 2 ? rtt_v3_add(p, rtt_v3(rng_range(&r, -0.01f, 0.01f), 0.0f, 0.0f)) : p;
            rtt_vec3 target = rtt_v3_add(light, rtt_v3(rng_range(&r, -0.3f, 0.3f), 0.0f, rng_range(&r, -0.3f, 0.3f)));
            rtt_vec3 d = rtt_v3_sub(target, o);
            float dist = rtt_v3_length(d);
            d = rtt_v3_scale(d, 1.0f / dist);
            rays[g * n + k] = (rtt_ray){{o.x, o.y, o.z}, {d.x, d.y, d.z}, 1e-4f, dist - 1e-4f};
        }
    }
    group_first[groups] = groups * n;
    return rays;
}

/* What one copy of the shadow kernels makes of the same rays. */
typedef struct shadowed {
    uint8_t *cone, *pyramid;
    float *edge;
    kd_counters counters;
} shadowed;

static shadowed shadow_copy(const fixture *f, rtt_isa isa, const rtt_ray *rays, const uint32_t *group_first,
                            uint32_t groups, const rtt_ray *edge_rays, const uint32_t *order, uint32_t edges,
                            const rtt_edge_width_model *model)
{
    const kd_shadow_kernels *row = kd_shadow_kernels_find(isa);
    assert_int_equal(row->isa, isa);
    const uint32_t rays_total = group_first[groups], packets = sc_group_packets(group_first, groups);
    ray_packet4 *scratch = aligned_alloc(16, packets * sizeof *scratch);
    uint8_t *masks = malloc(packets);
    shadowed out = {malloc(rays_total), malloc(rays_total), malloc(edges * sizeof(float)), {0, 0, 0}};
    assert_non_null(scratch);
    assert_non_null(masks);
    row->trace_groups(f->tree, NULL, rays, group_first, groups, scratch, masks, out.cone, 1, &out.counters);
    row->trace_groups(f->tree, kd_kernel_find("frustum", isa), rays, group_first, groups, scratch, masks, out.pyramid,
                      1, &out.counters);
    row->edge_width_stream(f->tree, model, edge_rays, order, edges, out.edge, &out.counters);
    free(scratch);
    free(masks);
    return out;
}

static void test_every_copy_of_the_shadow_kernels_returns_the_sse4_results_bit_for_bit(void **state)
{
    const fixture *f = *state;
    const uint32_t groups = 240, n = 16, edges = 4096;
    uint32_t *group_first = malloc((groups + 1) * sizeof *group_first);
    uint32_t *order = malloc(edges * sizeof *order);
    rtt_ray *edge_rays = malloc(edges * sizeof *edge_rays);
    assert_non_null(group_first);
    assert_non_null(order);
    assert_non_null(edge_rays);
    rtt_ray *rays = sample_groups(groups, n, group_first, 2718);
    rng r = {99};
    for (uint32_t i = 0; i < edges; i++) {
        rtt_vec3 p = rtt_v3(rng_range(&r, -1.5f, 1.5f), rng_range(&r, -1.3f, 1.0f), rng_range(&r, -1.5f, 1.5f));
        if (!rtt_edge_width_ray(rtt_v3(0.2f, 2.5f, 0.4f), p, 1e-4f, &edge_rays[i])) edge_rays[i] = edge_rays[0];
        order[i] = i;
    }
    const rtt_edge_width_model model = rtt_edge_width_model_make(f->scene, 0.05f, false);
    shadowed want = shadow_copy(f, RTT_ISA_SSE4, rays, group_first, groups, edge_rays, order, edges, &model);
    uint32_t blocked = 0;
    for (uint32_t i = 0; i < groups * n; i++) blocked += want.cone[i];
    assert_true(blocked > 0 && blocked < groups * n); /* the groups see both */
    for (rtt_isa isa = isa_next(RTT_ISA_SSE4); isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        shadowed got = shadow_copy(f, isa, rays, group_first, groups, edge_rays, order, edges, &model);
        assert_memory_equal(got.cone, want.cone, groups * n);
        assert_memory_equal(got.pyramid, want.pyramid, groups * n);
        assert_memory_equal(got.edge, want.edge, edges * sizeof(float));
        assert_memory_equal(&got.counters, &want.counters, sizeof got.counters);
        free(got.cone), free(got.pyramid), free(got.edge);
    }
    free(want.cone), free(want.pyramid), free(want.edge);
    free(rays), free(group_first), free(order), free(edge_rays);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_kernel_has_one_row_per_instruction_set),
        cmocka_unit_test(test_find_falls_back_to_the_widest_row_the_cpu_runs),
        cmocka_unit_test_setup_teardown(test_the_engine_names_the_copy_it_traces_with, setup_small_soup, teardown),
        cmocka_unit_test_setup_teardown(test_every_copy_returns_the_sse4_hits_bit_for_bit, setup_small_soup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_every_copy_of_the_shadow_kernels_returns_the_sse4_results_bit_for_bit,
                                        setup_small_soup, teardown),
        /* the same with the projected test */
        cmocka_unit_test_setup_teardown(test_every_copy_returns_the_sse4_hits_bit_for_bit, setup_small_soup_projected,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_every_copy_of_the_shadow_kernels_returns_the_sse4_results_bit_for_bit,
                                        setup_small_soup_projected, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

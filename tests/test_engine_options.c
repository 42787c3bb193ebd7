/* The engine layer's registry, options check and instruction-set choice
 * (engine/engine_registry.c, engine/cpu_features.c, engine/render_options.c),
 * tested with a stand-in engine class so no real engine is involved. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/engine.h"
#include "rtt/render.h"

static const char *stub_kernel(rtt_accel accel, uint32_t i)
{
    static const char *const names[] = {"alpha", "beta"};
    return accel <= RTT_ACCEL_KD && i < 2 ? names[i] : NULL;
}

static bool stub_check(const rtt_engine_options *opt, rtt_error *err)
{
    for (uint32_t i = 0; stub_kernel(RTT_ACCEL_KD, i); i++)
        if (strcmp(opt->traversal, stub_kernel(RTT_ACCEL_KD, i)) == 0) return true;
    return opt->traversal[0] == '\0' ? true : rtt_error_set(err, "no kernel \"%s\"", opt->traversal);
}

static rtt_engine *stub_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err)
{
    (void)scene, (void)opt;
    rtt_error_set(err, "stub engine: created");
    return NULL;
}

static const rtt_engine_class stub_class = {
    .name = "stub",
    .summary = "a stand-in",
    .uses = RTT_OPTION_TRAVERSAL | RTT_OPTION_TILE | RTT_OPTION_ISA,
    .shadow_methods = (1u << RTT_SHADOWS_NONE) | (1u << RTT_SHADOWS_HARD),
    .create = stub_create,
    .check = stub_check,
    .kernel = stub_kernel,
};

static const rtt_engine_class bare_class = {.name = "bare", .uses = 0, .shadow_methods = 1u, .create = stub_create};

static int register_classes(void **state)
{
    (void)state;
    return rtt_engine_register(&stub_class, NULL) && rtt_engine_register(&bare_class, NULL) ? 0 : -1;
}

static void test_registry_finds_registered_classes_by_name(void **state)
{
    (void)state;
    assert_ptr_equal(rtt_engine_find("stub"), &stub_class);
    assert_ptr_equal(rtt_engine_find("bare"), &bare_class);
    assert_null(rtt_engine_find("nosuch"));
    assert_null(rtt_engine_find(NULL));
    uint32_t count = 0;
    while (rtt_engine_class_at(count)) count++;
    assert_int_equal(count, 2);
    /* the same name again replaces, never duplicates */
    assert_true(rtt_engine_register(&stub_class, NULL));
    assert_null(rtt_engine_class_at(2));
}

static void test_unknown_engine_is_one_line_naming_the_registered_ones(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    assert_null(rtt_engine_create("nosuch", NULL, NULL, &err));
    assert_non_null(strstr(err.message, "unknown engine \"nosuch\""));
    assert_non_null(strstr(err.message, "stub, bare"));
    assert_null(strchr(err.message, '\n'));
}

static void test_create_checks_options_before_the_constructor(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    snprintf(opt.traversal, sizeof opt.traversal, "gamma");
    assert_null(rtt_engine_create("stub", NULL, &opt, &err));
    assert_string_equal(err.message, "no kernel \"gamma\"");
    strcpy(opt.traversal, "beta");
    assert_null(rtt_engine_create("stub", NULL, &opt, &err));
    assert_string_equal(err.message, "stub engine: created");
}

static void test_option_given_to_an_engine_that_does_not_use_it_is_refused(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    assert_true(rtt_engine_options_check("bare", &opt, &err)); /* defaults given by nobody are fine */
    opt.given = RTT_OPTION_TRAVERSAL;
    assert_false(rtt_engine_options_check("bare", &opt, &err));
    assert_string_equal(err.message, "engine \"bare\" does not use a traversal kernel");
    opt.given = RTT_OPTION_MAX_DEPTH;
    assert_false(rtt_engine_options_check("stub", &opt, &err));
    assert_string_equal(err.message, "engine \"stub\" does not use a tree depth bound");
    opt.given = RTT_OPTION_TILE | RTT_OPTION_ISA;
    assert_true(rtt_engine_options_check("stub", &opt, &err));
}

static void test_triangle_tests_parse_by_name_and_an_engine_that_has_no_choice_refuses_one(void **state)
{
    (void)state;
    rtt_isect isect = RTT_ISECT_DEFAULT;
    assert_true(rtt_isect_parse("watertight", &isect));
    assert_int_equal(isect, RTT_ISECT_WATERTIGHT);
    assert_true(rtt_isect_parse("projected", &isect));
    assert_int_equal(isect, RTT_ISECT_PROJECTED);
    assert_false(rtt_isect_parse("default", &isect));
    assert_false(rtt_isect_parse("moller", &isect));
    assert_false(rtt_isect_parse(NULL, &isect));
    assert_string_equal(rtt_isect_name(RTT_ISECT_WATERTIGHT), "watertight");
    rtt_error err = {{0}};
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.isect = RTT_ISECT_PROJECTED;
    opt.given = RTT_OPTION_ISECT;
    assert_false(rtt_engine_options_check("stub", &opt, &err));
    assert_string_equal(err.message, "engine \"stub\" does not use a triangle-test choice");
    opt.given = 0;
    opt.isect = RTT_ISECT_COUNT;
    assert_false(rtt_engine_options_check("stub", &opt, &err));
    assert_non_null(strstr(err.message, "unknown triangle test"));
}

static void test_generic_option_values_are_checked_for_every_engine(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_engine_options opt;
    static const uint32_t good_tiles[] = {0, 4, 8, 16, 32}, bad_tiles[] = {1, 2, 6, 12, 64, 1u << 31};
    for (size_t i = 0; i < sizeof good_tiles / sizeof good_tiles[0]; i++) {
        rtt_engine_options_default(&opt);
        opt.tile = good_tiles[i];
        assert_true(rtt_engine_options_check("bare", &opt, &err));
    }
    for (size_t i = 0; i < sizeof bad_tiles / sizeof bad_tiles[0]; i++) {
        rtt_engine_options_default(&opt);
        opt.tile = bad_tiles[i];
        assert_false(rtt_engine_options_check("bare", &opt, &err));
        assert_non_null(strstr(err.message, "4, 8, 16 or 32"));
    }
    rtt_engine_options_default(&opt);
    opt.max_tree_depth = RTT_KD_DEPTH_LIMIT + 1;
    assert_false(rtt_engine_options_check("bare", &opt, &err));
    rtt_engine_options_default(&opt);
    opt.isa = RTT_ISA_COUNT;
    assert_false(rtt_engine_options_check("bare", &opt, &err));
    rtt_engine_options_default(&opt);
    memset(opt.traversal, 'x', sizeof opt.traversal); /* no terminator */
    assert_false(rtt_engine_options_check("bare", &opt, &err));
}

static void test_isa_names_round_trip_and_auto_resolves_to_a_supported_set(void **state)
{
    (void)state;
    for (int isa = 0; isa < RTT_ISA_COUNT; isa++) {
        rtt_isa parsed;
        assert_true(rtt_isa_parse(rtt_isa_name((rtt_isa)isa), &parsed));
        assert_int_equal(parsed, isa);
    }
    rtt_isa parsed = RTT_ISA_SSE4;
    assert_false(rtt_isa_parse("avx", &parsed));
    assert_false(rtt_isa_parse(NULL, &parsed));
    unsetenv("RTT_ISA");
    rtt_isa widest = rtt_isa_resolve(RTT_ISA_AUTO);
    assert_true(widest > RTT_ISA_AUTO && rtt_isa_supported(widest));
    assert_true(rtt_isa_supported(RTT_ISA_SSE4)); /* rtt's baseline */
    for (int isa = widest + 1; isa < RTT_ISA_COUNT; isa++) assert_false(rtt_isa_supported((rtt_isa)isa));
    assert_int_equal(rtt_isa_resolve(RTT_ISA_SSE4), RTT_ISA_SSE4);
}

static void test_rtt_isa_environment_picks_the_set_and_bad_values_are_errors(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    setenv("RTT_ISA", "sse4", 1);
    assert_int_equal(rtt_isa_resolve(RTT_ISA_AUTO), RTT_ISA_SSE4);
    assert_true(rtt_engine_options_check("bare", &opt, &err));
    opt.isa = RTT_ISA_AVX2; /* an explicit choice wins over the environment */
    assert_int_equal(rtt_isa_resolve(opt.isa), RTT_ISA_AVX2);
    opt.isa = RTT_ISA_AUTO;
    setenv("RTT_ISA", "mmx", 1);
    assert_false(rtt_engine_options_check("bare", &opt, &err));
    assert_string_equal(err.message, "RTT_ISA=mmx: expected auto, sse4, avx2 or avx512");
    setenv("RTT_ISA", "", 1); /* set empty: as unset, the widest (a shell's RTT_ISA= ...) */
    assert_true(rtt_engine_options_check("bare", &opt, &err));
    rtt_isa widest = RTT_ISA_SSE4;
    for (int isa = RTT_ISA_SSE4; isa < RTT_ISA_COUNT; isa++)
        if (rtt_isa_supported((rtt_isa)isa)) widest = (rtt_isa)isa;
    assert_int_equal(rtt_isa_resolve(RTT_ISA_AUTO), widest);
    unsetenv("RTT_ISA");
    assert_true(rtt_engine_options_check("bare", &opt, &err));
}

static void test_render_options_refuse_a_shadow_method_the_engine_does_not_draw(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    assert_int_equal(opt.max_bounces, RTT_BOUNCES_OF_SCENE);
    assert_true(rtt_render_options_check("stub", &opt, &err)); /* hard */
    assert_true(rtt_shadow_method_parse("multi:4", &opt, &err));
    assert_false(rtt_render_options_check("stub", &opt, &err));
    assert_string_equal(err.message, "engine \"stub\" does not render multi shadows");
    rtt_render_options_default(&opt);
    opt.max_bounces = 0;
    assert_true(rtt_render_options_check("stub", &opt, &err));
    opt.max_bounces = RTT_MAX_BOUNCES + 1;
    assert_false(rtt_render_options_check("stub", &opt, &err));
}

static void test_shadow_method_messages_name_no_command_line_flag(void **state)
{
    (void)state;
    static const char *const bad[] = {"multi:0",        "cone:257",         "pyramid:x",     "edgewidth:-1",
                                      "soft",           "",                 "interleaved:3", "interleaved:33",
                                      "interleaved:16:", "interleaved:filter", "interleaved:8x", "interleaved:"};
    rtt_render_options opt;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        rtt_error err = {{0}};
        rtt_render_options_default(&opt);
        assert_false(rtt_shadow_method_parse(bad[i], &opt, &err));
        assert_null(strstr(err.message, "--"));
        assert_non_null(strstr(err.message, "shadow method"));
    }
}

static void test_interleaved_parses_its_count_and_filter_flag(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    assert_true(opt.shadow_filter);
    assert_false(opt.shadow_refine);
    static const struct { const char *text; uint32_t n; bool filter, refine; } good[] = {
        {"interleaved", 16, true, false},          {"interleaved:4", 4, true, false},
        {"interleaved:32", 32, true, false},       {"interleaved:8:nofilter", 8, false, false},
        {"interleaved:nofilter", 16, false, false}, {"interleaved:refine", 16, true, true},
        {"interleaved:8:refine", 8, true, true},
    };
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        rtt_render_options_default(&opt);
        assert_true(rtt_shadow_method_parse(good[i].text, &opt, &err));
        assert_int_equal(opt.shadows, RTT_SHADOWS_INTERLEAVED);
        assert_int_equal(opt.shadow_samples, good[i].n);
        assert_int_equal(opt.shadow_filter, good[i].filter);
        assert_int_equal(opt.shadow_refine, good[i].refine);
    }
    assert_false(rtt_shadow_method_parse("interleaved:refine:nofilter", &opt, &err));
    assert_string_equal(err.message, "shadow method \"interleaved:refine:nofilter\": expected "
                                     "interleaved[:N][:nofilter|:refine], N from 4 to 32");
    assert_string_equal(rtt_shadow_method_name(RTT_SHADOWS_INTERLEAVED), "interleaved");
    assert_false(rtt_shadow_method_parse("interleaved:64", &opt, &err));
    assert_string_equal(err.message, "shadow method \"interleaved:64\": the sample count must be a whole number from 4 to 32");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_registry_finds_registered_classes_by_name),
        cmocka_unit_test(test_interleaved_parses_its_count_and_filter_flag),
        cmocka_unit_test(test_unknown_engine_is_one_line_naming_the_registered_ones),
        cmocka_unit_test(test_create_checks_options_before_the_constructor),
        cmocka_unit_test(test_option_given_to_an_engine_that_does_not_use_it_is_refused),
        cmocka_unit_test(test_generic_option_values_are_checked_for_every_engine),
        cmocka_unit_test(test_isa_names_round_trip_and_auto_resolves_to_a_supported_set),
        cmocka_unit_test(test_rtt_isa_environment_picks_the_set_and_bad_values_are_errors),
        cmocka_unit_test(test_render_options_refuse_a_shadow_method_the_engine_does_not_draw),
        cmocka_unit_test(test_shadow_method_messages_name_no_command_line_flag),
        cmocka_unit_test(test_triangle_tests_parse_by_name_and_an_engine_that_has_no_choice_refuses_one),
    };
    return cmocka_run_group_tests(tests, register_classes, NULL);
}

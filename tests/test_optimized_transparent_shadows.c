/* Transparent shadows (include/rtt/shade.h): a floor point under two
 * transparent panes (transparency 0.5 and 0.6) sees the light through
 * both, vis = 0.5 * 0.6, under an opaque pane vis = 0, with no panes 1 —
 * in the reference renderer and in the optimized one, for hard, multi:N,
 * cone:N and pyramid:N shadows, at every instruction set.  Edge width on a
 * sphere light treats transparent occluders as opaque (vis 0 here). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "test_isa.h"
#include "test_tempdir.h"

static int setup(void **state) { return scratch_create(state, "transparent_shadows"); }

/* panes: "none", "glass" (0.5 over 0.6) or "opaque"; light: point or sphere */
static rtt_scene *make_scene(void **state, const char *panes, bool sphere)
{
    char text[4096];
    const char *pane_material = strcmp(panes, "opaque") == 0 ? "stone" : "glass";
    snprintf(text, sizeof text,
             "{\"camera\": {\"eye\": [4, 0.5, 0], \"look_at\": [0, 0, 0], \"fov\": 10}, \"ambient\": 0,"
             " \"materials\": [{\"name\": \"floor\"}, {\"name\": \"stone\"},"
             "  {\"name\": \"glass\", \"type\": \"transparent\", \"transparency\": 0.5},"
             "  {\"name\": \"glass2\", \"type\": \"transparent_reflective\", \"transparency\": 0.6, \"reflection\": 0.1}],"
             " \"lights\": [{\"type\": \"%s\", \"position\": [0, 10, 0]%s}],"
             " \"meshes\": [{\"shape\": {\"type\": \"quad\", \"corners\": [[-5,0,-5],[-5,0,5],[5,0,5],[5,0,-5]]},"
             " \"material\": \"floor\"}%s]}",
             sphere ? "sphere" : "point", sphere ? ", \"radius\": 0.3" : "",
             strcmp(panes, "none") == 0 ? ""
                                        : strcmp(pane_material, "glass") == 0
                                              ? ", {\"shape\": {\"type\": \"quad\", \"corners\": [[-1,1,-1],[-1,1,1],[1,1,1],[1,1,-1]]},"
                                                " \"material\": \"glass\"},"
                                                " {\"shape\": {\"type\": \"quad\", \"corners\": [[-1,2,-1],[-1,2,1],[1,2,1],[1,2,-1]]},"
                                                " \"material\": \"glass2\"}"
                                              : ", {\"shape\": {\"type\": \"quad\", \"corners\": [[-1,1,-1],[-1,1,1],[1,1,1],[1,1,-1]]},"
                                                " \"material\": \"stone\"}");
    const char *path = scratch_path(state, "scene.json");
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    rtt_error err;
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    if (!s) fail_msg("%s", err.message);
    return s;
}

/* The centre pixel's red channel (the floor at the origin). */
static float centre(const rtt_scene *s, bool optimized, rtt_shadow_method method, const char *traversal, rtt_isa isa)
{
    rtt_error err = {{0}};
    rtt_engine_options eo;
    rtt_engine_options_default(&eo);
    eo.isa = isa;
    rtt_engine *engine = optimized ? rtt_optimized_engine_create(s, &eo, &err) : rtt_reference_engine_create(s, &eo, &err);
    if (!engine) fail_msg("engine: %s", err.message);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    opt.width = opt.height = 16;
    opt.threads = 1;
    opt.shadows = method;
    opt.shadow_samples = 4;
    opt.engine.isa = isa;
    if (optimized) snprintf(opt.engine.traversal, sizeof opt.engine.traversal, "%s", traversal);
    rtt_image *image = rtt_image_create(16, 16, 0, &err);
    assert_non_null(image);
    bool ok = optimized ? rtt_optimized_render(engine, &opt, image, NULL, &err)
                        : rtt_reference_render(s, engine, &opt, image, NULL, &err);
    if (!ok) fail_msg("render: %s", err.message);
    float red = image->rgb[3 * (8 * 16 + 8)];
    rtt_image_free(image);
    rtt_engine_destroy(engine);
    return red;
}

static void check_method(void **state, rtt_shadow_method method, bool sphere, float expected_vis, const char *traversal)
{
    /* cone:N and pyramid:N trace multi:N's rays: the reference draws multi:N */
    const rtt_shadow_method reference =
        method == RTT_SHADOWS_CONE || method == RTT_SHADOWS_PYRAMID ? RTT_SHADOWS_MULTI : method;
    rtt_scene *none = make_scene(state, "none", sphere), *glass = make_scene(state, "glass", sphere),
              *opaque = make_scene(state, "opaque", sphere);
    const float lit = centre(none, false, reference, NULL, RTT_ISA_AUTO);
    assert_true(lit > 0.05f);
    const float through = centre(glass, false, reference, NULL, RTT_ISA_AUTO);
    if (fabsf(through / lit - expected_vis) > 1e-5f)
        fail_msg("reference: vis %g, expected %g", (double)(through / lit), (double)expected_vis);
    assert_true(centre(opaque, false, reference, NULL, RTT_ISA_AUTO) == 0.0f);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        float optimized = centre(glass, true, method, traversal, isa);
        if (fabsf(optimized - through) > 1e-6f)
            fail_msg("optimized %s at isa %d: %.9g, the reference %.9g", traversal, (int)isa, (double)optimized,
                     (double)through);
        assert_true(centre(opaque, true, method, traversal, isa) == 0.0f);
    }
    rtt_scene_free(none);
    rtt_scene_free(glass);
    rtt_scene_free(opaque);
}

static void test_hard_shadows_through_two_panes(void **state) { check_method(state, RTT_SHADOWS_HARD, false, 0.3f, "mft"); }
static void test_hard_shadows_through_two_panes_mono(void **state)
{
    check_method(state, RTT_SHADOWS_HARD, false, 0.3f, "mono");
}
static void test_multi_shadows_through_two_panes(void **state) { check_method(state, RTT_SHADOWS_MULTI, true, 0.3f, "mft"); }
static void test_cone_shadows_through_two_panes(void **state) { check_method(state, RTT_SHADOWS_CONE, true, 0.3f, "mft"); }
static void test_pyramid_shadows_through_two_panes(void **state)
{
    check_method(state, RTT_SHADOWS_PYRAMID, true, 0.3f, "frustum");
}

static void test_edge_width_treats_transparent_occluders_as_opaque(void **state)
{
    rtt_scene *glass = make_scene(state, "glass", true);
    assert_true(centre(glass, true, RTT_SHADOWS_EDGEWIDTH, "mft", RTT_ISA_AUTO) < 1e-3f);
    rtt_scene_free(glass);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_hard_shadows_through_two_panes, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_hard_shadows_through_two_panes_mono, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_multi_shadows_through_two_panes, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_cone_shadows_through_two_panes, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_pyramid_shadows_through_two_panes, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_edge_width_treats_transparent_occluders_as_opaque, setup, remove_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The viewer's parts that need no window (viewer/): the fly camera's maths,
 * the script reader's syntax and messages, and the choices the keys cycle,
 * read from the engine registry. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "fly_camera.h"
#include "rtt/rtt.h"
#include "view_choices.h"
#include "view_script.h"

static const rtt_camera start_camera = {
    .eye = {0.0f, 1.0f, 3.4f}, .look_at = {0.0f, 0.9f, 0.0f}, .up = {0.0f, 1.0f, 0.0f}, .fov_deg = 40.0f};

static bool same_camera(rtt_camera a, rtt_camera b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void unmoved_camera_is_the_start_camera_exactly(void **state)
{
    (void)state;
    fly_camera c = fly_camera_from(&start_camera, 4.0f);
    assert_true(same_camera(fly_camera_to(&c), start_camera));
    fly_camera_move(&c, 0.0f, 0.0f, 0.0f, 1.0f);
    fly_camera_turn(&c, 0.0f, 0.0f);
    assert_true(same_camera(fly_camera_to(&c), start_camera));
    assert_float_equal(c.speed, 1.0f, 1e-6f); /* a quarter of the scene size per second */
}

static void moves_along_forward_right_and_up(void **state)
{
    (void)state;
    const rtt_camera level = {.eye = {0, 0, 0}, .look_at = {0, 0, -2}, .up = {0, 1, 0}, .fov_deg = 60};
    fly_camera c = fly_camera_from(&level, 8.0f); /* speed 2 units/s */
    fly_camera_move(&c, 1.0f, 0.0f, 0.0f, 0.5f);
    assert_float_equal(c.eye.z, -1.0f, 1e-6f);
    fly_camera_move(&c, 0.0f, 1.0f, 0.0f, 0.5f);
    assert_float_equal(c.eye.x, 1.0f, 1e-6f); /* right of -z with y up is +x */
    fly_camera_move(&c, 0.0f, 0.0f, -1.0f, 1.0f);
    assert_float_equal(c.eye.y, -2.0f, 1e-6f);
    rtt_camera out = fly_camera_to(&c);
    assert_float_equal(out.look_at.z - out.eye.z, -2.0f, 1e-5f); /* the focus distance is kept */
    assert_false(same_camera(out, level));
}

static void turns_and_stops_short_of_the_poles(void **state)
{
    (void)state;
    const rtt_camera level = {.eye = {0, 0, 0}, .look_at = {0, 0, -1}, .up = {0, 1, 0}, .fov_deg = 60};
    fly_camera c = fly_camera_from(&level, 1.0f);
    fly_camera_turn(&c, 90.0f, 0.0f); /* right: from -z to +x */
    assert_float_equal(c.forward.x, 1.0f, 1e-5f);
    assert_float_equal(c.forward.z, 0.0f, 1e-5f);
    fly_camera_turn(&c, 0.0f, 30.0f); /* up 30 degrees */
    assert_float_equal(c.forward.y, sinf(30.0f * 3.14159265f / 180.0f), 1e-5f);
    fly_camera_turn(&c, 0.0f, 500.0f); /* past the pole: held 1 degree short */
    assert_float_equal(acosf(c.forward.y) * 180.0f / 3.14159265f, 1.0f, 1e-2f);
    fly_camera_turn(&c, 0.0f, -500.0f);
    assert_float_equal(acosf(c.forward.y) * 180.0f / 3.14159265f, 179.0f, 1e-2f);
    assert_float_equal(rtt_v3_length(c.forward), 1.0f, 1e-5f);
}

static void speed_scales_within_bounds(void **state)
{
    (void)state;
    fly_camera c = fly_camera_from(&start_camera, 4.0f);
    fly_camera_scale_speed(&c, 2.0f, 4.0f);
    assert_float_equal(c.speed, 2.0f, 1e-6f);
    for (int i = 0; i < 100; i++) fly_camera_scale_speed(&c, 10.0f, 4.0f);
    assert_float_equal(c.speed, 4e6f, 1.0f);
    for (int i = 0; i < 100; i++) fly_camera_scale_speed(&c, 0.1f, 4.0f);
    assert_float_equal(c.speed, 4e-6f, 1e-9f);
}

static void script_reads_every_command(void **state)
{
    (void)state;
    const char *text = "# a comment\n\nframes 3\nkey w 10  # held\nkey t\ndrag -5 7\nresize 320 200\nconverge\n"
                       "bench 4\nprint-overlay\nprint-camera\nscreenshot out.png\nset shadows multi:4\n";
    view_script s;
    rtt_error err = {{0}};
    assert_true(view_script_parse("s.txt", text, &s, &err));
    assert_int_equal(s.count, 11);
    assert_int_equal(s.commands[10].kind, VIEW_CMD_SET);
    assert_int_equal(s.commands[10].what, VIEW_CHOICE_SHADOWS);
    assert_string_equal(s.commands[10].text, "multi:4");
    assert_int_equal(s.commands[0].kind, VIEW_CMD_FRAMES);
    assert_int_equal(s.commands[0].a, 3);
    assert_int_equal(s.commands[0].line, 3);
    assert_int_equal(s.commands[1].kind, VIEW_CMD_KEY);
    assert_string_equal(s.commands[1].text, "w");
    assert_int_equal(s.commands[1].b, 10);
    assert_int_equal(s.commands[2].b, 0);
    assert_int_equal(s.commands[3].a, -5);
    assert_int_equal(s.commands[3].b, 7);
    assert_int_equal(s.commands[4].kind, VIEW_CMD_RESIZE);
    assert_int_equal(s.commands[9].kind, VIEW_CMD_SCREENSHOT);
    assert_string_equal(s.commands[9].text, "out.png");
    view_script_free(&s);
}

static void script_errors_name_file_and_line(void **state)
{
    (void)state;
    static const struct {
        const char *text, *message;
    } cases[] = {
        {"frames 1\nfly\n", "s.txt:2: unknown command \"fly\""},
        {"frames\n", "s.txt:1: expected \"frames N\""},
        {"frames 0\n", "s.txt:1: frames: the frame count must be a whole number from 1 to 100000"},
        {"frames 2x\n", "s.txt:1: frames: the frame count"},
        {"key w 0\n", "s.txt:1: key w: the hold must be"},
        {"drag 1\n", "s.txt:1: expected \"drag DX DY\""},
        {"resize 0 10\n", "s.txt:1: resize: W and H must be"},
        {"screenshot out.jpg\n", "s.txt:1: screenshot out.jpg: the file must end in .png or .exr"},
        {"print-overlay now\n", "s.txt:1: expected \"print-overlay\""},
        {"key a b c d e\n", "s.txt:1: too many words"},
        {"set speed 3\n", "s.txt:1: set speed: expected traversal, shadows or isa"},
        {"set isa\n", "s.txt:1: expected \"set traversal|shadows|isa VALUE\""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        view_script s;
        rtt_error err = {{0}};
        assert_false(view_script_parse("s.txt", cases[i].text, &s, &err));
        if (strncmp(err.message, cases[i].message, strlen(cases[i].message)) != 0)
            fail_msg("case %zu: \"%s\" does not start with \"%s\"", i, err.message, cases[i].message);
        assert_null(s.commands);
    }
}

static void choices_offer_every_kernel_method_and_isa(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    assert_true(rtt_builtin_engines_register(&err));
    rtt_render_options start;
    rtt_render_options_default(&start);
    view_choices c;
    assert_true(view_choices_make("optimized", &start, NULL, "mft/avx2", &c, &err));
    /* every kernel of every accel of the class, from the registry */
    const rtt_engine_class *cls = rtt_engine_find("optimized");
    uint32_t kernels = 0;
    for (int a = RTT_ACCEL_DEFAULT + 1; a < RTT_ACCEL_COUNT; a++)
        for (uint32_t i = 0; cls->kernel((rtt_accel)a, i); i++) kernels++;
    assert_int_equal(c.traversal_count, kernels);
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_TRAVERSAL), "mft");
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_SHADOWS), "hard");
    /* every shadow method the optimized renderer draws */
    uint32_t methods = 0;
    for (int m = 0; m < 32; m++) methods += (cls->shadow_methods >> m) & 1u;
    assert_int_equal(c.shadow_count, methods);
    /* the ISAs this CPU runs */
    uint32_t isas = 0;
    for (int i = RTT_ISA_AUTO + 1; i < RTT_ISA_COUNT; i++) isas += rtt_isa_supported((rtt_isa)i);
    assert_int_equal(c.isa_count, isas);

    /* stepping wraps both ways and applies as render options */
    for (uint32_t i = 0; i < c.traversal_count; i++) assert_true(view_choices_step(&c, VIEW_CHOICE_TRAVERSAL, 1));
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_TRAVERSAL), "mft");
    assert_true(view_choices_step(&c, VIEW_CHOICE_TRAVERSAL, -1));
    assert_true(view_choices_step(&c, VIEW_CHOICE_SHADOWS, 1));
    rtt_render_options applied = start;
    view_choices_apply(&c, &applied);
    assert_string_equal(applied.engine.traversal, view_choices_label(&c, VIEW_CHOICE_TRAVERSAL));
    assert_int_not_equal(applied.shadows, start.shadows);
    assert_true(rtt_render_options_check("optimized", &applied, &err));
}

static void choices_start_from_what_was_asked(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    assert_true(rtt_builtin_engines_register(&err));
    rtt_render_options start;
    rtt_render_options_default(&start);
    strcpy(start.engine.traversal, "cone");
    start.engine.isa = RTT_ISA_SSE4;
    assert_true(rtt_shadow_method_parse("multi:32", &start, &err));
    view_choices c;
    assert_true(view_choices_make("optimized", &start, "multi:32", "ignored", &c, &err));
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_TRAVERSAL), "cone");
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_SHADOWS), "multi:32");
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_ISA), "sse4");
    rtt_render_options applied = start;
    view_choices_apply(&c, &applied);
    assert_int_equal(applied.shadow_samples, 32);
    /* select by label, as a script's `set` does; another sample count takes its method's entry */
    assert_true(view_choices_select(&c, VIEW_CHOICE_TRAVERSAL, "packet"));
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_TRAVERSAL), "packet");
    assert_false(view_choices_select(&c, VIEW_CHOICE_TRAVERSAL, "no-such-kernel"));
    assert_true(view_choices_select(&c, VIEW_CHOICE_SHADOWS, "cone:8"));
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_SHADOWS), "cone:8");
    assert_false(view_choices_select(&c, VIEW_CHOICE_SHADOWS, "cone:0"));
    assert_true(view_choices_select(&c, VIEW_CHOICE_ISA, "sse4"));
    /* the reference engine has no kernels or ISAs to cycle: nothing to step */
    assert_true(view_choices_make("reference", &start, NULL, "", &c, &err));
    assert_int_equal(c.traversal_count, 0);
    assert_false(view_choices_step(&c, VIEW_CHOICE_TRAVERSAL, 1));
    assert_false(view_choices_step(&c, VIEW_CHOICE_ISA, 1));
    assert_string_equal(view_choices_label(&c, VIEW_CHOICE_TRAVERSAL), "");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(unmoved_camera_is_the_start_camera_exactly),
        cmocka_unit_test(moves_along_forward_right_and_up),
        cmocka_unit_test(turns_and_stops_short_of_the_poles),
        cmocka_unit_test(speed_scales_within_bounds),
        cmocka_unit_test(script_reads_every_command),
        cmocka_unit_test(script_errors_name_file_and_line),
        cmocka_unit_test(choices_offer_every_kernel_method_and_isa),
        cmocka_unit_test(choices_start_from_what_was_asked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The views file (scene/views.c) and a Quake III map's own camera and lights
 * (scene/q3bsp_entities.c): views in file order, found by name, one-line
 * located errors; the intermission camera and its target, the spawn-point
 * fallback at view height, light entities with q3map2's intensity, fall-off
 * and the radius rule; a malformed entity lump is one error line. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "rtt/views.h"
#include "scene_build.h"
#include "test_tempdir.h"

static int setup(void **state) { return scratch_create(state, "views"); }

static const char *write_text(void **state, const char *name, const char *text)
{
    const char *path = scratch_path(state, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

static void test_views_load_in_file_order(void **state)
{
    const char *path = write_text(state, "v.json",
                                  "{ \"_comment\": \"x\",\n"
                                  "  \"b\": { \"camera\": { \"eye\": [0, 0, 5], \"look_at\": [0, 0, 0] } },\n"
                                  "  \"a\": { \"camera\": { \"eye\": [1, 2, 3], \"look_at\": [0, 0, 0], \"fov\": 30 },\n"
                                  "         \"light\": { \"position\": [0, 4, 0], \"radius\": 0.5 }, \"size\": [64, 32] } }\n");
    rtt_view_list list;
    rtt_error err = {{0}};
    assert_true(rtt_views_load(path, &list, &err));
    assert_int_equal(list.count, 2);
    assert_string_equal(list.views[0].name, "b");
    assert_string_equal(list.views[1].name, "a");
    const rtt_view *a = rtt_views_find(&list, "a");
    assert_ptr_equal(a, &list.views[1]);
    assert_true(a->camera.fov_deg == 30.0f && a->camera.up.y == 1.0f);
    assert_true(a->has_light && a->light.type == RTT_LIGHT_SPHERE && a->light.radius == 0.5f);
    assert_int_equal(a->width, 64);
    assert_int_equal(a->height, 32);
    assert_false(list.views[0].has_light);
    assert_null(rtt_views_find(&list, "c"));
    char names[64];
    rtt_views_names(&list, names, sizeof names);
    assert_string_equal(names, "b, a");
    rtt_views_free(&list);
}

static void expect_error(void **state, const char *text, const char *message)
{
    const char *path = write_text(state, "bad.json", text);
    rtt_view_list list;
    rtt_error err = {{0}};
    assert_false(rtt_views_load(path, &list, &err));
    rtt_views_free(&list);
    if (!strstr(err.message, message)) fail_msg("got \"%s\", want \"%s\"", err.message, message);
}

static void test_views_errors_name_file_line_and_place(void **state)
{
    expect_error(state, "{\n \"a\": { \"camera\": { \"eye\": [0, 0, 1], \"look_at\": [0, 0, 1] } } }",
                 "bad.json:2: a.camera.look_at must differ from camera.eye");
    expect_error(state, "{ \"a\": {\n \"camera\": { \"eye\": [0, 0, 1], \"look_at\": [0, 0, 0], \"fov\": 0 } } }",
                 "bad.json:2: a.camera.fov must be a number between 1 and 179");
    expect_error(state, "{ \"a\": { \"light\": { \"position\": [0, 0, 0] } } }", "a: missing \"camera\"");
    expect_error(state, "{ \"a\": { \"camera\": { \"eye\": [0, 0, 1], \"look_at\": [0, 0, 0] }, \"size\": [0, 3] } }",
                 "a.size[0] must be an integer between 1 and 16384");
    expect_error(state, "{ }", "the file holds no views");
    expect_error(state, "[1, 2]", "must be a JSON object of views");
    expect_error(state, "{ \"a\": ", "JSON syntax error");
}

static void test_camera_check_and_the_light_that_follows(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_camera c = {rtt_v3(0, 0, 5), rtt_v3(0, 0, 0), rtt_v3(0, 0, 1), 60};
    assert_false(rtt_camera_check(&c, &err));
    assert_non_null(strstr(err.message, "parallel"));
    c.up = rtt_v3(0, 1, 0);
    assert_true(rtt_camera_check(&c, &err));
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    rtt_scene *scene = rtt_scene_from_triangles(tri, 1, &err);
    assert_non_null(scene);
    assert_int_equal(scene->light_source, RTT_LIGHTS_AT_CAMERA);
    rtt_scene_set_camera(scene, &c);
    assert_true(scene->lights[0].position.z == 5.0f);
    assert_int_equal(scene->camera_source, RTT_CAMERA_FROM_OPTIONS);
    rtt_scene_free(scene);
}

/* A .bsp holding only its header and an entity lump: what the entity
 * reader needs (it reads no other lump; the light grid is absent). */
static const char *write_map(void **state, const char *entities)
{
    const char *path = scratch_path(state, "map.bsp");
    uint8_t header[144] = {'I', 'B', 'S', 'P', 46, 0, 0, 0};
    uint32_t offset = sizeof header, length = (uint32_t)strlen(entities) + 1;
    memcpy(header + 8, &offset, 4);
    memcpy(header + 12, &length, 4);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fwrite(header, 1, sizeof header, f);
    fwrite(entities, 1, length, f);
    fclose(f);
    return path;
}

static rtt_scene *map_scene(void **state, const char *entities, bool *ok, rtt_error *err)
{
    rtt_scene *scene = rtt_scene_new("map.bsp", err); /* the entity reader needs no geometry */
    assert_non_null(scene);
    *ok = rtt_q3bsp_read_entities(scene, write_map(state, entities), err);
    return scene;
}

static void test_map_looks_from_its_intermission_point_at_its_target(void **state)
{
    rtt_error err = {{0}};
    bool ok;
    rtt_scene *s = map_scene(state,
                             "{ \"classname\" \"worldspawn\" }\n"
                             "{ \"classname\" \"info_player_deathmatch\" \"origin\" \"0 0 0\" }\n"
                             "{ \"classname\" \"info_player_intermission\" \"origin\" \"10 20 30\" \"target\" \"t1\" }\n"
                             "{ \"classname\" \"target_position\" \"targetname\" \"t1\" \"origin\" \"110 20 30\" }\n",
                             &ok, &err);
    assert_true(ok);
    assert_int_equal(s->camera_source, RTT_CAMERA_INTERMISSION);
    /* Quake (x, y, z) is rtt (x, z, -y) */
    assert_true(s->camera.eye.x == 10 && s->camera.eye.y == 30 && s->camera.eye.z == -20);
    assert_true(s->camera.look_at.x == 110 && s->camera.look_at.y == 30 && s->camera.look_at.z == -20);
    assert_true(s->camera.fov_deg == 74.0f);
    rtt_scene_free(s);
}

static void test_map_without_intermission_looks_from_a_spawn_point_along_its_angle(void **state)
{
    rtt_error err = {{0}};
    bool ok;
    rtt_scene *s = map_scene(state,
                             "{ \"classname\" \"team_CTF_redspawn\" \"origin\" \"0 0 100\" \"angle\" \"90\" }\n"
                             "{ \"classname\" \"info_player_deathmatch\" \"origin\" \"5 5 5\" }\n",
                             &ok, &err);
    assert_true(ok);
    assert_int_equal(s->camera_source, RTT_CAMERA_SPAWN_POINT);
    assert_true(s->camera.eye.x == 0 && s->camera.eye.y == 126 && s->camera.eye.z == 0); /* +26 view height */
    /* yaw 90: along Quake +y, rtt -z */
    assert_true(fabsf(s->camera.look_at.x) < 1e-3f && s->camera.look_at.z < -60.0f);
    rtt_scene_free(s);
}

static void test_light_entities_keep_q3map2_intensity_and_fall_off(void **state)
{
    rtt_error err = {{0}};
    bool ok;
    rtt_scene *s = map_scene(state,
                             "{ \"classname\" \"light\" \"origin\" \"1 2 3\" }\n"
                             "{ \"classname\" \"light\" \"origin\" \"0 0 0\" \"light\" \"400\" \"_color\" \"0.5 0.25 0\""
                             " \"spawnflags\" \"1\" \"fade\" \"2\" \"_deviance\" \"5\" }\n"
                             "{ \"classname\" \"light\" \"origin\" \"0 0 0\" \"light\" \"-100\" }\n",
                             &ok, &err);
    assert_true(ok);
    assert_int_equal(s->light_source, RTT_LIGHTS_MAP);
    assert_int_equal(s->light_count, 2); /* the negative light is skipped */
    const rtt_light *a = &s->lights[0], *b = &s->lights[1];
    assert_true(a->type == RTT_LIGHT_SPHERE && a->position.x == 1 && a->position.y == 3 && a->position.z == -2);
    assert_true(fabsf(a->intensity - 300.0f * 7500.0f / 255.0f) < 1e-2f);
    assert_true(a->attenuation[0] == 256.0f && a->attenuation[1] == 0.0f && a->attenuation[2] == 1.0f);
    assert_true(fabsf(a->radius - sqrtf(300.0f) / 2) < 1e-4f);
    assert_true(b->color.x == 1.0f && b->color.y == 0.5f && b->color.z == 0.0f);
    float reach = 400.0f * 0.9375f / 2.0f;
    assert_true(fabsf(b->intensity - 400.0f * 0.9375f / 255.0f) < 1e-4f);
    assert_true(b->attenuation[0] == 1.0f && fabsf(b->attenuation[1] - 2.0f / reach) < 1e-7f);
    assert_true(b->radius == 5.0f);
    rtt_scene_free(s);
}

static void test_malformed_entities_are_one_error_line(void **state)
{
    rtt_error err = {{0}};
    bool ok;
    rtt_scene *s = map_scene(state, "{ \"classname\" \"light\"\n \"origin\" \"1 2\" }", &ok, &err);
    assert_false(ok);
    assert_non_null(strstr(err.message, "entity 0 (light): \"origin\" must be three numbers"));
    rtt_scene_free(s);
    s = map_scene(state, "{ \"classname\" \"light\n", &ok, &err);
    assert_false(ok);
    assert_non_null(strstr(err.message, "entities, line 1 (entity 0): a string without its closing quote"));
    rtt_scene_free(s);
    s = map_scene(state, "\"classname\"", &ok, &err);
    assert_false(ok);
    assert_non_null(strstr(err.message, "expected '{'"));
    rtt_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_views_load_in_file_order, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_views_errors_name_file_line_and_place, setup, remove_scratch),
        cmocka_unit_test(test_camera_check_and_the_light_that_follows),
        cmocka_unit_test_setup_teardown(test_map_looks_from_its_intermission_point_at_its_target, setup,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_map_without_intermission_looks_from_a_spawn_point_along_its_angle,
                                        setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_light_entities_keep_q3map2_intensity_and_fall_off, setup,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_malformed_entities_are_one_error_line, setup, remove_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

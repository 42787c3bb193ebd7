/* The JSON scene file (scene/scene_schema.c, scene/scene_schema_meshes.c,
 * located errors by scene/json_locate.c) and the built-in shapes
 * (scene/shapes.c): good files give the right values and defaults, every bad
 * file in tests/data/scene_bad/ gives exactly the line in its .expected file,
 * every scene in scenes/ loads. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene_build.h"
#include "shapes.h"

#define BAD_DIR RTT_SOURCE_DIR "/tests/data/scene_bad"
#define SCENES_DIR RTT_SOURCE_DIR "/scenes"

/* Writes text to a fresh temporary .json file; returns its path (static buffer). */
static const char *write_temp_scene(const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "/tmp/rtt_test_scene_json_%ld.json", (long)getpid());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Parses and finishes; the scene, or NULL with err filled. */
static rtt_scene *parse(const char *path, rtt_error *err)
{
    rtt_scene *scene = rtt_scene_new(path, err);
    assert_non_null(scene);
    if (!rtt_scene_parse_json(scene, path, NULL, err) || !rtt_scene_finish(scene, err)) {
        rtt_scene_free(scene);
        return NULL;
    }
    return scene;
}

static rtt_scene *parse_text(const char *text)
{
    rtt_error err = {{0}};
    const char *path = write_temp_scene(text);
    rtt_scene *scene = parse(path, &err);
    if (!scene) fail_msg("%s", err.message);
    unlink(path);
    return scene;
}

static const char *parse_error(const char *text, char *out, size_t size)
{
    rtt_error err = {{0}};
    const char *path = write_temp_scene(text);
    rtt_scene *scene = parse(path, &err);
    assert_null(scene);
    unlink(path);
    const char *colon = strstr(err.message, ".json:");
    snprintf(out, size, "%s", colon ? colon + 5 : err.message); /* ":line: what" */
    return out;
}

#define TRIANGLE "{\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"triangles\": [[0,1,2]]}"

static void assert_vec3(rtt_vec3 v, float x, float y, float z)
{
    if (fabsf(v.x - x) > 1e-5f || fabsf(v.y - y) > 1e-5f || fabsf(v.z - z) > 1e-5f)
        fail_msg("(%g, %g, %g) is not (%g, %g, %g)", v.x, v.y, v.z, x, y, z);
}

static void test_scene_json_geometry_alone_takes_every_default(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"meshes\": [" TRIANGLE "]}");
    assert_int_equal(s->width, RTT_DEFAULT_WIDTH);
    assert_int_equal(s->height, RTT_DEFAULT_HEIGHT);
    assert_int_equal(s->max_bounces, RTT_DEFAULT_MAX_BOUNCES);
    assert_float_equal(s->ambient, RTT_DEFAULT_AMBIENT, 0.0);
    assert_vec3(s->background, 0, 0, 0);
    assert_int_equal(s->triangle_count, 1);
    assert_int_equal(s->material_count, 1);
    rtt_material d = rtt_material_default();
    assert_memory_equal(&s->materials[0], &d, sizeof d);
    assert_int_equal(s->triangle_material[0], 0);
    assert_string_equal(s->meshes[0].name, "mesh0");
    assert_float_equal(s->camera.fov_deg, RTT_DEFAULT_FOV_DEG, 0.0); /* framed by rtt_scene_finish */
    assert_int_equal(s->light_count, 1);
    assert_int_equal(s->lights[0].type, RTT_LIGHT_POINT);
    rtt_scene_free(s);
}

static void test_scene_json_reads_every_top_level_field(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\n"
                              " \"camera\": {\"eye\": [1, 2, 3], \"look_at\": [0, 1, 0], \"up\": [0, 0, 1], \"fov\": 35},\n"
                              " \"image\": {\"width\": 320, \"height\": 200},\n"
                              " \"background\": [0.1, 0.2, 0.3],\n"
                              " \"ambient\": 0.25, \"max_bounces\": 7, \"bezier_level\": 2,\n"
                              " \"meshes\": [" TRIANGLE "]\n"
                              "}\n");
    assert_vec3(s->camera.eye, 1, 2, 3);
    assert_vec3(s->camera.look_at, 0, 1, 0);
    assert_vec3(s->camera.up, 0, 0, 1);
    assert_float_equal(s->camera.fov_deg, 35.0, 0.0);
    assert_int_equal(s->width, 320);
    assert_int_equal(s->height, 200);
    assert_vec3(s->background, 0.1f, 0.2f, 0.3f);
    assert_float_equal(s->ambient, 0.25, 1e-7);
    assert_int_equal(s->max_bounces, 7);
    rtt_scene_free(s);
}

static void test_scene_json_max_bounces_zero_loads_as_no_reflections(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"max_bounces\": 0, \"meshes\": [" TRIANGLE "]}");
    assert_int_equal(s->max_bounces, 0);
    rtt_scene_free(s);
    char text[256];
    snprintf(text, sizeof text, "{\"max_bounces\": %u, \"meshes\": [" TRIANGLE "]}", RTT_MAX_BOUNCES);
    s = parse_text(text);
    assert_int_equal(s->max_bounces, RTT_MAX_BOUNCES);
    rtt_scene_free(s);
}

static void test_scene_json_max_bounces_past_the_limit_is_one_line_at_its_place(void **state)
{
    (void)state;
    char text[256], want[512];
    snprintf(text, sizeof text, "{\n\"meshes\": [" TRIANGLE "],\n\"max_bounces\": %u\n}", RTT_MAX_BOUNCES + 1u);
    const char *path = write_temp_scene(text);
    rtt_error err = {{0}};
    assert_null(parse(path, &err));
    unlink(path);
    snprintf(want, sizeof want, "%s:3: max_bounces must be an integer between 0 and %u", path, RTT_MAX_BOUNCES);
    assert_string_equal(err.message, want);
}

static void test_scene_json_camera_takes_default_up_and_fov(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"meshes\": [" TRIANGLE "]}");
    assert_vec3(s->camera.up, 0, 1, 0);
    assert_float_equal(s->camera.fov_deg, RTT_DEFAULT_FOV_DEG, 0.0);
    rtt_scene_free(s);
}

static void test_scene_json_materials_read_their_fields_and_default_the_rest(void **state)
{
    (void)state;
    rtt_scene *s = parse_text(
        "{\"materials\": [\n"
        "  {\"name\": \"wall\"},\n"
        "  {\"name\": \"plastic\", \"type\": \"specular\", \"diffuse\": [1, 0, 0], \"specular\": 0.8, \"shininess\": 64},\n"
        "  {\"name\": \"mirror\", \"type\": \"reflective\", \"reflection\": 0.9},\n"
        "  {\"name\": \"glass\", \"type\": \"transparent\", \"transparency\": 0.95, \"ior\": 1.33},\n"
        "  {\"name\": \"gem\", \"type\": \"transparent_reflective\", \"reflection\": 0.2, \"transparency\": 0.7,"
        "   \"edge_width_scale\": 2}\n"
        " ],\n"
        " \"meshes\": [{\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"triangles\": [[0,1,2]], \"material\": \"glass\"}]}");
    rtt_material d = rtt_material_default();
    assert_int_equal(s->material_count, 5);
    assert_string_equal(s->materials[0].name, "wall");
    assert_int_equal(s->materials[0].type, RTT_MATERIAL_DIFFUSE);
    assert_vec3(s->materials[0].diffuse, d.diffuse.x, d.diffuse.y, d.diffuse.z);
    assert_int_equal(s->materials[1].type, RTT_MATERIAL_SPECULAR);
    assert_vec3(s->materials[1].diffuse, 1, 0, 0);
    assert_float_equal(s->materials[1].specular, 0.8, 1e-6);
    assert_float_equal(s->materials[1].shininess, 64, 0);
    assert_int_equal(s->materials[2].type, RTT_MATERIAL_REFLECTIVE);
    assert_float_equal(s->materials[2].reflection, 0.9, 1e-6);
    assert_float_equal(s->materials[2].specular, d.specular, 0);
    assert_int_equal(s->materials[3].type, RTT_MATERIAL_TRANSPARENT);
    assert_float_equal(s->materials[3].transparency, 0.95, 1e-6);
    assert_float_equal(s->materials[3].ior, 1.33, 1e-6);
    assert_float_equal(s->materials[3].edge_width_scale, 1, 0);
    assert_int_equal(s->materials[4].type, RTT_MATERIAL_TRANSPARENT_REFLECTIVE);
    assert_float_equal(s->materials[4].edge_width_scale, 2, 0);
    assert_float_equal(s->materials[4].ior, d.ior, 0);
    assert_int_equal(s->triangle_material[0], 3);
    rtt_scene_free(s);
}

static void test_scene_json_lights_read_their_fields_and_default_the_rest(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"lights\": [\n"
                              "  {\"position\": [1, 2, 3]},\n"
                              "  {\"type\": \"point\", \"position\": [0, 1, 0], \"color\": [1, 0.5, 0], \"intensity\": 4,"
                              "   \"attenuation\": [1, 0.5, 0.25]},\n"
                              "  {\"type\": \"sphere\", \"position\": [0, 3, 0], \"radius\": 0.25}\n"
                              " ], \"meshes\": [" TRIANGLE "]}");
    assert_int_equal(s->light_count, 3);
    assert_int_equal(s->lights[0].type, RTT_LIGHT_POINT);
    assert_vec3(s->lights[0].position, 1, 2, 3);
    assert_vec3(s->lights[0].color, 1, 1, 1);
    assert_float_equal(s->lights[0].intensity, 1, 0);
    assert_float_equal(s->lights[0].attenuation[0], 1, 0);
    assert_float_equal(s->lights[0].attenuation[1], 0, 0);
    assert_float_equal(s->lights[0].attenuation[2], 0, 0);
    assert_float_equal(s->lights[0].radius, 0, 0);
    assert_vec3(s->lights[1].color, 1, 0.5f, 0);
    assert_float_equal(s->lights[1].intensity, 4, 0);
    assert_float_equal(s->lights[1].attenuation[1], 0.5, 0);
    assert_float_equal(s->lights[1].attenuation[2], 0.25, 0);
    assert_int_equal(s->lights[2].type, RTT_LIGHT_SPHERE);
    assert_float_equal(s->lights[2].radius, 0.25, 0);
    rtt_scene_free(s);
}

/* p' = T * Rz * Ry * Rx * S * p */
static void test_scene_json_transform_scales_then_rotates_then_translates(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"meshes\": [{\"vertices\": [[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,1,2]],"
                              " \"transform\": {\"translate\": [10, 20, 30], \"rotate_deg\": [0, 90, 0], \"scale\": 2}}]}");
    /* Ry(90): x -> -z, z -> x */
    assert_vec3(s->vertices[0], 10, 20, 28);
    assert_vec3(s->vertices[1], 10, 22, 30);
    assert_vec3(s->vertices[2], 12, 20, 30);
    rtt_scene_free(s);
    s = parse_text("{\"meshes\": [{\"vertices\": [[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,1,2]],"
                   " \"transform\": {\"rotate_deg\": [90, 0, 90], \"scale\": [1, 2, 3]}}]}");
    /* x: S -> (1,0,0), Rx -> (1,0,0), Rz(90) -> (0,1,0) */
    assert_vec3(s->vertices[0], 0, 1, 0);
    /* y: S -> (0,2,0), Rx(90) -> (0,0,2), Rz -> (0,0,2) */
    assert_vec3(s->vertices[1], 0, 0, 2);
    /* z: S -> (0,0,3), Rx(90) -> (0,-3,0), Rz(90) -> (3,0,0) */
    assert_vec3(s->vertices[2], 3, 0, 0);
    rtt_scene_free(s);
}

static void test_scene_json_shapes_are_named_and_use_their_material(void **state)
{
    (void)state;
    rtt_scene *s = parse_text("{\"materials\": [{\"name\": \"red\", \"diffuse\": [1, 0, 0]}], \"meshes\": [\n"
                              " {\"shape\": {\"type\": \"box\", \"min\": [0,0,0], \"max\": [1,1,1]}},\n"
                              " {\"shape\": {\"type\": \"sphere\", \"radius\": 1, \"subdivisions\": 1}, \"material\": \"red\","
                              "  \"name\": \"ball\"},\n"
                              " {\"shape\": {\"type\": \"quad\", \"corners\": [[0,0,0],[1,0,0],[1,0,1],[0,0,1]]}},\n"
                              " {\"shape\": {\"type\": \"cylinder\", \"radius\": 1, \"height\": 2, \"segments\": 8}},\n"
                              " {\"shape\": {\"type\": \"torus\", \"major_radius\": 1, \"minor_radius\": 0.25,"
                              "  \"segments\": [12, 6]}}]}");
    assert_int_equal(s->mesh_count, 5);
    assert_string_equal(s->meshes[0].name, "box");
    assert_string_equal(s->meshes[1].name, "ball");
    assert_int_equal(s->meshes[0].triangle_count, 12);
    assert_int_equal(s->meshes[1].triangle_count, 80);
    assert_int_equal(s->meshes[2].triangle_count, 2);
    assert_int_equal(s->meshes[3].triangle_count, 32);
    assert_int_equal(s->meshes[4].triangle_count, 144);
    /* "red" is 0; the default material is added after it, once */
    assert_int_equal(s->material_count, 2);
    assert_string_equal(s->materials[1].name, "default");
    assert_int_equal(s->meshes[0].material, 1);
    assert_int_equal(s->meshes[1].material, 0);
    assert_int_equal(s->meshes[2].material, 1);
    assert_true(s->meshes[0].closed);
    assert_true(s->meshes[1].closed);
    assert_false(s->meshes[2].closed);
    assert_true(s->meshes[3].closed);
    assert_true(s->meshes[4].closed);
    assert_int_equal(s->degenerate_count, 0);
    rtt_scene_free(s);
}

/* ---- the shapes themselves ---- */

/* Closed and wound outwards: every directed edge (by position) is matched by
 * exactly one reverse edge, and the enclosed volume is positive. */
static void assert_closed_outward(const rtt_shape_mesh *m, double expected_volume, double tolerance)
{
    uint32_t n = m->triangle_count;
    double volume = 0.0;
    for (uint32_t t = 0; t < n; t++) {
        const uint32_t *a = &m->indices[3 * t];
        rtt_vec3 p0 = m->positions[a[0]], p1 = m->positions[a[1]], p2 = m->positions[a[2]];
        volume += rtt_v3_dot(p0, rtt_v3_cross(p1, p2)) / 6.0;
        for (int k = 0; k < 3; k++) {
            rtt_vec3 from = m->positions[a[k]], to = m->positions[a[(k + 1) % 3]];
            int forward = 0, reverse = 0;
            for (uint32_t u = 0; u < n; u++) {
                const uint32_t *b = &m->indices[3 * u];
                for (int j = 0; j < 3; j++) {
                    rtt_vec3 f = m->positions[b[j]], g = m->positions[b[(j + 1) % 3]];
                    forward += !memcmp(&f, &from, sizeof f) && !memcmp(&g, &to, sizeof g);
                    reverse += !memcmp(&f, &to, sizeof f) && !memcmp(&g, &from, sizeof g);
                }
            }
            if (forward != 1 || reverse != 1) fail_msg("triangle %u edge %d: %d forward, %d reverse", t, k, forward, reverse);
        }
    }
    assert_float_equal(volume, expected_volume, tolerance);
}

static void test_scene_json_box_is_closed_and_outward(void **state)
{
    (void)state;
    rtt_shape_mesh m;
    assert_true(rtt_shape_box(rtt_v3(-1, 0, 2), rtt_v3(1, 3, 2.5f), &m));
    assert_closed_outward(&m, 2.0 * 3.0 * 0.5, 1e-5);
    for (uint32_t t = 0; t < m.triangle_count; t++) {
        rtt_vec3 *p = m.positions;
        const uint32_t *a = &m.indices[3 * t];
        rtt_vec3 g = rtt_v3_normalize(rtt_v3_cross(rtt_v3_sub(p[a[1]], p[a[0]]), rtt_v3_sub(p[a[2]], p[a[0]])));
        for (int k = 0; k < 3; k++) assert_float_equal(rtt_v3_dot(g, m.normals[a[k]]), 1.0, 1e-6);
    }
    rtt_shape_mesh_free(&m);
}

static void test_scene_json_sphere_is_closed_outward_and_round(void **state)
{
    (void)state;
    for (uint32_t level = 0; level <= 3; level++) {
        rtt_shape_mesh m;
        rtt_vec3 c = rtt_v3(1, 2, 3);
        assert_true(rtt_shape_sphere(c, 0.5f, level, &m));
        assert_int_equal(m.triangle_count, 20u << (2 * level));
        assert_int_equal(m.vertex_count, 10u * (1u << (2 * level)) + 2u); /* shared vertices: V - E + F = 2 */
        double sphere = 4.0 / 3.0 * 3.14159265358979 * 0.125;
        static const double shortfall[4] = {0.45, 0.15, 0.05, 0.02}; /* an inscribed polyhedron */
        assert_closed_outward(&m, sphere, sphere * shortfall[level]);
        for (uint32_t i = 0; i < m.vertex_count; i++) {
            rtt_vec3 d = rtt_v3_sub(m.positions[i], c);
            assert_float_equal(rtt_v3_length(d), 0.5, 1e-5);
            assert_float_equal(rtt_v3_dot(rtt_v3_normalize(d), m.normals[i]), 1.0, 1e-5);
        }
        rtt_shape_mesh_free(&m);
    }
}

static void test_scene_json_cylinder_and_torus_are_closed_and_outward(void **state)
{
    (void)state;
    rtt_shape_mesh m;
    assert_true(rtt_shape_cylinder(rtt_v3(0, -1, 0), 0.5f, 2.0f, 64, &m));
    double cylinder = 3.14159265358979 * 0.25 * 2.0;
    assert_closed_outward(&m, cylinder, cylinder * 0.01);
    rtt_shape_mesh_free(&m);
    assert_true(rtt_shape_torus(rtt_v3(0, 0, 0), 1.0f, 0.25f, 48, 24, &m));
    double torus = 2.0 * 3.14159265358979 * 3.14159265358979 * 1.0 * 0.0625;
    assert_closed_outward(&m, torus, torus * 0.02);
    rtt_shape_mesh_free(&m);
}

static void test_scene_json_quad_faces_its_winding(void **state)
{
    (void)state;
    rtt_vec3 corners[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    rtt_shape_mesh m;
    assert_true(rtt_shape_quad(corners, &m));
    assert_int_equal(m.triangle_count, 2);
    assert_vec3(m.normals[0], 0, 0, 1);
    rtt_shape_mesh_free(&m);
}

/* ---- errors ---- */

static void test_scene_json_locates_nested_values_by_line(void **state)
{
    (void)state;
    char got[512];
    assert_string_equal(parse_error("{\n\"materials\": [\n{\"name\": \"a\"},\n\n{\"name\": \"b\",\n\"ior\": 2}],\n"
                                    "\"meshes\": [" TRIANGLE "]}",
                                    got, sizeof got),
                        ":6: materials[1].ior is not used by a \"diffuse\" material");
    assert_string_equal(parse_error("{\"meshes\": [\n" TRIANGLE ",\n{\"vertices\": [[0,0,0],\n[1,0,0],\n[0,1,0]],\n"
                                    "\"triangles\": [[0,1,2],\n[2,1,3]]}]}",
                                    got, sizeof got),
                        ":7: meshes[1].triangles[1]: vertex index 3 is out of range (3 vertices)");
}

static void test_scene_json_missing_file_names_it(void **state)
{
    (void)state;
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_new("x", &err);
    assert_false(rtt_scene_parse_json(scene, BAD_DIR "/missing.json", NULL, &err));
    assert_string_equal(err.message, BAD_DIR "/missing.json: cannot open: No such file or directory");
    assert_false(rtt_scene_parse_json(scene, BAD_DIR, NULL, &err));
    assert_string_equal(err.message, BAD_DIR ": is a directory");
    rtt_scene_free(scene);
}

static bool has_suffix(const char *name, const char *suffix)
{
    size_t n = strlen(name), s = strlen(suffix);
    return n > s && strcmp(name + n - s, suffix) == 0;
}

/* Replaces every "$DIR" in text by dir. */
static void expand_dir(const char *text, const char *dir, char *out, size_t size)
{
    size_t used = 0;
    for (const char *c = text; *c && used + 1 < size;) {
        if (strncmp(c, "$DIR", 4) == 0) {
            used += (size_t)snprintf(out + used, size - used, "%s", dir);
            c += 4;
        } else {
            out[used++] = *c++;
        }
    }
    out[used < size ? used : size - 1] = '\0';
}

/* Every NAME.json in tests/data/scene_bad/ has NAME.expected holding its one
 * error line ($DIR stands for the directory), and the other way round. */
static void test_scene_json_each_bad_file_gives_its_exact_error(void **state)
{
    (void)state;
    DIR *dir = opendir(BAD_DIR);
    assert_non_null(dir);
    int checked = 0, failures = 0;
    for (struct dirent *e; (e = readdir(dir));) {
        char path[1024], expected_path[1024], expected_raw[1024] = "", expected[2048];
        if (has_suffix(e->d_name, ".json")) {
            snprintf(expected_path, sizeof expected_path, BAD_DIR "/%.*s.expected",
                     (int)(strlen(e->d_name) - 5), e->d_name);
            if (access(expected_path, R_OK) != 0) {
                print_error("%s has no .expected file\n", e->d_name);
                failures++;
            }
            continue;
        }
        if (!has_suffix(e->d_name, ".expected")) continue;
        snprintf(path, sizeof path, BAD_DIR "/%.*s.json", (int)(strlen(e->d_name) - 9), e->d_name);
        snprintf(expected_path, sizeof expected_path, BAD_DIR "/%s", e->d_name);
        FILE *f = fopen(expected_path, "rb");
        assert_non_null(f);
        if (!fgets(expected_raw, sizeof expected_raw, f)) expected_raw[0] = '\0';
        fclose(f);
        expected_raw[strcspn(expected_raw, "\n")] = '\0';
        expand_dir(expected_raw, BAD_DIR, expected, sizeof expected);

        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_new(path, &err);
        assert_non_null(scene);
        bool ok = rtt_scene_parse_json(scene, path, NULL, &err);
        rtt_scene_free(scene);
        checked++;
        if (ok) {
            print_error("%s: parsed, expected: %s\n", path, expected);
            failures++;
        } else if (strcmp(err.message, expected) != 0) {
            print_error("%s:\n  got      %s\n  expected %s\n", path, err.message, expected);
            failures++;
        }
    }
    closedir(dir);
    assert_true(checked >= 70);
    assert_int_equal(failures, 0);
}

/* Every scene under scenes/ loads through rtt_scene_load (as the CLI does). */
static void test_scene_json_every_scene_in_scenes_loads(void **state)
{
    (void)state;
    DIR *dir = opendir(SCENES_DIR);
    assert_non_null(dir);
    int loaded = 0, failures = 0;
    for (struct dirent *e; (e = readdir(dir));) {
        if (!has_suffix(e->d_name, ".json")) continue;
        char path[1024];
        snprintf(path, sizeof path, SCENES_DIR "/%s", e->d_name);
        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_load(path, NULL, &err);
        if (!scene) {
            print_error("%s\n", err.message);
            failures++;
            continue;
        }
        if (scene->triangle_count == 0 || scene->light_count == 0 || scene->material_count == 0) {
            print_error("%s: empty scene\n", path);
            failures++;
        }
        loaded++;
        rtt_scene_free(scene);
    }
    closedir(dir);
    assert_int_equal(failures, 0);
    assert_true(loaded >= 12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_json_geometry_alone_takes_every_default),
        cmocka_unit_test(test_scene_json_reads_every_top_level_field),
        cmocka_unit_test(test_scene_json_max_bounces_zero_loads_as_no_reflections),
        cmocka_unit_test(test_scene_json_max_bounces_past_the_limit_is_one_line_at_its_place),
        cmocka_unit_test(test_scene_json_camera_takes_default_up_and_fov),
        cmocka_unit_test(test_scene_json_materials_read_their_fields_and_default_the_rest),
        cmocka_unit_test(test_scene_json_lights_read_their_fields_and_default_the_rest),
        cmocka_unit_test(test_scene_json_transform_scales_then_rotates_then_translates),
        cmocka_unit_test(test_scene_json_shapes_are_named_and_use_their_material),
        cmocka_unit_test(test_scene_json_box_is_closed_and_outward),
        cmocka_unit_test(test_scene_json_sphere_is_closed_outward_and_round),
        cmocka_unit_test(test_scene_json_cylinder_and_torus_are_closed_and_outward),
        cmocka_unit_test(test_scene_json_quad_faces_its_winding),
        cmocka_unit_test(test_scene_json_locates_nested_values_by_line),
        cmocka_unit_test(test_scene_json_missing_file_names_it),
        cmocka_unit_test(test_scene_json_each_bad_file_gives_its_exact_error),
        cmocka_unit_test(test_scene_json_every_scene_in_scenes_loads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

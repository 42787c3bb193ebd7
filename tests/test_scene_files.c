/* What a file is and how scene/ reads it: rtt_file_kind_of (the one mapping
 * from extensions to readers, scene/file_kind.c), the loader and the scene
 * file's "file" references following it, and rtt_file_read
 * (scene/file_read.c): whole contents, size limits, one-line errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "file_read.h"
#include "rtt/scene.h"
#include "test_tempdir.h"

static int make_scratch(void **state) { return scratch_create(state, "scene_files"); }

static void write_file(const char *path, const char *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    fclose(f);
}

/* ---- rtt_file_kind_of ---- */

typedef struct kind_case {
    const char *path;
    rtt_file_kind kind;
} kind_case;

#define EXPECT_KINDS(...)                                                                                       \
    do {                                                                                                        \
        static const kind_case cases[] = {__VA_ARGS__};                                                         \
        expect_kinds(cases, sizeof cases / sizeof cases[0]);                                                    \
    } while (0)

static void expect_kinds(const kind_case *cases, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        rtt_file_kind got = rtt_file_kind_of(cases[i].path);
        if (got != cases[i].kind) fail_msg("\"%s\": kind %d, expected %d", cases[i].path, got, cases[i].kind);
    }
}

static void test_each_kind_is_named_by_its_extension(void **state)
{
    (void)state;
    EXPECT_KINDS({"scene.json", RTT_FILE_SCENE_JSON}, {"scenes/demo.json", RTT_FILE_SCENE_JSON},
                 {"/tmp/x/tree.kdt", RTT_FILE_KDT}, {"maps/q3dm1.bsp", RTT_FILE_Q3BSP}, {"bunny.obj", RTT_FILE_MESH},
                 {"a.ply", RTT_FILE_MESH}, {"b.off", RTT_FILE_MESH}, {"c.3ds", RTT_FILE_MESH},
                 {"d.gltf", RTT_FILE_MESH}, {"e.glb", RTT_FILE_MESH}, {"f.stl", RTT_FILE_MESH});
}

static void test_extensions_are_matched_in_any_case(void **state)
{
    (void)state;
    EXPECT_KINDS({"SCENE.JSON", RTT_FILE_SCENE_JSON}, {"Scene.Json", RTT_FILE_SCENE_JSON}, {"TREE.KDT", RTT_FILE_KDT},
                 {"Q3DM1.BSP", RTT_FILE_Q3BSP}, {"BUNNY.OBJ", RTT_FILE_MESH});
}

static void test_a_path_without_extension_is_unknown(void **state)
{
    (void)state;
    EXPECT_KINDS({"", RTT_FILE_UNKNOWN}, {"scene", RTT_FILE_UNKNOWN}, {"meshes/bunny", RTT_FILE_UNKNOWN},
                 {"scene.", RTT_FILE_UNKNOWN}, {"notes.txt", RTT_FILE_UNKNOWN} /* no reader claims it */);
}

static void test_a_dot_in_a_folder_name_is_not_an_extension(void **state)
{
    (void)state;
    EXPECT_KINDS({"a.b/scene", RTT_FILE_UNKNOWN}, {"scenes.json/bunny", RTT_FILE_UNKNOWN},
                 {"v1.2/maps/q3dm1", RTT_FILE_UNKNOWN}, {"a.b/scene.json", RTT_FILE_SCENE_JSON});
}

#define TRIANGLE_SCENE "{\"meshes\": [{\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"triangles\": [[0,1,2]]}]}"

static void test_loader_reads_an_upper_case_scene_file_as_json(void **state)
{
    const char *path = scratch_path(state, "SCENE.JSON");
    write_file(path, TRIANGLE_SCENE, strlen(TRIANGLE_SCENE));
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(path, NULL, &err);
    if (!scene) fail_msg("%s", err.message);
    assert_int_equal(scene->triangle_count, 1);
    rtt_scene_free(scene);
}

static void test_scene_file_refuses_baked_trees_and_scenes_as_meshes_in_any_case(void **state)
{
    static const char *const names[] = {"tree.KDT", "other.Json"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char text[256], path[200], want[400];
        snprintf(path, sizeof path, "%s", scratch_path(state, "refs.json"));
        snprintf(text, sizeof text, "{\"meshes\": [\n{\"file\": \"%s\"}]}", names[i]);
        write_file(path, text, strlen(text));
        rtt_error err = {{0}};
        assert_null(rtt_scene_load(path, NULL, &err));
        snprintf(want, sizeof want,
                 "%s:2: meshes[0].file: \"%s\" is not a mesh file (scene files and baked trees cannot be meshes)", path,
                 names[i]);
        assert_string_equal(err.message, want);
    }
}

/* ---- rtt_file_read ---- */

static void test_read_gives_every_byte_and_a_terminating_nul(void **state)
{
    const char *path = scratch_path(state, "bytes.bin");
    static const char bytes[] = {'a', '\0', 'b', '\n', 'c'};
    write_file(path, bytes, sizeof bytes);
    size_t length = 0;
    rtt_error err = {{0}};
    char *got = rtt_file_read(path, RTT_FILE_TEXT_MAX, &length, &err);
    if (!got) fail_msg("%s", err.message);
    assert_int_equal(length, sizeof bytes);
    assert_memory_equal(got, bytes, sizeof bytes);
    assert_int_equal(got[length], '\0');
    free(got);

    write_file(path, "", 0);
    got = rtt_file_read(path, RTT_FILE_TEXT_MAX, &length, &err);
    assert_non_null(got);
    assert_int_equal(length, 0);
    assert_int_equal(got[0], '\0');
    free(got);
}

static void test_read_accepts_the_limit_and_refuses_one_byte_more(void **state)
{
    const char *path = scratch_path(state, "limit.txt");
    char bytes[2049];
    memset(bytes, 'x', sizeof bytes);
    write_file(path, bytes, 2048);
    size_t length = 0;
    rtt_error err = {{0}};
    char *got = rtt_file_read(path, 2048, &length, &err);
    if (!got) fail_msg("%s", err.message);
    assert_int_equal(length, 2048);
    free(got);

    write_file(path, bytes, sizeof bytes);
    assert_null(rtt_file_read(path, 2048, &length, &err));
    char want[300];
    snprintf(want, sizeof want, "%s: larger than 2 KiB", path);
    assert_string_equal(err.message, want);
}

/* Only regular files are read: a device that never ends, or a FIFO that
 * would block, is refused before a byte is read. */
static void test_read_refuses_what_is_not_a_regular_file(void **state)
{
    size_t length = 0;
    rtt_error err = {{0}};
    assert_null(rtt_file_read("/dev/zero", (size_t)1 << 20, &length, &err));
    assert_string_equal(err.message, "/dev/zero: not a regular file (a character device)");
    const char *fifo = scratch_path(state, "fifo.json");
    assert_int_equal(mkfifo(fifo, 0600), 0);
    char want[300];
    assert_null(rtt_file_read(fifo, RTT_FILE_TEXT_MAX, &length, &err));
    snprintf(want, sizeof want, "%s: not a regular file (a FIFO)", fifo);
    assert_string_equal(err.message, want);
    unlink(fifo);
}

/* /proc files say they are empty and are not. */
static void test_read_does_not_trust_a_reported_size_of_zero(void **state)
{
    (void)state;
    size_t length = 0;
    rtt_error err = {{0}};
    char *got = rtt_file_read("/proc/self/status", RTT_FILE_TEXT_MAX, &length, &err);
    if (!got) fail_msg("%s", err.message);
    assert_true(length > 100);
    assert_int_equal(strncmp(got, "Name:", 5), 0);
    assert_int_equal(strlen(got), length);
    free(got);
}

static void test_read_failures_are_one_line_naming_the_file(void **state)
{
    size_t length = 0;
    rtt_error err = {{0}};
    const char *missing = scratch_path(state, "missing.json");
    char want[300];
    assert_null(rtt_file_read(missing, RTT_FILE_TEXT_MAX, &length, &err));
    snprintf(want, sizeof want, "%s: cannot open: No such file or directory", missing);
    assert_string_equal(err.message, want);

    scratch *s = *state;
    assert_null(rtt_file_read(s->dir, RTT_FILE_TEXT_MAX, &length, &err));
    snprintf(want, sizeof want, "%s: is a directory", s->dir);
    assert_string_equal(err.message, want);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_kind_is_named_by_its_extension),
        cmocka_unit_test(test_extensions_are_matched_in_any_case),
        cmocka_unit_test(test_a_path_without_extension_is_unknown),
        cmocka_unit_test(test_a_dot_in_a_folder_name_is_not_an_extension),
        cmocka_unit_test_setup_teardown(test_loader_reads_an_upper_case_scene_file_as_json, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_scene_file_refuses_baked_trees_and_scenes_as_meshes_in_any_case,
                                        make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_read_gives_every_byte_and_a_terminating_nul, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_read_accepts_the_limit_and_refuses_one_byte_more, make_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_read_refuses_what_is_not_a_regular_file, make_scratch, remove_scratch),
        cmocka_unit_test(test_read_does_not_trust_a_reported_size_of_zero),
        cmocka_unit_test_setup_teardown(test_read_failures_are_one_line_naming_the_file, make_scratch,
                                        remove_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

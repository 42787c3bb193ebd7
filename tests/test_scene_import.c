/* The mesh importers (scene/import_assimp.c, scene/import_q3bsp.c), through
 * the public rtt_scene_load: triangle counts and the global triangle order
 * of docs/ARCHITECTURE.md for every format, the MTL material mapping, one-line errors,
 * Quake III maps built in memory (good and corrupt), and the real data of
 * bench/fetch-scenes.sh. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "rtt/scene.h"

#define DATA_DIR RTT_SOURCE_DIR "/tests/data/import/"

static rtt_scene *load_level(const char *path, uint32_t level, rtt_error *err)
{
    rtt_scene_load_options opt = {.bezier_level = level};
    memset(err, 0, sizeof *err);
    return rtt_scene_load(path, &opt, err);
}

static rtt_scene *load_ok(const char *path)
{
    rtt_error err;
    rtt_scene *scene = load_level(path, 0, &err);
    if (!scene) fail_msg("loading %s failed: %s", path, err.message);
    return scene;
}

/* The error line of a load that must fail. */
static const char *load_error(const char *path, uint32_t level, rtt_error *err)
{
    rtt_scene *scene = load_level(path, level, err);
    if (scene) {
        rtt_scene_free(scene);
        fail_msg("%s loaded but should have been refused", path);
    }
    assert_null(strchr(err->message, '\n'));
    assert_non_null(strstr(err->message, path));
    return err->message;
}

static void assert_vec3(rtt_vec3 v, float x, float y, float z)
{
    if (fabsf(v.x - x) > 1e-5f || fabsf(v.y - y) > 1e-5f || fabsf(v.z - z) > 1e-5f)
        fail_msg("(%g, %g, %g) != (%g, %g, %g)", (double)v.x, (double)v.y, (double)v.z, (double)x, (double)y,
                 (double)z);
}

static void assert_triangle(const rtt_scene *s, uint32_t t, const float expected[9])
{
    assert_true(t < s->triangle_count);
    rtt_vec3 v[3];
    rtt_scene_triangle(s, t, v);
    for (int k = 0; k < 3; k++) assert_vec3(v[k], expected[3 * k], expected[3 * k + 1], expected[3 * k + 2]);
}

/* ---- Assimp formats ---- */

static void test_obj_polygons_fan_in_file_order(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "materials.obj");
    assert_int_equal(s->triangle_count, 10); /* 1 + 2 + 3 + 1 + 2 (one degenerate) + 1; the line makes none */
    assert_triangle(s, 0, (float[]){0, 0, 0, 1, 0, 0, 1, 1, 0});
    /* the pentagon 1 2 3 5 4 is the fan (1,2,3), (1,3,5), (1,5,4) */
    assert_triangle(s, 3, (float[]){0, 0, 0, 1, 0, 0, 1, 1, 0});
    assert_triangle(s, 4, (float[]){0, 0, 0, 1, 1, 0, 0.5f, 1.5f, 0});
    assert_triangle(s, 5, (float[]){0, 0, 0, 0.5f, 1.5f, 0, 0, 1, 0});
    assert_triangle(s, 8, (float[]){1, 0, 0, 1, 0, 0, 1, 0, 0}); /* degenerate, kept */
    assert_triangle(s, 9, (float[]){0, 1, 0, 1, 1, 0, 0.5f, 1.5f, 0});
    assert_int_equal(s->degenerate_count, 1);
    rtt_scene_free(s);
}

static void test_mtl_materials_map_onto_the_five_types(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "materials.obj");
    static const struct {
        uint32_t triangle;
        const char *name;
        rtt_material_type type;
    } expected[] = {
        {0, "matte", RTT_MATERIAL_DIFFUSE},
        {1, "shiny", RTT_MATERIAL_SPECULAR},
        {3, "mirror", RTT_MATERIAL_REFLECTIVE},
        {6, "glass", RTT_MATERIAL_TRANSPARENT},
        {7, "glassmirror", RTT_MATERIAL_TRANSPARENT_REFLECTIVE},
        {9, "matte", RTT_MATERIAL_DIFFUSE},
    };
    assert_int_equal(s->material_count, 5); /* each file material once, "matte" reused */
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++) {
        const rtt_material *m = &s->materials[s->triangle_material[expected[i].triangle]];
        assert_string_equal(m->name, expected[i].name);
        assert_int_equal(m->type, expected[i].type);
    }
    const rtt_material *matte = &s->materials[s->triangle_material[0]];
    assert_vec3(matte->diffuse, 0.8f, 0.2f, 0.2f);
    const rtt_material *shiny = &s->materials[s->triangle_material[1]];
    assert_float_equal(shiny->specular, 0.6f, 1e-6f);
    assert_float_equal(shiny->shininess, 50.0f, 1e-6f);
    const rtt_material *mirror = &s->materials[s->triangle_material[3]];
    assert_float_equal(mirror->reflection, 0.9f, 1e-6f);
    const rtt_material *glass = &s->materials[s->triangle_material[6]];
    assert_float_equal(glass->transparency, 0.75f, 1e-6f);
    assert_float_equal(glass->ior, 1.33f, 1e-6f);
    const rtt_material *both = &s->materials[s->triangle_material[7]];
    assert_float_equal(both->ior, 1.5f, 1e-6f);
    assert_true(both->reflection + both->transparency <= 1.0f + 1e-6f);
    rtt_scene_free(s);
}

static void test_off_pyramid_is_closed_and_in_order(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "pyramid.off");
    assert_int_equal(s->triangle_count, 6);
    assert_triangle(s, 0, (float[]){0, 0, 0, 1, 0, 0, 1, 0, 1});
    assert_triangle(s, 1, (float[]){0, 0, 0, 1, 0, 1, 0, 0, 1});
    assert_triangle(s, 5, (float[]){0, 0, 1, 0.5f, 1, 0.5f, 0, 0, 0});
    assert_int_equal(s->mesh_count, 1);
    assert_true(s->meshes[0].closed);
    /* OFF has no materials: grey diffuse, not Assimp's invented white */
    assert_int_equal(s->materials[s->triangle_material[0]].type, RTT_MATERIAL_DIFFUSE);
    assert_vec3(s->materials[s->triangle_material[0]].diffuse, 0.7f, 0.7f, 0.7f);
    rtt_scene_free(s);
}

static void test_ply_quad_and_triangle(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "quad.ply");
    assert_int_equal(s->triangle_count, 3);
    assert_triangle(s, 0, (float[]){0, 0, 0, 2, 0, 0, 2, 2, 0});
    assert_triangle(s, 2, (float[]){0, 2, 0, 2, 2, 0, 1, 3, 0});
    assert_int_equal(s->materials[s->triangle_material[0]].type, RTT_MATERIAL_DIFFUSE);
    rtt_scene_free(s);
}

static void test_stl_two_facets(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "two.stl");
    assert_int_equal(s->triangle_count, 2);
    assert_triangle(s, 0, (float[]){0, 0, 0, 1, 0, 0, 1, 1, 0});
    assert_triangle(s, 1, (float[]){0, 0, 0, 1, 1, 0, 0, 1, 5});
    rtt_scene_free(s);
}

static void test_gltf_applies_node_transforms(void **state)
{
    (void)state;
    rtt_scene *s = load_ok(DATA_DIR "square.gltf"); /* parent translates by 10 in x, child scales by 2 */
    assert_int_equal(s->triangle_count, 2);
    /* 11 from the origin, 2 wide: stored relative to its centre (11, 1, 0); compared in file coordinates */
    assert_true(s->origin[0] == 11.0 && s->origin[1] == 1.0 && s->origin[2] == 0.0);
    for (uint32_t i = 0; i < s->vertex_count; i++) {
        double p[3];
        rtt_scene_point_from_stored(s, s->vertices[i], p);
        s->vertices[i] = rtt_v3((float)p[0], (float)p[1], (float)p[2]);
    }
    assert_triangle(s, 0, (float[]){10, 0, 0, 12, 0, 0, 12, 2, 0});
    assert_triangle(s, 1, (float[]){10, 0, 0, 12, 2, 0, 10, 2, 0});
    rtt_scene_free(s);
}

/* ---- a 3DS file, written chunk by chunk ---- */

typedef struct byte_writer {
    uint8_t data[1024];
    size_t size;
} byte_writer;

static void put(byte_writer *w, const void *bytes, size_t n)
{
    assert_true(w->size + n <= sizeof w->data);
    memcpy(w->data + w->size, bytes, n);
    w->size += n;
}
static void put_u16(byte_writer *w, uint16_t v) { put(w, (uint8_t[]){v & 0xff, v >> 8}, 2); }
static void put_u32(byte_writer *w, uint32_t v)
{
    put(w, (uint8_t[]){v & 0xff, v >> 8 & 0xff, v >> 16 & 0xff, v >> 24}, 4);
}
static void put_f32(byte_writer *w, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32(w, u);
}
/* Opens a chunk; close_chunk patches its length. */
static size_t open_chunk(byte_writer *w, uint16_t id)
{
    size_t at = w->size;
    put_u16(w, id);
    put_u32(w, 0);
    return at;
}
static void close_chunk(byte_writer *w, size_t at)
{
    uint32_t length = (uint32_t)(w->size - at);
    memcpy(w->data + at + 2, (uint8_t[]){length & 0xff, length >> 8 & 0xff, length >> 16 & 0xff, length >> 24}, 4);
}

static void write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

/* A temporary path with the given suffix (the importers pick by extension). */
static void temp_path(char *out, size_t size, const char *suffix)
{
    snprintf(out, size, "%s/rtt_test_import_XXXXXX%s", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", suffix);
    int fd = mkstemps(out, (int)strlen(suffix));
    assert_true(fd >= 0);
    close(fd);
}

static void test_3ds_triangles_and_transparent_material(void **state)
{
    (void)state;
    byte_writer w = {{0}, 0};
    size_t main_chunk = open_chunk(&w, 0x4D4D);
    size_t version = open_chunk(&w, 0x0002);
    put_u32(&w, 3);
    close_chunk(&w, version);
    size_t editor = open_chunk(&w, 0x3D3D);
    size_t material = open_chunk(&w, 0xAFFF);
    size_t name = open_chunk(&w, 0xA000);
    put(&w, "smoke", 6);
    close_chunk(&w, name);
    size_t diffuse = open_chunk(&w, 0xA020), rgb = open_chunk(&w, 0x0011);
    put(&w, (uint8_t[]){255, 0, 0}, 3);
    close_chunk(&w, rgb);
    close_chunk(&w, diffuse);
    size_t transparency = open_chunk(&w, 0xA050), percent = open_chunk(&w, 0x0030);
    put_u16(&w, 50);
    close_chunk(&w, percent);
    close_chunk(&w, transparency);
    close_chunk(&w, material);
    size_t object = open_chunk(&w, 0x4000);
    put(&w, "quad", 5);
    size_t trimesh = open_chunk(&w, 0x4100);
    size_t vertices = open_chunk(&w, 0x4110);
    static const float corners[4][3] = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0}};
    put_u16(&w, 4);
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 3; k++) put_f32(&w, corners[i][k]);
    close_chunk(&w, vertices);
    size_t faces = open_chunk(&w, 0x4120);
    put_u16(&w, 2);
    static const uint16_t corner_ids[2][4] = {{0, 1, 2, 0}, {0, 2, 3, 0}};
    for (int f = 0; f < 2; f++)
        for (int k = 0; k < 4; k++) put_u16(&w, corner_ids[f][k]);
    size_t group = open_chunk(&w, 0x4130);
    put(&w, "smoke", 6);
    put_u16(&w, 2);
    put_u16(&w, 0);
    put_u16(&w, 1);
    close_chunk(&w, group);
    close_chunk(&w, faces);
    close_chunk(&w, trimesh);
    close_chunk(&w, object);
    close_chunk(&w, editor);
    close_chunk(&w, main_chunk);

    char path[512];
    temp_path(path, sizeof path, ".3ds");
    write_file(path, w.data, w.size);
    rtt_scene *s = load_ok(path);
    assert_int_equal(s->triangle_count, 2);
    rtt_vec3 first[3], last[3];
    rtt_scene_triangle(s, 0, first);
    rtt_scene_triangle(s, 1, last);
    /* Assimp's root node turns 3DS's Z-up into Y-up: (x, y, z) -> (x, z, -y) */
    assert_vec3(first[0], 0, 0, 0);
    assert_vec3(first[1], 3, 0, 0);
    assert_vec3(first[2], 3, 0, -3);
    assert_vec3(last[2], 0, 0, -3);
    const rtt_material *m = &s->materials[s->triangle_material[0]];
    assert_string_equal(m->name, "smoke");
    assert_int_equal(m->type, RTT_MATERIAL_TRANSPARENT);
    assert_float_equal(m->transparency, 0.5f, 1e-3f);
    assert_vec3(m->diffuse, 1, 0, 0);
    rtt_scene_free(s);
    unlink(path);
}

/* ---- Assimp errors ---- */

static void test_obj_nan_coordinate_is_refused(void **state)
{
    (void)state;
    rtt_error err;
    assert_string_equal(load_error(DATA_DIR "nan.obj", 0, &err),
                        DATA_DIR "nan.obj: face 2: corner 3 has a NaN or infinite coordinate (nan, 1, 1)");
}

static void test_obj_out_of_range_index_is_refused(void **state)
{
    (void)state;
    rtt_error err;
    const char *message = load_error(DATA_DIR "bad_index.obj", 0, &err);
    assert_non_null(strstr(message, "out of range"));
}

static void test_malformed_file_gives_one_line(void **state)
{
    (void)state;
    rtt_error err;
    const char *message = load_error(DATA_DIR "truncated.stl", 0, &err);
    assert_int_equal(strncmp(message, DATA_DIR "truncated.stl: ", strlen(DATA_DIR "truncated.stl: ")), 0);
    assert_true(strlen(message) > strlen(DATA_DIR "truncated.stl: "));
}

/* A file that does not look like its extension's format never reaches
 * Assimp, whose fallback importers read past their buffers on such input
 * (fuzz/regressions/assimp/gltf_not_json_heap_overflow). */
static void test_file_not_of_its_format_is_refused_before_assimp(void **state)
{
    (void)state;
    static const struct {
        const char *path, *bytes, *message;
    } cases[] = {
        { "test_scene_import_not.gltf", "elemen%indexarraylidt{\"a{sett", "not a glTF file (not a JSON object)" },
        { "test_scene_import_array.gltf", "[1, 2, 3]", "not a glTF file (not a JSON object)" },
        { "test_scene_import_trailing.gltf", "{\"asset\": {}} junk", "not a glTF file (not a JSON object)" },
        { "test_scene_import_not.ply", "element vertex 3\n", "not a ply file (it does not start with \"ply\")" },
        { "test_scene_import_not.glb", "gl", "not a glb file (it does not start with \"glTF\")" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        FILE *f = fopen(cases[i].path, "wb");
        assert_non_null(f);
        fputs(cases[i].bytes, f);
        fclose(f);
        rtt_error err;
        char want[300];
        snprintf(want, sizeof want, "%s: %s", cases[i].path, cases[i].message);
        assert_string_equal(load_error(cases[i].path, 0, &err), want);
        remove(cases[i].path);
    }
}

static void test_empty_file_and_file_without_triangles_are_refused(void **state)
{
    (void)state;
    rtt_error err;
    assert_string_equal(load_error(DATA_DIR "empty.obj", 0, &err), DATA_DIR "empty.obj: the file is empty");
    assert_string_equal(load_error(DATA_DIR "lines.obj", 0, &err), DATA_DIR "lines.obj: the file has no triangles");
}

/* ---- Quake III maps built in memory ---- */

enum { MAP_VERTICES = 17, MAP_MESHVERTS = 9, MAP_FACES = 4 };

typedef struct test_map {
    float vertices[MAP_VERTICES][11]; /* position, texcoord, lightmap, normal; colour bytes written apart */
    int32_t meshverts[MAP_MESHVERTS];
    int32_t faces[MAP_FACES][26];
} test_map;

static void set_vertex(test_map *m, int i, float x, float y, float z)
{
    memset(m->vertices[i], 0, sizeof m->vertices[i]);
    m->vertices[i][0] = x;
    m->vertices[i][1] = y;
    m->vertices[i][2] = z;
    m->vertices[i][9] = 1.0f; /* normal (0, 0, 1): Quake's up */
}

static void set_face(test_map *m, int f, int type, int vertex, int vertex_count, int meshvert, int meshvert_count,
                     int width, int height)
{
    memset(m->faces[f], 0, sizeof m->faces[f]);
    m->faces[f][2] = type;
    m->faces[f][3] = vertex;
    m->faces[f][4] = vertex_count;
    m->faces[f][5] = meshvert;
    m->faces[f][6] = meshvert_count;
    m->faces[f][24] = width;
    m->faces[f][25] = height;
}

/* Face 0: a polygon (quad of 2 triangles); face 1: a mesh (1 triangle);
 * face 2: a billboard; face 3: a 3x3 patch, flat at z = 10. */
static test_map good_map(void)
{
    test_map m;
    memset(&m, 0, sizeof m);
    set_vertex(&m, 0, 0, 0, 0);
    set_vertex(&m, 1, 1, 0, 0);
    set_vertex(&m, 2, 1, 1, 0);
    set_vertex(&m, 3, 0, 1, 0);
    set_vertex(&m, 4, 0, 0, 5);
    set_vertex(&m, 5, 2, 0, 5);
    set_vertex(&m, 6, 0, 2, 5);
    set_vertex(&m, 7, 9, 9, 9);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) set_vertex(&m, 8 + 3 * j + i, (float)i, (float)j, 10);
    const int32_t meshverts[MAP_MESHVERTS] = {0, 1, 2, 0, 2, 3, 0, 1, 2};
    memcpy(m.meshverts, meshverts, sizeof meshverts);
    set_face(&m, 0, 1, 0, 4, 0, 6, 0, 0);
    set_face(&m, 1, 3, 4, 3, 6, 3, 0, 0);
    set_face(&m, 2, 4, 7, 1, 0, 0, 0, 0);
    set_face(&m, 3, 2, 8, 9, 0, 0, 3, 3);
    return m;
}

static void le32(uint8_t *p, uint32_t v)
{
    p[0] = v & 0xff;
    p[1] = v >> 8 & 0xff;
    p[2] = v >> 16 & 0xff;
    p[3] = v >> 24;
}

/* Serializes m as IBSP 46: header, then vertices (lump 10), meshverts (11)
 * and faces (13); every other lump is empty.  Returns the size. */
static size_t write_map_bytes(const test_map *m, uint8_t *out)
{
    const uint32_t header = 144, vertices = MAP_VERTICES * 44, meshverts = MAP_MESHVERTS * 4, faces = MAP_FACES * 104;
    memset(out, 0, header + vertices + meshverts + faces);
    memcpy(out, "IBSP", 4);
    le32(out + 4, 46);
    for (int lump = 0; lump < 17; lump++) le32(out + 8 + 8 * lump, header);
    le32(out + 8 + 8 * 10, header);
    le32(out + 12 + 8 * 10, vertices);
    le32(out + 8 + 8 * 11, header + vertices);
    le32(out + 12 + 8 * 11, meshverts);
    le32(out + 8 + 8 * 13, header + vertices + meshverts);
    le32(out + 12 + 8 * 13, faces);
    uint8_t *p = out + header;
    for (int i = 0; i < MAP_VERTICES; i++, p += 44) {
        for (int k = 0; k < 11; k++) {
            uint32_t u;
            memcpy(&u, &m->vertices[i][k], 4);
            le32(p + 4 * k, u);
        }
        memset(p + 40, 255, 4);
    }
    for (int i = 0; i < MAP_MESHVERTS; i++, p += 4) le32(p, (uint32_t)m->meshverts[i]);
    for (int f = 0; f < MAP_FACES; f++)
        for (int k = 0; k < 26; k++, p += 4) le32(p, (uint32_t)m->faces[f][k]);
    return (size_t)(p - out);
}

enum { MAP_BYTES = 144 + MAP_VERTICES * 44 + MAP_MESHVERTS * 4 + MAP_FACES * 104 };

static void write_map(const char *path, const test_map *m)
{
    uint8_t bytes[MAP_BYTES];
    write_file(path, bytes, write_map_bytes(m, bytes));
}

static void test_q3bsp_faces_patch_and_billboard(void **state)
{
    (void)state;
    char path[512];
    temp_path(path, sizeof path, ".bsp");
    test_map m = good_map();
    write_map(path, &m);
    rtt_scene *s = load_ok(path);
    assert_int_equal(s->triangle_count, 2 + 1 + 32); /* the billboard adds nothing; the patch 2 * 4 * 4 */
    /* Quake (x, y, z) -> rtt (x, z, -y); corners 2 and 3 swapped (Quake winds clockwise) */
    assert_triangle(s, 0, (float[]){0, 0, 0, 1, 0, -1, 1, 0, 0});
    assert_triangle(s, 1, (float[]){0, 0, 0, 0, 0, -1, 1, 0, -1});
    assert_triangle(s, 2, (float[]){0, 5, 0, 0, 5, -2, 2, 5, 0});
    /* the patch's first and last quads, triangles (v00, v10, v01) and (v10, v11, v01) */
    assert_triangle(s, 3, (float[]){0, 10, 0, 0.5f, 10, 0, 0, 10, -0.5f});
    assert_triangle(s, 34, (float[]){2, 10, -1.5f, 2, 10, -2, 1.5f, 10, -2});
    /* the patch's normals come from its derivatives: Quake's +z, rtt's +y */
    assert_non_null(s->normals);
    assert_vec3(s->normals[s->triangles[34].v[0]], 0, 1, 0);
    assert_int_equal(s->mesh_count, 1);
    assert_int_equal(s->materials[s->triangle_material[0]].type, RTT_MATERIAL_DIFFUSE);
    rtt_scene_free(s);

    rtt_error err;
    s = load_level(path, 2, &err); /* the level is honoured: 2 * 2 * 2 patch triangles */
    assert_non_null(s);
    assert_int_equal(s->triangle_count, 2 + 1 + 8);
    rtt_scene_free(s);
    unlink(path);
}

static void test_q3bsp_patch_level_4_gives_32_triangles(void **state)
{
    (void)state;
    char path[512];
    temp_path(path, sizeof path, ".bsp");
    test_map m = good_map();
    set_face(&m, 0, 4, 7, 1, 0, 0, 0, 0); /* only the patch remains */
    set_face(&m, 1, 4, 7, 1, 0, 0, 0, 0);
    write_map(path, &m);
    rtt_error err;
    rtt_scene *s = load_level(path, 4, &err);
    assert_non_null(s);
    assert_int_equal(s->triangle_count, 32);
    rtt_scene_free(s);
    unlink(path);
}

static void test_q3bsp_inverted_patch_is_wound_the_other_way(void **state)
{
    (void)state;
    char path[512];
    temp_path(path, sizeof path, ".bsp");
    test_map m = good_map();
    for (int v = 8; v < 17; v++) m.vertices[v][9] = -1.0f; /* control normals point down */
    write_map(path, &m);
    rtt_scene *s = load_ok(path);
    assert_int_equal(s->triangle_count, 35);
    assert_triangle(s, 3, (float[]){0, 10, 0, 0, 10, -0.5f, 0.5f, 10, 0}); /* (v00, v01, v10) */
    assert_vec3(s->normals[s->triangles[3].v[0]], 0, -1, 0);
    rtt_scene_free(s);
    unlink(path);
}

/* Writes the map, optionally corrupts its bytes, and checks the exact error. */
static void expect_map_error(test_map m, void (*corrupt)(uint8_t *bytes, size_t *size), const char *format, ...)
{
    char path[512], expected[1600], message[900];
    temp_path(path, sizeof path, ".bsp");
    uint8_t bytes[MAP_BYTES];
    size_t size = write_map_bytes(&m, bytes);
    if (corrupt) corrupt(bytes, &size);
    write_file(path, bytes, size);
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    snprintf(expected, sizeof expected, "%s: %s", path, message);
    rtt_error err;
    assert_string_equal(load_error(path, 0, &err), expected);
    unlink(path);
}

static void bad_magic(uint8_t *b, size_t *n) { (void)n; memcpy(b, "VBSP", 4); }
static void bad_version(uint8_t *b, size_t *n) { (void)n; le32(b + 4, 47); }
static void faces_past_the_end(uint8_t *b, size_t *n) { (void)n; le32(b + 12 + 8 * 13, MAP_FACES * 104 + 104); }
static void faces_not_whole(uint8_t *b, size_t *n) { (void)n; le32(b + 12 + 8 * 13, MAP_FACES * 104 - 4); }
static void truncated_header(uint8_t *b, size_t *n) { (void)b; *n = 100; }

static void test_q3bsp_corrupt_files_are_refused_with_their_line(void **state)
{
    (void)state;
    const uint32_t faces_at = 144 + MAP_VERTICES * 44 + MAP_MESHVERTS * 4;
    expect_map_error(good_map(), bad_magic, "not a Quake III map (magic is not \"IBSP\")");
    expect_map_error(good_map(), bad_version, "IBSP version 47 is not supported (only 46)");
    expect_map_error(good_map(), truncated_header, "file is too small for an IBSP header (100 bytes, need 144)");
    expect_map_error(good_map(), faces_past_the_end, "lump 13: range %u+%u exceeds the file size %u", faces_at,
                     MAP_FACES * 104 + 104, (unsigned)MAP_BYTES);
    expect_map_error(good_map(), faces_not_whole, "lump 13 (faces): length %d is not a multiple of 104",
                     MAP_FACES * 104 - 4);

    test_map m = good_map();
    m.faces[1][5] = 7; /* meshverts 7, 8, 9 of 9 */
    expect_map_error(m, NULL, "face 1: meshvert range 7+3 exceeds 9 meshverts");
    m = good_map();
    m.faces[3][24] = 4;
    expect_map_error(m, NULL, "face 3: patch size 4x3: width and height must be odd and at least 3");
    m = good_map();
    m.meshverts[4] = 4; /* the quad has vertices 0..3 */
    expect_map_error(m, NULL, "face 0: meshvert 4 is 4, outside the face's 4 vertices");
    m = good_map();
    m.faces[0][4] = 40;
    expect_map_error(m, NULL, "face 0: vertex range 0+40 exceeds 17 vertices");
    m = good_map();
    m.faces[3][4] = 8;
    expect_map_error(m, NULL, "face 3: patch size 3x3 needs 9 control points, the face has 8");
    m = good_map();
    m.faces[2][2] = 7;
    expect_map_error(m, NULL, "face 2: unknown face type 7");
    m = good_map();
    m.vertices[5][1] = NAN;
    expect_map_error(m, NULL, "vertex 5: position is NaN or infinite");
    m = good_map();
    m.faces[0][6] = 5;
    expect_map_error(m, NULL, "face 0: meshvert count 5 is not a multiple of 3");
}

/* ---- real data (bench/fetch-scenes.sh) ---- */

static const char *data_dir(char *out, size_t size)
{
    const char *dir = getenv("RTT_DATA_DIR");
    if (dir && *dir)
        snprintf(out, size, "%s", dir);
    else
        snprintf(out, size, "%s/.cache/rtt-data", getenv("HOME") ? getenv("HOME") : ".");
    return out;
}

static rtt_scene *load_real(const char *relative, uint32_t level, double *seconds)
{
    char dir[400], path[512];
    data_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/%s", dir, relative);
    if (access(path, R_OK) != 0)
        fail_msg("%s is missing: run bench/fetch-scenes.sh (it fetches the real test data into %s)", path, dir);
    struct timespec start, end;
    clock_gettime(CLOCK_MONOTONIC, &start);
    rtt_error err;
    rtt_scene *s = load_level(path, level, &err);
    clock_gettime(CLOCK_MONOTONIC, &end);
    if (!s) fail_msg("loading %s failed: %s", path, err.message);
    *seconds = (double)(end.tv_sec - start.tv_sec) + 1e-9 * (double)(end.tv_nsec - start.tv_nsec);
    return s;
}

static void test_real_quake_maps_load(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        uint32_t min_triangles, max_triangles;
    } maps[] = {
        {"maps/oa_dm4.bsp", 3000, 20000},
        {"maps/ctf_inyard.bsp", 20000, 100000},
        {"maps/czest3ctf.bsp", 20000, 100000},
    };
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) {
        double seconds;
        rtt_scene *s = load_real(maps[i].file, 4, &seconds);
        printf("# %s: %u triangles (%u degenerate) at level 4 in %.1f ms\n", maps[i].file, s->triangle_count,
               s->degenerate_count, seconds * 1e3);
        assert_in_range(s->triangle_count, maps[i].min_triangles, maps[i].max_triangles);
        assert_true(s->degenerate_count < s->triangle_count / 10);
        /* a map is metres-to-kilometres of Quake units, with Y up (x, z, -y) */
        rtt_vec3 extent = rtt_v3_sub(s->bounds.hi, s->bounds.lo);
        assert_true(extent.x > 100.0f && extent.x < 100000.0f);
        assert_true(extent.y > 100.0f && extent.y < 100000.0f);
        rtt_scene_free(s);
    }
}

static void test_real_cgal_meshes_load_closed(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        uint32_t min_triangles, max_triangles;
    } meshes[] = {
        {"meshes/bunny00.off", 50000, 100000},
        {"meshes/armadillo.off", 30000, 400000},
        {"meshes/refined_elephant.off", 50000, 200000},
    };
    for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; i++) {
        double seconds;
        rtt_scene *s = load_real(meshes[i].file, 0, &seconds);
        printf("# %s: %u triangles, %u vertices, closed %d, in %.1f ms\n", meshes[i].file, s->triangle_count,
               s->vertex_count, s->meshes[0].closed, seconds * 1e3);
        assert_in_range(s->triangle_count, meshes[i].min_triangles, meshes[i].max_triangles);
        assert_int_equal(s->mesh_count, 1);
        rtt_scene_free(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_polygons_fan_in_file_order),
        cmocka_unit_test(test_mtl_materials_map_onto_the_five_types),
        cmocka_unit_test(test_off_pyramid_is_closed_and_in_order),
        cmocka_unit_test(test_ply_quad_and_triangle),
        cmocka_unit_test(test_stl_two_facets),
        cmocka_unit_test(test_gltf_applies_node_transforms),
        cmocka_unit_test(test_3ds_triangles_and_transparent_material),
        cmocka_unit_test(test_obj_nan_coordinate_is_refused),
        cmocka_unit_test(test_obj_out_of_range_index_is_refused),
        cmocka_unit_test(test_malformed_file_gives_one_line),
        cmocka_unit_test(test_file_not_of_its_format_is_refused_before_assimp),
        cmocka_unit_test(test_empty_file_and_file_without_triangles_are_refused),
        cmocka_unit_test(test_q3bsp_faces_patch_and_billboard),
        cmocka_unit_test(test_q3bsp_patch_level_4_gives_32_triangles),
        cmocka_unit_test(test_q3bsp_inverted_patch_is_wound_the_other_way),
        cmocka_unit_test(test_q3bsp_corrupt_files_are_refused_with_their_line),
        cmocka_unit_test(test_real_quake_maps_load),
        cmocka_unit_test(test_real_cgal_meshes_load_closed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

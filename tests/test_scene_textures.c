/* Textures of the scene model: bilinear sampling and sRGB decoding
 * (scene/textures.c), the image decoder (texture_image.c), pk3 archives
 * (pk3.c), shader scripts (q3_shader.c), a Quake III map textured from a
 * loose directory and from an archive (q3_textures.c), Assimp's maps (MTL,
 * glTF with an embedded image), the scene file's texture keys, a missing
 * texture (warned about, never an error), the refusal of .kdt, and the
 * normal and colour a hit shows (rtt_surface_at). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include <cmocka.h>

#include "kdt_format.h"
#include "pk3.h"
#include "q3_shader.h"
#include "rtt/shade.h"
#include "scene_build.h"
#include "test_tempdir.h"
#include "textures.h"

static int setup(void **state) { return scratch_create(state, "textures"); }

static void write_bytes(const char *path, const void *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    fclose(f);
}

/* An uncompressed 24-bit TGA of w x h texels, top row first. */
static size_t make_tga(uint8_t *out, uint32_t w, uint32_t h, const uint8_t *rgb)
{
    memset(out, 0, 18);
    out[2] = 2;
    out[12] = (uint8_t)w, out[13] = (uint8_t)(w >> 8), out[14] = (uint8_t)h, out[15] = (uint8_t)(h >> 8);
    out[16] = 24, out[17] = 0x20;
    for (uint32_t i = 0; i < w * h; i++) {
        out[18 + 3 * i] = rgb[3 * i + 2];
        out[18 + 3 * i + 1] = rgb[3 * i + 1];
        out[18 + 3 * i + 2] = rgb[3 * i];
    }
    return 18 + 3 * (size_t)w * h;
}

static void assert_near(float a, float b, float eps)
{
    if (!(fabsf(a - b) <= eps)) fail_msg("%.9g is not within %g of %.9g", (double)a, (double)eps, (double)b);
}

/* ---- sampling ---- */

static rtt_texture two_by_two(uint8_t texels[12])
{
    /* top row: black, white; bottom row: 255 red, 51 grey */
    const uint8_t v[12] = {0, 0, 0, 255, 255, 255, 255, 0, 0, 51, 51, 51};
    memcpy(texels, v, 12);
    return (rtt_texture){.name = "2x2", .width = 2, .height = 2, .rgb = texels};
}

static void test_bilinear_texel_centres_midpoints_and_wrap(void **state)
{
    (void)state;
    uint8_t texels[12];
    rtt_texture t = two_by_two(texels);
    /* texel centres: u = 0.25 / 0.75, v = 0.75 (top row) / 0.25 */
    assert_near(rtt_texture_sample(&t, 0.25f, 0.75f, false).x, 0.0f, 1e-6f);
    assert_near(rtt_texture_sample(&t, 0.75f, 0.75f, false).y, 1.0f, 1e-6f);
    assert_near(rtt_texture_sample(&t, 0.25f, 0.25f, false).x, 1.0f, 1e-6f);
    /* between the top two: half white */
    assert_near(rtt_texture_sample(&t, 0.5f, 0.75f, false).y, 0.5f, 1e-6f);
    /* the centre of all four: mean of green = (0 + 1 + 0 + 0.2) / 4 */
    assert_near(rtt_texture_sample(&t, 0.5f, 0.5f, false).y, 0.3f, 1e-6f);
    /* repeat: u = 0 lies between texel 1 (wrapped) and texel 0 */
    rtt_vec3 edge = rtt_texture_sample(&t, 0.0f, 0.75f, false), wrapped = rtt_texture_sample(&t, 5.0f, -2.25f, false);
    assert_near(edge.y, 0.5f, 1e-6f);
    assert_near(wrapped.x, edge.x, 1e-6f);
    /* non-finite coordinates are 0, never a crash */
    rtt_vec3 nan = rtt_texture_sample(&t, NAN, INFINITY, false);
    assert_true(isfinite(nan.x) && isfinite(nan.y) && isfinite(nan.z));
}

static void test_srgb_decoding(void **state)
{
    (void)state;
    uint8_t texels[12];
    rtt_texture t = two_by_two(texels);
    /* 51/255 = 0.2 encoded is 0.0331 linear (IEC 61966-2-1) */
    assert_near(rtt_texture_sample(&t, 0.75f, 0.25f, true).x, 0.0331048f, 1e-5f);
    assert_near(rtt_texture_sample(&t, 0.75f, 0.75f, true).x, 1.0f, 1e-6f);
    assert_near(rtt_texture_sample(&t, 0.25f, 0.75f, true).x, 0.0f, 1e-6f);
}

/* ---- decoding ---- */

static void test_decode_tga_and_refuse_bad_images(void **state)
{
    (void)state;
    uint8_t rgb[12] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120}, tga[64];
    size_t size = make_tga(tga, 2, 2, rgb);
    rtt_texture t = {0};
    char why[256];
    assert_true(rtt_texture_decode(tga, size, &t, why, sizeof why));
    assert_int_equal(t.width, 2);
    assert_int_equal(t.height, 2);
    assert_memory_equal(t.rgb, rgb, 12);
    free(t.rgb);
    /* not an image */
    assert_false(rtt_texture_decode((const uint8_t *)"hello, world", 12, &t, why, sizeof why));
    assert_non_null(strstr(why, "not a JPEG, PNG or TGA"));
    /* a header asking for 9000 x 9000 texels: refused before decoding */
    tga[12] = 9000 & 0xff, tga[13] = 9000 >> 8, tga[14] = 9000 & 0xff, tga[15] = 9000 >> 8;
    assert_false(rtt_texture_decode(tga, size, &t, why, sizeof why));
    /* truncated texels: stb_image reads zeros past the end (never past the
     * buffer); the image keeps its header's size */
    make_tga(tga, 2, 2, rgb);
    if (rtt_texture_decode(tga, 20, &t, why, sizeof why)) {
        assert_int_equal(t.width * t.height, 4);
        free(t.rgb);
    }
    assert_false(rtt_texture_decode(tga, 10, &t, why, sizeof why)); /* a cut header */
    assert_false(rtt_texture_decode(tga, 0, &t, why, sizeof why));
}

/* ---- pk3 archives ---- */

typedef struct zip_member {
    const char *name;
    const uint8_t *data;
    uint32_t size;
    bool deflate;
} zip_member;

static void put16(uint8_t **p, uint32_t v) { (*p)[0] = (uint8_t)v, (*p)[1] = (uint8_t)(v >> 8), *p += 2; }
static void put32(uint8_t **p, uint32_t v) { put16(p, v & 0xffff), put16(p, v >> 16); }

/* A zip of the members (stored or raw-deflated); returns its size. */
static size_t make_zip(uint8_t *out, const zip_member *m, uint32_t count)
{
    uint8_t *p = out;
    uint32_t offsets[8], compressed[8], crcs[8];
    uint8_t packed[8][4096];
    for (uint32_t i = 0; i < count; i++) {
        crcs[i] = (uint32_t)crc32(0L, m[i].data, m[i].size);
        if (m[i].deflate) {
            z_stream z = {0};
            assert_int_equal(deflateInit2(&z, 9, Z_DEFLATED, -MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
            z.next_in = (Bytef *)(uintptr_t)m[i].data, z.avail_in = m[i].size;
            z.next_out = packed[i], z.avail_out = sizeof packed[i];
            assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
            compressed[i] = (uint32_t)z.total_out;
            deflateEnd(&z);
        } else {
            memcpy(packed[i], m[i].data, m[i].size);
            compressed[i] = m[i].size;
        }
        offsets[i] = (uint32_t)(p - out);
        uint32_t n = (uint32_t)strlen(m[i].name);
        put32(&p, 0x04034b50), put16(&p, 20), put16(&p, 0), put16(&p, m[i].deflate ? 8 : 0), put32(&p, 0);
        put32(&p, crcs[i]), put32(&p, compressed[i]), put32(&p, m[i].size), put16(&p, n), put16(&p, 0);
        memcpy(p, m[i].name, n), p += n;
        memcpy(p, packed[i], compressed[i]), p += compressed[i];
    }
    uint32_t directory = (uint32_t)(p - out);
    for (uint32_t i = 0; i < count; i++) {
        uint32_t n = (uint32_t)strlen(m[i].name);
        put32(&p, 0x02014b50), put16(&p, 20), put16(&p, 20), put16(&p, 0), put16(&p, m[i].deflate ? 8 : 0);
        put32(&p, 0), put32(&p, crcs[i]), put32(&p, compressed[i]), put32(&p, m[i].size), put16(&p, n);
        put16(&p, 0), put16(&p, 0), put16(&p, 0), put16(&p, 0), put32(&p, 0), put32(&p, offsets[i]);
        memcpy(p, m[i].name, n), p += n;
    }
    uint32_t directory_size = (uint32_t)(p - out) - directory;
    put32(&p, 0x06054b50), put16(&p, 0), put16(&p, 0), put16(&p, count), put16(&p, count);
    put32(&p, directory_size), put32(&p, directory), put16(&p, 0);
    return (size_t)(p - out);
}

static const char *const shader_text =
    "// a comment { with braces }\n"
    "textures/test/alias\n{\n  qer_editorimage textures/test/other.tga\n"
    "  { map $lightmap\n blendfunc filter }\n"
    "  /* a block comment } */ { map textures/test/checker.jpg\n rgbGen identity }\n}\n";

static void test_pk3_stored_and_deflated_members(void **state)
{
    uint8_t text[600];
    memset(text, 'a', sizeof text);
    const zip_member members[] = {{"Scripts/Test.shader", (const uint8_t *)shader_text, (uint32_t)strlen(shader_text), true},
                                  {"textures/plain.txt", text, sizeof text, false}};
    static uint8_t zip[16384];
    size_t size = make_zip(zip, members, 2);
    const char *path = scratch_path(state, "a.pk3");
    write_bytes(path, zip, size);
    rtt_pk3 archive;
    rtt_error err;
    assert_true(rtt_pk3_open(&archive, path, &err));
    assert_int_equal(archive.count, 2);
    int64_t i = rtt_pk3_find(&archive, "scripts/test.SHADER"); /* case-insensitive, as Quake */
    assert_int_equal(i, 0);
    assert_int_equal(rtt_pk3_find(&archive, "textures/none.tga"), -1);
    size_t n;
    uint8_t *bytes = rtt_pk3_read(&archive, 0, &n, &err);
    assert_non_null(bytes);
    assert_int_equal(n, strlen(shader_text));
    assert_memory_equal(bytes, shader_text, n);
    free(bytes);
    bytes = rtt_pk3_read(&archive, 1, &n, &err);
    assert_non_null(bytes);
    assert_int_equal(n, sizeof text);
    free(bytes);
    rtt_pk3_close(&archive);
}

static void test_pk3_damage_is_refused_with_a_reason(void **state)
{
    static uint8_t zip[16384];
    const zip_member member = {"a.txt", (const uint8_t *)shader_text, (uint32_t)strlen(shader_text), true};
    size_t size = make_zip(zip, &member, 1);
    const char *path = scratch_path(state, "b.pk3");
    rtt_pk3 archive;
    rtt_error err;
    /* a flipped data byte: the CRC (or the deflate stream) catches it */
    zip[40] ^= 0x55;
    write_bytes(path, zip, size);
    assert_true(rtt_pk3_open(&archive, path, &err));
    size_t n;
    assert_null(rtt_pk3_read(&archive, 0, &n, &err));
    assert_non_null(strstr(err.message, "a.txt"));
    rtt_pk3_close(&archive);
    /* no end record */
    write_bytes(path, zip, size - 22);
    assert_false(rtt_pk3_open(&archive, path, &err));
    assert_non_null(strstr(err.message, "not a pk3"));
    /* a central directory offset past the end record */
    zip[40] ^= 0x55;
    zip[size - 6] = 0xff;
    write_bytes(path, zip, size);
    assert_false(rtt_pk3_open(&archive, path, &err));
    assert_false(rtt_pk3_open(&archive, scratch_path(state, "none.pk3"), &err));
}

/* ---- shader scripts ---- */

typedef struct shader_log {
    char text[1024];
} shader_log;

static void log_shader(void *context, const char *shader, const char *image)
{
    shader_log *log = context;
    size_t n = strlen(log->text);
    snprintf(log->text + n, sizeof log->text - n, "%s=%s;", shader, image ? image : "(none)");
}

static void test_shader_first_image_stage(void **state)
{
    (void)state;
    shader_log log = {""};
    char why[128];
    const char *text = "a\n{\n{\nmap $lightmap\n}\n{\nclampmap textures/a.tga\n}\n{\nmap textures/b.tga\n}\n}\n"
                       "b { { animMap 10 textures/anim1.tga textures/anim2.tga } }\n"
                       "c { surfaceparm nodraw }\n"
                       "\"quoted name\" { { map \"textures/q.tga\" } }\n";
    assert_true(rtt_q3_shader_parse(text, strlen(text), log_shader, &log, why, sizeof why));
    assert_string_equal(log.text, "a=textures/a.tga;b=textures/anim1.tga;c=(none);quoted name=textures/q.tga;");
    log.text[0] = '\0';
    assert_true(rtt_q3_shader_parse(shader_text, strlen(shader_text), log_shader, &log, why, sizeof why));
    assert_string_equal(log.text, "textures/test/alias=textures/test/checker.jpg;");
    /* syntax errors name the line; the shaders before them are kept */
    log.text[0] = '\0';
    const char *open = "ok { { map x.tga } }\nbroken {\n{ map y.tga }\n";
    assert_false(rtt_q3_shader_parse(open, strlen(open), log_shader, &log, why, sizeof why));
    assert_string_equal(log.text, "ok=x.tga;");
    assert_non_null(strstr(why, "not closed"));
    const char *deep = "x { { { map a.tga } } }";
    assert_false(rtt_q3_shader_parse(deep, strlen(deep), log_shader, &log, why, sizeof why));
    assert_non_null(strstr(why, "line 1"));
    const char *stray = "}";
    assert_false(rtt_q3_shader_parse(stray, 1, log_shader, &log, why, sizeof why));
    const char *no_block = "name other";
    assert_false(rtt_q3_shader_parse(no_block, strlen(no_block), log_shader, &log, why, sizeof why));
}

/* ---- a textured Quake III map ---- */

static void le32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static void lef(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    le32(p, u);
}

/* IBSP 46: one polygon face (a quad, 2 triangles) with texture 0 and a
 * second with texture 1; lumps 1 (textures), 10, 11, 13. */
static size_t make_map(uint8_t *out, const char *texture0, const char *texture1)
{
    enum { HEADER = 144, TEXTURES = 2 * 72, VERTICES = 4 * 44, MESHVERTS = 6 * 4, FACES = 2 * 104 };
    memset(out, 0, HEADER + TEXTURES + VERTICES + MESHVERTS + FACES);
    memcpy(out, "IBSP", 4);
    le32(out + 4, 46);
    for (int lump = 0; lump < 17; lump++) le32(out + 8 + 8 * lump, HEADER);
    le32(out + 8 + 8 * 1, HEADER), le32(out + 12 + 8 * 1, TEXTURES);
    le32(out + 8 + 8 * 10, HEADER + TEXTURES), le32(out + 12 + 8 * 10, VERTICES);
    le32(out + 8 + 8 * 11, HEADER + TEXTURES + VERTICES), le32(out + 12 + 8 * 11, MESHVERTS);
    le32(out + 8 + 8 * 13, HEADER + TEXTURES + VERTICES + MESHVERTS), le32(out + 12 + 8 * 13, FACES);
    uint8_t *t = out + HEADER;
    snprintf((char *)t, 64, "%s", texture0);
    snprintf((char *)t + 72, 64, "%s", texture1);
    const float corners[4][5] = {{0, 0, 0, 0, 1}, {1, 0, 0, 1, 1}, {1, 1, 0, 1, 0}, {0, 1, 0, 0, 0}};
    uint8_t *v = out + HEADER + TEXTURES;
    for (int i = 0; i < 4; i++, v += 44) {
        for (int k = 0; k < 5; k++) lef(v + 4 * k, corners[i][k]); /* position, then (s, t) */
        lef(v + 36, 1.0f);                                         /* normal +z */
    }
    const int32_t meshverts[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++) le32(out + HEADER + TEXTURES + VERTICES + 4 * i, (uint32_t)meshverts[i]);
    uint8_t *f = out + HEADER + TEXTURES + VERTICES + MESHVERTS;
    for (int face = 0; face < 2; face++, f += 104) {
        le32(f, (uint32_t)face), le32(f + 8, 1), le32(f + 12, 0), le32(f + 16, 4), le32(f + 20, 0), le32(f + 24, 6);
    }
    return HEADER + TEXTURES + VERTICES + MESHVERTS + FACES;
}

static void test_q3_map_textures_from_an_archive_and_loose_files(void **state)
{
    scratch *sc = *state;
    char dir[256];
    /* <scratch>/maps/m.bsp, <scratch>/pk3/tex.pk3 with a script and a
     * JPEG-named shader image stored as TGA bytes under .tga */
    snprintf(dir, sizeof dir, "%s/maps", sc->dir);
    mkdir(dir, 0755);
    snprintf(dir, sizeof dir, "%s/pk3", sc->dir);
    mkdir(dir, 0755);
    uint8_t rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255}, tga[64];
    size_t tga_size = make_tga(tga, 2, 2, rgb);
    const zip_member members[] = {{"scripts/test.shader", (const uint8_t *)shader_text, (uint32_t)strlen(shader_text), true},
                                  {"textures/test/checker.tga", tga, (uint32_t)tga_size, false}};
    static uint8_t zip[16384];
    size_t zip_size = make_zip(zip, members, 2);
    write_bytes(scratch_path(state, "pk3/tex.pk3"), zip, zip_size);
    static uint8_t map[2048];
    size_t map_size = make_map(map, "textures/test/alias", "textures/test/nowhere");
    char map_path[256];
    snprintf(map_path, sizeof map_path, "%s/maps/m.bsp", sc->dir);
    write_bytes(map_path, map, map_size);
    unsetenv("RTT_TEXTURE_PATH");
    rtt_error err;
    rtt_scene *s = rtt_scene_load(map_path, NULL, &err);
    if (!s) fail_msg("%s", err.message);
    assert_int_equal(s->triangle_count, 4);
    assert_int_equal(s->texture_count, 1); /* the shader's stage image, .jpg replaced by .tga */
    assert_string_equal(s->textures[0].name, "textures/test/checker.tga");
    assert_int_equal(s->missing_texture_count, 1); /* textures/test/nowhere */
    assert_non_null(strstr(s->missing_texture, "nowhere"));
    const rtt_material *m0 = &s->materials[s->triangle_material[0]], *m1 = &s->materials[s->triangle_material[2]];
    assert_string_equal(m0->name, "textures/test/alias");
    assert_int_equal(m0->diffuse_map, 1);
    assert_int_equal(m1->diffuse_map, 0);
    assert_non_null(s->texcoords);
    /* vertex 0: (s, t) = (0, 1) is (u, v) = (0, 0) */
    assert_near(s->texcoords[0], 0.0f, 0.0f);
    assert_near(s->texcoords[1], 0.0f, 0.0f);
    assert_near(s->texcoords[5], 1.0f, 0.0f);
    rtt_scene_free(s);

    /* RTT_TEXTURE_PATH: a loose textures/ directory overrides nothing here,
     * the archive is not on the path, so the loose image is the one used */
    snprintf(dir, sizeof dir, "%s/loose", sc->dir);
    mkdir(dir, 0755);
    snprintf(dir, sizeof dir, "%s/loose/textures", sc->dir);
    mkdir(dir, 0755);
    snprintf(dir, sizeof dir, "%s/loose/textures/test", sc->dir);
    mkdir(dir, 0755);
    write_bytes(scratch_path(state, "loose/textures/test/nowhere.tga"), tga, tga_size);
    snprintf(dir, sizeof dir, "%s/loose", sc->dir);
    setenv("RTT_TEXTURE_PATH", dir, 1);
    s = rtt_scene_load(map_path, NULL, &err);
    unsetenv("RTT_TEXTURE_PATH");
    if (!s) fail_msg("%s", err.message);
    assert_int_equal(s->texture_count, 1);
    assert_string_equal(s->textures[0].name, "textures/test/nowhere.tga");
    assert_int_equal(s->missing_texture_count, 1); /* alias's image is in the archive, not on the path */
    rtt_scene_free(s);
}

static void test_q3_map_without_texture_source_keeps_one_grey_material(void **state)
{
    static uint8_t map[2048];
    size_t map_size = make_map(map, "textures/a", "textures/b");
    const char *path = scratch_path(state, "alone.bsp");
    write_bytes(path, map, map_size);
    setenv("RTT_TEXTURE_PATH", "/nonexistent-rtt-dir", 1);
    rtt_error err;
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    unsetenv("RTT_TEXTURE_PATH");
    if (!s) fail_msg("%s", err.message);
    assert_int_equal(s->material_count, 1);
    assert_int_equal(s->texture_count, 0);
    assert_null(s->texcoords);
    assert_int_equal(s->missing_texture_count, 1);
    assert_non_null(strstr(s->missing_texture, "no pk3 archive"));
    rtt_scene_free(s);
}

/* ---- scene files and Assimp ---- */

static rtt_scene *load(const char *path)
{
    rtt_error err;
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    if (!s) fail_msg("%s: %s", path, err.message);
    return s;
}

static void test_scene_file_textures_are_shared_and_sampled(void **state)
{
    (void)state;
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/tex_diffuse.json");
    assert_int_equal(s->texture_count, 1); /* two materials, one image */
    assert_int_equal(s->materials[0].diffuse_map, 1);
    assert_int_equal(s->materials[1].diffuse_map, 1);
    assert_int_equal(s->textures[0].width, 32);
    assert_int_equal(s->texcoord_count, s->vertex_count);
    assert_int_equal(s->missing_texture_count, 0);
    assert_true(rtt_scene_texture_bytes(s) >= 32 * 32 * 3 + s->vertex_count * 8);
    /* the floor's hit at texcoord (0.0625, 0.0625) * 3 ... the colour is the
     * texture's, not the material's grey */
    rtt_ray ray = {{0.1f, 1.0f, 1.9f}, {0.0f, -1.0f, 0.0f}, 0.0f, INFINITY};
    rtt_hit hit = {1.0f, 0.0f, 0.0f, 0};
    /* triangle 0 = corners (-2,0,-2), (-2,0,2), (2,0,2): find (u, v) of (0.1, 0, 1.9) */
    hit.u = (1.9f + 2.0f) / 4.0f - (0.1f + 2.0f) / 4.0f;
    hit.v = (0.1f + 2.0f) / 4.0f;
    rtt_surface surface = rtt_surface_at(s, &ray, &hit);
    rtt_vec3 expected = rtt_texture_sample(&s->textures[0], 3.0f * (0.1f + 2.0f) / 4.0f,
                                           3.0f * (1.0f - (1.9f + 2.0f) / 4.0f), true);
    assert_near(surface.diffuse.x, expected.x, 1e-5f);
    assert_near(surface.diffuse.z, expected.z, 1e-5f);
    assert_true(fabsf(surface.diffuse.x - s->materials[0].diffuse.x) > 1e-3f);
    rtt_scene_free(s);
}

static void test_normal_map_perturbs_in_tangent_space(void **state)
{
    (void)state;
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/tex_normal.json");
    assert_int_equal(s->texture_count, 2);
    /* the wall (z = -0.5, facing +z, u along +x, v along +y): at a bump's
     * right flank (texel x 5 of 8 in its cell) the normal tilts to +x */
    const rtt_texture *bumps = &s->textures[s->materials[0].normal_map - 1];
    float tu = (5.5f + 8.0f) / 32.0f, tv = 1.0f - 3.5f / 32.0f; /* cell 1's row 3, column 5 */
    rtt_vec3 c = rtt_texture_sample(bumps, tu, tv, false);
    float u = tu / 2.0f * 1.6f - 1.6f, y = tv / 2.0f * 1.6f; /* the wall maps u 0..2 to x -1.6..0 */
    /* triangle 0 of the wall: (-1.6,0), (0,0), (0,1.6): barycentrics of (u, y) */
    rtt_hit hit = {1.0f, (u + 1.6f) / 1.6f - y / 1.6f, y / 1.6f, 0};
    rtt_ray ray = {{u, y, 1.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, INFINITY};
    rtt_surface surface = rtt_surface_at(s, &ray, &hit);
    rtt_vec3 m = rtt_v3_normalize(rtt_v3(2 * c.x - 1, 2 * c.y - 1, 2 * c.z - 1));
    assert_true(m.x > 0.1f);
    assert_near(surface.normal.x, m.x, 1e-4f);
    assert_near(surface.normal.y, m.y, 1e-4f);
    assert_near(surface.normal.z, m.z, 1e-4f);
    rtt_scene_free(s);
}

static void test_obj_mtl_maps(void **state)
{
    (void)state;
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/meshes/textured_quad.obj");
    assert_int_equal(s->texture_count, 2);
    assert_int_equal(s->missing_texture_count, 0);
    const rtt_material *m = &s->materials[s->triangle_material[0]];
    assert_int_equal(m->diffuse_map, 1);
    assert_int_equal(m->normal_map, 2);
    assert_non_null(strstr(s->textures[0].name, "checker.tga"));
    assert_non_null(strstr(s->textures[1].name, "bumps.tga"));
    assert_non_null(s->texcoords);
    rtt_scene_free(s);
}

static const char base64_chars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void base64(const uint8_t *in, size_t n, char *out)
{
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = base64_chars[v >> 18 & 63];
        out[o++] = base64_chars[v >> 12 & 63];
        out[o++] = i + 1 < n ? base64_chars[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? base64_chars[v & 63] : '=';
    }
    out[o] = '\0';
}

static void test_gltf_embedded_base_colour_texture(void **state)
{
    FILE *png = fopen(RTT_SOURCE_DIR "/scenes/textures/checker.png", "rb");
    assert_non_null(png);
    static uint8_t image[4096];
    size_t image_size = fread(image, 1, sizeof image, png);
    fclose(png);
    /* one triangle with TEXCOORD_0: positions (3 x vec3) then uvs (3 x vec2) */
    const float data[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    static char image64[8192], data64[256], text[16384];
    base64(image, image_size, image64);
    base64((const uint8_t *)data, sizeof data, data64);
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"material\":0}]}],"
             "\"materials\":[{\"name\":\"tex\",\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
             "\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"data:image/png;base64,%s\"}],"
             "\"buffers\":[{\"byteLength\":60,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}]}",
             image64, data64);
    const char *path = scratch_path(state, "tri.gltf");
    write_bytes(path, text, strlen(text));
    rtt_scene *s = load(path);
    assert_int_equal(s->texture_count, 1);
    assert_int_equal(s->textures[0].width, 32);
    assert_int_equal(s->materials[s->triangle_material[0]].diffuse_map, 1);
    assert_non_null(s->texcoords);
    rtt_scene_free(s);
}

static void test_missing_texture_warns_and_keeps_the_colour(void **state)
{
    const char *scene =
        "{\"materials\": [{\"name\": \"m\", \"diffuse\": [0.2, 0.4, 0.6], \"diffuse_map\": \"no/such.tga\"}],"
        " \"meshes\": [{\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"triangles\": [[0,1,2]],"
        " \"texcoords\": [[0,0],[1,0],[0,1]], \"material\": \"m\"}]}";
    const char *path = scratch_path(state, "missing.json");
    write_bytes(path, scene, strlen(scene));
    rtt_scene *s = load(path);
    assert_int_equal(s->missing_texture_count, 1);
    assert_non_null(strstr(s->missing_texture, "no/such.tga"));
    assert_int_equal(s->texture_count, 0);
    assert_int_equal(s->materials[0].diffuse_map, 0);
    assert_null(s->texcoords); /* nothing samples a texture: the coordinates are dropped */
    rtt_ray ray = {{0.2f, 0.2f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY};
    rtt_hit hit = {1.0f, 0.2f, 0.2f, 0};
    rtt_surface surface = rtt_surface_at(s, &ray, &hit);
    assert_near(surface.diffuse.y, 0.4f, 0.0f);
    rtt_scene_free(s);
}

static void test_untextured_scene_pays_nothing(void **state)
{
    (void)state;
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/mat_diffuse.json");
    assert_null(s->texcoords);
    assert_null(s->textures);
    assert_int_equal(rtt_scene_texture_bytes(s), 0);
    rtt_scene_free(s);
}

static void test_kdt_refuses_textured_scenes(void **state)
{
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/tex_diffuse.json");
    rtt_error err;
    const char *path = scratch_path(state, "t.kdt");
    assert_false(rtt_kdt_write(path, s, NULL, &err));
    assert_non_null(strstr(err.message, "does not carry textures"));
    struct stat info;
    assert_int_not_equal(stat(path, &info), 0); /* nothing written */
    rtt_scene_free(s);
}

static void test_transmission_of_materials(void **state)
{
    (void)state;
    rtt_scene *s = load(RTT_SOURCE_DIR "/scenes/shadow_transparent.json");
    assert_true(rtt_scene_has_transparent_shadows(s));
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        const rtt_material *m = &s->materials[s->triangle_material[t]];
        float expected = strcmp(m->name, "glass") == 0 ? 0.7f : strcmp(m->name, "tinted") == 0 ? 0.4f : 0.0f;
        assert_near(rtt_shadow_transmission(s, t), expected, 1e-7f);
    }
    rtt_scene_free(s);
    s = load(RTT_SOURCE_DIR "/scenes/mat_diffuse.json");
    assert_false(rtt_scene_has_transparent_shadows(s));
    rtt_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bilinear_texel_centres_midpoints_and_wrap),
        cmocka_unit_test(test_srgb_decoding),
        cmocka_unit_test(test_decode_tga_and_refuse_bad_images),
        cmocka_unit_test_setup_teardown(test_pk3_stored_and_deflated_members, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_pk3_damage_is_refused_with_a_reason, setup, remove_scratch),
        cmocka_unit_test(test_shader_first_image_stage),
        cmocka_unit_test_setup_teardown(test_q3_map_textures_from_an_archive_and_loose_files, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_q3_map_without_texture_source_keeps_one_grey_material, setup,
                                        remove_scratch),
        cmocka_unit_test(test_scene_file_textures_are_shared_and_sampled),
        cmocka_unit_test(test_normal_map_perturbs_in_tangent_space),
        cmocka_unit_test(test_obj_mtl_maps),
        cmocka_unit_test_setup_teardown(test_gltf_embedded_base_colour_texture, setup, remove_scratch),
        cmocka_unit_test_setup_teardown(test_missing_texture_warns_and_keeps_the_colour, setup, remove_scratch),
        cmocka_unit_test(test_untextured_scene_pays_nothing),
        cmocka_unit_test_setup_teardown(test_kdt_refuses_textured_scenes, setup, remove_scratch),
        cmocka_unit_test(test_transmission_of_materials),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

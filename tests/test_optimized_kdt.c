/* The baked kd-tree file (.kdt): rtt_optimized_bake writes it, rtt_scene_load
 * reads it back (scene/kdt_file.c).  A round trip gives the same scene and
 * the same tree, so the same hits; every corruption is refused with its
 * exact one-line message; a forged file (re-checksummed) loads but the
 * optimized engine refuses its tree; random damage never crashes. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "engine_optimized.h"
#include "kdt_format.h"
#include "rtt/optimized.h"
#include "scene_build.h"

#define BAKED "test_optimized_kdt.kdt"
#define DAMAGED "test_optimized_kdt_damaged.kdt"

typedef struct rng {
    uint64_t s;
} rng;

static uint32_t rng_u32(rng *r)
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return (uint32_t)(r->s >> 32);
}

static float rng_range(rng *r, float lo, float hi) { return lo + (hi - lo) * (float)(rng_u32(r) >> 8) / 16777216.0f; }

/* A soup with two materials and two lights (one a sphere). */
static rtt_scene *make_scene(void)
{
    rng r = {41};
    const uint32_t n = 800;
    float *xyz = malloc(n * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t i = 0; i < n; i++) {
        float c[3] = {rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1)};
        for (int k = 0; k < 9; k++) xyz[9 * i + k] = c[k % 3] + rng_range(&r, -0.1f, 0.1f);
    }
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, n, &err);
    free(xyz);
    if (!scene) fail_msg("%s", err.message);
    rtt_material m = rtt_material_default();
    strcpy(m.name, "glass");
    m.type = RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
    m.diffuse = rtt_v3(0.1f, 0.2f, 0.3f);
    m.ior = 1.33f;
    uint32_t glass = rtt_scene_add_material(scene, &m);
    assert_true(glass != UINT32_MAX);
    for (uint32_t i = 0; i < n; i += 3) scene->triangle_material[i] = glass;
    rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = rtt_v3(0, 3, 0), .color = rtt_v3(1, 0.5f, 0.25f),
                       .intensity = 2.0f, .attenuation = {1, 0.1f, 0.01f}, .radius = 0.5f};
    assert_true(rtt_scene_add_light(scene, &light, &err));
    scene->width = 320, scene->height = 200;
    return scene;
}

static void bake(const rtt_scene *scene, const char *path)
{
    rtt_error err = {{0}};
    if (!rtt_optimized_bake(scene, NULL, path, &err)) fail_msg("bake: %s", err.message);
}

static unsigned char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *bytes = malloc(*size);
    assert_non_null(bytes);
    assert_int_equal(fread(bytes, 1, *size, f), *size);
    fclose(f);
    return bytes;
}

static void write_all(const char *path, const unsigned char *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    fclose(f);
}

static void fix_checksum(unsigned char *bytes, size_t size)
{
    uint64_t sum = rtt_kdt_checksum_update(KDT_CHECKSUM_INIT, bytes + KDT_CHECKSUM_START, size - KDT_CHECKSUM_START);
    memcpy(bytes + offsetof(kdt_header, checksum), &sum, sizeof sum);
}

static const kdt_section *section(const unsigned char *bytes, kdt_section_id id)
{
    return (const kdt_section *)(bytes + sizeof(kdt_header)) + id;
}

/* Loads `bytes` from a file and expects exactly `message` (after "path: "). */
static void expect_refused(const unsigned char *bytes, size_t size, const char *message)
{
    write_all(DAMAGED, bytes, size);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(DAMAGED, NULL, &err);
    if (scene) fail_msg("accepted a damaged file; expected: %s", message);
    char want[600];
    snprintf(want, sizeof want, "%s: %s", DAMAGED, message);
    assert_string_equal(err.message, want);
    assert_null(strchr(err.message, '\n'));
}

/* ---- round trip ------------------------------------------------------------ */

static void test_round_trip_keeps_scene_and_tree(void **state)
{
    (void)state;
    rtt_scene *scene = make_scene();
    bake(scene, BAKED);
    rtt_error err = {{0}};
    rtt_scene *loaded = rtt_scene_load(BAKED, NULL, &err);
    if (!loaded) fail_msg("load: %s", err.message);
    assert_non_null(loaded->baked);

    assert_int_equal(loaded->triangle_count, scene->triangle_count);
    assert_int_equal(loaded->vertex_count, scene->vertex_count);
    assert_int_equal(loaded->mesh_count, scene->mesh_count);
    assert_int_equal(loaded->degenerate_count, scene->degenerate_count);
    assert_memory_equal(loaded->vertices, scene->vertices, scene->vertex_count * sizeof(rtt_vec3));
    assert_memory_equal(loaded->triangles, scene->triangles, scene->triangle_count * sizeof(rtt_triangle));
    assert_memory_equal(loaded->triangle_material, scene->triangle_material, scene->triangle_count * 4);
    assert_memory_equal(loaded->triangle_mesh, scene->triangle_mesh, scene->triangle_count * 4);
    assert_int_equal(loaded->normals == NULL, scene->normals == NULL);
    if (scene->normals) assert_memory_equal(loaded->normals, scene->normals, scene->vertex_count * sizeof(rtt_vec3));
    assert_int_equal(loaded->material_count, scene->material_count);
    for (uint32_t i = 0; i < scene->material_count; i++) {
        rtt_material want = scene->materials[i], got = loaded->materials[i];
        assert_string_equal(got.name, want.name); /* bytes past the name's end are not kept */
        memset(want.name, 0, sizeof want.name);
        memset(got.name, 0, sizeof got.name);
        assert_memory_equal(&got, &want, sizeof want);
    }
    assert_int_equal(loaded->light_count, scene->light_count);
    for (uint32_t i = 0; i < scene->light_count; i++)
        assert_memory_equal(&loaded->lights[i], &scene->lights[i], sizeof(rtt_light));
    for (uint32_t i = 0; i < scene->mesh_count; i++) {
        assert_string_equal(loaded->meshes[i].name, scene->meshes[i].name);
        assert_int_equal(loaded->meshes[i].first_triangle, scene->meshes[i].first_triangle);
        assert_int_equal(loaded->meshes[i].triangle_count, scene->meshes[i].triangle_count);
        assert_int_equal(loaded->meshes[i].material, scene->meshes[i].material);
        assert_int_equal(loaded->meshes[i].closed, scene->meshes[i].closed);
    }
    assert_memory_equal(&loaded->camera, &scene->camera, sizeof scene->camera);
    assert_memory_equal(&loaded->bounds, &scene->bounds, sizeof scene->bounds);
    assert_memory_equal(&loaded->background, &scene->background, sizeof scene->background);
    assert_int_equal(loaded->width, 320);
    assert_int_equal(loaded->height, 200);
    assert_true(loaded->ambient == scene->ambient);
    assert_int_equal(loaded->max_bounces, scene->max_bounces);

    /* the engine adopts the baked tree: the same arrays as a fresh build */
    rtt_engine *fresh = rtt_optimized_engine_create(scene, NULL, &err);
    rtt_engine *adopted = rtt_optimized_engine_create(loaded, NULL, &err);
    assert_non_null(fresh);
    assert_non_null(adopted);
    const kd_tree *a = kd_engine_tree(fresh), *b = kd_engine_tree(adopted);
    assert_ptr_equal(b->nodes, (const void *)loaded->baked->nodes);
    assert_int_equal(a->node_count, b->node_count);
    assert_int_equal(a->leaf_count, b->leaf_count);
    assert_int_equal(a->triangle_count, b->triangle_count);
    assert_memory_equal(a->nodes, b->nodes, a->node_count * sizeof *a->nodes);
    assert_memory_equal(a->leaves, b->leaves, a->leaf_count * sizeof *a->leaves);
    assert_memory_equal(a->triangles, b->triangles, a->triangle_count * sizeof *a->triangles);
    rtt_tree_info ia, ib;
    assert_true(rtt_engine_tree_info(fresh, &ia));
    assert_true(rtt_engine_tree_info(adopted, &ib));
    assert_int_equal(ia.depth, ib.depth);
    assert_int_equal(ia.max_depth, ib.max_depth);
    assert_int_equal(ia.empty_leaf_count, ib.empty_leaf_count);
    assert_int_equal(ia.references, ib.references);
    assert_int_equal(ia.reference_cap, ib.reference_cap);
    assert_true(ia.sah_cost == ib.sah_cost);

    rng r = {43};
    const uint32_t n = 2000;
    rtt_ray *rays = malloc(n * sizeof *rays);
    rtt_hit *ha = malloc(n * sizeof *ha), *hb = malloc(n * sizeof *hb);
    assert_non_null(rays);
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) /* aimed into the soup */
            rays[i].org[k] = rng_range(&r, -2, 2), rays[i].dir[k] = rng_range(&r, -1, 1) - rays[i].org[k];
        rays[i].tnear = 0.0f, rays[i].tfar = INFINITY;
    }
    rtt_engine_intersect(fresh, rays, ha, n);
    rtt_engine_intersect(adopted, rays, hb, n);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < n; i++) hits += ha[i].prim != RTT_MISS;
    assert_true(hits > n / 10);
    assert_memory_equal(ha, hb, n * sizeof *ha);
    free(rays);
    free(ha);
    free(hb);
    rtt_engine_destroy(fresh);
    rtt_engine_destroy(adopted);
    rtt_scene_free(loaded);
    rtt_scene_free(scene);
}

static void test_bake_replaces_a_file_only_when_complete(void **state)
{
    (void)state;
    rtt_scene *scene = make_scene();
    rtt_error err = {{0}};
    assert_false(rtt_optimized_bake(scene, NULL, "no-such-directory/x.kdt", &err));
    assert_non_null(strstr(err.message, "no-such-directory/x.kdt: cannot create"));
    bake(scene, BAKED);
    bake(scene, BAKED); /* over an existing one */
    rtt_scene *loaded = rtt_scene_load(BAKED, NULL, &err);
    if (!loaded) fail_msg("%s", err.message);
    rtt_scene_free(loaded);
    rtt_scene_free(scene);
}

/* ---- corrupt files --------------------------------------------------------- */

static unsigned char *baked_bytes(size_t *size)
{
    rtt_scene *scene = make_scene();
    bake(scene, BAKED);
    rtt_scene_free(scene);
    return read_all(BAKED, size);
}

static void test_truncated_file_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    expect_refused(bytes, 100, "truncated: 100 bytes, shorter than the 144-byte .kdt header");
    char want[200];
    snprintf(want, sizeof want, "truncated: %zu bytes, the header says %zu", size - 1, size);
    expect_refused(bytes, size - 1, want);
    expect_refused(bytes, 0, "truncated: 0 bytes, shorter than the 144-byte .kdt header");
    free(bytes);
}

static void test_bad_magic_version_checksum_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    bytes[0] = 'X';
    expect_refused(bytes, size, "not a .kdt file (bad magic)");
    bytes[0] = 'R';
    uint32_t version = 2;
    memcpy(bytes + offsetof(kdt_header, version), &version, 4);
    expect_refused(bytes, size, "unsupported .kdt version 2 (this build reads version 1)");
    version = KDT_VERSION;
    memcpy(bytes + offsetof(kdt_header, version), &version, 4);
    bytes[size - 5] ^= 0x40;
    expect_refused(bytes, size, "checksum mismatch: the file is corrupt");
    free(bytes);
}

static kdt_node *nodes_of(unsigned char *bytes, uint32_t *count)
{
    const kdt_header *h = (const kdt_header *)bytes;
    *count = h->node_count;
    return (kdt_node *)(bytes + section(bytes, KDT_SECTION_NODES)->offset);
}

static void test_bad_child_index_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    uint32_t count;
    kdt_node *nodes = nodes_of(bytes, &count);
    assert_true((nodes[0].bits & 3u) != 3u); /* the root is split */
    const uint32_t saved = nodes[0].bits;
    char want[300];

    nodes[0].bits = (count << 2) | (saved & 3u);
    fix_checksum(bytes, size);
    snprintf(want, sizeof want,
             "node 0: child index %u out of range (%u nodes, children follow their parent) (nodes section)", count,
             count);
    expect_refused(bytes, size, want);

    nodes[0].bits = (0u << 2) | (saved & 3u); /* a cycle back to the root */
    fix_checksum(bytes, size);
    snprintf(want, sizeof want,
             "node 0: child index 0 out of range (%u nodes, children follow their parent) (nodes section)", count);
    expect_refused(bytes, size, want);
    free(bytes);
}

static void test_bad_leaf_index_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    uint32_t count, leaf_node = 0;
    kdt_node *nodes = nodes_of(bytes, &count);
    while ((nodes[leaf_node].bits & 3u) != 3u) leaf_node++;
    const kdt_header *h = (const kdt_header *)bytes;
    nodes[leaf_node].leaf = h->leaf_count;
    fix_checksum(bytes, size);
    char want[300];
    snprintf(want, sizeof want, "node %u: leaf index %u out of range (%u leaves) (nodes section)", leaf_node,
             h->leaf_count, h->leaf_count);
    expect_refused(bytes, size, want);
    free(bytes);
}

static void test_bad_leaf_range_and_prim_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    const kdt_header *h = (const kdt_header *)bytes;
    kdt_leaf *leaves = (kdt_leaf *)(bytes + section(bytes, KDT_SECTION_LEAVES)->offset);
    kdt_triangle *records = (kdt_triangle *)(bytes + section(bytes, KDT_SECTION_RECORDS)->offset);
    char want[300];

    const kdt_leaf saved = leaves[0];
    leaves[0].first = h->record_count;
    leaves[0].count = 1;
    fix_checksum(bytes, size);
    snprintf(want, sizeof want, "leaf 0: records %u+1 out of range (%u records) (leaves section)", h->record_count,
             h->record_count);
    expect_refused(bytes, size, want);
    leaves[0] = saved;

    const uint32_t prim0 = records[0].prim;
    records[0].prim = h->triangle_count;
    fix_checksum(bytes, size);
    snprintf(want, sizeof want, "record 0: prim %u out of range (%u triangles) (triangle records section)",
             h->triangle_count, h->triangle_count);
    expect_refused(bytes, size, want);
    records[0].prim = prim0;

    /* what the header says of the build must agree with the tree */
    kdt_header *header = (kdt_header *)bytes;
    const uint64_t cap = header->reference_cap;
    header->reference_cap = header->record_count - 1u;
    fix_checksum(bytes, size);
    snprintf(want, sizeof want, "%u triangle references over the cap %u (header)", header->record_count,
             header->record_count - 1u);
    expect_refused(bytes, size, want);
    header->reference_cap = cap;
    header->sah_cost = -1.0;
    fix_checksum(bytes, size);
    expect_refused(bytes, size, "SAH cost or build time is not a finite number >= 0 (header)");
    free(bytes);
}

static void test_bad_scene_indices_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    const kdt_header *h = (const kdt_header *)bytes;
    char want[300];

    uint32_t *materials = (uint32_t *)(bytes + section(bytes, KDT_SECTION_TRIANGLE_MATERIAL)->offset);
    uint32_t saved = materials[5];
    materials[5] = h->material_count;
    fix_checksum(bytes, size);
    snprintf(want, sizeof want, "triangle 5: material %u out of range (%u materials) (triangle materials section)",
             h->material_count, h->material_count);
    expect_refused(bytes, size, want);
    materials[5] = saved;

    rtt_vec3 *vertices = (rtt_vec3 *)(bytes + section(bytes, KDT_SECTION_VERTICES)->offset);
    vertices[7].y = NAN;
    fix_checksum(bytes, size);
    expect_refused(bytes, size, "vertex 7 is not finite (vertices section)");
    free(bytes);
}

static void test_bad_section_table_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    kdt_section *nodes = (kdt_section *)section(bytes, KDT_SECTION_NODES);
    nodes->offset = (uint64_t)size + 16u;
    fix_checksum(bytes, size);
    char want[300];
    snprintf(want, sizeof want,
             "nodes section at %zu, %llu bytes, lies outside the file or overlaps (section table)", size + 16u,
             (unsigned long long)nodes->size);
    expect_refused(bytes, size, want);
    free(bytes);
}

/* A baked tree is held to the scene file's bounce limit: up to
 * RTT_MAX_BOUNCES loads, one more is refused. */
static void test_baked_max_bounces_past_the_limit_refused(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    kdt_scene_settings *settings = (kdt_scene_settings *)(bytes + section(bytes, KDT_SECTION_SETTINGS)->offset);
    settings->max_bounces = RTT_MAX_BOUNCES;
    fix_checksum(bytes, size);
    write_all(DAMAGED, bytes, size);
    rtt_error err = {{0}};
    rtt_scene *loaded = rtt_scene_load(DAMAGED, NULL, &err);
    if (!loaded) fail_msg("%s", err.message);
    assert_int_equal(loaded->max_bounces, RTT_MAX_BOUNCES);
    rtt_scene_free(loaded);

    settings->max_bounces = RTT_MAX_BOUNCES + 1u;
    fix_checksum(bytes, size);
    char want[200];
    snprintf(want, sizeof want, "max bounces %u over %u (settings section)", RTT_MAX_BOUNCES + 1u, RTT_MAX_BOUNCES);
    expect_refused(bytes, size, want);
    free(bytes);
}

/* Random damage with a valid checksum: refused with one line or loaded,
 * never a crash (run under ASan in CI). */
/* ---- forged files: re-checksummed, so the loader accepts them; the engine
 * replays the builder over the file's planes (optimized/kd/kdt_verify.c) ---- */

/* Loads the forged bytes (which must load) and expects the optimized engine
 * to refuse them with `message` after "path: " (exactly, or as a part when
 * `exact` is false). */
static void expect_engine_refuses(const unsigned char *bytes, size_t size, const char *message, bool exact)
{
    write_all(DAMAGED, bytes, size);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(DAMAGED, NULL, &err);
    if (!scene) fail_msg("the loader refused a forged file (%s); expected the engine to: %s", err.message, message);
    rtt_engine *engine = rtt_optimized_engine_create(scene, NULL, &err);
    if (engine) fail_msg("the engine adopted a forged tree; expected: %s", message);
    char want[600];
    snprintf(want, sizeof want, "%s: %s", DAMAGED, message);
    if (exact) assert_string_equal(err.message, want);
    else if (!strstr(err.message, message)) fail_msg("got \"%s\", expected it to contain \"%s\"", err.message, message);
    assert_null(strchr(err.message, '\n'));
    rtt_scene_free(scene);
}

/* The first leaf with at least `minimum` triangles. */
static uint32_t leaf_with(const unsigned char *bytes, uint32_t minimum)
{
    const kdt_header *h = (const kdt_header *)bytes;
    const kdt_leaf *leaves = (const kdt_leaf *)(bytes + section(bytes, KDT_SECTION_LEAVES)->offset);
    for (uint32_t l = 0; l < h->leaf_count; l++)
        if (leaves[l].count >= minimum) return l;
    fail_msg("no leaf holds %u triangles", minimum);
    return 0;
}

static void test_forged_tree_refused_by_engine(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    unsigned char *forged = malloc(size);
    assert_non_null(forged);
    char want[300];
#define FORGE() memcpy(forged, bytes, size)
#define HEADER ((kdt_header *)forged)
#define LEAVES ((kdt_leaf *)(forged + section(forged, KDT_SECTION_LEAVES)->offset))
#define RECORDS ((kdt_triangle *)(forged + section(forged, KDT_SECTION_RECORDS)->offset))

    /* the untouched file is adopted */
    write_all(DAMAGED, bytes, size);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(DAMAGED, NULL, &err);
    assert_non_null(scene);
    rtt_engine *engine = rtt_optimized_engine_create(scene, NULL, &err);
    if (!engine) fail_msg("the engine refused a file it baked: %s", err.message);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);

    /* a record that is not its triangle's: the first leaf holding it says so */
    FORGE();
    uint32_t leaf = leaf_with(forged, 1);
    kdt_triangle *record = &RECORDS[LEAVES[leaf].first];
    record->n_d += 1.0f;
    fix_checksum(forged, size);
    snprintf(want, sizeof want, "leaf %u: the record of triangle %u is not that triangle's", leaf, record->prim);
    expect_engine_refuses(forged, size, want, true);

    /* a moved vertex: its triangles' records no longer match */
    FORGE();
    rtt_vec3 *vertices = (rtt_vec3 *)(forged + section(forged, KDT_SECTION_VERTICES)->offset);
    vertices[0].x += 0.01f;
    fix_checksum(forged, size);
    expect_engine_refuses(forged, size, "is not that triangle's", false);

    /* a triangle dropped from a leaf it reaches */
    FORGE();
    leaf = leaf_with(forged, 2);
    uint32_t dropped = RECORDS[LEAVES[leaf].first + LEAVES[leaf].count - 1].prim;
    LEAVES[leaf].count--;
    fix_checksum(forged, size);
    snprintf(want, sizeof want, "leaf %u: triangle %u reaches it but is not in it", leaf, dropped);
    expect_engine_refuses(forged, size, want, true);

    /* leaves out of prim order */
    FORGE();
    leaf = leaf_with(forged, 2);
    kdt_triangle swap = RECORDS[LEAVES[leaf].first];
    RECORDS[LEAVES[leaf].first] = RECORDS[LEAVES[leaf].first + 1];
    RECORDS[LEAVES[leaf].first + 1] = swap;
    fix_checksum(forged, size);
    snprintf(want, sizeof want, "leaf %u: triangles not in ascending order", leaf);
    expect_engine_refuses(forged, size, want, true);

    /* a leaf box that no longer covers its triangles: culling would lose hits */
    FORGE();
    leaf = leaf_with(forged, 1);
    LEAVES[leaf].hi[0] = LEAVES[leaf].lo[0];
    LEAVES[leaf].hi[1] = LEAVES[leaf].lo[1];
    fix_checksum(forged, size);
    expect_engine_refuses(forged, size, "its box does not cover triangle", false);

    /* the root's split plane moved: the leaves are no longer those of the planes */
    FORGE();
    kdt_node *root = (kdt_node *)(forged + section(forged, KDT_SECTION_NODES)->offset);
    const int axis = (int)(root->bits & 3u);
    root->split = root->split + 0.25f * (HEADER->tree_hi[axis] - root->split);
    fix_checksum(forged, size);
    expect_engine_refuses(forged, size, "reach", false);

    /* a split plane outside its cell */
    FORGE();
    root = (kdt_node *)(forged + section(forged, KDT_SECTION_NODES)->offset);
    root->split = HEADER->tree_hi[root->bits & 3u] + 1.0f;
    fix_checksum(forged, size);
    snprintf(want, sizeof want, "node 0: split plane %g lies outside its cell", (double)root->split);
    expect_engine_refuses(forged, size, want, true);

    /* a root box larger than the triangles' bounds */
    FORGE();
    HEADER->tree_lo[0] -= 1.0f;
    fix_checksum(forged, size);
    expect_engine_refuses(forged, size, "the baked tree's root box is not the bounds of its triangles", true);
#undef FORGE
#undef HEADER
#undef LEAVES
#undef RECORDS
    free(forged);
    free(bytes);
}

/* Big trees are checked on two threads, one per subtree of the root: the
 * same verdict and the same message as one thread. */
static void test_big_tree_checked_alike_on_one_and_two_threads(void **state)
{
    (void)state;
    rng r = {59};
    const uint32_t n = 30000;
    float *xyz = malloc(n * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t i = 0; i < n; i++) {
        float c[3] = {rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1)};
        for (int k = 0; k < 9; k++) xyz[9 * i + k] = c[k % 3] + rng_range(&r, -0.02f, 0.02f);
    }
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, n, &err);
    free(xyz);
    if (!scene) fail_msg("%s", err.message);
    bake(scene, BAKED);
    rtt_scene_free(scene);
    size_t size;
    unsigned char *bytes = read_all(BAKED, &size);
    for (int forged = 0; forged < 2; forged++) {
        if (forged) { /* the last leaf with two triangles loses its last one: the right subtree */
            const kdt_header *h = (const kdt_header *)bytes;
            kdt_leaf *leaves = (kdt_leaf *)(bytes + section(bytes, KDT_SECTION_LEAVES)->offset);
            uint32_t leaf = h->leaf_count;
            while (leaf > 0 && leaves[leaf - 1].count < 2) leaf--;
            assert_true(leaf > h->leaf_count / 2);
            leaves[leaf - 1].count--;
            fix_checksum(bytes, size);
        }
        write_all(DAMAGED, bytes, size);
        rtt_scene *loaded = rtt_scene_load(DAMAGED, NULL, &err);
        if (!loaded) fail_msg("load: %s", err.message);
        char message[2][sizeof err.message];
        for (uint32_t threads = 1; threads <= 2; threads++) {
            rtt_engine_options opt;
            rtt_engine_options_default(&opt);
            opt.threads = threads;
            rtt_error e = {{0}};
            rtt_engine *engine = rtt_optimized_engine_create(loaded, &opt, &e);
            assert_true((engine == NULL) == (forged == 1));
            rtt_engine_destroy(engine);
            snprintf(message[threads - 1], sizeof message[0], "%s", e.message);
        }
        assert_string_equal(message[0], message[1]);
        if (forged) assert_non_null(strstr(message[0], "reaches it but is not in it"));
        rtt_scene_free(loaded);
    }
    free(bytes);
}

static void test_random_damage_never_crashes(void **state)
{
    (void)state;
    size_t size;
    unsigned char *bytes = baked_bytes(&size);
    unsigned char *copy = malloc(size);
    assert_non_null(copy);
    rng r = {47};
    uint32_t refused = 0;
    for (int round = 0; round < 300; round++) {
        memcpy(copy, bytes, size);
        int flips = 1 + (int)(rng_u32(&r) % 4);
        for (int i = 0; i < flips; i++) {
            /* half the damage in the header and section table, where it matters most */
            size_t at = rng_u32(&r) % 2 ? KDT_CHECKSUM_START + rng_u32(&r) % (sizeof(kdt_header) + 300 - 32)
                                        : rng_u32(&r) % size;
            copy[at] ^= (unsigned char)(1u << (rng_u32(&r) % 8));
        }
        fix_checksum(copy, size);
        write_all(DAMAGED, copy, size);
        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_load(DAMAGED, NULL, &err);
        if (!scene) {
            refused++;
            assert_non_null(strstr(err.message, DAMAGED ": "));
            assert_null(strchr(err.message, '\n'));
            continue;
        }
        rtt_engine *engine = rtt_optimized_engine_create(scene, NULL, &err);
        if (engine) {
            rtt_ray ray = {{0, 0, -3}, {0.01f, 0.02f, 1}, 0, INFINITY};
            rtt_hit hit;
            rtt_engine_intersect(engine, &ray, &hit, 1);
            rtt_engine_destroy(engine);
        }
        rtt_scene_free(scene);
    }
    print_message("%u of 300 damaged files refused\n", refused);
    assert_true(refused > 100);
    free(copy);
    free(bytes);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_keeps_scene_and_tree),
        cmocka_unit_test(test_bake_replaces_a_file_only_when_complete),
        cmocka_unit_test(test_truncated_file_refused),
        cmocka_unit_test(test_bad_magic_version_checksum_refused),
        cmocka_unit_test(test_bad_child_index_refused),
        cmocka_unit_test(test_bad_leaf_index_refused),
        cmocka_unit_test(test_bad_leaf_range_and_prim_refused),
        cmocka_unit_test(test_bad_scene_indices_refused),
        cmocka_unit_test(test_bad_section_table_refused),
        cmocka_unit_test(test_baked_max_bounces_past_the_limit_refused),
        cmocka_unit_test(test_forged_tree_refused_by_engine),
        cmocka_unit_test(test_big_tree_checked_alike_on_one_and_two_threads),
        cmocka_unit_test(test_random_damage_never_crashes),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    remove(BAKED);
    remove(DAMAGED);
    return failed;
}

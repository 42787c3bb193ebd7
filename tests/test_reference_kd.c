/* The reference kd-tree (Thesis 2.2.1) and its recursive traversal (Listing
 * 2.1): builder invariants on random triangle soups, traversal and occlusion
 * against brute force over every triangle, and watertightness of a closed
 * sphere.  Scenes are assembled by hand here so the tests need nothing from
 * the scene loaders. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "isect_watertight.h"
#include "kd_reference.h"
#include "rtt/reference.h"

/* ---- helpers --------------------------------------------------------- */

typedef struct rng {
    uint64_t state;
} rng;

static uint32_t rng_next(rng *r)
{
    r->state = r->state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(r->state >> 33);
}

/* uniform in [0, 1) */
static float rng_float(rng *r)
{
    return (float)(rng_next(r) >> 7) / 16777216.0f;
}

static float rng_range(rng *r, float lo, float hi)
{
    return lo + (hi - lo) * rng_float(r);
}

/* A scene holding the given vertices and index triples, nothing else. */
static rtt_scene *scene_make(const rtt_vec3 *vertices, uint32_t vertex_count, const uint32_t *indices,
                             uint32_t triangle_count)
{
    rtt_scene *scene = calloc(1, sizeof *scene);
    assert_non_null(scene);
    strcpy(scene->path, "test-scene");
    scene->vertex_count = vertex_count;
    scene->triangle_count = triangle_count;
    scene->vertices = malloc((vertex_count ? vertex_count : 1) * sizeof *scene->vertices);
    scene->triangles = malloc((triangle_count ? triangle_count : 1) * sizeof *scene->triangles);
    assert_non_null(scene->vertices);
    assert_non_null(scene->triangles);
    memcpy(scene->vertices, vertices, vertex_count * sizeof *vertices);
    for (uint32_t i = 0; i < triangle_count; i++)
        for (int k = 0; k < 3; k++) scene->triangles[i].v[k] = indices[3 * i + k];
    return scene;
}

static rtt_scene *scene_from_soup(const rtt_vec3 *corners, uint32_t triangle_count)
{
    uint32_t *indices = malloc((3 * triangle_count + 1) * sizeof *indices);
    assert_non_null(indices);
    for (uint32_t i = 0; i < 3 * triangle_count; i++) indices[i] = i;
    rtt_scene *scene = scene_make(corners, 3 * triangle_count, indices, triangle_count);
    free(indices);
    return scene;
}

static void scene_destroy(rtt_scene *scene)
{
    free(scene->vertices);
    free(scene->triangles);
    free(scene);
}

typedef enum soup_kind {
    SOUP_RANDOM,        /* small and a few large triangles anywhere in the cube */
    SOUP_GRID_ALIGNED,  /* corners on a coarse grid: flat, coplanar, touching, in-plane triangles */
    SOUP_WITH_DEGENERATE,
    SOUP_FLAT           /* every triangle in one plane z = 0.5: a flat root box */
} soup_kind;

/* n random triangles in [offset, offset + scale]^3. */
static rtt_vec3 *soup_make(rng *r, soup_kind kind, uint32_t n, float scale, float offset)
{
    rtt_vec3 *corners = malloc(3 * (size_t)n * sizeof *corners);
    assert_non_null(corners);
    for (uint32_t i = 0; i < n; i++) {
        rtt_vec3 *tri = &corners[3 * i];
        if (kind == SOUP_GRID_ALIGNED) {
            /* corners on a grid of eighths, one axis often held constant */
            int flat_axis = (int)(rng_next(r) % 4);
            float flat_value = (float)(rng_next(r) % 9) / 8.0f;
            for (int k = 0; k < 3; k++) {
                float c[3];
                for (int a = 0; a < 3; a++) c[a] = (float)(rng_next(r) % 9) / 8.0f;
                if (flat_axis < 3) c[flat_axis] = flat_value;
                tri[k] = rtt_v3(c[0], c[1], c[2]);
            }
        } else {
            rtt_vec3 centre = rtt_v3(rng_float(r), rng_float(r), rng_float(r));
            float size = (i % 17 == 0) ? 0.6f : 0.08f;
            for (int k = 0; k < 3; k++)
                tri[k] = rtt_v3(centre.x + rng_range(r, -size, size), centre.y + rng_range(r, -size, size),
                                centre.z + rng_range(r, -size, size));
            if (kind == SOUP_FLAT)
                for (int k = 0; k < 3; k++) tri[k].z = 0.5f;
            if (kind == SOUP_WITH_DEGENERATE && i % 7 == 0) {
                tri[1] = tri[0];                                               /* repeated corner */
                if (i % 14 == 0) tri[2] = rtt_v3_madd(tri[0], rtt_v3(1, 2, 3), 0.01f); /* a line */
            }
        }
        for (int k = 0; k < 3; k++)
            tri[k] = rtt_v3(offset + scale * tri[k].x, offset + scale * tri[k].y, offset + scale * tri[k].z);
    }
    return corners;
}

/* ---- exact-ish triangle/box overlap (separating axis test, double) ------ */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* True when triangle and box share interior points; touching along a face,
 * edge or corner does not count (the builder may leave such triangles out). */
static bool triangle_overlaps_box_interior(const rtt_vec3 tri[3], rtt_bounds box)
{
    double v[3][3], lo[3], hi[3], e[3][3];
    double magnitude = 0.0;
    for (int a = 0; a < 3; a++) {
        lo[a] = rtt_v3_get(box.lo, a);
        hi[a] = rtt_v3_get(box.hi, a);
        magnitude = fmax(magnitude, fmax(fabs(lo[a]), fabs(hi[a])));
        for (int k = 0; k < 3; k++) {
            v[k][a] = rtt_v3_get(tri[k], a);
            magnitude = fmax(magnitude, fabs(v[k][a]));
        }
    }
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++) e[k][a] = v[(k + 1) % 3][a] - v[k][a];

    double axes[13][3];
    int count = 0;
    for (int a = 0; a < 3; a++) {
        double n[3] = {0, 0, 0};
        n[a] = 1.0;
        memcpy(axes[count++], n, sizeof n);
    }
    double normal[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                        e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    memcpy(axes[count++], normal, sizeof normal);
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++) {
            double unit[3] = {0, 0, 0};
            unit[a] = 1.0;
            double c[3] = {e[k][1] * unit[2] - e[k][2] * unit[1], e[k][2] * unit[0] - e[k][0] * unit[2],
                           e[k][0] * unit[1] - e[k][1] * unit[0]};
            memcpy(axes[count++], c, sizeof c);
        }
    for (int i = 0; i < count; i++) {
        double length = sqrt(dot3(axes[i], axes[i]));
        if (length == 0.0) continue;
        double tmin = INFINITY, tmax = -INFINITY;
        for (int k = 0; k < 3; k++) {
            double p = dot3(v[k], axes[i]);
            tmin = fmin(tmin, p);
            tmax = fmax(tmax, p);
        }
        double centre[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
        double radius = 0.0;
        for (int a = 0; a < 3; a++) radius += 0.5 * (hi[a] - lo[a]) * fabs(axes[i][a]);
        double c = dot3(centre, axes[i]);
        double tolerance = 1e-9 * magnitude * length;
        if (!(tmax > c - radius + tolerance && tmin < c + radius - tolerance)) return false;
    }
    return true;
}

/* ---- walking the tree ------------------------------------------------ */

typedef struct tree_check {
    const rtt_kd_tree *tree;
    const rtt_scene *scene;
    uint32_t leaves, empty_leaves, nodes, deepest;
    uint64_t references;
    uint32_t missing;          /* overlapping triangles absent from a leaf */
    uint32_t degenerate_found; /* degenerate triangles present in a leaf */
    uint32_t unsorted;         /* leaf lists not strictly ascending */
    uint32_t two_empty_children;
    bool check_overlaps;       /* the slow part: every triangle against every leaf */
} tree_check;

static bool leaf_holds(const rtt_kd_tree *tree, const rtt_kd_node *leaf, uint32_t prim)
{
    for (uint32_t i = 0; i < leaf->count; i++)
        if (tree->prims[leaf->first + i] == prim) return true;
    return false;
}

static bool is_empty_leaf(const rtt_kd_tree *tree, uint32_t index)
{
    return tree->nodes[index].axis == RTT_KD_LEAF && tree->nodes[index].count == 0;
}

static rtt_bounds triangle_bounds(const rtt_vec3 tri[3])
{
    return rtt_bounds_grow(rtt_bounds_grow(rtt_bounds_grow(rtt_bounds_empty(), tri[0]), tri[1]), tri[2]);
}

/* Closed boxes share a point (a necessary condition for interior overlap). */
static bool bounds_overlap(rtt_bounds a, rtt_bounds b)
{
    for (int k = 0; k < 3; k++)
        if (rtt_v3_get(a.hi, k) < rtt_v3_get(b.lo, k) || rtt_v3_get(a.lo, k) > rtt_v3_get(b.hi, k)) return false;
    return true;
}

static void check_node(tree_check *check, uint32_t index, rtt_bounds box, uint32_t depth)
{
    const rtt_kd_tree *tree = check->tree;
    const rtt_kd_node *node = &tree->nodes[index];
    check->nodes++;
    if (depth > check->deepest) check->deepest = depth;
    if (node->axis != RTT_KD_LEAF) {
        if (is_empty_leaf(tree, node->children[0]) && is_empty_leaf(tree, node->children[1]))
            check->two_empty_children++;
        rtt_bounds lower = box, upper = box;
        rtt_v3_set(&lower.hi, (int)node->axis, node->split);
        rtt_v3_set(&upper.lo, (int)node->axis, node->split);
        check_node(check, node->children[0], lower, depth + 1);
        check_node(check, node->children[1], upper, depth + 1);
        return;
    }
    check->leaves++;
    if (node->count == 0) check->empty_leaves++;
    check->references += node->count;
    for (uint32_t i = 0; i < node->count; i++) {
        uint32_t prim = tree->prims[node->first + i];
        if (rtt_reference_triangle_is_degenerate(tree->triangles[prim])) check->degenerate_found++;
        if (i > 0 && tree->prims[node->first + i - 1] >= prim) check->unsorted++;
    }
    for (uint32_t prim = 0; check->check_overlaps && prim < check->scene->triangle_count; prim++) {
        if (!bounds_overlap(triangle_bounds(tree->triangles[prim]), box)) continue; /* quick reject */
        if (rtt_reference_triangle_is_degenerate(tree->triangles[prim])) continue;
        if (triangle_overlaps_box_interior(tree->triangles[prim], box) && !leaf_holds(tree, node, prim))
            check->missing++;
    }
}

static tree_check check_tree(const rtt_kd_tree *tree, const rtt_scene *scene, bool check_overlaps)
{
    tree_check check = {.tree = tree, .scene = scene, .check_overlaps = check_overlaps};
    check_node(&check, 0, tree->bounds, 0);
    return check;
}

static void build_or_fail(const rtt_scene *scene, const rtt_kd_build_options *opt, rtt_kd_tree *tree)
{
    rtt_error err = {{0}};
    if (!rtt_kd_reference_build(scene, opt, tree, &err)) fail_msg("build failed: %s", err.message);
}

/* ---- builder invariants ---------------------------------------------- */

static void test_leaf_holds_every_overlapping_triangle(void **state)
{
    (void)state;
    const soup_kind kinds[] = {SOUP_RANDOM, SOUP_GRID_ALIGNED, SOUP_WITH_DEGENERATE};
    for (size_t k = 0; k < 3; k++) {
        rng r = {1000 + k};
        rtt_vec3 *corners = soup_make(&r, kinds[k], 600, 1.0f, 0.0f);
        rtt_scene *scene = scene_from_soup(corners, 600);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        assert_true(tree.info.leaf_count > 20); /* the soup was actually split */
        tree_check check = check_tree(&tree, scene, true);
        assert_int_equal(check.missing, 0);
        assert_int_equal(check.unsorted, 0);
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
        free(corners);
    }
}

static void test_degenerate_triangles_never_enter_leaves(void **state)
{
    (void)state;
    rng r = {77};
    rtt_vec3 *corners = soup_make(&r, SOUP_WITH_DEGENERATE, 700, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 700);
    rtt_kd_tree tree;
    build_or_fail(scene, NULL, &tree);
    tree_check check = check_tree(&tree, scene, true);
    assert_int_equal(check.degenerate_found, 0);
    assert_true(check.references > 0);
    rtt_kd_reference_free(&tree);
    scene_destroy(scene);
    free(corners);
}

static void test_no_inner_node_has_two_empty_children(void **state)
{
    (void)state;
    for (uint64_t seed = 1; seed <= 3; seed++) {
        rng r = {seed};
        rtt_vec3 *corners = soup_make(&r, seed == 2 ? SOUP_GRID_ALIGNED : SOUP_RANDOM, 1500, 1.0f, 0.0f);
        rtt_scene *scene = scene_from_soup(corners, 1500);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        tree_check check = check_tree(&tree, scene, false);
        assert_int_equal(check.two_empty_children, 0);
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
        free(corners);
    }
}

static void test_depth_never_exceeds_max_depth(void **state)
{
    (void)state;
    rng r = {5};
    rtt_vec3 *corners = soup_make(&r, SOUP_RANDOM, 2000, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 2000);
    const uint32_t limits[] = {0, 3, 6, 200};
    for (size_t i = 0; i < 4; i++) {
        rtt_kd_build_options opt = {.max_depth = limits[i]};
        rtt_kd_tree tree;
        build_or_fail(scene, &opt, &tree);
        tree_check check = check_tree(&tree, scene, limits[i] <= 6);
        uint32_t expected_max = limits[i] == 0 ? (uint32_t)lround(2.0 + log2(2000.0))
                                : limits[i] > RTT_KD_DEPTH_LIMIT ? RTT_KD_DEPTH_LIMIT : limits[i];
        assert_int_equal(tree.info.max_depth, expected_max);
        assert_true(check.deepest <= tree.info.max_depth);
        assert_int_equal(check.deepest, tree.info.depth);
        assert_int_equal(check.missing, 0);
        rtt_kd_reference_free(&tree);
    }
    scene_destroy(scene);
    free(corners);
}

static void test_reference_cap_is_held_and_reported(void **state)
{
    (void)state;
    rng r = {9};
    rtt_vec3 *corners = soup_make(&r, SOUP_RANDOM, 800, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 800);
    rtt_kd_tree free_tree, capped_tree;
    build_or_fail(scene, NULL, &free_tree);
    assert_int_equal(free_tree.info.reference_cap, 16u * 800u + 1000000u);
    assert_true(free_tree.info.references > 800 + 100); /* duplication happens without the cap */
    rtt_kd_build_options opt = {.reference_cap = 800 + 100};
    build_or_fail(scene, &opt, &capped_tree);
    tree_check check = check_tree(&capped_tree, scene, true);
    assert_int_equal(capped_tree.info.reference_cap, 900);
    assert_true(capped_tree.info.references <= 900);
    assert_int_equal(check.missing, 0); /* the capped tree is still complete */
    rtt_kd_reference_free(&free_tree);
    rtt_kd_reference_free(&capped_tree);
    scene_destroy(scene);
    free(corners);
}

static void test_tree_info_counts_match_the_tree(void **state)
{
    (void)state;
    rng r = {11};
    rtt_vec3 *corners = soup_make(&r, SOUP_GRID_ALIGNED, 1000, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 1000);
    rtt_kd_tree tree;
    build_or_fail(scene, NULL, &tree);
    tree_check check = check_tree(&tree, scene, false);
    assert_int_equal(tree.info.node_count, check.nodes);
    assert_int_equal(tree.info.node_count, tree.node_count);
    assert_int_equal(tree.info.leaf_count, check.leaves);
    assert_int_equal(tree.info.empty_leaf_count, check.empty_leaves);
    assert_int_equal(tree.info.references, check.references);
    assert_int_equal(tree.info.depth, check.deepest);
    /* a split tree is cheaper than one leaf of every triangle */
    assert_true(tree.info.sah_cost > 0.0 && tree.info.sah_cost < RTT_KD_COST_INTERSECT * 1000);
    assert_true(tree.info.memory_bytes >= tree.node_count * sizeof(rtt_kd_node));
    assert_true(tree.info.build_seconds >= 0.0);
    rtt_kd_reference_free(&tree);
    scene_destroy(scene);
    free(corners);
}

/* Areas are taken in double, so a scene at 1e+-20 gets the tree it would
 * get at unit scale (in float its areas overflow or vanish). */
static void test_tiny_and_huge_scenes_are_split_like_unit_ones(void **state)
{
    (void)state;
    const float scales[] = {1.0f, 1e-20f, 1e20f};
    uint32_t leaves[3];
    for (int i = 0; i < 3; i++) {
        rng r = {21};
        rtt_vec3 *corners = soup_make(&r, SOUP_RANDOM, 500, scales[i], 0.0f);
        rtt_scene *scene = scene_from_soup(corners, 500);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        leaves[i] = tree.info.leaf_count;
        assert_true(isfinite(tree.info.sah_cost) && tree.info.sah_cost < RTT_KD_COST_INTERSECT * 500);
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
        free(corners);
    }
    assert_true(leaves[0] > 50);
    assert_true(leaves[1] > leaves[0] / 2 && leaves[1] < leaves[0] * 2);
    assert_true(leaves[2] > leaves[0] / 2 && leaves[2] < leaves[0] * 2);
}

static void test_empty_and_all_degenerate_scenes_build_one_empty_leaf(void **state)
{
    (void)state;
    const rtt_vec3 corners[6] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 0, 0}, {3, 0, 0}, {3, 0, 0}};
    for (uint32_t n = 0; n <= 2; n += 2) {
        rtt_scene *scene = scene_from_soup(corners, n);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        assert_int_equal(tree.node_count, 1);
        assert_int_equal(tree.info.leaf_count, 1);
        assert_int_equal(tree.info.empty_leaf_count, 1);
        rtt_ray ray = {{-1, 0.5f, 0.5f}, {1, 0, 0}, 0, INFINITY};
        rtt_hit hit;
        rtt_kd_reference_intersect(&tree, &ray, &hit);
        assert_int_equal(hit.prim, RTT_MISS);
        assert_true(isinf(hit.t));
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
    }
}

/* ---- traversal against brute force ----------------------------------- */

static rtt_hit brute_force_closest(const rtt_scene *scene, const rtt_ray *ray)
{
    rtt_hit best = {INFINITY, 0, 0, RTT_MISS};
    for (uint32_t prim = 0; prim < scene->triangle_count; prim++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, prim, tri);
        float t, u, v;
        if (rtt_reference_intersect_triangle(ray, tri, &t, &u, &v) && t < best.t) best = (rtt_hit){t, u, v, prim};
    }
    return best;
}

static bool brute_force_any(const rtt_scene *scene, const rtt_ray *ray)
{
    for (uint32_t prim = 0; prim < scene->triangle_count; prim++) {
        rtt_vec3 tri[3];
        rtt_scene_triangle(scene, prim, tri);
        float t, u, v;
        if (rtt_reference_intersect_triangle(ray, tri, &t, &u, &v)) return true;
    }
    return false;
}

/* The tolerance of the brief: t within 1e-6 relative; a different prim only
 * when brute force confirms that prim is hit at (nearly) the same t. */
static bool hits_agree(const rtt_scene *scene, const rtt_ray *ray, rtt_hit tree_hit, rtt_hit truth)
{
    if (truth.prim == RTT_MISS || tree_hit.prim == RTT_MISS) return truth.prim == tree_hit.prim;
    const float tolerance = 1e-6f * fmaxf(fabsf(truth.t), FLT_MIN);
    if (fabsf(tree_hit.t - truth.t) > tolerance) return false;
    if (tree_hit.prim == truth.prim) return true;
    rtt_vec3 tri[3];
    rtt_scene_triangle(scene, tree_hit.prim, tri);
    float t, u, v;
    return rtt_reference_intersect_triangle(ray, tri, &t, &u, &v) && fabsf(t - truth.t) <= tolerance;
}

typedef enum ray_kind {
    RAY_INSIDE,        /* origin inside the bounds, random direction */
    RAY_FAR_AWAY,      /* origin far outside, aimed at the bounds */
    RAY_AXIS_PARALLEL, /* one non-zero component, the others +0 or -0 */
    RAY_AT_VERTEX,     /* aimed exactly at a triangle corner */
    RAY_ON_SPLIT,      /* origin exactly on a split plane of the tree */
    RAY_KIND_COUNT
} ray_kind;

static rtt_vec3 random_unit(rng *r)
{
    for (;;) {
        rtt_vec3 d = rtt_v3(rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
        float len = rtt_v3_length(d);
        if (len > 0.1f && len <= 1.0f) return rtt_v3_scale(d, 1.0f / len);
    }
}

static rtt_vec3 random_point_in(rng *r, rtt_bounds b)
{
    return rtt_v3(rng_range(r, b.lo.x, b.hi.x), rng_range(r, b.lo.y, b.hi.y), rng_range(r, b.lo.z, b.hi.z));
}

/* A random inner node and its box. */
static uint32_t random_inner_node(rng *r, const rtt_kd_tree *tree, rtt_bounds *box)
{
    uint32_t index = 0;
    *box = tree->bounds;
    uint32_t chosen = UINT32_MAX;
    rtt_bounds chosen_box = *box;
    while (tree->nodes[index].axis != RTT_KD_LEAF) {
        chosen = index;
        chosen_box = *box;
        if (rng_next(r) % 3 == 0) break;
        const rtt_kd_node *node = &tree->nodes[index];
        int side = (int)(rng_next(r) & 1);
        if (side == 0) rtt_v3_set(&box->hi, (int)node->axis, node->split);
        else rtt_v3_set(&box->lo, (int)node->axis, node->split);
        index = node->children[side];
    }
    *box = chosen_box;
    return chosen;
}

static rtt_ray random_ray(rng *r, ray_kind kind, const rtt_scene *scene, const rtt_kd_tree *tree)
{
    rtt_bounds b = tree->bounds;
    rtt_vec3 extent = rtt_v3_sub(b.hi, b.lo);
    float size = fmaxf(extent.x, fmaxf(extent.y, extent.z));
    rtt_vec3 org = random_point_in(r, b), dir = random_unit(r);
    switch (kind) {
    case RAY_INSIDE:
        break;
    case RAY_FAR_AWAY:
        org = rtt_v3_madd(rtt_v3_scale(rtt_v3_add(b.lo, b.hi), 0.5f), random_unit(r), 50.0f * size);
        dir = rtt_v3_normalize(rtt_v3_sub(random_point_in(r, b), org));
        break;
    case RAY_AXIS_PARALLEL: {
        float d[3];
        for (int a = 0; a < 3; a++) d[a] = (rng_next(r) & 1) ? -0.0f : 0.0f;
        d[rng_next(r) % 3] = (rng_next(r) & 1) ? -1.0f : 1.0f;
        dir = rtt_v3(d[0], d[1], d[2]);
        if (rng_next(r) & 1) { /* put the origin on a corner's coordinates */
            rtt_vec3 corner = scene->vertices[rng_next(r) % scene->vertex_count];
            for (int a = 0; a < 3; a++)
                if (d[a] == 0.0f) rtt_v3_set(&org, a, rtt_v3_get(corner, a));
        }
        break;
    }
    case RAY_AT_VERTEX: {
        rtt_vec3 target = scene->vertices[rng_next(r) % scene->vertex_count];
        if (rng_next(r) & 1) org = rtt_v3_madd(target, random_unit(r), 3.0f * size);
        dir = rtt_v3_sub(target, org); /* not normalized: t = 1 at the vertex */
        if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) dir = random_unit(r);
        break;
    }
    case RAY_ON_SPLIT: {
        rtt_bounds box;
        uint32_t node = random_inner_node(r, tree, &box);
        if (node != UINT32_MAX) {
            org = random_point_in(r, box);
            rtt_v3_set(&org, (int)tree->nodes[node].axis, tree->nodes[node].split);
            if (rng_next(r) % 4 == 0) rtt_v3_set(&dir, (int)tree->nodes[node].axis, 0.0f); /* in the plane */
        }
        break;
    }
    default:
        break;
    }
    return (rtt_ray){{org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, 0.0f, INFINITY};
}

typedef struct comparison {
    uint32_t rays, hits, disagreements, occlusion_disagreements;
} comparison;

static comparison compare_with_brute_force(const rtt_scene *scene, const rtt_kd_tree *tree, rng *r,
                                           uint32_t rays_per_kind)
{
    comparison result = {0};
    for (int kind = 0; kind < RAY_KIND_COUNT; kind++) {
        for (uint32_t i = 0; i < rays_per_kind; i++) {
            rtt_ray ray = random_ray(r, (ray_kind)kind, scene, tree);
            if (i % 5 == 4) ray.tfar = rng_range(r, 0.0f, 2.0f) * rtt_v3_length(rtt_v3_sub(tree->bounds.hi,
                                                                                          tree->bounds.lo));
            rtt_hit truth = brute_force_closest(scene, &ray), hit;
            rtt_kd_reference_intersect(tree, &ray, &hit);
            result.rays++;
            if (truth.prim != RTT_MISS) result.hits++;
            if (!hits_agree(scene, &ray, hit, truth)) result.disagreements++;
            if (rtt_kd_reference_occluded(tree, &ray) != brute_force_any(scene, &ray))
                result.occlusion_disagreements++;
        }
    }
    return result;
}

static void test_closest_hit_matches_brute_force_on_random_soups(void **state)
{
    (void)state;
    const struct { soup_kind kind; float scale, offset; } cases[] = {
        {SOUP_RANDOM, 1.0f, 0.0f},          {SOUP_GRID_ALIGNED, 1.0f, 0.0f},
        {SOUP_WITH_DEGENERATE, 1.0f, -0.5f}, {SOUP_RANDOM, 1e-20f, 0.0f},
        {SOUP_RANDOM, 1e20f, 0.0f},          {SOUP_GRID_ALIGNED, 1e-3f, 0.0f},
        {SOUP_RANDOM, 1.0f, 1e4f},          {SOUP_GRID_ALIGNED, 4.0f, -1e5f},
        {SOUP_FLAT, 1.0f, 0.0f},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rng r = {200 + c};
        rtt_vec3 *corners = soup_make(&r, cases[c].kind, 400, cases[c].scale, cases[c].offset);
        rtt_scene *scene = scene_from_soup(corners, 400);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        comparison result = compare_with_brute_force(scene, &tree, &r, 600);
        if (result.disagreements || result.occlusion_disagreements)
            fail_msg("case %zu: %u closest-hit and %u occlusion disagreements in %u rays", c,
                     result.disagreements, result.occlusion_disagreements, result.rays);
        assert_true(result.hits > result.rays / 10); /* the rays did find geometry */
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
        free(corners);
    }
}

static void test_occlusion_respects_the_open_interval(void **state)
{
    (void)state;
    const rtt_vec3 corners[3] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    rtt_scene *scene = scene_from_soup(corners, 1);
    rtt_kd_tree tree;
    build_or_fail(scene, NULL, &tree);
    rtt_ray ray = {{0.25f, 0.25f, 0.0f}, {0, 0, 1}, 0.0f, 1.0f}; /* ends exactly on the triangle */
    assert_false(rtt_kd_reference_occluded(&tree, &ray));
    ray.tfar = nextafterf(1.0f, 2.0f);
    assert_true(rtt_kd_reference_occluded(&tree, &ray));
    ray.tnear = 1.0f; /* starts exactly on it */
    assert_false(rtt_kd_reference_occluded(&tree, &ray));
    rtt_kd_reference_free(&tree);
    scene_destroy(scene);
}

static void test_nan_and_infinite_rays_miss(void **state)
{
    (void)state;
    rng r = {3};
    rtt_vec3 *corners = soup_make(&r, SOUP_RANDOM, 200, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 200);
    rtt_kd_tree tree;
    build_or_fail(scene, NULL, &tree);
    const rtt_ray bad[] = {
        {{NAN, 0.5f, 0.5f}, {1, 0, 0}, 0, INFINITY},      {{0.5f, 0.5f, 0.5f}, {NAN, 0, 1}, 0, INFINITY},
        {{0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, INFINITY},     {{INFINITY, 0.5f, 0.5f}, {-1, 0, 0}, 0, INFINITY},
        {{0.5f, 0.5f, 0.5f}, {INFINITY, 1, 0}, 0, INFINITY}, {{0.5f, 0.5f, 0.5f}, {1, 0, 0}, NAN, INFINITY},
        {{0.5f, 0.5f, 0.5f}, {1, 1, 1}, 0, NAN},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        rtt_hit hit;
        rtt_kd_reference_intersect(&tree, &bad[i], &hit);
        assert_int_equal(hit.prim, RTT_MISS);
        assert_true(isinf(hit.t) && hit.t > 0);
        assert_false(rtt_kd_reference_occluded(&tree, &bad[i]));
    }
    rtt_kd_reference_free(&tree);
    scene_destroy(scene);
    free(corners);
}

/* ---- watertightness -------------------------------------------------- */

/* A closed UV sphere with shared vertices (poles are single vertices). */
static rtt_scene *sphere_make(rtt_vec3 centre, float radius, uint32_t rings, uint32_t segments)
{
    uint32_t vertex_count = 2 + (rings - 1) * segments;
    uint32_t triangle_count = 2 * segments * (rings - 1);
    rtt_vec3 *vertices = malloc(vertex_count * sizeof *vertices);
    uint32_t *indices = malloc(3 * triangle_count * sizeof *indices);
    assert_non_null(vertices);
    assert_non_null(indices);
    vertices[0] = rtt_v3(centre.x, centre.y, centre.z + radius);
    vertices[1] = rtt_v3(centre.x, centre.y, centre.z - radius);
    for (uint32_t i = 1; i < rings; i++) {
        double theta = M_PI * i / rings;
        for (uint32_t j = 0; j < segments; j++) {
            double phi = 2.0 * M_PI * j / segments;
            vertices[2 + (i - 1) * segments + j] =
                rtt_v3(centre.x + (float)(radius * sin(theta) * cos(phi)),
                       centre.y + (float)(radius * sin(theta) * sin(phi)), centre.z + (float)(radius * cos(theta)));
        }
    }
#define RING_VERTEX(i, j) (2 + ((i) - 1) * segments + ((j) % segments))
    uint32_t t = 0;
    for (uint32_t j = 0; j < segments; j++) {
        uint32_t top[3] = {0, RING_VERTEX(1, j), RING_VERTEX(1, j + 1)};
        uint32_t bottom[3] = {1, RING_VERTEX(rings - 1, j + 1), RING_VERTEX(rings - 1, j)};
        memcpy(&indices[3 * t++], top, sizeof top);
        memcpy(&indices[3 * t++], bottom, sizeof bottom);
    }
    for (uint32_t i = 1; i + 1 < rings; i++)
        for (uint32_t j = 0; j < segments; j++) {
            uint32_t a = RING_VERTEX(i, j), b = RING_VERTEX(i, j + 1), c = RING_VERTEX(i + 1, j),
                     d = RING_VERTEX(i + 1, j + 1);
            uint32_t first[3] = {a, c, d}, second[3] = {a, d, b};
            memcpy(&indices[3 * t++], first, sizeof first);
            memcpy(&indices[3 * t++], second, sizeof second);
        }
#undef RING_VERTEX
    assert_int_equal(t, triangle_count);
    rtt_scene *scene = scene_make(vertices, vertex_count, indices, triangle_count);
    free(vertices);
    free(indices);
    return scene;
}

/* Rays from inside aimed exactly at every vertex and every edge midpoint must
 * hit the sphere: zero escapes (docs/ARCHITECTURE.md, Conformance). */
static void test_rays_from_inside_a_closed_sphere_never_escape(void **state)
{
    (void)state;
    const struct { rtt_vec3 centre; float radius; } spheres[] = {
        {{0, 0, 0}, 1.0f}, {{3e-19f, -2e-19f, 1e-19f}, 1e-18f}, {{1e4f, -2e4f, 3e3f}, 7.0f}, {{0, 0, 0}, 1e18f},
    };
    for (size_t s = 0; s < sizeof spheres / sizeof spheres[0]; s++) {
        rtt_scene *scene = sphere_make(spheres[s].centre, spheres[s].radius, 16, 29);
        rtt_kd_tree tree;
        build_or_fail(scene, NULL, &tree);
        rng r = {40 + s};
        uint32_t escapes = 0, rays = 0;
        for (int o = 0; o < 4; o++) {
            rtt_vec3 org = o == 0 ? spheres[s].centre
                                  : rtt_v3_madd(spheres[s].centre, random_unit(&r), 0.6f * spheres[s].radius);
            for (uint32_t prim = 0; prim < scene->triangle_count; prim++) {
                rtt_vec3 tri[3];
                rtt_scene_triangle(scene, prim, tri);
                for (int k = 0; k < 3; k++) {
                    rtt_vec3 targets[2] = {tri[k], rtt_v3_scale(rtt_v3_add(tri[k], tri[(k + 1) % 3]), 0.5f)};
                    for (int g = 0; g < 2; g++) {
                        rtt_vec3 dir = rtt_v3_sub(targets[g], org);
                        rtt_ray ray = {{org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, 0.0f, INFINITY};
                        rtt_hit hit;
                        rtt_kd_reference_intersect(&tree, &ray, &hit);
                        rays++;
                        if (hit.prim == RTT_MISS || !rtt_kd_reference_occluded(&tree, &ray)) escapes++;
                    }
                }
            }
        }
        if (escapes) fail_msg("sphere %zu: %u of %u rays escaped", s, escapes, rays);
        rtt_kd_reference_free(&tree);
        scene_destroy(scene);
    }
}

/* ---- the engine interface -------------------------------------------- */

static void test_engine_traces_streams_and_reports_its_tree(void **state)
{
    (void)state;
    rng r = {17};
    rtt_vec3 *corners = soup_make(&r, SOUP_RANDOM, 300, 1.0f, 0.0f);
    rtt_scene *scene = scene_from_soup(corners, 300);
    rtt_error err = {{0}};
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.max_tree_depth = 7;
    rtt_engine *engine = rtt_reference_engine_create(scene, &opt, &err);
    assert_non_null(engine);
    assert_ptr_equal(engine->scene, scene);
    assert_string_equal(engine->vt->name, "reference");
    rtt_tree_info info;
    assert_true(rtt_engine_tree_info(engine, &info));
    assert_int_equal(info.max_depth, 7);
    assert_true(info.depth <= 7 && info.leaf_count > 1);

    enum { N = 64 };
    rtt_ray rays[N];
    rtt_hit hits[N];
    uint8_t occluded[N];
    for (int i = 0; i < N; i++) {
        rtt_vec3 org = rtt_v3(rng_float(&r), rng_float(&r), -1.0f);
        rays[i] = (rtt_ray){{org.x, org.y, org.z}, {0, 0, i == 0 ? -1.0f : 1.0f}, 0.0f, INFINITY};
    }
    rtt_engine_intersect(engine, rays, hits, N);
    rtt_engine_occluded(engine, rays, occluded, N);
    assert_int_equal(hits[0].prim, RTT_MISS); /* pointing away from everything */
    assert_true(isinf(hits[0].t));
    for (int i = 0; i < N; i++) {
        rtt_hit truth = brute_force_closest(scene, &rays[i]);
        assert_int_equal(hits[i].prim, truth.prim);
        assert_int_equal(occluded[i], truth.prim != RTT_MISS);
    }
    rtt_engine_destroy(engine);
    scene_destroy(scene);
    free(corners);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_leaf_holds_every_overlapping_triangle),
        cmocka_unit_test(test_degenerate_triangles_never_enter_leaves),
        cmocka_unit_test(test_no_inner_node_has_two_empty_children),
        cmocka_unit_test(test_depth_never_exceeds_max_depth),
        cmocka_unit_test(test_reference_cap_is_held_and_reported),
        cmocka_unit_test(test_tree_info_counts_match_the_tree),
        cmocka_unit_test(test_tiny_and_huge_scenes_are_split_like_unit_ones),
        cmocka_unit_test(test_empty_and_all_degenerate_scenes_build_one_empty_leaf),
        cmocka_unit_test(test_closest_hit_matches_brute_force_on_random_soups),
        cmocka_unit_test(test_occlusion_respects_the_open_interval),
        cmocka_unit_test(test_nan_and_infinite_rays_miss),
        cmocka_unit_test(test_rays_from_inside_a_closed_sphere_never_escape),
        cmocka_unit_test(test_engine_traces_streams_and_reports_its_tree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

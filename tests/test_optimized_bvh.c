/* The BVH of the optimized engine (optimized/bvh/): the binned SAH
 * builder's invariants for a sweep of leaf sizes and depth bounds, the same
 * tree for one thread and two, and every BVH kernel at every instruction
 * set this CPU runs under both triangle tests (the default, watertight, and
 * --isect projected) against two oracles: a brute force over every triangle
 * record with the scalar form of the same test (the traversal must lose no
 * hit: equal t, u, v and prim, bit for bit), and the reference engine --
 * under the watertight test bit for bit (the same arithmetic), under the
 * projected test within the conformance tolerance (a hit/miss at an edge of
 * the hit triangle counted apart, as that test is not watertight).  And
 * bvh-mft's primary rays made from the camera frame, per pixel against the
 * brute force and the reference, for three cameras and two block tilings,
 * and its back-face culling on solids (ties only, none where the eye is
 * inside a solid's box).
 * And watertightness: from inside a closed mesh, rays aimed at its corners and
 * edges escape through no BVH kernel (closest hit, occlusion, hard-shadow
 * apex frusta, soft-shadow frusta:N) under the watertight test. */
#include <float.h>
#include <stdio.h>
#include <xmmintrin.h>

#include "bvh_build.h"
#include "test_fixtures_bvh.h"
#include "test_double_crossing.h"
#include "test_scenes_solids.h"
#include "test_tempdir.h"

/* ---- the builder ------------------------------------------------------- */

typedef struct walk {
    const rtt_scene *scene;
    const bvh_tree *tree;
    uint32_t leaf_size, max_depth;
    uint8_t *seen;      /* per prim */
    uint32_t depth, leaves, records, nodes;
} walk;

static void expect_box_holds(const bvh_child *c, const rtt_vec3 p[3])
{
    for (int v = 0; v < 3; v++)
        for (int a = 0; a < 3; a++) {
            assert_true(c->lo[a] <= rtt_v3_get(p[v], a));
            assert_true(c->hi[a] >= rtt_v3_get(p[v], a));
        }
}

/* Every record below `c` lies in c's box; returns nothing, counts into w. */
static void walk_child(walk *w, const bvh_child *c, uint32_t depth, const bvh_child *const *up, uint32_t up_count)
{
    const bvh_child *chain[BVH_TRAVERSAL_STACK + 1];
    if (up_count) memcpy(chain, up, up_count * sizeof *up);
    chain[up_count] = c;
    if (c->count > 0) {
        assert_true(c->count <= w->leaf_size || depth == w->max_depth);
        assert_true(depth <= w->max_depth);
        assert_true(c->index + c->count <= w->tree->triangle_count);
        for (uint32_t i = 0; i < c->count; i++) {
            const kd_triangle *rec = &w->tree->triangles[c->index + i];
            assert_true(rec->prim < w->scene->triangle_count);
            assert_int_equal(w->seen[rec->prim], 0);
            w->seen[rec->prim] = 1;
            rtt_vec3 p[3];
            rtt_scene_triangle(w->scene, rec->prim, p);
            for (uint32_t k = 0; k <= up_count; k++) expect_box_holds(chain[k], p);
        }
        w->depth = depth > w->depth ? depth : w->depth;
        w->leaves++;
        w->records += c->count;
        return;
    }
    assert_true(c->index < w->tree->node_count);
    w->nodes++;
    for (int k = 0; k < 2; k++) walk_child(w, &w->tree->nodes[c->index].child[k], depth + 1, chain, up_count + 1);
}

static rtt_scene *soup_with_specials(uint32_t count, float size, uint64_t seed)
{
    rng r = {seed};
    float *xyz = malloc((size_t)count * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t i = 0; i < count; i++) {
        float c[3] = {rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1)};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) xyz[9 * i + 3 * v + a] = c[a] + rng_range(&r, -size, size);
        if (i % 7 == 3) /* flat on an axis: boxes of zero thickness */
            for (int v = 0; v < 3; v++) xyz[9 * i + 3 * v + i % 3] = 0.25f;
        if (i % 11 == 5) memcpy(&xyz[9 * i + 6], &xyz[9 * i + 3], 3 * sizeof(float)); /* degenerate */
        if (i % 13 == 6) memcpy(&xyz[9 * i], &xyz[9 * (i - 1)], 9 * sizeof(float));   /* duplicate */
    }
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, count, &err);
    free(xyz);
    if (!scene) fail_msg("scene: %s", err.message);
    return scene;
}

static void build_split(const rtt_scene *scene, uint32_t leaf_size, uint32_t max_depth, uint32_t threads,
                        float split_share, bvh_tree *tree)
{
    bvh_build_options opt = {.leaf_size = leaf_size, .max_depth = max_depth, .threads = threads, .split_share = split_share};
    rtt_error err = {{0}};
    if (!bvh_build_sah(scene, &opt, tree, &err)) fail_msg("build: %s", err.message);
}

/* The default build (pre-splitting on; the soups below have no triangle it cuts). */
static void build(const rtt_scene *scene, uint32_t leaf_size, uint32_t max_depth, uint32_t threads, bvh_tree *tree)
{
    bvh_build_options opt = {.leaf_size = leaf_size, .max_depth = max_depth, .threads = threads};
    rtt_error err = {{0}};
    if (!bvh_build_sah(scene, &opt, tree, &err)) fail_msg("build: %s", err.message);
}

static void test_builder_invariants_for_leaf_sizes_and_depths(void **state)
{
    (void)state;
    rtt_scene *scene = soup_with_specials(3000, 0.05f, 41);
    const uint32_t leaf_sizes[] = {1, 2, 4, 8, 16};
    const uint32_t depths[] = {0, 3, 8, 64};
    for (size_t l = 0; l < sizeof leaf_sizes / sizeof leaf_sizes[0]; l++)
        for (size_t d = 0; d < sizeof depths / sizeof depths[0]; d++) {
            bvh_tree tree;
            build_split(scene, leaf_sizes[l], depths[d], 2, -1.0f, &tree); /* one reference per triangle */
            walk w = {.scene = scene, .tree = &tree, .leaf_size = leaf_sizes[l],
                      .max_depth = depths[d] ? depths[d] : BVH_DEPTH_LIMIT};
            w.seen = calloc(scene->triangle_count, 1);
            assert_non_null(w.seen);
            walk_child(&w, &tree.root, 0, NULL, 0);
            /* every triangle with a record is in exactly one leaf; degenerates in none */
            for (uint32_t p = 0; p < scene->triangle_count; p++) {
                rtt_vec3 v[3];
                rtt_scene_triangle(scene, p, v);
                kd_triangle rec;
                assert_int_equal(w.seen[p], kd_triangle_record(&rec, v, p) ? 1 : 0);
            }
            assert_int_equal(w.records, tree.triangle_count);
            assert_int_equal(w.nodes, tree.node_count);
            assert_int_equal(w.leaves, tree.info.leaf_count);
            assert_int_equal(w.depth, tree.info.depth);
            assert_true(tree.info.depth <= w.max_depth);
            assert_true(tree.info.sah_cost > 0.0);
            free(w.seen);
            bvh_tree_free(&tree);
        }
    rtt_scene_free(scene);
}

/* Pre-splitting (bvh_build.c): a soup of small triangles with a few that
 * span the scene.  Per leaf, every record's prim is a triangle with a
 * record; each triangle is in one leaf at least, and only the big ones in
 * more; the references stay within the cap; and every point of every
 * triangle (a grid of barycentric points in double, the corners among
 * them) lies in the boxes of some leaf holding its record and of all that
 * leaf's ancestors, so a ray meeting the triangle anywhere reaches a leaf
 * that tests it.  The same at one and two threads, byte for byte. */
typedef struct split_walk {
    const rtt_scene *scene;
    const bvh_tree *tree;
    uint32_t *leaves_of;   /* per prim: leaves holding it */
    uint8_t *covered;      /* per prim and sample point */
    uint32_t records;
} split_walk;

enum { SPLIT_GRID = 8, SPLIT_POINTS = (SPLIT_GRID + 1) * (SPLIT_GRID + 2) / 2 };

/* The grid's points of triangle `prim`, in double. */
static void split_points(const rtt_scene *scene, uint32_t prim, double q[SPLIT_POINTS][3])
{
    rtt_vec3 v[3];
    rtt_scene_triangle(scene, prim, v);
    int k = 0;
    for (int i = 0; i <= SPLIT_GRID; i++)
        for (int j = 0; j <= SPLIT_GRID - i; j++, k++) {
            const double a = (double)i / SPLIT_GRID, b = (double)j / SPLIT_GRID, c = 1.0 - a - b;
            for (int x = 0; x < 3; x++)
                q[k][x] = c * rtt_v3_get(v[0], x) + a * rtt_v3_get(v[1], x) + b * rtt_v3_get(v[2], x);
        }
}

static bool box_holds_point(const bvh_child *c, const double q[3])
{
    for (int x = 0; x < 3; x++)
        if (!(c->lo[x] <= q[x] && q[x] <= c->hi[x])) return false;
    return true;
}

static void split_walk_child(split_walk *w, const bvh_child *c, const bvh_child **chain, uint32_t depth)
{
    chain[depth] = c;
    if (c->count == 0) {
        for (int k = 0; k < 2; k++) split_walk_child(w, &w->tree->nodes[c->index].child[k], chain, depth + 1);
        return;
    }
    assert_true(c->index + c->count <= w->tree->triangle_count);
    for (uint32_t i = 0; i < c->count; i++) {
        const uint32_t prim = w->tree->triangles[c->index + i].prim;
        assert_true(prim < w->scene->triangle_count);
        assert_int_equal(w->tree->corners[c->index + i].prim, prim);
        w->leaves_of[prim]++;
        w->records++;
        double q[SPLIT_POINTS][3];
        split_points(w->scene, prim, q);
        for (int k = 0; k < SPLIT_POINTS; k++) {
            bool inside = true;
            for (uint32_t d = 0; d <= depth && inside; d++) inside = box_holds_point(chain[d], q[k]);
            if (inside) w->covered[(size_t)prim * SPLIT_POINTS + k] = 1;
        }
    }
}

static void test_pre_split_triangles_are_covered_by_their_leaves(void **state)
{
    (void)state;
    rtt_scene *small = soup_with_specials(4000, 0.02f, 53);
    /* the soup's triangles and 24 big ones across the box, some slanted */
    const uint32_t big = 24, n = small->triangle_count + big;
    float *xyz = malloc((size_t)n * 9 * sizeof *xyz);
    assert_non_null(xyz);
    for (uint32_t t = 0; t < small->triangle_count; t++) {
        rtt_vec3 v[3];
        rtt_scene_triangle(small, t, v);
        for (int c = 0; c < 3; c++)
            for (int x = 0; x < 3; x++) xyz[9 * t + 3 * c + x] = rtt_v3_get(v[c], x);
    }
    rng r = {59};
    for (uint32_t t = small->triangle_count; t < n; t++)
        for (int c = 0; c < 9; c++) xyz[9 * t + c] = rng_range(&r, -1.2f, 1.2f);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, n, &err);
    free(xyz);
    assert_non_null(scene);
    const float shares[] = {0.0f, 0.02f, 1.0f};
    for (size_t s = 0; s < sizeof shares / sizeof shares[0]; s++) {
        bvh_tree tree, two;
        build_split(scene, 4, 0, 1, shares[s], &tree);
        build_split(scene, 4, 0, 2, shares[s], &two);
        assert_int_equal(tree.triangle_count, two.triangle_count);
        assert_memory_equal(tree.nodes, two.nodes, tree.node_count * sizeof *tree.nodes);
        assert_memory_equal(tree.corners, two.corners, tree.triangle_count * sizeof *tree.corners);
        bvh_tree_free(&two);
        split_walk w = {.scene = scene, .tree = &tree};
        w.leaves_of = calloc(scene->triangle_count, sizeof *w.leaves_of);
        w.covered = calloc((size_t)scene->triangle_count * SPLIT_POINTS, 1);
        assert_non_null(w.leaves_of);
        assert_non_null(w.covered);
        const bvh_child *chain[BVH_TRAVERSAL_STACK + 1];
        split_walk_child(&w, &tree.root, chain, 0);
        assert_int_equal(w.records, tree.triangle_count);
        uint32_t with_record = 0, split = 0;
        for (uint32_t p = 0; p < scene->triangle_count; p++) {
            rtt_vec3 v[3];
            rtt_scene_triangle(scene, p, v);
            kd_triangle rec;
            if (!kd_triangle_record(&rec, v, p)) {
                assert_int_equal(w.leaves_of[p], 0);
                continue;
            }
            with_record++;
            if (w.leaves_of[p] == 0) fail_msg("share %g: triangle %u is in no leaf", shares[s], p);
            if (w.leaves_of[p] > 1) {
                split++;
                if (p < small->triangle_count) fail_msg("share %g: small triangle %u was cut", shares[s], p);
            }
            for (int k = 0; k < SPLIT_POINTS; k++)
                if (!w.covered[(size_t)p * SPLIT_POINTS + k])
                    fail_msg("share %g: point %d of triangle %u is in no leaf holding it", shares[s], k, p);
        }
        assert_true(tree.info.references == tree.triangle_count);
        assert_true(tree.info.references <= tree.info.reference_cap);
        assert_true(split > 0); /* the big ones were cut at every share tried */
        assert_true(tree.triangle_count > with_record);
        free(w.leaves_of);
        free(w.covered);
        bvh_tree_free(&tree);
    }
    rtt_scene_free(small);
    rtt_scene_free(scene);
}

/* The builder computes on no denormal: the record index it keeps in a
 * reference's fourth lane is one as a float, and Intel cores take a
 * microcode assist for each denormal operand (the build ran 3.5x slower on
 * a Xeon than on an EPYC).  The MXCSR's denormal-operand flag (DE) is
 * sticky: clear before the build (one thread: all on this one), clear
 * after.  The soup's coordinates are normal floats. */
static void test_build_takes_no_denormal_operand(void **state)
{
    (void)state;
    rtt_scene *scene = soup_with_specials(20000, 0.03f, 47);
    const unsigned int flags = 0x3f, denormal_operand = 0x2;
    const unsigned int saved = _mm_getcsr();
    _mm_setcsr(saved & ~flags);
    bvh_tree tree;
    build(scene, 4, 0, 1, &tree);
    const unsigned int after = _mm_getcsr();
    _mm_setcsr(saved);
    assert_true(tree.triangle_count > 0);
    if (after & denormal_operand) fail_msg("the BVH build took a denormal operand (MXCSR %#x)", after);
    bvh_tree_free(&tree);
    rtt_scene_free(scene);
}

static void test_one_and_two_threads_build_the_same_bytes(void **state)
{
    (void)state;
    rtt_scene *scene = soup_with_specials(40000, 0.03f, 43);
    bvh_tree one, two;
    build(scene, 4, 0, 1, &one);
    build(scene, 4, 0, 2, &two);
    assert_int_equal(one.node_count, two.node_count);
    assert_int_equal(one.triangle_count, two.triangle_count);
    assert_memory_equal(&one.root, &two.root, sizeof one.root);
    assert_memory_equal(one.nodes, two.nodes, one.node_count * sizeof *one.nodes);
    assert_memory_equal(one.triangles, two.triangles, one.triangle_count * sizeof *one.triangles);
    assert_memory_equal(one.corners, two.corners, one.triangle_count * sizeof *one.corners);
    bvh_tree_free(&one);
    bvh_tree_free(&two);
    rtt_scene_free(scene);
}

static void test_degenerate_only_and_empty_scenes_build_and_miss(void **state)
{
    (void)state;
    const float xyz[18] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 0, 0, 3, 0, 0, 3, 0, 0};
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, 2, &err);
    assert_non_null(scene);
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.accel = RTT_ACCEL_BVH;
    rtt_engine *e = rtt_optimized_engine_create(scene, &opt, &err);
    assert_non_null(e);
    assert_int_equal(bvh_engine_tree(e)->triangle_count, 0);
    rtt_ray ray = {{-1, 0, 0}, {1, 0, 0}, 0, INFINITY};
    rtt_hit hit;
    uint8_t occ = 1;
    rtt_engine_intersect(e, &ray, &hit, 1);
    rtt_engine_occluded(e, &ray, &occ, 1);
    assert_int_equal(hit.prim, RTT_MISS);
    assert_int_equal(occ, 0);
    rtt_engine_destroy(e);
    rtt_scene_free(scene);
}

/* ---- the kernels ------------------------------------------------------- */

static int setup_bvh(void **state) { return setup_bvh_seeded(state, 0x9e3779b97f4a7c15ull); }

/* Against the reference: both miss, or the same t within tolerance (a
 * different prim only as a tie); a hit within tolerance of tnear or tfar,
 * and a miss next to an edge (the projected test is not watertight), are
 * counted apart. */
static uint32_t reference_disagreements(const fixture *f, const rtt_ray *rays, const rtt_hit *got, uint32_t n,
                                        uint32_t *edge)
{
    rtt_hit *want = malloc(n * sizeof *want);
    assert_non_null(want);
    rtt_engine_intersect(f->reference, rays, want, n);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < n; i++) {
        const int gh = got[i].prim != RTT_MISS, wh = want[i].prim != RTT_MISS;
        if (!gh && !wh) continue;
        if (gh != wh) {
            if (near_interval_end(&rays[i], gh ? got[i].t : want[i].t)) continue;
            const rtt_hit *h = wh ? &want[i] : &got[i];
            if (h->u < 1e-4f || h->v < 1e-4f || h->u + h->v > 1.0f - 1e-4f) {
                (*edge)++;
                continue;
            }
            if (bad++ < 5) print_message("ray %u: prim %u t %.9g, reference prim %u t %.9g\n", i, got[i].prim, got[i].t, want[i].prim, want[i].t);
            continue;
        }
        if (fabsf(got[i].t - want[i].t) > t_tolerance(want[i].t)) {
            if (bad < 5) print_message("ray %u: prim %u t %.9g, reference prim %u t %.9g u %g v %g\n", i, got[i].prim, got[i].t, want[i].prim, want[i].t, want[i].u, want[i].v);
            bad += !near_interval_end(&rays[i], got[i].t) && !near_interval_end(&rays[i], want[i].t);
            continue;
        }
        if (got[i].prim != want[i].prim)
            bad += !(prim_hit_at(f, &rays[i], got[i].prim, want[i].t) &&
                     prim_hit_at(f, &rays[i], want[i].prim, got[i].t));
    }
    free(want);
    return bad;
}

/* Rays the reference answers otherwise, to the bit (the watertight test). */
static uint32_t reference_bit_differences(const fixture *f, const rtt_ray *rays, const rtt_hit *got,
                                          const uint8_t *occ, uint32_t n)
{
    rtt_hit *want = malloc(n * sizeof *want);
    uint8_t *want_occ = malloc(n);
    assert_non_null(want), assert_non_null(want_occ);
    rtt_engine_intersect(f->reference, rays, want, n);
    rtt_engine_occluded(f->reference, rays, want_occ, n);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (memcmp(&got[i], &want[i], sizeof got[i]) == 0 && occ[i] == want_occ[i]) continue;
        if (bad++ < 5)
            print_message("ray %u: prim %u t %a u %a v %a occ %d, reference prim %u t %a u %a v %a occ %d\n", i,
                          got[i].prim, (double)got[i].t, (double)got[i].u, (double)got[i].v, occ[i], want[i].prim,
                          (double)want[i].t, (double)want[i].u, (double)want[i].v, want_occ[i]);
    }
    free(want), free(want_occ);
    return bad;
}

static void check_every_kernel_on(const bvh_fixture *f, const bvh_tree *tree, const rtt_ray *rays, uint32_t n)
{
    rtt_hit *want = malloc(n * sizeof *want), *got = malloc(n * sizeof *got);
    uint8_t *occ = malloc(n);
    assert_non_null(want), assert_non_null(got), assert_non_null(occ);
    for (uint32_t i = 0; i < n; i++) want[i] = bvh_records_closest(tree, &rays[i]);
    const bvh_kernel *row;
    for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
        if (!isa_runs(row->isa)) continue;
        bvh_counters counters = {0};
        row->trace(tree, &(bvh_query){.rays = rays, .count = n, .hits = got, .counters = &counters});
        row->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = occ});
        uint32_t lost = 0, occ_bad = 0, edge = 0;
        for (uint32_t i = 0; i < n; i++) {
            if (memcmp(&got[i], &want[i], sizeof got[i]) != 0) {
                if (lost++ < 5)
                    print_message("%s/%s ray %u: prim %u t %.9g, brute force prim %u t %.9g\n", row->name,
                                  rtt_isa_name(row->isa), i, got[i].prim, got[i].t, want[i].prim, want[i].t);
            }
            occ_bad += occ[i] != (want[i].prim != RTT_MISS);
        }
        const uint32_t bad = reference_disagreements(&f->base, rays, got, n, &edge);
        const uint32_t bits = tree->watertight ? reference_bit_differences(&f->base, rays, got, occ, n) : 0;
        print_message("%-11s %-7s %-10s %u rays: %u lost against the records, %u occluded wrong, %u off the "
                      "reference (%u not its bits), %u edge escapes, %.1f AABB tests per packet\n",
                      row->name, rtt_isa_name(row->isa), bvh_tree_test_name(tree), n, lost, occ_bad, bad, bits, edge,
                      (double)counters.aabb_tests / (double)(counters.packets ? counters.packets : 1));
        assert_int_equal(lost, 0);
        assert_int_equal(occ_bad, 0);
        assert_int_equal(bad, 0);
        assert_int_equal(bits, 0);
        assert_true(edge <= (tree->watertight ? 0 : n / 1000 + 1));
    }
    free(want), free(got), free(occ);
}

/* Every kernel at every ISA under both triangle tests. */
static void check_every_kernel(const bvh_fixture *f, const rtt_ray *rays, uint32_t n)
{
    for (uint32_t t = 0; t < BVH_FIXTURE_TESTS; t++) check_every_kernel_on(f, f->trees[t], rays, n);
}

static void test_kernels_on_primary_rays(void **state)
{
    const bvh_fixture *f = *state;
    uint32_t n;
    /* wide, narrow, and a camera whose rays cross the axis planes */
    rtt_ray *rays = primary_rays(64, 8, rtt_v3(0.3f, 0.4f, 3.0f), 0.6f, &n);
    check_every_kernel(f, rays, n);
    free(rays);
    rays = primary_rays(32, 8, rtt_v3(2.5f, 1.5f, -2.0f), 0.05f, &n);
    check_every_kernel(f, rays, n);
    free(rays);
    rays = primary_rays(32, 8, rtt_v3(0.0f, 0.0f, 2.5f), 2.0f, &n);
    check_every_kernel(f, rays, n);
    free(rays);
}

/* bvh-mft's rays made from the camera frame (bvh_camera_block): per pixel
 * the brute force's hit on rtt_camera_ray's ray, bit for bit, and under
 * the watertight test the reference's bits, at every ISA; images whose
 * sides are no multiple of the group's, and blocks that start off the
 * group grid. */
static void check_camera_kernel(const bvh_fixture *f, const bvh_tree *tree, const rtt_camera *camera, uint32_t w,
                                uint32_t h)
{
    const rtt_camera_frame frame = rtt_camera_frame_make(camera, w, h);
    const size_t n = (size_t)w * h;
    rtt_ray *rays = malloc(n * sizeof *rays);
    rtt_hit *want = malloc(n * sizeof *want), *got = malloc(n * sizeof *got);
    uint8_t *occ = malloc(n);
    assert_true(rays && want && got && occ);
    uint32_t hit = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            rays[(size_t)y * w + x] = rtt_camera_ray(&frame, x, y);
            want[(size_t)y * w + x] = bvh_records_closest(tree, &rays[(size_t)y * w + x]);
            hit += want[(size_t)y * w + x].prim != RTT_MISS;
        }
    assert_true(hit > 0 && hit < n); /* both answers are checked */
    bvh_camera_block block = {{frame.eye.x, frame.eye.y, frame.eye.z}, {frame.corner.x, frame.corner.y, frame.corner.z},
                              {frame.du.x, frame.du.y, frame.du.z}, {frame.dv.x, frame.dv.y, frame.dv.z}, 0, 0, 0, 0, false};
    const bvh_kernel *row;
    for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
        if (!row->trace_camera) {
            assert_string_not_equal(row->name, "bvh-mft");
            continue;
        }
        if (!isa_runs(row->isa)) continue;
        /* the whole image in 16 x 16 blocks, then in 13 x 7 blocks from (3,
         * 5); each with the hits stored and streamed (past the caches where
         * a block's rows start on 64-byte lines: the 16-wide blocks) */
        for (int pass = 0; pass < 4; pass++) {
            const bool cut = pass & 1;
            const uint32_t bw = cut ? 13 : 16, bh = cut ? 7 : 16, sx = cut ? 3 : 0, sy = cut ? 5 : 0;
            block.stream = pass >= 2;
            memset(got, 0xab, n * sizeof *got);
            for (uint32_t y0 = 0; y0 < h; y0 += y0 ? bh : (sy ? sy : bh))
                for (uint32_t x0 = 0; x0 < w; x0 += x0 ? bw : (sx ? sx : bw)) {
                    const uint32_t x1 = x0 ? x0 + bw : (sx ? sx : bw), y1 = y0 ? y0 + bh : (sy ? sy : bh);
                    block.x0 = x0, block.y0 = y0, block.x1 = x1 < w ? x1 : w, block.y1 = y1 < h ? y1 : h;
                    _Alignas(64) rtt_hit part[16 * 16];
                    bvh_counters counters = {0};
                    row->trace_camera(tree, &block, part, &counters);
                    assert_true(counters.packets > 0);
                    for (uint32_t y = block.y0; y < block.y1; y++)
                        for (uint32_t x = block.x0; x < block.x1; x++)
                            got[(size_t)y * w + x] = part[(y - y0) * (block.x1 - x0) + (x - x0)];
                }
            uint32_t lost = 0;
            for (size_t i = 0; i < n; i++)
                if (memcmp(&got[i], &want[i], sizeof got[i]) != 0 && lost++ < 5)
                    print_message("%s camera (%s) pixel %zu: prim %u t %a, brute force prim %u t %a\n", row->name,
                                  rtt_isa_name(row->isa), i, got[i].prim, (double)got[i].t, want[i].prim,
                                  (double)want[i].t);
            for (size_t i = 0; i < n; i++) occ[i] = want[i].prim != RTT_MISS;
            const uint32_t bits = tree->watertight ? reference_bit_differences(&f->base, rays, got, occ, (uint32_t)n) : 0;
            print_message("%s camera %-7s %-10s %ux%u in %ux%u blocks%s: %u lost%s\n", row->name,
                          rtt_isa_name(row->isa), bvh_tree_test_name(tree), w, h, bw, bh,
                          block.stream ? ", streamed" : "", lost,
                          tree->watertight ? (bits ? ", not the reference's bits" : ", the reference's bits") : "");
            assert_int_equal(lost, 0);
            assert_int_equal(bits, 0);
        }
    }
    free(rays), free(want), free(got), free(occ);
}

static void test_mft_camera_rays(void **state)
{
    const bvh_fixture *f = *state;
    /* wide, narrow, and a camera whose rays cross the axis planes (looking down an axis) */
    static const struct { rtt_vec3 eye, at; float fov; uint32_t w, h; } cams[] = {
        {{0.3f, 0.4f, 3.0f}, {0, 0, 0}, 110.0f, 61, 45},
        {{2.5f, 1.5f, -2.0f}, {0, 0, 0}, 4.0f, 37, 29},
        {{0.0f, 0.0f, 2.5f}, {0, 0, 0}, 60.0f, 48, 32},
    };
    for (size_t c = 0; c < sizeof cams / sizeof cams[0]; c++) {
        rtt_camera cam = f->base.scene->camera;
        cam.eye = cams[c].eye, cam.look_at = cams[c].at, cam.up = rtt_v3(0, 1, 0), cam.fov_deg = cams[c].fov;
        for (uint32_t t = 0; t < BVH_FIXTURE_TESTS; t++) check_camera_kernel(f, f->trees[t], &cam, cams[c].w, cams[c].h);
    }
}

static void test_kernels_on_random_rays_with_specials(void **state)
{
    const bvh_fixture *f = *state;
    rtt_ray *rays = random_rays(4099, 53, ALL_SPECIALS);
    check_every_kernel(f, rays, 4099);
    free(rays);
}

static void test_kernels_on_shadow_rays(void **state)
{
    const bvh_fixture *f = *state;
    rtt_ray *rays = shadow_rays(4096, rtt_v3(0.5f, 3.0f, 0.7f), 59);
    check_every_kernel(f, rays, 4096);
    free(rays);
}

/* Shadow rays leaving an axis-aligned floor (a map's common case): origins
 * exactly in the plane z = 0 of a tiled floor, towards points above, so the
 * floor's triangles under a ray have all three corners in its origin's kz
 * plane (T = 0: the watertight test's double path, which the packet kernels
 * answer without asking when tnear >= 0).  Every kernel at every ISA, closest
 * hit and occlusion, against the records' scalar test, with tnear 0, 1e-4
 * and -1e-3 (below zero the floor itself is crossed at t = +-0, a hit). */
static void test_kernels_on_shadow_rays_leaving_an_axis_aligned_floor(void **state)
{
    (void)state;
    enum { TILES = 8, OCCLUDERS = 40, RAYS = 3 * 1024 };
    const uint32_t count = 2 * TILES * TILES + OCCLUDERS;
    float *xyz = malloc(9 * (size_t)count * sizeof *xyz);
    assert_non_null(xyz);
    uint32_t t = tiled_floor(xyz, TILES, 0.0f);
    rng r = {0x5EEDF100Aull};
    for (; t < count; t++) {
        const float c[3] = {rng_range(&r, -4, 4), rng_range(&r, -4, 4), rng_range(&r, 0.5f, 3.0f)};
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) xyz[9 * t + 3 * v + a] = c[a] + rng_range(&r, -0.6f, 0.6f);
    }
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, count, &err);
    free(xyz);
    if (!scene) fail_msg("scene: %s", err.message);
    bvh_tree tree;
    build(scene, 4, 0, 1, &tree);
    tree.watertight = true;
    rtt_ray *rays = malloc(RAYS * sizeof *rays);
    rtt_hit *want = malloc(RAYS * sizeof *want), *got = malloc(RAYS * sizeof *got);
    uint8_t *occ = malloc(RAYS);
    assert_true(rays && want && got && occ);
    const float tnears[3] = {0.0f, 1e-4f, -1e-3f};
    uint32_t floor_hits = 0, blocked = 0;
    for (uint32_t i = 0; i < RAYS; i++) {
        const float org[3] = {rng_range(&r, -3.9f, 3.9f), rng_range(&r, -3.9f, 3.9f), 0.0f};
        const float to[3] = {rng_range(&r, -6, 6), rng_range(&r, -6, 6), rng_range(&r, 4, 6)};
        const float d[3] = {to[0] - org[0], to[1] - org[1], to[2] - org[2]};
        const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        rays[i] = (rtt_ray){{org[0], org[1], org[2]}, {d[0] / len, d[1] / len, d[2] / len}, tnears[i % 3], len * 0.999f};
        want[i] = bvh_records_closest(&tree, &rays[i]);
        floor_hits += want[i].prim != RTT_MISS && want[i].prim < 2 * TILES * TILES;
        blocked += want[i].prim != RTT_MISS;
    }
    assert_true(floor_hits > 0);          /* the rays of tnear < 0 cross their floor */
    assert_true(blocked > floor_hits);    /* and some rays meet an occluder */
    assert_true(blocked < RAYS);          /* and some see the light */
    const bvh_kernel *row;
    for (uint32_t k = 0; (row = bvh_kernel_row_at(k)); k++) {
        if (!isa_runs(row->isa)) continue;
        row->trace(&tree, &(bvh_query){.rays = rays, .count = RAYS, .hits = got});
        row->trace(&tree, &(bvh_query){.rays = rays, .count = RAYS, .occluded = occ});
        for (uint32_t i = 0; i < RAYS; i++) {
            if (memcmp(&got[i], &want[i], sizeof got[i]) != 0)
                fail_msg("%s (%s) ray %u (tnear %g): prim %u t %a, the records' test prim %u t %a", row->name,
                         rtt_isa_name(row->isa), i, (double)rays[i].tnear, got[i].prim, (double)got[i].t, want[i].prim,
                         (double)want[i].t);
            if (occ[i] != (want[i].prim != RTT_MISS))
                fail_msg("%s (%s) ray %u (tnear %g): occluded %u, the records' test says %u", row->name,
                         rtt_isa_name(row->isa), i, (double)rays[i].tnear, occ[i], want[i].prim != RTT_MISS);
        }
        print_message("%-11s %-7s %u rays off a floor: %u stopped by their floor, %u blocked, all as the records' test\n",
                      row->name, rtt_isa_name(row->isa), RAYS, floor_hits, blocked);
    }
    free(rays), free(want), free(got), free(occ);
    bvh_tree_free(&tree);
    rtt_scene_free(scene);
}

/* Tiny triangles far from the rays' common origin: 4e-6 to 4e-4 across,
 * about 20 units off (a fuzzed scene's case), so the edge planes through the
 * origin are cross products of long, nearly parallel vectors, rounded to a
 * large fraction of their own length.  Sixteen rays per origin, each aimed
 * at a point of a different triangle (some within 1e-3 of an edge): the
 * frusta kernels' culling must lose none of their hits.  Every kernel at
 * every ISA, closest hit and occlusion, against the records' scalar test. */
static void test_kernels_on_tiny_triangles_far_from_a_common_origin(void **state)
{
    (void)state;
    enum { TRIS = 256, RAYS = 16 * 256 };
    float *xyz = tiny_far_triangles(TRIS, 0x71A7ull);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, TRIS, &err);
    if (!scene) fail_msg("scene: %s", err.message);
    bvh_tree tree;
    build(scene, 4, 0, 1, &tree);
    tree.watertight = true;
    rtt_ray *rays = rays_at_tiny_far_triangles(xyz, TRIS, RAYS, 0x71A8ull);
    free(xyz);
    rtt_hit *want = malloc(RAYS * sizeof *want), *got = malloc(RAYS * sizeof *got);
    uint8_t *occ = malloc(RAYS);
    assert_true(want && got && occ);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < RAYS; i++) {
        want[i] = bvh_records_closest(&tree, &rays[i]);
        hits += want[i].prim != RTT_MISS;
    }
    /* aimed inside: most hit (3120 of 4096); rounding the direction moves the
     * aim by about 1e-6 here, off many of the smallest triangles */
    assert_true(hits > RAYS / 2);
    uint32_t failed = 0;
    const bvh_kernel *row;
    for (uint32_t k = 0; (row = bvh_kernel_row_at(k)); k++) {
        if (!isa_runs(row->isa)) continue;
        row->trace(&tree, &(bvh_query){.rays = rays, .count = RAYS, .hits = got});
        row->trace(&tree, &(bvh_query){.rays = rays, .count = RAYS, .occluded = occ});
        uint32_t lost = 0, occ_bad = 0;
        for (uint32_t i = 0; i < RAYS; i++) {
            if (memcmp(&got[i], &want[i], sizeof got[i]) != 0 && lost++ < 3)
                print_message("%s (%s) ray %u: prim %u t %a, the records' test prim %u t %a\n", row->name,
                              rtt_isa_name(row->isa), i, got[i].prim, (double)got[i].t, want[i].prim,
                              (double)want[i].t);
            occ_bad += occ[i] != (want[i].prim != RTT_MISS);
        }
        print_message("%-11s %-7s %u rays at tiny far triangles (%u hits): %u answered otherwise than the records' "
                      "test, %u occluded wrong\n", row->name, rtt_isa_name(row->isa), RAYS, hits, lost, occ_bad);
        failed += lost + occ_bad;
    }
    assert_int_equal(failed, 0);
    free(rays), free(want), free(got), free(occ);
    bvh_tree_free(&tree);
    rtt_scene_free(scene);
}

/* ---- back-face culling on the camera path ---- */

static void build_with_solids(const rtt_scene *scene, bvh_tree *tree)
{
    build(scene, 4, 0, 1, tree);
    rtt_error err = {{0}};
    if (!bvh_tree_mark_solids(tree, scene, &err)) fail_msg("solids: %s", err.message);
    tree->watertight = true;
}

/* Every camera row's hits on the scene's camera (w x h, 16 x 16 blocks)
 * against the brute force over every record: the same hit bit for bit, or
 * a tie (both prims crossed, in double, within 1e-5 of their barycentric
 * range and of the t, at a shared edge) on at most 1% of the pixels.
 * Returns the ray/triangle tests (counters.isect_tests) of the last row. */
static uint64_t camera_hits_checked(const rtt_scene *s, const bvh_tree *tree, uint32_t w, uint32_t h)
{
    const rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    const size_t n = (size_t)w * h;
    rtt_ray *rays = malloc(n * sizeof *rays);
    rtt_hit *want = malloc(n * sizeof *want), *got = malloc(n * sizeof *got);
    assert_true(rays && want && got);
    uint32_t seen = 0;
    for (size_t i = 0; i < n; i++) {
        rays[i] = rtt_camera_ray(&frame, (uint32_t)(i % w), (uint32_t)(i / w));
        want[i] = bvh_records_closest(tree, &rays[i]);
        seen += want[i].prim != RTT_MISS;
    }
    assert_true(seen > n / 10);
    const double extent = rtt_v3_length(rtt_v3_sub(s->bounds.hi, s->bounds.lo)) +
                          rtt_v3_length(rtt_v3_sub(s->bounds.lo, s->camera.eye));
    bvh_camera_block block = {{frame.eye.x, frame.eye.y, frame.eye.z}, {frame.corner.x, frame.corner.y, frame.corner.z},
                              {frame.du.x, frame.du.y, frame.du.z}, {frame.dv.x, frame.dv.y, frame.dv.z}, 0, 0, 0, 0, false};
    uint64_t tested = 0;
    const bvh_kernel *row;
    for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
        if (!row->trace_camera || !isa_runs(row->isa)) continue;
        bvh_counters counters = {0};
        for (uint32_t y0 = 0; y0 < h; y0 += 16)
            for (uint32_t x0 = 0; x0 < w; x0 += 16) {
                block.x0 = x0, block.y0 = y0, block.x1 = x0 + 16 < w ? x0 + 16 : w, block.y1 = y0 + 16 < h ? y0 + 16 : h;
                _Alignas(64) rtt_hit part[16 * 16];
                row->trace_camera(tree, &block, part, &counters);
                for (uint32_t y = y0; y < block.y1; y++)
                    for (uint32_t x = x0; x < block.x1; x++)
                        got[(size_t)y * w + x] = part[(y - y0) * (block.x1 - x0) + (x - x0)];
            }
        uint32_t ties = 0;
        for (size_t i = 0; i < n; i++) {
            if (!memcmp(&got[i], &want[i], sizeof got[i])) continue;
            if (got[i].prim == want[i].prim || got[i].prim == RTT_MISS || want[i].prim == RTT_MISS)
                fail_msg("%s camera (%s) pixel %zu: prim %u t %a, brute force prim %u t %a", row->name,
                         rtt_isa_name(row->isa), i, got[i].prim, (double)got[i].t, want[i].prim, (double)want[i].t);
            const double tol = 1e-5 * (fabs((double)want[i].t) + extent);
            for (int k = 0; k < 2; k++) {
                const rtt_hit *hit = k ? &got[i] : &want[i];
                double t = INFINITY;
                const double inside = crossing(s, hit->prim, &rays[i], &t);
                if (inside < -1e-5 || fabs(t - hit->t) > tol || fabs((double)got[i].t - want[i].t) > tol)
                    fail_msg("%s camera (%s) pixel %zu: prim %u t %.9g against the brute force's %u t %.9g: not a tie "
                             "(%g)", row->name, rtt_isa_name(row->isa), i, got[i].prim, got[i].t, want[i].prim,
                             want[i].t, inside);
            }
            ties++;
        }
        print_message("%s camera %-7s %ux%u: %u ties, %llu ray/triangle tests\n", row->name, rtt_isa_name(row->isa), w,
                      h, ties, (unsigned long long)counters.isect_tests);
        assert_true(ties <= n / 100);
        tested = counters.isect_tests;
    }
    free(rays), free(want), free(got);
    return tested;
}

/* Two solid spheres (meshes of one scene; the second wound inside out, so
 * its own outward side is used): bvh-mft's camera path drops their back
 * faces while the eye is outside their boxes -- fewer ray/triangle tests than
 * with the culling off (bvh_tree.solid NULL), hits equal but for ties --
 * and keeps every face of a solid whose box holds the eye, which then sees
 * its inner side: from inside the big sphere only the small one's back
 * faces go. */
static void test_mft_camera_drops_back_faces_only_where_no_eye_ray_meets_them_first(void **state)
{
    const char *path = scratch_path(state, "two_spheres.json");
    rtt_error err = {{0}};
    rtt_scene *s = two_spheres_scene(path, &err);
    if (!s) fail_msg("%s: not two closed spheres (%s)", path, err.message);
    /* the second sphere wound inside out: its part's volume is negative */
    for (uint32_t t = s->meshes[1].first_triangle; t < s->meshes[1].first_triangle + s->meshes[1].triangle_count; t++) {
        const uint32_t v = s->triangles[t].v[1];
        s->triangles[t].v[1] = s->triangles[t].v[2], s->triangles[t].v[2] = v;
    }
    bvh_tree tree;
    build(s, 4, 0, 1, &tree);
    assert_null(tree.solid); /* the build alone finds none */
    const uint64_t bare = tree.info.memory_bytes;
    bvh_tree_free(&tree);
    build_with_solids(s, &tree);
    assert_non_null(tree.solid);
    /* the solids' bytes counted once, however often they are marked */
    const uint64_t marked = tree.info.memory_bytes;
    assert_true(marked > bare);
    rtt_error again = {{0}};
    assert_true(bvh_tree_mark_solids(&tree, s, &again));
    assert_int_equal(tree.info.memory_bytes, marked);
    assert_int_equal(tree.solid_count, 2);
    for (uint32_t i = 0; i < tree.triangle_count; i++) {
        const uint32_t mesh = s->triangle_mesh[tree.triangles[i].prim];
        assert_int_equal(tree.solid[i], mesh == 0 ? 1 : -2); /* outward +1 and -1, solids 1 and 2 */
    }
    static const struct { float eye[3]; bool inside_big; } cams[] = {
        {{0.6f, 1.9f, 4.5f}, false}, {{3.5f, -1.0f, 2.0f}, false}, {{0.1f, 0.2f, 0.3f}, true}};
    for (size_t c = 0; c < sizeof cams / sizeof cams[0]; c++) {
        s->camera = (rtt_camera){rtt_v3(cams[c].eye[0], cams[c].eye[1], cams[c].eye[2]), rtt_v3(0.9f, 0.0f, 0.0f),
                                 rtt_v3(0.0f, 1.0f, 0.0f), cams[c].inside_big ? 100.0f : 50.0f};
        const uint64_t culled = camera_hits_checked(s, &tree, 96, 80);
        int32_t *solid = tree.solid;
        tree.solid = NULL;
        const uint64_t all = camera_hits_checked(s, &tree, 96, 80);
        tree.solid = solid;
        print_message("eye %zu: %llu ray/triangle tests with back faces dropped, %llu without\n", c,
                      (unsigned long long)culled, (unsigned long long)all);
        assert_true(culled < all);
        if (!cams[c].inside_big) continue;
        /* from inside the big sphere: it keeps both faces, the small one is
         * culled; without the small one, nothing is */
        bvh_tree_free(&tree);
        rtt_scene *big = rtt_scene_load(path, NULL, &err);
        assert_non_null(big);
        big->meshes[1].triangle_count = 0;
        big->camera = s->camera;
        big->triangle_count = big->meshes[0].triangle_count;
        build_with_solids(big, &tree);
        assert_int_equal(tree.solid_count, 1);
        const uint64_t kept = camera_hits_checked(big, &tree, 96, 80);
        solid = tree.solid;
        tree.solid = NULL;
        assert_int_equal(camera_hits_checked(big, &tree, 96, 80), kept);
        tree.solid = solid;
        bvh_tree_free(&tree);
        rtt_scene_free(big);
        build_with_solids(s, &tree);
    }
    bvh_tree_free(&tree);
    rtt_scene_free(s);
}

static int setup_scratch(void **state) { return scratch_create(state, "bvh"); }

/* ---- watertightness ---- */

static int setup_bvh_octahedron(void **state)
{
    setup_octahedron(state);
    bvh_fixture_from(state);
    return 0;
}

/* Soft-shadow points inside the octahedron, each towards a tiny "light"
 * beyond one of its corners or edge midpoints (seen from the point): every
 * sample ray passes within a few ulps of that corner or edge, and every one
 * must be occluded. */
static uint32_t frusta_escapes(const bvh_tree *tree, const rtt_ray *aimed, uint32_t n,
                               const bvh_shadow_kernel *row)
{
    bvh_shadow_sets *sets = calloc(1, sizeof *sets);
    bvh_shadow_point *pts = malloc(n * sizeof *pts);
    uint32_t *occ = malloc(n * sizeof *occ);
    assert_non_null(sets), assert_non_null(pts), assert_non_null(occ);
    sets->samples = 16;
    rng r = {0x5eedull};
    for (uint32_t s = 0; s < 16; s++) {
        sets->lo[s][0] = sets->lo[s][1] = 1.0f, sets->hi[s][0] = sets->hi[s][1] = 0.0f;
        for (uint32_t k = 0; k < 16; k++) {
            const float x = rng_float(&r), y = rng_float(&r);
            sets->x[s][k] = x, sets->y[s][k] = y;
            sets->lo[s][0] = fminf(sets->lo[s][0], x), sets->hi[s][0] = fmaxf(sets->hi[s][0], x);
            sets->lo[s][1] = fminf(sets->lo[s][1], y), sets->hi[s][1] = fmaxf(sets->hi[s][1], y);
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        const rtt_ray *a = &aimed[i];
        bvh_shadow_point *p = &pts[i];
        for (int k = 0; k < 3; k++) {
            p->org[k] = a->org[k];
            p->base[k] = a->org[k] + 2.0f * a->dir[k]; /* twice as far as the corner or edge point */
            p->du[k] = k == 0 ? 1e-6f : 0.0f, p->dv[k] = k == 1 ? 1e-6f : 0.0f;
        }
        p->set = i % 16;
    }
    row->trace(tree, &(bvh_shadow_query){.points = pts, .count = n, .sets = sets, .epsilon = 1e-5f, .occluded = occ});
    uint32_t escapes = 0;
    for (uint32_t i = 0; i < n; i++) escapes += (uint32_t)__builtin_popcount(~occ[i] & 0xffffu);
    free(sets), free(pts), free(occ);
    return escapes;
}

/* Hard shadows through bvh-mft's apex frusta: origins near the centre, every
 * ray to one point beyond a corner, so the rays pass within about 1e-6 of
 * it. */
static uint32_t apex_escapes(const bvh_tree *tree, const bvh_kernel *row)
{
    enum { RAYS = 1024 };
    rtt_ray *rays = malloc(RAYS * sizeof *rays);
    uint8_t *occ = malloc(RAYS);
    assert_non_null(rays), assert_non_null(occ);
    rng r = {0xa9e7ull};
    uint32_t escapes = 0;
    for (uint32_t corner = 0; corner < 3 * tree->triangle_count; corner++) {
        const bvh_corners *c = &tree->corners[corner / 3];
        const float centre[3] = {OCTAHEDRON_CENTRE_X, OCTAHEDRON_CENTRE_Y, OCTAHEDRON_CENTRE_Z};
        float toward[3];
        for (int k = 0; k < 3; k++) toward[k] = centre[k] + 3.0f * (c->v[corner % 3][k] - centre[k]);
        for (uint32_t i = 0; i < RAYS; i++) {
            float org[3], d[3];
            for (int k = 0; k < 3; k++) org[k] = centre[k] + rng_range(&r, -1e-6f, 1e-6f), d[k] = toward[k] - org[k];
            const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            rays[i] = (rtt_ray){{org[0], org[1], org[2]}, {d[0] / len, d[1] / len, d[2] / len}, 0.0f, len * 0.999f};
        }
        row->trace(tree, &(bvh_query){.rays = rays, .count = RAYS, .occluded = occ, .toward = toward});
        for (uint32_t i = 0; i < RAYS; i++) escapes += !occ[i];
    }
    free(rays), free(occ);
    return escapes;
}

static void test_watertight_kernels_let_no_ray_aimed_at_corners_or_edges_out_of_a_closed_mesh(void **state)
{
    const bvh_fixture *f = *state;
    enum { RAYS = 4096 };
    rtt_ray *own = octahedron_corner_and_edge_rays(f->base.scene, RAYS, 1, 0xC0FFEEull);
    rtt_ray *shared = octahedron_corner_and_edge_rays(f->base.scene, RAYS, 16, 0xBEEFull); /* frusta of 16 */
    rtt_hit *hits = malloc(RAYS * sizeof *hits);
    uint8_t *occ = malloc(RAYS);
    assert_non_null(hits), assert_non_null(occ);
    for (uint32_t t = 0; t < BVH_FIXTURE_TESTS; t++) {
        const bvh_tree *tree = f->trees[t];
        const bvh_kernel *row;
        for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
            if (!isa_runs(row->isa)) continue;
            uint32_t escapes = 0;
            for (int set = 0; set < 2; set++) {
                const rtt_ray *rays = set ? shared : own;
                row->trace(tree, &(bvh_query){.rays = rays, .count = RAYS, .hits = hits});
                row->trace(tree, &(bvh_query){.rays = rays, .count = RAYS, .occluded = occ});
                for (uint32_t i = 0; i < RAYS; i++) escapes += (hits[i].prim == RTT_MISS) + !occ[i];
            }
            const uint32_t apex = strcmp(row->name, "bvh-mft") == 0 ? apex_escapes(tree, row) : 0;
            print_message("%-10s %-11s %-7s %u closest-hit and occlusion rays at corners and edges: %u escaped; "
                          "hard shadows past corners: %u escaped\n",
                          bvh_tree_test_name(tree), row->name, rtt_isa_name(row->isa), 4 * RAYS, escapes, apex);
            if (tree->watertight) assert_int_equal(escapes, 0), assert_int_equal(apex, 0);
        }
        const bvh_shadow_kernel *shadow;
        for (uint32_t r = 0; (shadow = bvh_shadow_kernel_row_at(r)); r++) {
            if (!isa_runs(shadow->isa)) continue;
            const uint32_t escapes = frusta_escapes(tree, own, RAYS, shadow);
            print_message("%-10s frusta:16   %-7s %u soft-shadow rays past corners and edges: %u escaped\n",
                          bvh_tree_test_name(tree), rtt_isa_name(shadow->isa), 16 * RAYS, escapes);
            if (tree->watertight) assert_int_equal(escapes, 0);
        }
    }
    free(own), free(shared), free(hits), free(occ);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builder_invariants_for_leaf_sizes_and_depths),
        cmocka_unit_test(test_pre_split_triangles_are_covered_by_their_leaves),
        cmocka_unit_test(test_build_takes_no_denormal_operand),
        cmocka_unit_test(test_one_and_two_threads_build_the_same_bytes),
        cmocka_unit_test(test_degenerate_only_and_empty_scenes_build_and_miss),
        cmocka_unit_test_setup_teardown(test_kernels_on_primary_rays, setup_bvh, teardown_bvh),
        cmocka_unit_test_setup_teardown(test_mft_camera_rays, setup_bvh, teardown_bvh),
        cmocka_unit_test_setup_teardown(test_mft_camera_drops_back_faces_only_where_no_eye_ray_meets_them_first,
                                        setup_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_kernels_on_random_rays_with_specials, setup_bvh, teardown_bvh),
        cmocka_unit_test_setup_teardown(test_kernels_on_shadow_rays, setup_bvh, teardown_bvh),
        cmocka_unit_test(test_kernels_on_shadow_rays_leaving_an_axis_aligned_floor),
        cmocka_unit_test(test_kernels_on_tiny_triangles_far_from_a_common_origin),
        cmocka_unit_test_setup_teardown(
            test_watertight_kernels_let_no_ray_aimed_at_corners_or_edges_out_of_a_closed_mesh, setup_bvh_octahedron,
            teardown_bvh),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* The BVH tests' fixture (test_optimized_bvh.c, test_optimized_bvh_frusta.c):
 * the shared triangle soup with the reference engine (test_fixtures_optimized.h)
 * and two optimized engines with --accel bvh on it, one per triangle test
 * (the default, watertight, and --isect projected), and the brute force
 * over a tree's records with the scalar form of the tree's test. */
#ifndef RTT_TEST_FIXTURES_BVH_H
#define RTT_TEST_FIXTURES_BVH_H

#include "isect_projected_bary.h"
#include "isect_woop_watertight.h"
#include "test_fixtures_optimized.h"

#define BVH_FIXTURE_TESTS 2u

typedef struct bvh_fixture {
    fixture base;      /* the soup, the reference engine (and a kd engine, unused) */
    rtt_engine *bvh;   /* the default options: the watertight test */
    const bvh_tree *tree;
    rtt_engine *engines[BVH_FIXTURE_TESTS];  /* [0] = bvh (watertight), [1] --isect projected */
    const bvh_tree *trees[BVH_FIXTURE_TESTS];
} bvh_fixture;

static inline const char *bvh_tree_test_name(const bvh_tree *tree)
{
    return tree->watertight ? "watertight" : "projected";
}

/* An optimized --accel bvh engine on `scene` with triangle test `isect`. */
static inline rtt_engine *bvh_engine_with(const rtt_scene *scene, rtt_isect isect)
{
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.accel = RTT_ACCEL_BVH;
    opt.isect = isect;
    rtt_error err = {{0}};
    rtt_engine *e = rtt_optimized_engine_create(scene, &opt, &err);
    if (!e) fail_msg("bvh engine: %s", err.message);
    assert_non_null(bvh_engine_tree(e));
    return e;
}

/* Both BVH engines on the fixture's scene (already in f->base). */
static inline void bvh_fixture_engines(bvh_fixture *f)
{
    f->engines[0] = f->bvh = bvh_engine_with(f->base.scene, RTT_ISECT_DEFAULT);
    f->engines[1] = bvh_engine_with(f->base.scene, RTT_ISECT_PROJECTED);
    for (uint32_t i = 0; i < BVH_FIXTURE_TESTS; i++) f->trees[i] = bvh_engine_tree(f->engines[i]);
    f->tree = f->trees[0];
    assert_string_equal(rtt_engine_isect_name(f->engines[0]), "watertight"); /* the BVH's default */
    assert_true(f->trees[0]->watertight && !f->trees[1]->watertight);
}

static inline bvh_fixture *bvh_fixture_from(void **state)
{
    fixture *base = *state;
    bvh_fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    f->base = *base;
    free(base);
    bvh_fixture_engines(f);
    *state = f;
    return f;
}

/* 2000 triangles of the soup of `seed`. */
static inline int setup_bvh_seeded(void **state, uint64_t seed)
{
    setup_soup(state, 2000, 0.08f, seed);
    bvh_fixture_from(state);
    return 0;
}

/* The ray as the scalar tests take it; false for a ray every kernel refuses. */
static inline bool bvh_records_ray(const rtt_ray *r, kd_ray1 *ray)
{
    if (!ray_is_traceable(r) || !(r->tnear <= r->tfar)) return false;
    *ray = (kd_ray1){{r->org[0], r->org[1], r->org[2]}, {r->dir[0], r->dir[1], r->dir[2]}, r->tnear, r->tfar};
    return true;
}

/* Record i against one ray with the scalar form of the tree's test: the
 * closest hit lowered into *hit (ties to the smaller prim), or with hit
 * NULL true when the ray crosses it. */
static inline bool bvh_records_test(const bvh_tree *tree, uint32_t i, const kd_ray1 *ray, kd_hit1 *hit)
{
    if (!tree->watertight) {
        if (!hit) return occluded1_projected_bary(&tree->triangles[i], ray);
        isect1_projected_bary(&tree->triangles[i], ray, hit);
        return false;
    }
    wt_ray1 shear;
    wt_ray1_setup(&shear, ray);
    const bvh_corners *c = &tree->corners[i];
    float t, u, v;
    if (!isect1_watertight_corners(c->v[0], c->v[1], c->v[2], ray, &shear, &t, &u, &v)) return false;
    const uint32_t prim = tree->triangles[i].prim;
    if (hit && (t < hit->t || (t == hit->t && prim < hit->prim))) *hit = (kd_hit1){t, u, v, prim};
    return true;
}

/* The closest record hit by one ray, over every record. */
static inline rtt_hit bvh_records_closest(const bvh_tree *tree, const rtt_ray *r)
{
    kd_hit1 hit = {INFINITY, 0.0f, 0.0f, RTT_MISS};
    kd_ray1 ray;
    if (bvh_records_ray(r, &ray))
        for (uint32_t i = 0; i < tree->triangle_count; i++) bvh_records_test(tree, i, &ray, &hit);
    return hit.prim == RTT_MISS ? (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS} : (rtt_hit){hit.t, hit.u, hit.v, hit.prim};
}

/* Occlusion of one ray by any record. */
static inline int bvh_records_occlude(const bvh_tree *tree, const rtt_ray *r)
{
    kd_ray1 ray;
    if (!bvh_records_ray(r, &ray)) return 0;
    for (uint32_t i = 0; i < tree->triangle_count; i++)
        if (bvh_records_test(tree, i, &ray, NULL)) return 1;
    return 0;
}

/* A floor of tiles x tiles unit squares (two triangles each) centred on
 * the origin in the plane z = slope x, into xyz (9 floats a triangle);
 * returns the triangles written, 2 tiles^2. */
static inline uint32_t tiled_floor(float *xyz, int tiles, float slope)
{
    uint32_t t = 0;
    for (int y = 0; y < tiles; y++)
        for (int x = 0; x < tiles; x++) {
            const float x0 = (float)(x - tiles / 2), y0 = (float)(y - tiles / 2), x1 = x0 + 1.0f, y1 = y0 + 1.0f;
            const float quad[2][9] = {{x0, y0, slope * x0, x1, y0, slope * x1, x1, y1, slope * x1},
                                      {x0, y0, slope * x0, x1, y1, slope * x1, x0, y1, slope * x0}};
            for (int k = 0; k < 2; k++, t++) memcpy(&xyz[9 * t], quad[k], sizeof quad[k]);
        }
    return t;
}

static inline int teardown_bvh(void **state)
{
    bvh_fixture *f = *state;
    for (uint32_t i = 0; i < BVH_FIXTURE_TESTS; i++) rtt_engine_destroy(f->engines[i]);
    fixture *base = malloc(sizeof *base);
    assert_non_null(base);
    *base = f->base;
    free(f);
    *state = base;
    return teardown(state);
}

#endif

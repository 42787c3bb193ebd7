/* The BVH tests' fixture (test_optimized_bvh.c, test_optimized_bvh_frusta.c):
 * the shared triangle soup with the reference engine (test_fixtures_optimized.h)
 * and an optimized engine with --accel bvh on it. */
#ifndef RTT_TEST_FIXTURES_BVH_H
#define RTT_TEST_FIXTURES_BVH_H

#include "test_fixtures_optimized.h"

typedef struct bvh_fixture {
    fixture base;      /* the soup, the reference engine (and a kd engine, unused) */
    rtt_engine *bvh;
    const bvh_tree *tree;
} bvh_fixture;

/* 2000 triangles of the soup of `seed`. */
static inline int setup_bvh_seeded(void **state, uint64_t seed)
{
    setup_soup(state, 2000, 0.08f, seed);
    fixture *base = *state;
    bvh_fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    f->base = *base;
    free(base);
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.accel = RTT_ACCEL_BVH;
    rtt_error err = {{0}};
    f->bvh = rtt_optimized_engine_create(f->base.scene, &opt, &err);
    if (!f->bvh) fail_msg("bvh engine: %s", err.message);
    f->tree = bvh_engine_tree(f->bvh);
    assert_non_null(f->tree);
    *state = f;
    return 0;
}

static inline int teardown_bvh(void **state)
{
    bvh_fixture *f = *state;
    rtt_engine_destroy(f->bvh);
    fixture *base = malloc(sizeof *base);
    assert_non_null(base);
    *base = f->base;
    free(f);
    *state = base;
    return teardown(state);
}

#endif

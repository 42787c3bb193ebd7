/* Frames that do not allocate (rtt view's contract): with an
 * rtt_render_cache, the optimized renderer's second and later frames of the
 * same size call no allocator at all — the scratch is kept in the cache and
 * the thread pool's workers persist.  The allocator is counted through the
 * linker's --wrap (tests/CMakeLists.txt), which sees every call from rtt's
 * static libraries.  The cached frames must equal uncached ones. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/rtt.h"

static atomic_ulong allocations;

void *__real_malloc(size_t size);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t size);
void *__real_aligned_alloc(size_t align, size_t size);
void *__wrap_malloc(size_t size)
{
    atomic_fetch_add(&allocations, 1);
    return __real_malloc(size);
}
void *__wrap_calloc(size_t n, size_t size)
{
    atomic_fetch_add(&allocations, 1);
    return __real_calloc(n, size);
}
void *__wrap_realloc(void *p, size_t size)
{
    atomic_fetch_add(&allocations, 1);
    return __real_realloc(p, size);
}
void *__wrap_aligned_alloc(size_t align, size_t size)
{
    atomic_fetch_add(&allocations, 1);
    return __real_aligned_alloc(align, size);
}

static void render_frames(const char *shadows, uint32_t threads)
{
    rtt_error err = {{0}};
    assert_true(rtt_builtin_engines_register(&err));
    rtt_scene *scene = rtt_scene_load(RTT_SOURCE_DIR "/scenes/demo.json", NULL, &err);
    assert_non_null(scene);
    rtt_engine *engine = rtt_engine_create("optimized", scene, NULL, &err);
    assert_non_null(engine);
    rtt_render_options opt;
    rtt_render_options_default(&opt);
    assert_true(rtt_shadow_method_parse(shadows, &opt, &err));
    opt.width = 48;
    opt.height = 40;
    opt.threads = threads;
    rtt_image *plain = rtt_image_create(opt.width, opt.height, 0, &err);
    rtt_image *cached = rtt_image_create(opt.width, opt.height, 0, &err);
    assert_true(plain && cached);
    assert_true(rtt_render(engine, &opt, plain, NULL, &err));
    opt.cache = rtt_render_cache_create();
    assert_non_null(opt.cache);
    rtt_render_stats stats;
    assert_true(rtt_render(engine, &opt, cached, &stats, &err)); /* fills the cache */
    for (int frame = 0; frame < 4; frame++) {
        memset(cached->rgb, 0, sizeof(float) * 3 * opt.width * opt.height);
        const unsigned long before = atomic_load(&allocations);
        assert_true(rtt_render(engine, &opt, cached, &stats, &err));
        const unsigned long during = atomic_load(&allocations) - before;
        if (during != 0) fail_msg("%s, %u threads, frame %d: %lu allocations", shadows, threads, frame + 2, during);
        assert_memory_equal(plain->rgb, cached->rgb, sizeof(float) * 3 * opt.width * opt.height);
        assert_int_equal(stats.primary_rays, (uint64_t)opt.width * opt.height); /* stats are per frame */
    }
    rtt_render_cache_destroy(opt.cache);
    rtt_image_free(plain);
    rtt_image_free(cached);
    rtt_engine_destroy(engine);
    rtt_scene_free(scene);
}

static void hard_shadows_one_thread(void **state) { (void)state; render_frames("hard", 1); }
static void hard_shadows_two_threads(void **state) { (void)state; render_frames("hard", 2); }
static void cone_shadows_three_threads(void **state) { (void)state; render_frames("cone:8", 3); }
static void edgewidth_two_threads(void **state) { (void)state; render_frames("edgewidth", 2); }

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hard_shadows_one_thread),
        cmocka_unit_test(hard_shadows_two_threads),
        cmocka_unit_test(cone_shadows_three_threads),
        cmocka_unit_test(edgewidth_two_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

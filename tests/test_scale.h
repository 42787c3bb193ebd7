/* How much of its heaviest sweeps a test runs.  The Release suites (the
 * default ISA and RTT_ISA=sse4) run every sweep whole; the sanitizer builds
 * (ci/sanitize.sh: ASan + UBSan, TSan), which run every test 3 to 20 times
 * slower and are there for memory errors and races rather than answers,
 * run the same checks on a quarter of the rays or points. */
#ifndef RTT_TEST_SCALE_H
#define RTT_TEST_SCALE_H

#include <stdint.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TEST_SANITIZED 1
#endif
#endif
#ifndef TEST_SANITIZED
#define TEST_SANITIZED 0
#endif
/* 1 in a ThreadSanitizer build, which looks for races: a renderer's threads
 * and tiles are the same at every instruction set, so its sweeps over them
 * there may run at the one the CPU picks. */
#if defined(__SANITIZE_THREAD__)
#define TEST_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TEST_TSAN 1
#endif
#endif
#ifndef TEST_TSAN
#define TEST_TSAN 0
#endif

/* n, or n / 4 (at least 1) in a sanitizer build. */
static inline uint32_t test_sweep(uint32_t n) { return TEST_SANITIZED ? (n / 4 ? n / 4 : 1) : n; }

#endif

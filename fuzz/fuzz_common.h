/* Helpers shared by the libFuzzer harnesses (fuzz/ only).
 *
 * Every harness defines LLVMFuzzerTestOneInput; it is linked either with
 * libFuzzer (-fsanitize=fuzzer, RTT_FUZZ=ON) or with replay_main.c into a
 * plain executable that ctest runs over the committed corpus and
 * regressions.  A harness reports a broken invariant with fuzz_fail(), which
 * prints one line and aborts so both drivers see a crash. */
#ifndef RTT_FUZZ_COMMON_H
#define RTT_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Prints "fuzz: <message>" to stderr and aborts. */
_Noreturn void fuzz_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Aborts unless err holds one non-empty, terminated line (the error contract). */
void fuzz_check_error_line(const rtt_error *err);

/* Writes data to a fresh temporary file whose name ends in `extension`
 * (".json"), loads it with rtt_scene_load, removes the file and returns the
 * scene (NULL when the loader refused it; err then holds its message).
 * Aborts when a refusal breaks the error contract (empty or multi-line). */
rtt_scene *fuzz_load_scene_bytes(const uint8_t *data, size_t size, const char *extension, rtt_error *err);

/* Aborts unless a loaded scene keeps the scene model's promises: every index
 * in range, finite vertices, at least one material and one light, meshes
 * tiling the global triangle order. */
void fuzz_check_scene(const rtt_scene *scene);

#endif

/* Fuzz target: the mesh header checks (scene/mesh_header_check.c) on their
 * own, without Assimp behind them, so every mutation reaches the scanners.
 * The first byte picks the format, the rest is the file.  What must hold:
 * no read past the buffer (ASan), no allocation a header's count asks for,
 * a refusal is one line naming the file, and an accepted file's counts are
 * ones its bytes can hold. */
#include <string.h>

#include "fuzz_common.h"
#include "mesh_header_check.h"

static const char *const formats[] = {"off", "ply", "stl", "gltf", "glb"};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 1 << 16) return 0;
    const char *format = formats[data[0] % (sizeof formats / sizeof formats[0])];
    const size_t length = size - 1;
    rtt_mesh_header header;
    rtt_error err = {{0}};
    /* a path without a directory: a glTF's external buffers are looked for
     * in the working directory, where none of these names exist */
    if (!rtt_mesh_header_scan("fuzz-input", format, data + 1, length, &header, &err)) {
        if (strncmp(err.message, "fuzz-input: ", 12) != 0 || strchr(err.message, '\n') || !err.message[12])
            fuzz_fail("refusal breaks the one-line contract: \"%s\"", err.message);
        return 0;
    }
    /* each face of OFF and PLY takes at least one byte of the body, each
     * binary STL triangle 50, each ascii one more than 50 */
    if (header.counted && header.faces > length) fuzz_fail("%s: %llu faces accepted from %zu bytes", format,
                                                            (unsigned long long)header.faces, length);
    return 0;
}

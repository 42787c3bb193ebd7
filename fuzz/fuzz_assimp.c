/* Fuzz target: our validation of what Assimp returns (scene/import_assimp.c).
 * The first byte picks the file type, the rest is the file.  Assimp's own
 * parsers are not ours to fix; what must hold is that whatever Assimp hands
 * back (NaN vertices, out-of-range indices, points and lines, empty meshes)
 * either becomes a valid scene or one clear error line. */
#include "fuzz_common.h"

static const char *const extensions[] = { ".obj", ".ply", ".off", ".stl", ".gltf" };

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 1 << 16)
        return 0;
    const char *extension = extensions[data[0] % (sizeof extensions / sizeof extensions[0])];
    rtt_error err;
    rtt_scene *scene = fuzz_load_scene_bytes(data + 1, size - 1, extension, &err);
    if (scene) {
        fuzz_check_scene(scene);
        rtt_scene_free(scene);
    }
    return 0;
}

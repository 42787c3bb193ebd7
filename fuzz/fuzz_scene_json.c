/* Fuzz target: the JSON scene parser (scene/scene_schema.c via rtt_scene_load).
 * Bytes become a .json file; a refusal must be one clear line, an accepted
 * scene must keep every promise of the scene model. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 16)
        return 0;   /* scene files are small; big inputs only slow the search */
    rtt_error err;
    rtt_scene *scene = fuzz_load_scene_bytes(data, size, ".json", &err);
    if (scene) {
        fuzz_check_scene(scene);
        rtt_scene_free(scene);
    }
    return 0;
}

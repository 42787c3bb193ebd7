/* Fuzz target: our Quake III IBSP 46 loader (scene/import_q3bsp.c via
 * rtt_scene_load).  Every lump offset, count and index comes from the bytes,
 * so this is where a loader that trusts its input would read out of bounds. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20)
        return 0;
    rtt_error err;
    rtt_scene *scene = fuzz_load_scene_bytes(data, size, ".bsp", &err);
    if (scene) {
        fuzz_check_scene(scene);
        rtt_scene_free(scene);
    }
    return 0;
}

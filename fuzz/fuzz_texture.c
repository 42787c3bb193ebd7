/* Fuzz target: texture images (scene/texture_image.c: JPEG, PNG and TGA
 * through stb_image) as they come from pk3 archives, MTL/glTF references
 * and embedded glTF images.  A decoded image must have the sides it says,
 * within RTT_TEXTURE_MAX_SIDE, and be sampled anywhere without reading out
 * of bounds; a refusal must give a reason. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "textures.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    rtt_texture t;
    memset(&t, 0, sizeof t);
    char why[256] = "";
    if (!rtt_texture_decode(data, size, &t, why, sizeof why)) {
        if (why[0] == '\0') fuzz_fail("a refusal without a reason");
        return 0;
    }
    if (t.width == 0 || t.height == 0 || t.width > RTT_TEXTURE_MAX_SIDE || t.height > RTT_TEXTURE_MAX_SIDE)
        fuzz_fail("decoded %u x %u texels", t.width, t.height);
    /* corners, centres, wrapped and non-finite coordinates */
    const float at[] = {0.0f, 0.5f, 1.0f, -0.25f, 3.75f, 1e30f, -1e-30f, NAN, INFINITY};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++)
        for (size_t j = 0; j < sizeof at / sizeof at[0]; j++) {
            rtt_vec3 c = rtt_texture_sample(&t, at[i], at[j], (i + j) % 2 == 0);
            if (!(c.x >= 0.0f && c.x <= 1.0f && c.y >= 0.0f && c.y <= 1.0f && c.z >= 0.0f && c.z <= 1.0f))
                fuzz_fail("sample (%g, %g) is (%g, %g, %g)", (double)at[i], (double)at[j], (double)c.x, (double)c.y,
                          (double)c.z);
        }
    free(t.rgb);
    return 0;
}

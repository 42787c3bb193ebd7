/* Fuzz target: the Quake III shader script parser of scene/q3_shader.c
 * (scripts come from pk3 archives, that is from anyone's map pack).  Every
 * reported name must be a C string of fewer than RTT_Q3_NAME_MAX bytes; a
 * refusal must give a reason. */
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "q3_shader.h"

static void on_shader(void *context, const char *shader, const char *image)
{
    size_t *count = context;
    if (strlen(shader) >= RTT_Q3_NAME_MAX || (image && strlen(image) >= RTT_Q3_NAME_MAX)) fuzz_fail("a name is too long");
    if (image && image[0] == '$') fuzz_fail("\"%s\" reported as an image", image); /* $lightmap is never one */
    (*count)++;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    char why[160] = "";
    size_t count = 0;
    if (!rtt_q3_shader_parse((const char *)data, size, on_shader, &count, why, sizeof why) && why[0] == '\0')
        fuzz_fail("a refusal without a reason");
    return 0;
}

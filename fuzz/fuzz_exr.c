/* Fuzz target: the EXR reader (image/exr_read.c).  Golden images and
 * `rtt compare` inputs come from outside, so a broken file must be refused
 * with one line naming it, never crash or read past OpenEXR's buffers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_common.h"
#include "rtt/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 18)
        return 0;
    const char *dir = getenv("TMPDIR");
    char path[512];
    snprintf(path, sizeof path, "%s/rtt_fuzz_XXXXXX.exr", dir && dir[0] ? dir : "/tmp");
    int fd = mkstemps(path, 4);
    if (fd < 0)
        fuzz_fail("cannot create a temporary file %s", path);
    if (size && write(fd, data, size) != (ssize_t)size)
        fuzz_fail("cannot write %s", path);
    close(fd);
    rtt_error err = { "" };
    rtt_image *image = rtt_image_read_exr(path, &err);
    unlink(path);
    if (!image) {
        if (strncmp(err.message, path, strlen(path)) != 0 || strchr(err.message, '\n'))
            fuzz_fail("refusal is not one line naming the file: %s", err.message);
        return 0;
    }
    if (image->width == 0 || image->height == 0 || !image->rgb)
        fuzz_fail("accepted an empty image");
    /* touch every sample so ASan sees any short plane */
    volatile float sum = 0.0f;
    size_t pixels = (size_t)image->width * image->height;
    for (size_t i = 0; i < pixels * 3; i++)
        sum += image->rgb[i] + (image->normal ? image->normal[i] : 0.0f);
    for (size_t i = 0; i < pixels; i++)
        sum += (image->depth ? image->depth[i] : 0.0f) + (float)(image->prim ? image->prim[i] & 1 : 0);
    (void)sum;
    rtt_image_free(image);
    return 0;
}

/* rtt_image_write: picks the writer from the file extension. */
#include <string.h>
#include <strings.h>

#include "rtt/image.h"

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && strcasecmp(path + n - e, ext) == 0;
}

bool rtt_image_write(const rtt_image *image, const char *path, rtt_error *err)
{
    if (has_extension(path, ".exr"))
        return rtt_image_write_exr(image, path, err);
    if (has_extension(path, ".png"))
        return rtt_image_write_png(image, path, err);
    return rtt_error_set(err, "%s: unknown image format (use .exr or .png)", path);
}

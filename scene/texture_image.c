/* Image files for textures through stb_image (Debian's libstb-dev; its
 * implementation is compiled once, in stb_image_impl.c, with the formats
 * textures use: JPEG and TGA (Quake III's pk3 archives), PNG (OBJ/MTL and
 * glTF)).
 * Everything is decoded to 8-bit RGB; the size is checked with stbi_info
 * before decoding so a small hostile file cannot ask for a huge image. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "textures.h"

#include "stb_image_config.h"

bool rtt_texture_decode(const uint8_t *bytes, size_t size, rtt_texture *out, char *why, size_t why_size)
{
    if (size == 0 || size > RTT_TEXTURE_FILE_MAX || size > (size_t)INT32_MAX) {
        snprintf(why, why_size, "%zu bytes is not an image file size this reader takes", size);
        return false;
    }
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(bytes, (int)size, &w, &h, &channels)) {
        snprintf(why, why_size, "not a JPEG, PNG or TGA image (%s)", stbi_failure_reason());
        return false;
    }
    if (w <= 0 || h <= 0 || (uint32_t)w > RTT_TEXTURE_MAX_SIDE || (uint32_t)h > RTT_TEXTURE_MAX_SIDE) {
        snprintf(why, why_size, "%d x %d texels: a side is above %u", w, h, RTT_TEXTURE_MAX_SIDE);
        return false;
    }
    uint8_t *rgb = stbi_load_from_memory(bytes, (int)size, &w, &h, &channels, 3);
    if (!rgb) {
        snprintf(why, why_size, "cannot decode the image (%s)", stbi_failure_reason());
        return false;
    }
    /* stb_image's buffer is malloc'ed (STBI_MALLOC defaults to malloc): the
     * scene frees it with free() like its own arrays */
    out->rgb = rgb;
    out->width = (uint32_t)w;
    out->height = (uint32_t)h;
    return true;
}

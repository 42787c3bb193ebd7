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

/* Debian's stb_image (git 2022-09-08) builds a JPEG Huffman table without
 * checking that its 16 code-length counts sum to at most 256, the size of
 * the table's arrays, so a hostile DHT segment writes past them (found by
 * fuzz_texture).  stb_image reads a marker as 0xFF, any 0xFF fill bytes,
 * then its code, and takes a DHT wherever it meets one (before a frame or
 * between scans), so every DHT marker of a file it reads as JPEG (0xFF..
 * 0xD8 first) is checked here, its bytes past the end read as 0 as
 * stb_image reads them.  False when one of its tables has more codes. */
static bool jpeg_huffman_tables_fit(const uint8_t *bytes, size_t size)
{
    size_t i = 0;
    while (i < size && bytes[i] == 0xFF) i++;
    if (i == 0 || i >= size || bytes[i] != 0xD8) return true; /* not a JPEG to stb_image */
    for (; i + 1 < size; i++) {
        if (bytes[i] != 0xFF || bytes[i + 1] != 0xC4) continue;
        size_t p = i + 2;
        if (p + 2 > size) return true;
        long left = (long)((unsigned)bytes[p] << 8 | bytes[p + 1]) - 2; /* the segment's length */
        p += 2;
        while (left > 0 && p < size) {
            p++; /* table class and number */
            unsigned codes = 0;
            for (int k = 0; k < 16; k++, p++) codes += p < size ? bytes[p] : 0u;
            if (codes > 256) return false;
            left -= 17 + (long)codes;
            p += codes;
        }
    }
    return true;
}

bool rtt_texture_decode(const uint8_t *bytes, size_t size, rtt_texture *out, char *why, size_t why_size)
{
    if (size == 0 || size > RTT_TEXTURE_FILE_MAX || size > (size_t)INT32_MAX) {
        snprintf(why, why_size, "%zu bytes is not an image file size this reader takes", size);
        return false;
    }
    if (!jpeg_huffman_tables_fit(bytes, size)) {
        snprintf(why, why_size, "a JPEG Huffman table (DHT) with more than 256 codes");
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

/* stb_image's configuration, the same for its declarations (texture_image.c)
 * and its one implementation (stb_image_impl.c): JPEG, PNG and TGA from
 * memory, 8-bit only, images no larger than a texture may be. */
#ifndef RTT_SCENE_STB_IMAGE_CONFIG_H
#define RTT_SCENE_STB_IMAGE_CONFIG_H

#include "textures.h"

#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#define STBI_ONLY_TGA
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#define STBI_MAX_DIMENSIONS RTT_TEXTURE_MAX_SIDE
#define STBI_NO_FAILURE_STRINGS_DEFAULT
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wshadow"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#endif

/* The scene's textures and texture coordinates (textures.c) and the image
 * decoder behind them (texture_image.c): internal to scene/. */
#ifndef RTT_SCENE_TEXTURES_H
#define RTT_SCENE_TEXTURES_H

#include <stddef.h>
#include <stdint.h>

#include "rtt/scene.h"

/* Encoded image files larger than this are refused before decoding. */
#define RTT_TEXTURE_FILE_MAX (64u << 20)

/* Decodes a JPEG, PNG or TGA image held in memory into 8-bit RGB (stb_image;
 * every other format is refused).  Sides above RTT_TEXTURE_MAX_SIDE are
 * refused before any texel is decoded.  On failure returns false with the
 * reason in `why`; out->name is left to the caller. */
bool rtt_texture_decode(const uint8_t *bytes, size_t size, rtt_texture *out, char *why, size_t why_size);

/* A texture for a material: the one already in the scene under the same
 * name, or a new one decoded from the bytes (or read from the file at
 * `path` when bytes is NULL).  Returns the material's map value (1 + its
 * index), or 0 when it cannot be read: then the scene records the miss
 * (rtt_scene_texture_missing) and the material keeps its colour.  Only out
 * of memory for the table itself fails the load (false, err set). */
bool rtt_scene_texture_add(rtt_scene *scene, const char *name, const char *path, const uint8_t *bytes, size_t size,
                           uint32_t *map, rtt_error *err);

/* Records a texture that could not be read (the first one's reason is kept). */
void rtt_scene_texture_missing(rtt_scene *scene, const char *name, const char *why);

/* Texture coordinates (u, v; v up) for vertices [first, first + count) of
 * the scene, which must be the last ones appended; earlier vertices without
 * coordinates get (0, 0).  Non-finite coordinates become 0. */
bool rtt_scene_set_texcoords(rtt_scene *scene, uint32_t first, const float *uv, uint32_t count, rtt_error *err);

/* At rtt_scene_finish: checks every material's map index, gives the
 * vertices after the last textured mesh (0, 0), and drops the texture
 * coordinates when no material has a map. */
bool rtt_scene_textures_finish(rtt_scene *scene, rtt_error *err);
void rtt_scene_textures_free(rtt_scene *scene);

#endif

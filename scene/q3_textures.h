/* The textures of a Quake III map (q3_textures.c): its shader names
 * resolved to images in pk3 archives and loose directories.  Internal to
 * scene/. */
#ifndef RTT_SCENE_Q3_TEXTURES_H
#define RTT_SCENE_Q3_TEXTURES_H

#include <stdint.h>

#include "rtt/scene.h"

/* The environment variable naming the texture search directories
 * (colon-separated); unset: the map's directory, its parent and the
 * parent's pk3/ (bench/fetch-scenes.sh puts the archives there). */
#define RTT_TEXTURE_PATH_VARIABLE "RTT_TEXTURE_PATH"

/* Materials for a map's triangles: names[i] (RTT_Q3 name records of
 * name_stride bytes, the first 64 the NUL-padded shader name) is texture i
 * of the map; triangle_texture[t] the texture of triangle t (out of range:
 * none).  On success *materials is either NULL (no texture source was
 * found, or the map names no textures: the caller keeps its one grey
 * material) or a new array of one scene material per triangle, and
 * *textured says whether any of them has a diffuse map (then the caller
 * gives the vertices their texture coordinates).  Missing images are
 * recorded in the scene (rtt_scene_texture_missing), never errors. */
bool rtt_q3_map_materials(rtt_scene *scene, const char *map_path, const uint8_t *names, uint32_t name_count,
                          uint32_t name_stride, const uint32_t *triangle_texture, uint32_t triangle_count,
                          uint32_t **materials, bool *textured, rtt_error *err);

#endif

/* Texture maps of Assimp's materials (assimp_textures.c), for
 * import_assimp.c: internal to scene/. */
#ifndef RTT_SCENE_ASSIMP_TEXTURES_H
#define RTT_SCENE_ASSIMP_TEXTURES_H

#include "rtt/scene.h"

struct aiScene;
struct aiMaterial;

/* Sets out's diffuse_map and normal_map from material m of `ai` (model
 * file `model_path`); a map that cannot be read leaves 0 and is recorded
 * as missing.  False only when out of memory. */
bool rtt_assimp_material_textures(rtt_scene *scene, const char *model_path, const struct aiScene *ai,
                                  const struct aiMaterial *m, rtt_material *out, rtt_error *err);

#endif

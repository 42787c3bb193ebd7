/* The texture maps of a material Assimp imported (MTL map_Kd / norm /
 * map_bump, 3DS texture and bump maps, glTF baseColorTexture and
 * normalTexture): the first diffuse map becomes the material's diffuse
 * map, the first normal map (aiTextureType_NORMALS), else the first height
 * map (MTL bump, 3DS bump: exporters write tangent-space normal maps
 * there), its normal map.
 *
 * A map's path is relative to the model file's directory (or absolute);
 * "*N" names the file's embedded texture N (glTF buffers, GLB), which must
 * be a compressed image (JPEG, PNG or TGA bytes).  A map that cannot be
 * read is recorded as missing (textures.c), never an error. */
#include <assimp/material.h>
#include <assimp/scene.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "assimp_textures.h"
#include "textures.h"

/* A map of the given type, or false when the material has none. */
static bool texture_path(const struct aiMaterial *m, enum aiTextureType type, struct aiString *out)
{
    if (aiGetMaterialTextureCount(m, type) == 0) return false;
    return aiGetMaterialTexture(m, type, 0, out, NULL, NULL, NULL, NULL, NULL, NULL) == aiReturn_SUCCESS &&
           out->length > 0;
}

static bool embedded_texture(rtt_scene *scene, const char *model_path, const struct aiScene *ai, const char *ref,
                             uint32_t *map, rtt_error *err)
{
    char name[600];
    snprintf(name, sizeof name, "%s:%s", model_path, ref);
    char *end = NULL;
    unsigned long index = strtoul(ref + 1, &end, 10);
    if (!end || *end || end == ref + 1 || index >= ai->mNumTextures || !ai->mTextures[index]) {
        rtt_scene_texture_missing(scene, name, "no such embedded texture");
        return true;
    }
    const struct aiTexture *t = ai->mTextures[index];
    if (t->mHeight != 0 || !t->pcData) {
        rtt_scene_texture_missing(scene, name, "an uncompressed embedded texture (only image files are read)");
        return true;
    }
    return rtt_scene_texture_add(scene, name, NULL, (const uint8_t *)t->pcData, t->mWidth, map, err);
}

static bool load_map(rtt_scene *scene, const char *model_path, const struct aiScene *ai, const char *ref,
                     uint32_t *map, rtt_error *err)
{
    if (ref[0] == '*') return embedded_texture(scene, model_path, ai, ref, map, err);
    char path[1200];
    const char *slash = strrchr(model_path, '/');
    if (ref[0] == '/' || !slash)
        snprintf(path, sizeof path, "%s", ref);
    else
        snprintf(path, sizeof path, "%.*s/%s", (int)(slash - model_path), model_path, ref);
    for (char *c = path; *c; c++)
        if (*c == '\\') *c = '/'; /* Windows exporters */
    return rtt_scene_texture_add(scene, path, path, NULL, 0, map, err);
}

bool rtt_assimp_material_textures(rtt_scene *scene, const char *model_path, const struct aiScene *ai,
                                  const struct aiMaterial *m, rtt_material *out, rtt_error *err)
{
    struct aiString ref;
    if (texture_path(m, aiTextureType_DIFFUSE, &ref) &&
        !load_map(scene, model_path, ai, ref.data, &out->diffuse_map, err))
        return false;
    if ((texture_path(m, aiTextureType_NORMALS, &ref) || texture_path(m, aiTextureType_HEIGHT, &ref)) &&
        !load_map(scene, model_path, ai, ref.data, &out->normal_map, err))
        return false;
    return true;
}

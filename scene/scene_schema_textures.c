/* The texture keys of the scene file (scene/README.md): materials[i].
 * diffuse_map / normal_map (an image file relative to the scene file) and
 * meshes[i].texcoords (one [u, v] per vertex of an inline mesh), and the
 * path rule the scene file's references share. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_kind.h"
#include "scene_schema.h"
#include "textures.h"

bool rtt_schema_read_texture(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t *map)
{
    if (!cJSON_IsString(v) || !v->valuestring[0])
        return rtt_schema_fail(p, at, " must be a non-empty string (an image file: JPEG, PNG or TGA)");
    char resolved[1024];
    rtt_path_beside(p->src.path, v->valuestring, resolved, sizeof resolved);
    rtt_error inner;
    if (!rtt_scene_texture_add(p->scene, resolved, resolved, NULL, 0, map, &inner))
        return rtt_schema_fail(p, at, ": %s", inner.message);
    return true; /* an unreadable image is recorded as missing: the material keeps its colour */
}

bool rtt_schema_read_texcoords(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, uint32_t vertex_count,
                               float **out)
{
    if (!cJSON_IsArray(v) || (uint32_t)cJSON_GetArraySize(v) != vertex_count)
        return rtt_schema_fail(p, at, " must be an array of one [u, v] per vertex (%u)", vertex_count);
    if (!(*out = malloc(sizeof **out * 2u * vertex_count + 1))) return rtt_schema_fail(p, at, ": out of memory");
    int i = 0;
    for (const cJSON *c = v->child; c; c = c->next, i++) {
        rtt_json_place e = rtt_json_element(at, i);
        if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 2 || !cJSON_IsNumber(c->child) ||
            !cJSON_IsNumber(c->child->next) || !isfinite(c->child->valuedouble) ||
            !isfinite(c->child->next->valuedouble) || fabs(c->child->valuedouble) > 1e6 ||
            fabs(c->child->next->valuedouble) > 1e6)
            return rtt_schema_fail(p, &e, " must be [u, v], two finite numbers of magnitude at most 1e6");
        (*out)[2 * i] = (float)c->child->valuedouble;
        (*out)[2 * i + 1] = (float)c->child->next->valuedouble;
    }
    return true;
}

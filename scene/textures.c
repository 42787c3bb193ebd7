/* Textures of the scene model: the table of images materials sample, the
 * per-vertex texture coordinates, bilinear sampling (Thesis 4.2.1, step 3:
 * "texture lookups for diffuse and normal maps using bilinear filtering").
 *
 * A scene pays for textures only when it has them: the table and the
 * coordinates stay NULL until a material names a map that could be read.
 * A texture that cannot be read is not an error of the scene: the material
 * keeps its own colour (or its interpolated normal), the scene counts the
 * miss and keeps the first reason, and the command line prints one warning.
 * Images are shared: a second material naming the same file gets the same
 * texture. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_read.h"
#include "textures.h"

void rtt_scene_texture_missing(rtt_scene *scene, const char *name, const char *why)
{
    if (scene->missing_texture_count++ == 0)
        snprintf(scene->missing_texture, sizeof scene->missing_texture, "%.200s: %.110s", name, why);
}

bool rtt_scene_texture_add(rtt_scene *scene, const char *name, const char *path, const uint8_t *bytes, size_t size,
                           uint32_t *map, rtt_error *err)
{
    *map = 0;
    for (uint32_t i = 0; i < scene->texture_count; i++)
        if (strcmp(scene->textures[i].name, name) == 0) {
            *map = i + 1;
            return true;
        }
    rtt_texture texture;
    memset(&texture, 0, sizeof texture);
    snprintf(texture.name, sizeof texture.name, "%s", name);
    char why[256];
    uint8_t *file = NULL;
    if (!bytes) {
        rtt_error read_err;
        file = (uint8_t *)rtt_file_read(path, RTT_TEXTURE_FILE_MAX, &size, &read_err);
        if (!file) {
            const char *colon = strstr(read_err.message, ": ");
            rtt_scene_texture_missing(scene, name, colon ? colon + 2 : read_err.message);
            return true;
        }
        bytes = file;
    }
    bool decoded = rtt_texture_decode(bytes, size, &texture, why, sizeof why);
    free(file);
    if (!decoded) {
        rtt_scene_texture_missing(scene, name, why);
        return true;
    }
    rtt_texture *grown = realloc(scene->textures, ((size_t)scene->texture_count + 1) * sizeof *grown);
    if (!grown) {
        free(texture.rgb);
        return rtt_error_set(err, "%s: out of memory for texture %s", scene->path, name);
    }
    scene->textures = grown;
    scene->textures[scene->texture_count++] = texture;
    *map = scene->texture_count;
    return true;
}

bool rtt_scene_set_texcoords(rtt_scene *scene, uint32_t first, const float *uv, uint32_t count, rtt_error *err)
{
    if ((uint64_t)first + count != scene->vertex_count || first < scene->texcoord_count)
        return rtt_error_set(err, "%s: texture coordinates for vertices %u+%u do not follow the last ones (%u of %u)",
                             scene->path, first, count, scene->texcoord_count, scene->vertex_count);
    float *grown = realloc(scene->texcoords, (size_t)scene->vertex_count * 2 * sizeof *grown + 1);
    if (!grown) return rtt_error_set(err, "%s: out of memory for texture coordinates", scene->path);
    scene->texcoords = grown;
    for (size_t i = 2 * (size_t)scene->texcoord_count; i < 2 * (size_t)first; i++) grown[i] = 0.0f;
    for (size_t i = 0; i < 2 * (size_t)count; i++) grown[2 * (size_t)first + i] = isfinite(uv[i]) ? uv[i] : 0.0f;
    scene->texcoord_count = scene->vertex_count;
    return true;
}

bool rtt_scene_textures_finish(rtt_scene *scene, rtt_error *err)
{
    bool mapped = false;
    for (uint32_t i = 0; i < scene->material_count; i++) {
        const rtt_material *m = &scene->materials[i];
        if (m->diffuse_map > scene->texture_count || m->normal_map > scene->texture_count)
            return rtt_error_set(err, "%s: material %u: texture %u or %u is out of range (%u textures)", scene->path,
                                 i, m->diffuse_map, m->normal_map, scene->texture_count);
        mapped = mapped || m->diffuse_map || m->normal_map;
    }
    if (mapped && !scene->texcoords)
        rtt_scene_texture_missing(scene, scene->path, "materials have texture maps but no mesh has texture coordinates");
    if (!mapped || !scene->texcoords) { /* nothing samples a texture: drop what would go unused */
        for (uint32_t i = 0; i < scene->material_count; i++) {
            scene->materials[i].diffuse_map = 0;
            scene->materials[i].normal_map = 0;
        }
        free(scene->texcoords);
        scene->texcoords = NULL;
        scene->texcoord_count = 0;
        return true;
    }
    if (scene->texcoord_count < scene->vertex_count) { /* meshes without coordinates after the last with */
        float *grown = realloc(scene->texcoords, (size_t)scene->vertex_count * 2 * sizeof *grown + 1);
        if (!grown) return rtt_error_set(err, "%s: out of memory for texture coordinates", scene->path);
        for (size_t i = 2 * (size_t)scene->texcoord_count; i < 2 * (size_t)scene->vertex_count; i++) grown[i] = 0.0f;
        scene->texcoords = grown;
        scene->texcoord_count = scene->vertex_count;
    }
    return true;
}

void rtt_scene_textures_free(rtt_scene *scene)
{
    for (uint32_t i = 0; i < scene->texture_count; i++) free(scene->textures[i].rgb);
    free(scene->textures);
    free(scene->texcoords);
}

size_t rtt_scene_texture_bytes(const rtt_scene *scene)
{
    size_t bytes = (size_t)scene->texcoord_count * 2 * sizeof(float) + (size_t)scene->texture_count * sizeof(rtt_texture);
    for (uint32_t i = 0; i < scene->texture_count; i++)
        bytes += (size_t)scene->textures[i].width * scene->textures[i].height * 3;
    return bytes;
}

/* sRGB (IEC 61966-2-1) to linear, per 8-bit value: a table made once. */
static float srgb_table[256];
static pthread_once_t srgb_once = PTHREAD_ONCE_INIT;

static void make_srgb_table(void)
{
    for (int i = 0; i < 256; i++) {
        float x = (float)i / 255.0f;
        srgb_table[i] = x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
    }
}

static float srgb_to_linear(uint8_t c) { return srgb_table[c]; }

static rtt_vec3 texel(const rtt_texture *t, uint32_t x, uint32_t y, bool srgb)
{
    const uint8_t *p = &t->rgb[((size_t)y * t->width + x) * 3];
    if (srgb) return rtt_v3(srgb_to_linear(p[0]), srgb_to_linear(p[1]), srgb_to_linear(p[2]));
    return rtt_v3((float)p[0] / 255.0f, (float)p[1] / 255.0f, (float)p[2] / 255.0f);
}

/* Bilinear between the four texel centres around (u, v): texel (i, j)'s
 * centre is at u = (i + 0.5) / width, v = 1 - (j + 0.5) / height; both
 * directions repeat. */
rtt_vec3 rtt_texture_sample(const rtt_texture *t, float u, float v, bool srgb)
{
    if (srgb) pthread_once(&srgb_once, make_srgb_table);
    if (!isfinite(u)) u = 0.0f;
    if (!isfinite(v)) v = 0.0f;
    u -= floorf(u);
    v -= floorf(v);
    float x = u * (float)t->width - 0.5f, y = (1.0f - v) * (float)t->height - 0.5f;
    float fx0 = floorf(x), fy0 = floorf(y);
    float fx = x - fx0, fy = y - fy0;
    int64_t x0 = (int64_t)fx0, y0 = (int64_t)fy0;
    uint32_t xa = (uint32_t)((x0 % t->width + t->width) % t->width), xb = (xa + 1) % t->width;
    uint32_t ya = (uint32_t)((y0 % t->height + t->height) % t->height), yb = (ya + 1) % t->height;
    rtt_vec3 top = rtt_v3_add(rtt_v3_scale(texel(t, xa, ya, srgb), 1.0f - fx), rtt_v3_scale(texel(t, xb, ya, srgb), fx));
    rtt_vec3 bottom = rtt_v3_add(rtt_v3_scale(texel(t, xa, yb, srgb), 1.0f - fx), rtt_v3_scale(texel(t, xb, yb, srgb), fx));
    return rtt_v3_add(rtt_v3_scale(top, 1.0f - fy), rtt_v3_scale(bottom, fy));
}

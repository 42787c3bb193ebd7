/* Quake III map textures: shader names to images, as the engine finds them.
 *
 * Where: the directories of $RTT_TEXTURE_PATH (colon-separated), else the
 * map's directory, its parent and the parent's pk3/ (the cache layout of
 * bench/fetch-scenes.sh: maps/ and pk3/ side by side).  In each directory,
 * loose files (dir/textures/...) and every NAME.pk3 archive; archives are read
 * in place (pk3.c), nothing is extracted.  Like the engine, a later archive
 * (by name, then by directory) overrides an earlier one, loose files
 * override archives.
 *
 * What: a shader name (the map's texture lump) is looked up in the shader
 * scripts (scripts/NAME.shader of every source, first definition wins); a
 * shader with an image stage draws that stage's image (q3_shader.c), a name
 * without a shader is itself the image.  The image's extension is
 * replaced, like the engine does, by .tga, then .jpg, then .png until one
 * exists.  A shader whose image cannot be found or decoded keeps the grey
 * default colour and is counted as missing (one warning for the scene).
 *
 * Cost: nothing when no source is found (the map keeps one grey
 * material); else one material per shader the faces use and one texture
 * per distinct image. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "file_read.h"
#include "pk3.h"
#include "q3_shader.h"
#include "q3_textures.h"
#include "scene_build.h"
#include "textures.h"

#define Q3_MAX_SOURCES 256u
#define Q3_MAX_SHADERS (1u << 16)

typedef struct q3_shader {
    char name[RTT_Q3_NAME_MAX], image[RTT_Q3_NAME_MAX];
    bool has_image;
} q3_shader;

typedef struct q3_sources {
    char dirs[Q3_MAX_SOURCES][512];
    uint32_t dir_count;
    rtt_pk3 archives[Q3_MAX_SOURCES];
    uint32_t archive_count;
    q3_shader *shaders;
    uint32_t shader_count, shader_capacity;
    rtt_scene *scene;
} q3_sources;

static bool is_directory(const char *path)
{
    struct stat info;
    return stat(path, &info) == 0 && S_ISDIR(info.st_mode);
}

static void add_dir(q3_sources *src, const char *dir)
{
    if (src->dir_count >= Q3_MAX_SOURCES || !*dir || !is_directory(dir)) return;
    for (uint32_t i = 0; i < src->dir_count; i++)
        if (strcmp(src->dirs[i], dir) == 0) return;
    snprintf(src->dirs[src->dir_count++], sizeof src->dirs[0], "%s", dir);
}

static void search_dirs(q3_sources *src, const char *map_path)
{
    const char *list = getenv(RTT_TEXTURE_PATH_VARIABLE);
    if (list) {
        char dir[512];
        for (const char *p = list; *p;) {
            size_t n = strcspn(p, ":");
            snprintf(dir, sizeof dir, "%.*s", (int)(n < sizeof dir - 1 ? n : sizeof dir - 1), p);
            add_dir(src, dir);
            p += n + (p[n] == ':');
        }
        return;
    }
    char dir[512], parent[600], pk3[640];
    const char *slash = strrchr(map_path, '/');
    if (slash)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - map_path < 511 ? slash - map_path : 511), map_path);
    else
        snprintf(dir, sizeof dir, ".");
    snprintf(parent, sizeof parent, "%s/..", dir);
    snprintf(pk3, sizeof pk3, "%s/../pk3", dir);
    add_dir(src, dir);
    add_dir(src, parent);
    add_dir(src, pk3);
}

static int compare_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static bool has_suffix(const char *name, const char *suffix)
{
    size_t n = strlen(name), s = strlen(suffix);
    return n >= s && strcasecmp(name + n - s, suffix) == 0;
}

/* Every *.pk3 of every directory, by name within a directory. */
static void open_archives(q3_sources *src)
{
    for (uint32_t d = 0; d < src->dir_count; d++) {
        DIR *dir = opendir(src->dirs[d]);
        if (!dir) continue;
        char *names[Q3_MAX_SOURCES];
        uint32_t count = 0;
        for (struct dirent *e; (e = readdir(dir)) && count < Q3_MAX_SOURCES;)
            if (has_suffix(e->d_name, ".pk3") && (names[count] = strdup(e->d_name))) count++;
        closedir(dir);
        qsort(names, count, sizeof *names, compare_names);
        for (uint32_t i = 0; i < count; i++) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", src->dirs[d], names[i]);
            free(names[i]);
            if (src->archive_count >= Q3_MAX_SOURCES) continue;
            rtt_error err;
            if (rtt_pk3_open(&src->archives[src->archive_count], path, &err))
                src->archive_count++;
            else
                rtt_scene_texture_missing(src->scene, path, err.message);
        }
    }
}

static void on_shader(void *context, const char *name, const char *image)
{
    q3_sources *src = context;
    for (uint32_t i = 0; i < src->shader_count; i++)
        if (strcasecmp(src->shaders[i].name, name) == 0) return; /* the first definition wins */
    if (src->shader_count >= Q3_MAX_SHADERS) return;
    if (src->shader_count == src->shader_capacity) {
        uint32_t capacity = src->shader_capacity ? 2 * src->shader_capacity : 256;
        q3_shader *grown = realloc(src->shaders, capacity * sizeof *grown);
        if (!grown) return;
        src->shaders = grown;
        src->shader_capacity = capacity;
    }
    q3_shader *s = &src->shaders[src->shader_count++];
    snprintf(s->name, sizeof s->name, "%s", name);
    s->has_image = image != NULL;
    snprintf(s->image, sizeof s->image, "%s", image ? image : "");
}

static void parse_script(q3_sources *src, const char *label, const char *text, size_t size)
{
    char why[160];
    if (!rtt_q3_shader_parse(text, size, on_shader, src, why, sizeof why))
        rtt_scene_texture_missing(src->scene, label, why); /* the shaders before the error are kept */
}

static void read_scripts(q3_sources *src)
{
    for (uint32_t d = 0; d < src->dir_count; d++) {
        char scripts[600];
        snprintf(scripts, sizeof scripts, "%s/scripts", src->dirs[d]);
        DIR *dir = opendir(scripts);
        if (!dir) continue;
        for (struct dirent *e; (e = readdir(dir));) {
            if (!has_suffix(e->d_name, ".shader")) continue;
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", scripts, e->d_name);
            size_t size;
            rtt_error err;
            char *text = rtt_file_read(path, RTT_PK3_MEMBER_MAX, &size, &err);
            if (text) parse_script(src, path, text, size);
            free(text);
        }
        closedir(dir);
    }
    for (uint32_t a = 0; a < src->archive_count; a++) {
        const rtt_pk3 *archive = &src->archives[a];
        for (uint32_t i = 0; i < archive->count; i++) {
            const char *name = rtt_pk3_name(archive, i);
            if (strncasecmp(name, "scripts/", 8) != 0 || !has_suffix(name, ".shader")) continue;
            size_t size;
            rtt_error err;
            uint8_t *text = rtt_pk3_read(archive, i, &size, &err);
            char label[700];
            snprintf(label, sizeof label, "%s:%s", archive->path, name);
            if (text)
                parse_script(src, label, (const char *)text, size);
            else
                rtt_scene_texture_missing(src->scene, label, err.message);
            free(text);
        }
    }
}

static void close_sources(q3_sources *src)
{
    for (uint32_t a = 0; a < src->archive_count; a++) rtt_pk3_close(&src->archives[a]);
    free(src->shaders);
}

/* The image `name` (extension replaced by each of .tga, .jpg, .png) as a
 * texture of the scene: loose files first (directories in order), then the
 * archives from the last.  *map is 0 when it is nowhere or unreadable. */
static bool find_image(q3_sources *src, const char *name, uint32_t *map, rtt_error *err)
{
    static const char *const extensions[] = {".tga", ".jpg", ".png"};
    char stem[RTT_Q3_NAME_MAX];
    snprintf(stem, sizeof stem, "%s", name);
    char *dot = strrchr(stem, '.'), *slash = strrchr(stem, '/');
    if (dot && (!slash || dot > slash)) *dot = '\0';
    *map = 0;
    for (size_t e = 0; e < 3; e++) {
        char member[RTT_Q3_NAME_MAX + 8];
        snprintf(member, sizeof member, "%s%s", stem, extensions[e]);
        for (uint32_t d = 0; d < src->dir_count; d++) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", src->dirs[d], member);
            struct stat info;
            if (stat(path, &info) == 0 && S_ISREG(info.st_mode))
                return rtt_scene_texture_add(src->scene, member, path, NULL, 0, map, err);
        }
        for (uint32_t a = src->archive_count; a-- > 0;) {
            int64_t i = rtt_pk3_find(&src->archives[a], member);
            if (i < 0) continue;
            for (uint32_t t = 0; t < src->scene->texture_count; t++) /* decoded already */
                if (strcmp(src->scene->textures[t].name, member) == 0) {
                    *map = t + 1;
                    return true;
                }
            size_t size;
            rtt_error read_err;
            uint8_t *bytes = rtt_pk3_read(&src->archives[a], (uint32_t)i, &size, &read_err);
            if (!bytes) {
                rtt_scene_texture_missing(src->scene, member, read_err.message);
                return true;
            }
            bool ok = rtt_scene_texture_add(src->scene, member, NULL, bytes, size, map, err);
            free(bytes);
            return ok;
        }
    }
    rtt_scene_texture_missing(src->scene, name, "in no texture directory or pk3 archive");
    return true;
}

/* The scene material of shader `name`: grey with the shader's image as its
 * diffuse map when it has one that can be read. */
static bool shader_material(q3_sources *src, const char *name, uint32_t *material, rtt_error *err)
{
    rtt_material m = rtt_material_default();
    snprintf(m.name, sizeof m.name, "%s", name);
    const char *image = name;
    for (uint32_t i = 0; i < src->shader_count; i++)
        if (strcasecmp(src->shaders[i].name, name) == 0) {
            image = src->shaders[i].has_image ? src->shaders[i].image : NULL;
            break;
        }
    if (image && !find_image(src, image, &m.diffuse_map, err)) return false;
    *material = rtt_scene_add_material(src->scene, &m);
    if (*material == UINT32_MAX) return rtt_error_set(err, "%s: out of memory for materials", src->scene->path);
    return true;
}

bool rtt_q3_map_materials(rtt_scene *scene, const char *map_path, const uint8_t *names, uint32_t name_count,
                          uint32_t name_stride, const uint32_t *triangle_texture, uint32_t triangle_count,
                          uint32_t **materials, bool *textured, rtt_error *err)
{
    *materials = NULL;
    *textured = false;
    if (name_count == 0) return true;
    q3_sources *src = calloc(1, sizeof *src);
    if (!src) return rtt_error_set(err, "%s: out of memory", map_path);
    src->scene = scene;
    search_dirs(src, map_path);
    open_archives(src);
    bool loose = false;
    for (uint32_t d = 0; d < src->dir_count; d++) {
        char textures[600];
        snprintf(textures, sizeof textures, "%s/textures", src->dirs[d]);
        loose = loose || is_directory(textures);
    }
    if (src->archive_count == 0 && !loose) { /* nowhere to look: the one grey material */
        rtt_scene_texture_missing(scene, map_path, "no pk3 archive or textures/ directory in the texture path");
        close_sources(src);
        free(src);
        return true;
    }
    read_scripts(src);
    uint32_t *by_texture = malloc((size_t)name_count * sizeof *by_texture);
    uint32_t *out = malloc((size_t)triangle_count * sizeof *out + 1);
    bool ok = by_texture && out ? true : rtt_error_set(err, "%s: out of memory", map_path);
    for (uint32_t i = 0; ok && i < name_count; i++) by_texture[i] = UINT32_MAX;
    uint32_t grey = UINT32_MAX;
    for (uint32_t t = 0; ok && t < triangle_count; t++) {
        uint32_t k = triangle_texture[t];
        if (k >= name_count) { /* no texture: the grey default */
            if (grey == UINT32_MAX) {
                rtt_material m = rtt_material_default();
                snprintf(m.name, sizeof m.name, "q3bsp");
                grey = rtt_scene_add_material(scene, &m);
                if (grey == UINT32_MAX) ok = rtt_error_set(err, "%s: out of memory for materials", map_path);
            }
            out[t] = grey;
            continue;
        }
        if (by_texture[k] == UINT32_MAX) {
            char name[RTT_Q3_NAME_MAX];
            memcpy(name, names + (size_t)k * name_stride, RTT_Q3_NAME_MAX - 1);
            name[RTT_Q3_NAME_MAX - 1] = '\0';
            for (char *c = name; *c; c++)
                if (*c == '\\') *c = '/';
            ok = shader_material(src, name, &by_texture[k], err);
            if (ok && scene->materials[by_texture[k]].diffuse_map) *textured = true;
        }
        out[t] = by_texture[k];
    }
    free(by_texture);
    close_sources(src);
    free(src);
    if (!ok) {
        free(out);
        return false;
    }
    *materials = out;
    return true;
}

/* bench/views.json: a camera view and a light per benchmark scene, applied
 * over whatever the scene file has (a bare mesh or map has neither).
 *
 *   { "NAME": { "camera": { "eye": [x,y,z], "look_at": [x,y,z], "up": [x,y,z], "fov": deg },
 *               "light":  { "position": [x,y,z], "color": [r,g,b], "intensity": I,
 *                           "attenuation": [c,l,q], "radius": R },
 *               "size": [w, h] },  ... }
 *
 * Keys starting with "_" are comments.  Everything but camera.eye,
 * camera.look_at and light.position has a default (up +z as in Quake maps,
 * fov 60, white, intensity 1, no attenuation, radius 0 = point light). */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"

typedef struct view_reader {
    const char *path, *name;
    rtt_error *err;
} view_reader;

static bool read_floats(const view_reader *r, const cJSON *parent, const char *key, float *out, int n, bool required)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(parent, key);
    if (!item) return required ? rtt_error_set(r->err, "%s: %s: \"%s\" is missing", r->path, r->name, key) : true;
    if (n == 1) {
        if (!cJSON_IsNumber(item))
            return rtt_error_set(r->err, "%s: %s: \"%s\" must be a number", r->path, r->name, key);
        out[0] = (float)item->valuedouble;
        return true;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n)
        return rtt_error_set(r->err, "%s: %s: \"%s\" must be an array of %d numbers", r->path, r->name, key, n);
    for (int k = 0; k < n; k++) {
        const cJSON *v = cJSON_GetArrayItem(item, k);
        if (!cJSON_IsNumber(v))
            return rtt_error_set(r->err, "%s: %s: \"%s\" must be an array of %d numbers", r->path, r->name, key, n);
        out[k] = (float)v->valuedouble;
    }
    return true;
}

static bool read_camera(const view_reader *r, const cJSON *view, rtt_camera *camera)
{
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(view, "camera");
    if (!cJSON_IsObject(c)) return rtt_error_set(r->err, "%s: %s: \"camera\" must be an object", r->path, r->name);
    float eye[3], at[3], up[3] = {0, 0, 1}, fov = RTT_DEFAULT_FOV_DEG;
    if (!read_floats(r, c, "eye", eye, 3, true) || !read_floats(r, c, "look_at", at, 3, true) ||
        !read_floats(r, c, "up", up, 3, false) || !read_floats(r, c, "fov", &fov, 1, false))
        return false;
    if (!(fov >= 1.0f && fov <= 179.0f))
        return rtt_error_set(r->err, "%s: %s: \"fov\" must be a number between 1 and 179", r->path, r->name);
    camera->eye = rtt_v3(eye[0], eye[1], eye[2]);
    camera->look_at = rtt_v3(at[0], at[1], at[2]);
    camera->up = rtt_v3(up[0], up[1], up[2]);
    camera->fov_deg = fov;
    return true;
}

static bool read_light(const view_reader *r, const cJSON *view, rtt_light *light)
{
    const cJSON *l = cJSON_GetObjectItemCaseSensitive(view, "light");
    if (!cJSON_IsObject(l)) return rtt_error_set(r->err, "%s: %s: \"light\" must be an object", r->path, r->name);
    float pos[3], color[3] = {1, 1, 1}, intensity = 1.0f, att[3] = {1, 0, 0}, radius = 0.0f;
    if (!read_floats(r, l, "position", pos, 3, true) || !read_floats(r, l, "color", color, 3, false) ||
        !read_floats(r, l, "intensity", &intensity, 1, false) || !read_floats(r, l, "attenuation", att, 3, false) ||
        !read_floats(r, l, "radius", &radius, 1, false))
        return false;
    if (radius < 0.0f) return rtt_error_set(r->err, "%s: %s: \"radius\" must not be negative", r->path, r->name);
    memset(light, 0, sizeof *light);
    light->type = radius > 0.0f ? RTT_LIGHT_SPHERE : RTT_LIGHT_POINT;
    light->position = rtt_v3(pos[0], pos[1], pos[2]);
    light->color = rtt_v3(color[0], color[1], color[2]);
    light->intensity = intensity;
    memcpy(light->attenuation, att, sizeof att);
    light->radius = radius;
    return true;
}

void bench_base_name(const char *path, char out[64])
{
    const char *slash = strrchr(path, '/');
    const char *start = slash ? slash + 1 : path;
    size_t n = strcspn(start, ".");
    if (n > 63) n = 63;
    memcpy(out, start, n);
    out[n] = '\0';
}

bool rtt_bench_apply_view(rtt_scene *scene, const char *views_path, const char *name, char view_out[64],
                          rtt_error *err)
{
    char derived[64];
    if (!name) {
        bench_base_name(scene->path, derived);
        name = derived;
    }
    FILE *file = fopen(views_path, "rb");
    if (!file) return rtt_error_set(err, "%s: cannot open", views_path);
    char *text = NULL;
    size_t length = 0;
    for (size_t cap = 0;;) {
        if (length + 4096 > cap) {
            cap = cap ? 2 * cap : 65536;
            char *grown = realloc(text, cap + 1);
            if (!grown) break;
            text = grown;
        }
        size_t got = fread(text + length, 1, 4096, file);
        length += got;
        if (got == 0) break;
    }
    fclose(file);
    if (!text) return rtt_error_set(err, "%s: out of memory", views_path);
    text[length] = '\0';
    cJSON *root = cJSON_Parse(text);
    free(text);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return rtt_error_set(err, "%s: not a JSON object of views", views_path);
    }
    view_reader r = {views_path, name, err};
    const cJSON *view = cJSON_GetObjectItemCaseSensitive(root, name);
    bool ok = cJSON_IsObject(view) ? true : rtt_error_set(err, "%s: no view named \"%s\"", views_path, name);
    rtt_camera camera;
    rtt_light light;
    float size[2] = {0, 0};
    ok = ok && read_camera(&r, view, &camera) && read_light(&r, view, &light) &&
         read_floats(&r, view, "size", size, 2, false);
    if (ok && (size[0] < 0 || size[1] < 0 || size[0] > 16384 || size[1] > 16384))
        ok = rtt_error_set(err, "%s: %s: \"size\" must be two whole numbers from 1 to 16384", views_path, name);
    if (ok && scene->light_count == 0)
        ok = rtt_error_set(err, "%s: the scene has no light slot (rtt_scene_finish was not called)", scene->path);
    if (ok) {
        /* the view is in the scene's own coordinates: move it to the stored ones */
        const double eye[3] = {camera.eye.x, camera.eye.y, camera.eye.z};
        const double at[3] = {camera.look_at.x, camera.look_at.y, camera.look_at.z};
        const double pos[3] = {light.position.x, light.position.y, light.position.z};
        camera.eye = rtt_scene_point_to_stored(scene, eye);
        camera.look_at = rtt_scene_point_to_stored(scene, at);
        light.position = rtt_scene_point_to_stored(scene, pos);
        scene->camera = camera;
        scene->lights[0] = light;
        scene->light_count = 1;
        if (size[0] >= 1 && size[1] >= 1) {
            scene->width = (uint32_t)size[0];
            scene->height = (uint32_t)size[1];
        }
        snprintf(view_out, 64, "%s", name);
    }
    cJSON_Delete(root);
    return ok;
}

/* The views file (format in include/rtt/views.h) and the calls that put a
 * camera or the camera light into a loaded scene.
 *
 * The camera of a view is read by the scene file's own camera reader
 * (scene_schema.c), so both files take the same keys, defaults and checks
 * and report errors the same way: "file:line: NAME.camera.fov must be ...". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_schema.h"
#include "rtt/views.h"

#define MAX_IMAGE_SIDE 16384.0
#define MAX_VIEWS 65536

static bool read_view_light(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, rtt_light *out,
                            double position_out[3])
{
    static const char *const keys[] = {"position", "color", "intensity", "attenuation", "attenuation_distance",
                                       "radius", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    rtt_light light = {.type = RTT_LIGHT_POINT, .color = rtt_v3(1, 1, 1), .intensity = 1.0f,
                       .attenuation = {1.0f, 0.0f, 0.0f}};
    rtt_json_place at;
    const cJSON *position = rtt_schema_member(obj, place, "position", &at);
    if (!position) return rtt_schema_fail(p, place, ": missing \"position\"");
    if (!rtt_schema_read_point(p, position, &at, position_out)) return false;
    light.position = rtt_v3((float)position_out[0], (float)position_out[1], (float)position_out[2]);
    RTT_SCHEMA_OPTIONAL(obj, place, "color", rtt_schema_read_color(p, v, at, &light.color));
    RTT_SCHEMA_OPTIONAL(obj, place, "intensity", rtt_schema_read_nonneg(p, v, at, false, &light.intensity));
    RTT_SCHEMA_OPTIONAL(obj, place, "radius", rtt_schema_read_nonneg(p, v, at, false, &light.radius));
    RTT_SCHEMA_OPTIONAL(obj, place, "attenuation", rtt_schema_read_attenuation(p, v, at, light.attenuation));
    RTT_SCHEMA_OPTIONAL(obj, place, "attenuation_distance",
                        rtt_schema_read_nonneg(p, v, at, true, &light.attenuation_distance));
    light.type = light.radius > 0.0f ? RTT_LIGHT_SPHERE : RTT_LIGHT_POINT;
    *out = light;
    return true;
}

static bool read_size(rtt_schema_parser *p, const cJSON *v, const rtt_json_place *at, rtt_view *view)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
        return rtt_schema_fail(p, at, " must be [width, height], integers from 1 to 16384");
    rtt_json_place w = rtt_json_element(at, 0), h = rtt_json_element(at, 1);
    return rtt_schema_read_uint(p, cJSON_GetArrayItem(v, 0), &w, 1, MAX_IMAGE_SIDE, &view->width) &&
           rtt_schema_read_uint(p, cJSON_GetArrayItem(v, 1), &h, 1, MAX_IMAGE_SIDE, &view->height);
}

static bool read_view(rtt_schema_parser *p, const cJSON *obj, const rtt_json_place *place, rtt_view *view)
{
    static const char *const keys[] = {"camera", "light", "size", NULL};
    if (!rtt_schema_check_object(p, obj, place, keys)) return false;
    memset(view, 0, sizeof *view);
    if (strlen(obj->string) >= sizeof view->name)
        return rtt_schema_fail(p, place, ": a view name must be 1 to 63 bytes");
    strcpy(view->name, obj->string);
    rtt_json_place at;
    const cJSON *camera = rtt_schema_member(obj, place, "camera", &at);
    if (!camera) return rtt_schema_fail(p, place, ": missing \"camera\"");
    if (!rtt_schema_parse_camera(p, camera, &at, &view->camera, view->eye, view->look_at)) return false;
    const cJSON *light = rtt_schema_member(obj, place, "light", &at);
    if (light && !read_view_light(p, light, &at, &view->light, view->light_position)) return false;
    view->has_light = light != NULL;
    RTT_SCHEMA_OPTIONAL(obj, place, "size", read_size(p, v, at, view));
    return true;
}

static bool read_views(rtt_schema_parser *p, const cJSON *root, rtt_view_list *out)
{
    const rtt_json_place place = {NULL, NULL, -1};
    if (!cJSON_IsObject(root)) return rtt_schema_fail(p, &place, ": a views file must be a JSON object of views");
    uint32_t count = 0;
    for (const cJSON *c = root->child; c; c = c->next) count += c->string[0] != '_';
    if (count == 0) return rtt_schema_fail(p, &place, ": the file holds no views");
    if (count > MAX_VIEWS) return rtt_schema_fail(p, &place, ": more than %d views", MAX_VIEWS);
    out->views = calloc(count, sizeof *out->views);
    if (!out->views) return rtt_schema_fail(p, &place, ": out of memory for %u views", count);
    int index = 0;
    for (const cJSON *c = root->child; c; c = c->next, index++) {
        if (c->string[0] == '_') continue;
        rtt_json_place at = {&place, c->string, index};
        if (!c->string[0]) return rtt_schema_fail(p, &at, ": a view needs a name");
        if (rtt_views_find(out, c->string)) return rtt_schema_fail(p, &at, ": view given twice");
        if (!read_view(p, c, &at, &out->views[out->count])) return false;
        out->count++;
    }
    return true;
}

static bool read_views_root(rtt_schema_parser *p, const cJSON *root, void *list)
{
    return read_views(p, root, list);
}

bool rtt_views_load(const char *path, rtt_view_list *out, rtt_error *err)
{
    memset(out, 0, sizeof *out);
    rtt_schema_parser p = {NULL, {path, NULL, 0}, err, UINT32_MAX, 0};
    return rtt_schema_parse_file(path, "a views file holds at least one view", &p, read_views_root, out);
}

void rtt_views_free(rtt_view_list *list)
{
    free(list->views);
    list->views = NULL;
    list->count = 0;
}

const rtt_view *rtt_views_find(const rtt_view_list *list, const char *name)
{
    for (uint32_t i = 0; i < list->count; i++)
        if (strcmp(list->views[i].name, name) == 0) return &list->views[i];
    return NULL;
}

void rtt_views_names(const rtt_view_list *list, char *out, size_t size)
{
    size_t used = 0;
    if (size) out[0] = '\0';
    for (uint32_t i = 0; i < list->count && used + 1 < size; i++) {
        int n = snprintf(out + used, size - used, "%s%s", i ? ", " : "", list->views[i].name);
        if (n < 0 || (size_t)n >= size - used) {
            if (size >= 4) strcpy(out + size - 4, "...");
            return;
        }
        used += (size_t)n;
    }
}

/* ---- cameras into scenes ---- */

static bool finite3(rtt_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

bool rtt_camera_check(const rtt_camera *c, rtt_error *err)
{
    if (!finite3(c->eye) || !finite3(c->look_at) || !finite3(c->up))
        return rtt_error_set(err, "the camera's eye, look-at and up must be finite");
    if (!(c->fov_deg >= 1.0f && c->fov_deg <= 179.0f))
        return rtt_error_set(err, "the field of view must be between 1 and 179 degrees (it is %g)",
                             (double)c->fov_deg);
    rtt_vec3 view = rtt_v3_sub(c->look_at, c->eye);
    if (!(rtt_v3_length(view) > 0.0f)) return rtt_error_set(err, "the eye and the look-at point are the same point");
    if (!(rtt_v3_length(c->up) > 0.0f)) return rtt_error_set(err, "the up vector is zero");
    rtt_vec3 side = rtt_v3_cross(rtt_v3_normalize(view), rtt_v3_normalize(c->up));
    if (!(rtt_v3_length(side) > 1e-6f)) return rtt_error_set(err, "the up vector is parallel to the view direction");
    return true;
}

void rtt_scene_set_camera(rtt_scene *scene, const rtt_camera *camera)
{
    const double eye[3] = {camera->eye.x, camera->eye.y, camera->eye.z};
    const double at[3] = {camera->look_at.x, camera->look_at.y, camera->look_at.z};
    rtt_scene_set_camera_at(scene, camera, eye, at);
}

void rtt_scene_set_camera_at(rtt_scene *scene, const rtt_camera *camera, const double eye[3], const double at[3])
{
    /* given in the scene's own coordinates: stored relative to its origin */
    scene->camera = *camera;
    scene->camera.eye = rtt_scene_point_to_stored(scene, eye);
    scene->camera.look_at = rtt_scene_point_to_stored(scene, at);
    camera = &scene->camera;
    scene->camera_source = RTT_CAMERA_FROM_OPTIONS;
    if (scene->light_source == RTT_LIGHTS_AT_CAMERA && scene->light_count == 1)
        scene->lights[0].position = camera->eye;
}

bool rtt_scene_use_view_light(rtt_scene *scene, const rtt_view *view, rtt_error *err)
{
    if (!view->has_light) return rtt_error_set(err, "view \"%s\" has no light", view->name);
    rtt_light *one = realloc(scene->lights, sizeof *one);
    if (!one) return rtt_error_set(err, "%s: out of memory for a light", scene->path);
    *one = view->light;
    one->position = rtt_scene_point_to_stored(scene, view->light_position);
    scene->lights = one;
    scene->light_count = 1;
    scene->light_source = RTT_LIGHTS_FROM_OPTIONS;
    return true;
}

bool rtt_scene_use_camera_light(rtt_scene *scene, rtt_error *err)
{
    rtt_light *one = realloc(scene->lights, sizeof *one);
    if (!one) return rtt_error_set(err, "%s: out of memory for a light", scene->path);
    *one = (rtt_light){.type = RTT_LIGHT_POINT, .position = scene->camera.eye, .color = rtt_v3(1, 1, 1),
                       .intensity = 1.0f, .attenuation = {1.0f, 0.0f, 0.0f}};
    scene->lights = one;
    scene->light_count = 1;
    scene->light_source = RTT_LIGHTS_AT_CAMERA;
    return true;
}

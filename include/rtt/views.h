/* Cameras from outside a scene file: the views file, and the calls that put a
 * camera (or a light at the camera) into a loaded scene.
 *
 * A views file (bench/views.json is one) is one JSON object of named views,
 * in file order:
 *
 *   { "NAME": { "camera": { "eye": [x,y,z], "look_at": [x,y,z], "up": [x,y,z], "fov": deg },
 *               "light":  { "position": [x,y,z], "color": [r,g,b], "intensity": I,
 *                           "attenuation": [c,l,q], "attenuation_distance": D, "radius": R },
 *               "size": [w, h] },  ... }
 *
 * "camera" is required and reads as a scene file's camera (scene/README.md:
 * up defaults to [0, 1, 0], fov to 60 degrees, vertical); "light" (a sphere
 * light when radius > 0, else a point light; color white, intensity 1,
 * attenuation [1, 0, 0] over D = 1 unless given; positions in double) and "size" (two integers 1..16384) are
 * optional.  Keys starting with "_" are comments.  Unknown keys are errors;
 * every error is one line "file:line: NAME.camera.fov must be ...".  A list
 * of views is also a camera path: the MPI renderer and the viewer step through
 * it in file order. */
#ifndef RTT_VIEWS_H
#define RTT_VIEWS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/scene.h"

typedef struct rtt_view {
    char name[64];
    rtt_camera camera;       /* eye and look_at rounded to float: use eye and look_at below */
    double eye[3], look_at[3]; /* in the scene's own coordinates, as the file gives them */
    bool has_light;
    rtt_light light;         /* when has_light; its position rounded to float */
    double light_position[3]; /* when has_light: in the scene's own coordinates */
    uint32_t width, height;  /* "size", or 0 when the view gives none */
} rtt_view;

typedef struct rtt_view_list {
    uint32_t count;
    rtt_view *views;         /* in file order */
} rtt_view_list;

/* Reads every view of the file at `path` into *out (freed with
 * rtt_views_free, also after a failure).  false + err on an unreadable or
 * malformed file. */
bool rtt_views_load(const char *path, rtt_view_list *out, rtt_error *err);
void rtt_views_free(rtt_view_list *list);
/* The view called `name`, or NULL. */
const rtt_view *rtt_views_find(const rtt_view_list *list, const char *name);
/* The names of the views, ", "-separated and cut short to fit `size`. */
void rtt_views_names(const rtt_view_list *list, char *out, size_t size);

/* Whether a camera can be looked through: finite eye, look_at and up, look_at
 * apart from eye, up not parallel to the view direction, fov 1..179.  err
 * names the field ("eye and look_at are the same point"). */
bool rtt_camera_check(const rtt_camera *camera, rtt_error *err);

/* Puts `camera` (in the scene's own coordinates: moved to the stored ones,
 * rtt_scene.origin) into the scene (after rtt_camera_check).  When the scene's
 * light is the default one at the camera (light_source RTT_LIGHTS_AT_CAMERA),
 * it moves with the camera. */
void rtt_scene_set_camera(rtt_scene *scene, const rtt_camera *camera);
/* The same with eye and look_at in double (camera's own are ignored): a
 * camera 1e7 from the origin keeps its place to the scene's precision. */
void rtt_scene_set_camera_at(rtt_scene *scene, const rtt_camera *camera, const double eye[3],
                             const double look_at[3]);
/* Replaces the scene's lights by the default: one white point light at the
 * camera's eye, intensity 1, no fall-off. */
bool rtt_scene_use_camera_light(rtt_scene *scene, rtt_error *err);
/* Replaces the scene's lights by the view's one light (view->has_light; its
 * position, in the scene's own coordinates, moved to the stored ones). */
bool rtt_scene_use_view_light(rtt_scene *scene, const rtt_view *view, rtt_error *err);

#endif

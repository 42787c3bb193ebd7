/* Internal API the loaders use to append geometry and materials to a scene
 * under construction, and the loaders themselves (not part of include/: only
 * scene/ and its tests use it). */
#ifndef RTT_SCENE_BUILD_H
#define RTT_SCENE_BUILD_H

#include <math.h>

#include "rtt/scene.h"

/* An empty scene with no geometry, materials or lights; path is kept for messages. */
rtt_scene *rtt_scene_new(const char *path, rtt_error *err);

/* Appends a material and returns its index, or UINT32_MAX when out of memory. */
uint32_t rtt_scene_add_material(rtt_scene *scene, const rtt_material *material);
bool rtt_scene_add_light(rtt_scene *scene, const rtt_light *light, rtt_error *err);
/* The same with the position in the scene's own coordinates in double (the
 * light's own position is ignored): kept in double until rtt_scene_finish
 * moves it to the stored frame, so a light 1e7 from the origin keeps its
 * place to the scene's precision, not float's at 1e7.  After finish both
 * take the position as stored coordinates. */
bool rtt_scene_add_light_at(rtt_scene *scene, const rtt_light *light, const double position[3], rtt_error *err);
/* The scene file's camera, its eye and look_at in the scene's own
 * coordinates in double (camera->eye and look_at are ignored), moved to the
 * stored frame by rtt_scene_finish. */
void rtt_scene_set_file_camera(rtt_scene *scene, const rtt_camera *camera, const double eye[3],
                               const double look_at[3]);
/* Every number of the light is finite (position, colour, intensity,
 * attenuation and its distance, radius, quad edges). */
static inline bool rtt_light_is_finite(const rtt_light *l)
{
    return rtt_v3_is_finite(l->position) && rtt_v3_is_finite(l->color) && isfinite(l->intensity) &&
           isfinite(l->attenuation[0]) && isfinite(l->attenuation[1]) && isfinite(l->attenuation[2]) &&
           isfinite(l->radius) && isfinite(l->attenuation_distance) && rtt_v3_is_finite(l->edge_u) &&
           rtt_v3_is_finite(l->edge_v);
}
/* The default material: grey diffuse (see rtt_material in scene.h). */
rtt_material rtt_material_default(void);

/* Appends one mesh: vertex positions (and optional normals, NULL when the
 * file has none), triangles as index triples into these vertices, one
 * material per triangle (or NULL to use `material` for all).  Transform is a
 * row-major 4x4 (double) applied to positions in double (and its inverse transpose to normals),
 * or NULL.  Validates: NaN or infinite coordinates and out-of-range indices
 * are errors naming `source` and the place ("vertex 12", "face 7").  */
bool rtt_scene_add_mesh(rtt_scene *scene, const char *source, const char *name, const rtt_vec3 *positions,
                        const rtt_vec3 *normals, uint32_t vertex_count, const uint32_t *indices,
                        uint32_t triangle_count, const uint32_t *triangle_materials, uint32_t material,
                        const double transform[16], rtt_error *err);
/* The same with positions in double (3 per vertex), as a scene file gives
 * them: they stay in double until the scene is centred. */
bool rtt_scene_add_mesh_exact(rtt_scene *scene, const char *source, const char *name, const double *positions,
                              const rtt_vec3 *normals, uint32_t vertex_count, const uint32_t *indices,
                              uint32_t triangle_count, uint32_t material, const double transform[16],
                              rtt_error *err);

/* Importers: each appends the meshes of one file to `scene`.
 * material_override: index of a scene material to use instead of the file's
 * own, or UINT32_MAX to map the file's materials (MTL/3DS) onto the five types. */
bool rtt_import_assimp(rtt_scene *scene, const char *path, const double transform[16], uint32_t material_override,
                       rtt_error *err);
bool rtt_import_q3bsp(rtt_scene *scene, const char *path, const double transform[16], uint32_t material_override,
                      uint32_t bezier_level, rtt_error *err);
/* A Quake III map's own camera (intermission point, else the first spawn
 * point) and its light entities as lights (q3bsp_entities.c, which documents
 * the rules); run after rtt_import_q3bsp when the map is the whole scene. */
bool rtt_q3bsp_read_entities(rtt_scene *scene, const char *path, rtt_error *err);
/* Lights (and the ambient term) for a map with no light entities, from its
 * light grid of cells grid_size[3] units apart (q3bsp_lightgrid.c, which
 * documents the rule); nothing when the map has no usable grid. */
bool rtt_q3bsp_lights_from_grid(rtt_scene *scene, const char *path, const float grid_size[3], rtt_error *err);
/* The baked kd-tree file (kdt_file.c): the whole scene plus the optimized
 * engine's tree, validated section by section; scene->baked carries the tree. */
rtt_scene *rtt_kdt_read_scene(const char *path, rtt_error *err);
/* The JSON scene file (scene_schema.c): fills `scene` from the file, one
 * located error line on failure (scene/README.md). */
bool rtt_scene_parse_json(rtt_scene *scene, const char *path, const rtt_scene_load_options *opt, rtt_error *err);

#endif

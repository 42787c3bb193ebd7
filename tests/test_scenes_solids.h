/* Scenes of solids written to a file for the back-face culling tests
 * (test_optimized_pgrid.c, test_optimized_bvh.c). */
#ifndef RTT_TEST_SCENES_SOLIDS_H
#define RTT_TEST_SCENES_SOLIDS_H

#include <stdio.h>

#include "rtt/scene.h"

/* Two solid spheres, two meshes of one scene (subdivided icosahedra): one
 * of radius 1.5 round the origin, whose box holds the camera's eye (0.1,
 * 0.2, 0.3), and one of radius 0.3 at (0.9, 0, 0), ahead of it.  False when
 * the file cannot be written. */
static inline bool two_spheres_scene_write(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return false;
    fputs("{\"camera\": {\"eye\": [0.1, 0.2, 0.3], \"look_at\": [2.5, 0, 0], \"fov\": 100},\n"
          " \"meshes\": [\n"
          "  {\"name\": \"around\", \"shape\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1.5, \"subdivisions\": 3}},\n"
          "  {\"name\": \"ahead\", \"shape\": {\"type\": \"sphere\", \"center\": [0.9, 0, 0], \"radius\": 0.3, \"subdivisions\": 3}}\n"
          " ]}\n",
          f);
    return fclose(f) == 0;
}

/* That scene written to path and loaded; NULL (err says why, or empty when
 * the spheres are not two closed meshes) on failure. */
static inline rtt_scene *two_spheres_scene(const char *path, rtt_error *err)
{
    if (!two_spheres_scene_write(path)) return NULL;
    rtt_scene *s = rtt_scene_load(path, NULL, err);
    if (s && !(s->mesh_count == 2 && s->meshes[0].closed && s->meshes[1].closed)) {
        rtt_scene_free(s);
        return NULL;
    }
    return s;
}

#endif

/* The scene model shared by every engine ("model only what a scene requires").
 *
 * A scene is geometry in the global triangle order of docs/ARCHITECTURE.md (meshes in
 * file order, faces in file order, polygons fan-triangulated in order) plus
 * whatever else the scene file names; everything else takes the defaults
 * below.  Engines read the struct directly and never modify it.  */
#ifndef RTT_SCENE_H
#define RTT_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"
#include "rtt/vec3.h"

/* Defaults for what a scene file leaves out. */
#define RTT_DEFAULT_WIDTH 512u
#define RTT_DEFAULT_HEIGHT 512u
#define RTT_DEFAULT_FOV_DEG 60.0f
#define RTT_DEFAULT_MAX_BOUNCES 3u      /* reflection/refraction depth */
#define RTT_DEFAULT_BEZIER_LEVEL 4u     /* Quake III patch subdivisions per side */
#define RTT_DEFAULT_AMBIENT 0.05f

/* The deepest reflection/refraction recursion scene files and renders allow
 * (0: no secondary rays).  Scene files, baked trees and render options are
 * held to it: the renderers recurse (or keep one shading level per bounce)
 * that deep. */
#define RTT_MAX_BOUNCES 64u

/* The thesis' five fixed-function shader types (Listing 4.7). */
typedef enum rtt_material_type {
    RTT_MATERIAL_DIFFUSE = 0,               /* M_D  */
    RTT_MATERIAL_SPECULAR = 1,              /* M_S  diffuse + Phong specular */
    RTT_MATERIAL_REFLECTIVE = 2,            /* M_R  + reflective */
    RTT_MATERIAL_TRANSPARENT = 3,           /* M_T  diffuse + transparent */
    RTT_MATERIAL_TRANSPARENT_REFLECTIVE = 4 /* M_TR all four */
} rtt_material_type;

/* Every field is present for every type; the type says which ones the shader
 * reads (unused ones stay at their defaults).  Defaults: grey diffuse 0.7,
 * specular 0.5 with exponent 32, reflection 0.5, transparency 0.8, ior 1.5,
 * edge width scale 1. */
typedef struct rtt_material {
    char name[64];
    rtt_material_type type;
    rtt_vec3 diffuse;          /* base colour */
    float specular;            /* s_info.blend: Phong highlight intensity */
    float shininess;           /* s_info.exp: Phong exponent */
    float reflection;          /* r_info.blend: weight of the reflected ray */
    float transparency;        /* t_info.blend: weight of the refracted ray */
    float ior;                 /* t_info.refract_index */
    float edge_width_scale;    /* Edge Width Soft Shadows: scales widths of thin occluders */
    /* d_info.diffMap / normMap (Listing 4.7): 0 for none, else 1 + an index
     * into rtt_scene.textures.  A diffuse map replaces `diffuse` (the thesis
     * ignores the base colour when a map is given); a normal map perturbs
     * the shading normal in the triangle's tangent space. */
    uint32_t diffuse_map, normal_map;
} rtt_material;

/* An image a material samples (scene/textures.c): 8-bit RGB texels, rows
 * top to bottom, repeated in both directions, filtered bilinearly.  Diffuse
 * maps are sRGB-encoded (decoded to linear when sampled), normal maps are
 * linear (each channel c maps to 2c/255 - 1). */
typedef struct rtt_texture {
    char name[256];            /* where it came from, for messages and rtt info */
    uint32_t width, height;
    uint8_t *rgb;              /* width * height * 3 bytes */
} rtt_texture;

typedef enum rtt_light_type {
    RTT_LIGHT_POINT = 0,
    RTT_LIGHT_SPHERE = 1, /* spherical area light: soft shadows */
    RTT_LIGHT_QUAD = 2    /* one-sided parallelogram light: soft shadows */
} rtt_light_type;

/* Irradiance at distance d: colour * intensity / (c + l*r + q*r*r), r =
 * d / attenuation_distance, d the distance to `position`: c, l and q are
 * pure numbers and the fall-off's length is attenuation_distance, which
 * scales with the scene like every other length (0 means 1: the scene's unit,
 * what every light had before it existed), so a scene scaled by 1e-20 or
 * 1e20 with its lights renders the same image.  A quad light is the parallelogram position +
 * s*edge_u + t*edge_v, s, t in [-1/2, 1/2], emitting on the side of its
 * normal normalize(edge_u x edge_v) only, as a Lambertian emitter: a point at
 * distance d in direction l from the centre receives the irradiance above
 * times max(0, normal . l) and nothing behind the quad's plane.  Every shadow
 * method shades an area light from its centre and multiplies by the
 * visibility it finds (rtt/shade.h). */
typedef struct rtt_light {
    rtt_light_type type;
    rtt_vec3 position;
    rtt_vec3 color;
    float intensity;
    float attenuation[3]; /* constant, linear, quadratic; default {1, 0, 0} */
    float radius;         /* sphere lights only; 0 for point lights */
    rtt_vec3 edge_u, edge_v; /* quad lights only (edge_u x edge_v non-zero); 0 otherwise */
    float attenuation_distance; /* the length d is measured in; 0 (the default) means 1 */
} rtt_light;

typedef struct rtt_camera {
    rtt_vec3 eye, look_at, up;
    float fov_deg; /* vertical field of view */
} rtt_camera;

/* Where a scene's camera and lights came from (rtt info prints it). */
typedef enum rtt_camera_source {
    RTT_CAMERA_FROM_FILE = 0,     /* the scene file's (or the .kdt's) */
    RTT_CAMERA_FRAMING,           /* the default framing the bounds */
    RTT_CAMERA_INTERMISSION,      /* a Quake III map's info_player_intermission */
    RTT_CAMERA_SPAWN_POINT,       /* a Quake III map's first spawn point */
    RTT_CAMERA_FROM_OPTIONS       /* put there by the caller (rtt_scene_set_camera) */
} rtt_camera_source;

typedef enum rtt_light_source {
    RTT_LIGHTS_FROM_FILE = 0,     /* the scene file's (or the .kdt's) */
    RTT_LIGHTS_AT_CAMERA,         /* the default: one point light at the eye */
    RTT_LIGHTS_MAP,               /* a Quake III map's light entities */
    RTT_LIGHTS_MAP_GRID,          /* lights found in a Quake III map's light grid */
    RTT_LIGHTS_FROM_OPTIONS       /* put there by the caller */
} rtt_light_source;

/* One imported mesh: a run of triangles in the global order. */
typedef struct rtt_mesh {
    char name[64];
    uint32_t first_triangle, triangle_count;
    uint32_t material;
    bool closed; /* every edge shared by exactly two of its triangles (edge width needs it) */
} rtt_mesh;

typedef struct rtt_triangle {
    uint32_t v[3]; /* indices into rtt_scene.vertices */
} rtt_triangle;

/* Opaque tree carried by a scene loaded from a baked .kdt (see optimized/). */
typedef struct rtt_baked_tree rtt_baked_tree;

typedef struct rtt_scene {
    char path[512];                   /* the file it came from, for messages */

    /* geometry */
    uint32_t vertex_count, triangle_count, mesh_count;
    rtt_vec3 *vertices;
    rtt_vec3 *normals;                /* per vertex, or NULL when no mesh supplies them */
    rtt_triangle *triangles;          /* global triangle order */
    uint32_t *triangle_material;      /* material index per triangle */
    uint32_t *triangle_mesh;          /* mesh index per triangle */
    rtt_mesh *meshes;
    uint32_t degenerate_count;        /* zero-area triangles (kept, never hit) */
    /* triangles with an area in the file's coordinates (read in double)
     * that collapse to zero area once stored in float: counted in
     * degenerate_count too; the command line warns about them */
    uint32_t collapsed_count;
    rtt_bounds bounds;                /* of all vertices used by triangles (stored coordinates) */
    /* Stored coordinates are the scene's own minus `origin`, the centre of
     * its bounds: vertices are read in double and stored in float relative
     * to it, so precision follows the scene's size, not where it is.
     * Camera, lights and vertices are stored relative to it; rays handed to
     * an engine are in stored coordinates (rtt_scene_ray_to_stored), and
     * t, u, v, prim do not depend on the shift. */
    double origin[3];
    float *texcoords;                 /* (u, v) per vertex, v up; NULL unless a material has a texture */
    uint32_t texcoord_count;          /* vertices texcoords covers (all of them after loading) */

    /* shading; always at least one material and one light after loading */
    uint32_t material_count, light_count;
    rtt_material *materials;
    rtt_light *lights;
    rtt_camera camera;
    rtt_camera_source camera_source;
    rtt_light_source light_source;
    uint32_t width, height;
    rtt_vec3 background;
    float ambient;
    uint32_t max_bounces;

    /* textures: only in scenes whose materials name them */
    uint32_t texture_count;
    rtt_texture *textures;
    uint32_t missing_texture_count;   /* texture files that could not be read: those materials keep their colour */
    char missing_texture[320];        /* the first of them and why, for the one warning the command line prints */

    rtt_baked_tree *baked;            /* non-NULL for scenes loaded from .kdt */
    void (*baked_free)(rtt_baked_tree *);

    /* the memory budget (rtt/memory_budget.h): bytes allowed (0: the
     * machine's default), bytes and triangles the loaders reserved */
    uint64_t memory_budget, memory_reserved, memory_triangles;
} rtt_scene;

typedef struct rtt_scene_load_options {
    uint32_t bezier_level;            /* 0 → RTT_DEFAULT_BEZIER_LEVEL */
    uint64_t max_memory;              /* the scene's memory budget in bytes; 0 → rtt_memory_budget_default() */
} rtt_scene_load_options;

/* What a file is by its extension: the text after the last dot of the last
 * path component, in any case ("a.b/scene" has none).  rtt_scene_load reads
 * each kind with its own reader. */
typedef enum rtt_file_kind {
    RTT_FILE_UNKNOWN = 0, /* no extension, or one no reader claims (Assimp may still know the content) */
    RTT_FILE_SCENE_JSON,  /* .json: a scene file (scene/README.md) */
    RTT_FILE_KDT,         /* .kdt: a baked tree, the scene and its kd-tree */
    RTT_FILE_Q3BSP,       /* .bsp: a Quake III map */
    RTT_FILE_MESH         /* an extension Assimp reads: .obj, .ply, .off, .3ds, .gltf, .glb, .stl, ... */
} rtt_file_kind;

rtt_file_kind rtt_file_kind_of(const char *path);

/* A point of the scene's own coordinates in stored coordinates (minus
 * origin, in double, then rounded), and back. */
rtt_vec3 rtt_scene_point_to_stored(const rtt_scene *scene, const double p[3]);
void rtt_scene_point_from_stored(const rtt_scene *scene, rtt_vec3 p, double out[3]);

/* Loads a scene file (.json), a bare mesh (anything Assimp reads; a file of
 * unknown kind is offered to Assimp too), a Quake III map (.bsp) or a baked
 * tree (.kdt), picked by rtt_file_kind_of, and fills in every default.  opt
 * may be NULL.  Returns NULL and fills err on failure. */
rtt_scene *rtt_scene_load(const char *path, const rtt_scene_load_options *opt, rtt_error *err);
void rtt_scene_free(rtt_scene *scene);

/* Builds a scene from raw triangles (9 floats each, global order) with every
 * default applied: used by tests, fuzzers and `rtt trace` on tris.bin. */
rtt_scene *rtt_scene_from_triangles(const float *xyz9, uint32_t triangle_count, rtt_error *err);

/* Fills in defaults (camera framing the bounds, point light at the camera,
 * grey diffuse material), computes bounds, degenerate count and mesh
 * closedness.  Loaders call it last; tests that assemble scenes by hand too. */
bool rtt_scene_finish(rtt_scene *scene, rtt_error *err);

/* Zero area (cross product of the edges exactly zero in double precision)
 * or a non-finite corner: such triangles keep their index but never hit. */
bool rtt_triangle_is_degenerate(const rtt_vec3 tri[3]);

/* Corner positions of triangle i. */
static inline void rtt_scene_triangle(const rtt_scene *s, uint32_t i, rtt_vec3 out[3])
{
    const rtt_triangle *t = &s->triangles[i];
    out[0] = s->vertices[t->v[0]];
    out[1] = s->vertices[t->v[1]];
    out[2] = s->vertices[t->v[2]];
}

/* The offset, in world units, that secondary rays start past a surface:
 * relative to the scene's size so scaled scenes behave alike.  Both
 * renderers use it so their images agree. */
float rtt_scene_ray_epsilon(const rtt_scene *scene);

/* The textures of scene/textures.c. */
#define RTT_TEXTURE_MAX_SIDE 8192u      /* larger images are refused (memory bound) */

/* Bilinear sample at (u, v) (v up, repeated), as raw channel values in
 * [0, 1] (srgb false) or decoded from sRGB to linear (srgb true). */
rtt_vec3 rtt_texture_sample(const rtt_texture *texture, float u, float v, bool srgb);
/* Bytes the scene's textures and texture coordinates take (0 without). */
size_t rtt_scene_texture_bytes(const rtt_scene *scene);

#endif

/* The baked kd-tree file (.kdt, "RTTest offline", docs/ARCHITECTURE.md): the on-disk
 * layout shared by scene/ (kdt_file.c reads and writes it) and optimized/
 * (kdt_bake.c fills it, engine_optimized.c adopts the tree).  scene/ may not
 * see optimized/'s headers, so the tree records are defined here and
 * optimized/ _Static_asserts that kd_tree.h's agree byte for byte.
 *
 * File layout, little-endian, every record written as the struct below:
 *   kdt_header                       144 bytes
 *   kdt_section[KDT_SECTION_COUNT]   24 bytes each, in kdt_section_id order
 *   section data                     each at a 16-byte aligned offset, in
 *                                    id order, not overlapping, zero padded
 * checksum = FNV-1a 64 of every byte from offset KDT_CHECKSUM_START (just
 * after the checksum field) to the end of the file.  The magic, version,
 * header size and file size before it are checked exactly instead. */
#ifndef RTT_SCENE_KDT_FORMAT_H
#define RTT_SCENE_KDT_FORMAT_H

#include <stddef.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/scene.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error ".kdt records are written as in memory: a little-endian target is required"
#endif

#define KDT_MAGIC "RTTKDT\0\0"
#define KDT_VERSION 2u
#define KDT_DEPTH_LIMIT 64u          /* deeper trees are refused: kernels' stacks rely on it */
#define KDT_ALIGN 16u
#define KDT_CHECKSUM_START 32u

typedef enum kdt_section_id {
    KDT_SECTION_SETTINGS = 0,        /* kdt_scene_settings, one */
    KDT_SECTION_VERTICES,            /* rtt_vec3 x vertex_count */
    KDT_SECTION_NORMALS,             /* rtt_vec3 x vertex_count, or empty */
    KDT_SECTION_TRIANGLES,           /* rtt_triangle x triangle_count */
    KDT_SECTION_TRIANGLE_MATERIAL,   /* uint32 x triangle_count */
    KDT_SECTION_TRIANGLE_MESH,       /* uint32 x triangle_count */
    KDT_SECTION_MESHES,              /* kdt_mesh x mesh_count */
    KDT_SECTION_MATERIALS,           /* kdt_material x material_count */
    KDT_SECTION_LIGHTS,              /* kdt_light x light_count */
    KDT_SECTION_NODES,               /* kdt_node x node_count */
    KDT_SECTION_LEAVES,              /* kdt_leaf x leaf_count */
    KDT_SECTION_RECORDS,             /* kdt_triangle x record_count */
    KDT_SECTION_COUNT
} kdt_section_id;

/* 144 bytes. */
typedef struct kdt_header {
    char magic[8];
    uint32_t version;
    uint32_t header_size;            /* sizeof(kdt_header) */
    uint64_t file_size;
    uint64_t checksum;               /* FNV-1a 64 of bytes [KDT_CHECKSUM_START, file_size) */
    uint32_t section_count;          /* KDT_SECTION_COUNT */
    uint32_t flags;                  /* 0 */
    uint32_t vertex_count, triangle_count, mesh_count, material_count, light_count;
    uint32_t node_count, leaf_count, record_count;
    float tree_lo[3], tree_hi[3];    /* the root's box (empty when no record) */
    /* build settings and what the build measured (rtt_tree_info) */
    uint32_t max_depth, depth, empty_leaf_count, reserved;
    uint64_t reference_cap;
    double sah_cost, build_seconds;
    uint64_t reserved2;
} kdt_header;
_Static_assert(sizeof(kdt_header) == 144, "kdt_header is 144 bytes");
_Static_assert(offsetof(kdt_header, checksum) + 8 == KDT_CHECKSUM_START, "checksum covers what follows it");

/* 24 bytes: where a section is and how big its elements are. */
typedef struct kdt_section {
    uint32_t id;                     /* kdt_section_id, equal to its index */
    uint32_t element_size;
    uint64_t offset, size;           /* bytes from the start of the file */
} kdt_section;
_Static_assert(sizeof(kdt_section) == 24, "kdt_section is 24 bytes");

/* 80 bytes: everything of rtt_scene that is not an array. */
typedef struct kdt_scene_settings {
    float eye[3], look_at[3], up[3], fov_deg;
    uint32_t width, height, max_bounces, degenerate_count;
    float background[3], ambient;
    uint32_t has_normals, collapsed_count;
    double origin[3];                /* the scene's coordinates = stored + origin (rtt_scene.origin) */
} kdt_scene_settings;
_Static_assert(sizeof(kdt_scene_settings) == 104, "kdt_scene_settings is 104 bytes");

/* 80 bytes. */
typedef struct kdt_mesh {
    char name[64];
    uint32_t first_triangle, triangle_count, material, closed;
} kdt_mesh;
_Static_assert(sizeof(kdt_mesh) == 80, "kdt_mesh is 80 bytes");

/* 104 bytes. */
typedef struct kdt_material {
    char name[64];
    uint32_t type;
    float diffuse[3];
    float specular, shininess, reflection, transparency, ior, edge_width_scale;
} kdt_material;
_Static_assert(sizeof(kdt_material) == 104, "kdt_material is 104 bytes");

/* 48 bytes. */
typedef struct kdt_light {
    uint32_t type;
    float position[3], color[3], intensity, attenuation[3], radius;
} kdt_light;
_Static_assert(sizeof(kdt_light) == 48, "kdt_light is 48 bytes");

/* The tree records: kd_tree.h's kd_node, kd_leaf and kd_triangle exactly
 * (optimized/engine_optimized.c asserts it).  Node: bits = (index << 2) |
 * axis; axis 3 = leaf with `leaf` its index into the leaves; else `split`
 * is the plane and index, index + 1 the children. */
typedef struct kdt_node {
    union {
        float split;
        uint32_t leaf;
    };
    uint32_t bits;
} kdt_node;
_Static_assert(sizeof(kdt_node) == 8, "kdt_node is 8 bytes");

typedef struct kdt_leaf {
    uint32_t first, count;
    float lo[3], hi[3];
} kdt_leaf;
_Static_assert(sizeof(kdt_leaf) == 32, "kdt_leaf is 32 bytes");

typedef struct kdt_triangle {
    float n_u, n_v, a_k, a_u, a_v, b_nu, b_nv, c_nu, c_nv;
    uint32_t k, prim, pad;
} kdt_triangle;
_Static_assert(sizeof(kdt_triangle) == 48, "kdt_triangle is 48 bytes");

/* The tree a .kdt carries (scene->baked), validated: every child index is
 * greater than its parent's, every node but the root has one parent, depth
 * <= KDT_DEPTH_LIMIT, leaf ranges inside the records, prims < the scene's
 * triangle count, every float finite.  Arrays are malloc'd (16-byte
 * aligned) and owned; rtt_kdt_baked_free releases them.  The writer takes
 * the same struct as a view of the engine's arrays. */
struct rtt_baked_tree {
    kdt_node *nodes;
    kdt_leaf *leaves;
    kdt_triangle *records;
    uint32_t node_count, leaf_count, record_count;
    rtt_bounds bounds;               /* the root's box */
    rtt_tree_info info;
};

static inline uint64_t rtt_kdt_checksum_update(uint64_t hash, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; i++) hash = (hash ^ p[i]) * 0x100000001b3ull;
    return hash;
}
#define KDT_CHECKSUM_INIT 0xcbf29ce484222325ull

/* Writes scene + tree as a .kdt at path (temporary + rename: an existing
 * file is replaced only by a complete one). */
bool rtt_kdt_write(const char *path, const rtt_scene *scene, const rtt_baked_tree *tree, rtt_error *err);
void rtt_kdt_baked_free(rtt_baked_tree *tree);

#endif

/* Mesh files checked against themselves (mesh_header_check.c), before and
 * after Assimp.
 *
 * Assimp believes a header's counts: it allocates what a header declares
 * before reading a byte of the body, reads a truncated file up to its end
 * and returns what it got, and clamps an out-of-range face index onto the
 * last vertex.  So before Assimp sees a file, its header's counts are
 * checked against the body that follows (OFF, PLY, STL: the whole body is
 * walked, nothing allocated; glTF/GLB: every accessor inside its buffer
 * view, every view inside its buffer, every buffer inside its bytes), and
 * after Assimp the imported mesh is checked against the counts.  Every
 * message names the file, the element and its number, from 0:
 *   "bunny.off: face 17: vertex index 9 is out of range (8 vertices)"
 *   "bunny.ply: the file ends in face 20283 of the 75408 the header declares" */
#ifndef RTT_SCENE_MESH_HEADER_CHECK_H
#define RTT_SCENE_MESH_HEADER_CHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/error.h"

struct aiScene;

/* What a file's header declares, once checked against its body. */
typedef struct rtt_mesh_header {
    bool counted;        /* the format declares its counts (OFF, PLY, STL) */
    uint64_t vertices;   /* declared (STL: 3 per triangle) */
    uint64_t faces;      /* declared (STL: triangles) */
    uint64_t triangles;  /* the triangles the faces fan into (OFF, PLY, STL); glTF: accessors' bound */
    uint64_t bytes;      /* glTF/GLB: the bytes of every buffer */
} rtt_mesh_header;

/* The check of `bytes` (the whole file) as format `format` (its extension,
 * any case: "off", "ply", "stl", "gltf", "glb"; other formats pass with
 * nothing counted).  `path` names the file in messages and is where a glTF's
 * external buffers are looked for. */
bool rtt_mesh_header_scan(const char *path, const char *format, const unsigned char *bytes, size_t size,
                          rtt_mesh_header *out, rtt_error *err);
/* The same on the file at `path` (mapped, not read into memory). */
bool rtt_mesh_header_check_file(const char *path, rtt_mesh_header *out, rtt_error *err);
/* After Assimp: the faces it imported against the header's. */
bool rtt_mesh_header_check_import(const char *path, const rtt_mesh_header *header, const struct aiScene *ai,
                                  rtt_error *err);

#endif

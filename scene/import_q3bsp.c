/* Quake III Arena maps (IBSP version 46, as in OpenArena's pak files).
 *
 * Our own loader: Assimp's Q3 BSP importer crashes on the OpenArena maps
 * (docs/ARCHITECTURE.md).  Only four of the 17 lumps are read:
 *
 *   lump 1   textures   72 bytes: name[64] (the shader), flags, contents
 *   lump 10  vertices   44 bytes: position[3], texcoord[2], lightmap[2],
 *                       normal[3] (floats), colour[4] (bytes)
 *   lump 11  meshverts   4 bytes: int32 offset from a face's first vertex
 *   lump 13  faces     104 bytes: texture, effect, type, vertex, n_vertices,
 *                       meshvert, n_meshverts, lightmap index, lightmap
 *                       start[2] and size[2], lightmap origin[3] and
 *                       vectors[2][3], normal[3], patch size[2]
 *
 * Face types: 1 polygon and 3 mesh are triangle lists in meshverts
 * (vertex = face.vertex + meshvert, three at a time, in order); 2 is a
 * biquadratic Bezier patch of w x h control points (both odd, >= 3), made of
 * (w-1)/2 x (h-1)/2 sub-patches of 3x3 points; 4 billboards (flares) have no
 * geometry and are skipped.  Any other type is an error.
 *
 * Global triangle order: faces in file order (all models: world and brush
 * entities alike); within a polygon or mesh face, meshvert order; within a
 * patch, sub-patches row by row (sub-patch (px, py) uses control points
 * (2py + j) * w + 2px + i, px fastest), and within a sub-patch its
 * bezier_level x bezier_level quads row by row, each as the triangles
 * (v00, v10, v01), (v10, v11, v01).  A patch's tessellated vertices are
 * shared between its sub-patches (watertight inside a patch).
 *
 * Winding: rtt's front faces are counter-clockwise (the geometric normal
 * agrees with the shading normal); Quake's are clockwise, so the second and
 * third corners of every polygon and mesh triangle are swapped (checked on
 * the OpenArena maps: 99% of triangles then agree with the file's normals,
 * the rest are two-sided or odd faces).  Patch quads as above already agree
 * (dP/du x dP/dv points along Quake's control-point normals); a patch whose
 * control normals say otherwise (inverted in the editor) is wound the other
 * way round instead.
 *
 * Normals: polygons and meshes keep the file's per-vertex normals; patch
 * vertices get the normalized cross product of the Bezier partial
 * derivatives, falling back to the interpolated control-point normals where
 * the derivative degenerates (collapsed rows of control points).
 *
 * Coordinates: Quake is Z-up, rtt is Y-up; every position and normal is
 * converted with (x, y, z) -> (x, z, -y), a rotation (determinant +1), so
 * winding and handedness are preserved.  `transform` applies after that.
 *
 * The whole map becomes one rtt mesh (one per face would be tens of
 * thousands) with one grey diffuse material per shader its faces use, each
 * with the shader's image as its diffuse map where q3_textures.c finds one
 * (then the vertices carry the file's texture coordinates, t flipped to v
 * up, Bezier-interpolated on patches); with no texture source at all, one
 * grey diffuse material for the whole map; or `material_override`.  Its vertex array
 * is the whole vertex lump (so shared indices stay shared) followed by the
 * patch grids; vertices no triangle uses do not count for the bounds.
 *
 * Hostile input: every count, offset and length is checked against the file
 * size before use, lumps must be whole records, every face range and
 * meshvert must lie in its face, every float must be finite.  Output is
 * bounded by the input, so a small file cannot ask for a huge allocation:
 * polygons and meshes may have at most 4 triangles per vertex of the map
 * (faces share meshvert ranges, but own disjoint vertex ranges; the
 * OpenArena maps have 0.5 to 0.7), and all patches together at most as many
 * 3x3 sub-patches as the map has vertices (a patch has more control points
 * than sub-patches).  */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/files.h"
#include "rtt/memory_budget.h"
#include "q3_textures.h"
#include "scene_build.h"
#include "textures.h"

#define BSP_HEADER_SIZE 144u /* magic, version, 17 lump entries of (offset, length) */
#define BSP_LUMP_COUNT 17u
#define BSP_VERSION 46
#define BSP_LUMP_TEXTURES 1u
#define BSP_TEXTURE_SIZE 72u
#define BSP_LUMP_VERTICES 10u
#define BSP_LUMP_MESHVERTS 11u
#define BSP_LUMP_FACES 13u
#define BSP_VERTEX_SIZE 44u
#define BSP_MESHVERT_SIZE 4u
#define BSP_FACE_SIZE 104u
#define BSP_MAX_BEZIER_LEVEL 64u
#define BSP_MAX_TRIANGLES (1u << 28) /* the scene's own limit (scene.c) */
#define BSP_TRIANGLES_PER_VERTEX 4u  /* real maps: 0.7; a planar face: < 2 */

enum { FACE_POLYGON = 1, FACE_PATCH = 2, FACE_MESH = 3, FACE_BILLBOARD = 4 };

typedef struct bsp_face {
    int32_t texture, type, vertex, vertex_count, meshvert, meshvert_count, width, height;
} bsp_face;

typedef struct bsp_map {
    const char *path;
    long file_size;
    uint8_t *vertex_lump, *meshvert_lump, *face_lump, *texture_lump;
    uint32_t vertex_count, meshvert_count, face_count, texture_count;
    uint32_t level;
} bsp_map;

/* What the faces produce, counted before anything is allocated. */
typedef struct bsp_totals {
    uint64_t triangles, list_triangles, patch_vertices, subpatches;
} bsp_totals;

static const char *lump_name(uint32_t lump)
{
    switch (lump) {
    case BSP_LUMP_VERTICES: return "vertices";
    case BSP_LUMP_MESHVERTS: return "meshverts";
    case BSP_LUMP_FACES: return "faces";
    case BSP_LUMP_TEXTURES: return "textures";
    default: return "lump";
    }
}

/* Little-endian reads that need no alignment. */
static int32_t read_i32(const uint8_t *p)
{
    return (int32_t)((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
}

static float read_f32(const uint8_t *p)
{
    uint32_t bits = (uint32_t)read_i32(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static rtt_vec3 read_vec3(const uint8_t *p) { return rtt_v3(read_f32(p), read_f32(p + 4), read_f32(p + 8)); }

/* Quake's Z-up to rtt's Y-up. */
static rtt_vec3 z_up_to_y_up(rtt_vec3 q) { return rtt_v3(q.x, q.z, -q.y); }

static rtt_vec3 vertex_position(const bsp_map *map, uint32_t i)
{
    return read_vec3(map->vertex_lump + (size_t)i * BSP_VERTEX_SIZE);
}

static rtt_vec3 vertex_normal(const bsp_map *map, uint32_t i)
{
    return read_vec3(map->vertex_lump + (size_t)i * BSP_VERTEX_SIZE + 28);
}

static uint32_t meshvert(const bsp_map *map, uint32_t i)
{
    return (uint32_t)read_i32(map->meshvert_lump + (size_t)i * BSP_MESHVERT_SIZE);
}

static bsp_face read_face(const bsp_map *map, uint32_t i)
{
    const uint8_t *p = map->face_lump + (size_t)i * BSP_FACE_SIZE;
    return (bsp_face){.texture = read_i32(p),
                      .type = read_i32(p + 8),
                      .vertex = read_i32(p + 12),
                      .vertex_count = read_i32(p + 16),
                      .meshvert = read_i32(p + 20),
                      .meshvert_count = read_i32(p + 24),
                      .width = read_i32(p + 96),
                      .height = read_i32(p + 100)};
}

/* ---- reading and validating the container ---- */

static bool read_at(FILE *file, const bsp_map *map, long offset, void *out, size_t size, rtt_error *err)
{
    if (fseek(file, offset, SEEK_SET) != 0 || fread(out, 1, size, file) != size)
        return rtt_error_set(err, "%s: read error at byte %ld", map->path, offset);
    return true;
}

static bool read_lump(FILE *file, const bsp_map *map, const uint8_t *header, uint32_t lump, uint32_t record_size,
                      uint8_t **out, uint32_t *count, rtt_error *err)
{
    int32_t offset = read_i32(header + 8 + 8 * lump), length = read_i32(header + 12 + 8 * lump);
    if (length % (int32_t)record_size != 0)
        return rtt_error_set(err, "%s: lump %u (%s): length %d is not a multiple of %u", map->path, lump,
                             lump_name(lump), length, record_size);
    *count = (uint32_t)length / record_size;
    *out = malloc((size_t)length + 1);
    if (!*out) return rtt_error_set(err, "%s: out of memory for lump %u (%d bytes)", map->path, lump, length);
    return read_at(file, map, offset, *out, (size_t)length, err);
}

static bool read_header(FILE *file, bsp_map *map, uint8_t header[BSP_HEADER_SIZE], rtt_error *err)
{
    if (fseek(file, 0, SEEK_END) != 0 || (map->file_size = ftell(file)) < 0)
        return rtt_error_set(err, "%s: cannot determine the file size", map->path);
    if (map->file_size < (long)BSP_HEADER_SIZE)
        return rtt_error_set(err, "%s: file is too small for an IBSP header (%ld bytes, need %u)", map->path,
                             map->file_size, BSP_HEADER_SIZE);
    if (!read_at(file, map, 0, header, BSP_HEADER_SIZE, err)) return false;
    if (memcmp(header, "IBSP", 4) != 0)
        return rtt_error_set(err, "%s: not a Quake III map (magic is not \"IBSP\")", map->path);
    int32_t version = read_i32(header + 4);
    if (version != BSP_VERSION)
        return rtt_error_set(err, "%s: IBSP version %d is not supported (only %d)", map->path, version, BSP_VERSION);
    for (uint32_t lump = 0; lump < BSP_LUMP_COUNT; lump++) {
        int32_t offset = read_i32(header + 8 + 8 * lump), length = read_i32(header + 12 + 8 * lump);
        if (offset < 0 || length < 0)
            return rtt_error_set(err, "%s: lump %u: negative offset %d or length %d", map->path, lump, offset,
                                 length);
        if ((int64_t)offset + length > (int64_t)map->file_size)
            return rtt_error_set(err, "%s: lump %u: range %d+%d exceeds the file size %ld", map->path, lump, offset,
                                 length, map->file_size);
    }
    return true;
}

static bool read_map(const char *path, bsp_map *map, rtt_error *err)
{
    FILE *file = rtt_file_open_regular(path, err);
    if (!file) return false;
    uint8_t header[BSP_HEADER_SIZE];
    bool ok = read_header(file, map, header, err) &&
              read_lump(file, map, header, BSP_LUMP_VERTICES, BSP_VERTEX_SIZE, &map->vertex_lump,
                        &map->vertex_count, err) &&
              read_lump(file, map, header, BSP_LUMP_MESHVERTS, BSP_MESHVERT_SIZE, &map->meshvert_lump,
                        &map->meshvert_count, err) &&
              read_lump(file, map, header, BSP_LUMP_FACES, BSP_FACE_SIZE, &map->face_lump, &map->face_count, err) &&
              read_lump(file, map, header, BSP_LUMP_TEXTURES, BSP_TEXTURE_SIZE, &map->texture_lump,
                        &map->texture_count, err);
    fclose(file);
    return ok;
}

static bool check_vertices(const bsp_map *map, rtt_error *err)
{
    for (uint32_t i = 0; i < map->vertex_count; i++) {
        if (!rtt_v3_is_finite(vertex_position(map, i)))
            return rtt_error_set(err, "%s: vertex %u: position is NaN or infinite", map->path, i);
        if (!rtt_v3_is_finite(vertex_normal(map, i)))
            return rtt_error_set(err, "%s: vertex %u: normal is NaN or infinite", map->path, i);
    }
    return true;
}

/* ---- validating faces and counting what they produce ---- */

static bool check_vertex_range(const bsp_map *map, uint32_t index, const bsp_face *f, rtt_error *err)
{
    if (f->vertex < 0 || f->vertex_count < 0 || (int64_t)f->vertex + f->vertex_count > map->vertex_count)
        return rtt_error_set(err, "%s: face %u: vertex range %d+%d exceeds %u vertices", map->path, index, f->vertex,
                             f->vertex_count, map->vertex_count);
    return true;
}

static bool check_triangle_face(const bsp_map *map, uint32_t index, const bsp_face *f, bsp_totals *totals,
                                rtt_error *err)
{
    if (f->meshvert < 0 || f->meshvert_count < 0 || (int64_t)f->meshvert + f->meshvert_count > map->meshvert_count)
        return rtt_error_set(err, "%s: face %u: meshvert range %d+%d exceeds %u meshverts", map->path, index,
                             f->meshvert, f->meshvert_count, map->meshvert_count);
    if (f->meshvert_count % 3 != 0)
        return rtt_error_set(err, "%s: face %u: meshvert count %d is not a multiple of 3", map->path, index,
                             f->meshvert_count);
    for (int32_t k = 0; k < f->meshvert_count; k++) {
        uint32_t offset = meshvert(map, (uint32_t)(f->meshvert + k));
        if (offset >= (uint32_t)f->vertex_count)
            return rtt_error_set(err, "%s: face %u: meshvert %d is %d, outside the face's %d vertices", map->path,
                                 index, f->meshvert + k, (int32_t)offset, f->vertex_count);
    }
    totals->list_triangles += (uint64_t)f->meshvert_count / 3;
    totals->triangles += (uint64_t)f->meshvert_count / 3;
    return true;
}

static bool check_patch_face(const bsp_map *map, uint32_t index, const bsp_face *f, bsp_totals *totals,
                             rtt_error *err)
{
    if (f->width < 3 || f->height < 3 || f->width % 2 == 0 || f->height % 2 == 0)
        return rtt_error_set(err, "%s: face %u: patch size %dx%d: width and height must be odd and at least 3",
                             map->path, index, f->width, f->height);
    if ((int64_t)f->width * f->height != f->vertex_count)
        return rtt_error_set(err, "%s: face %u: patch size %dx%d needs %lld control points, the face has %d",
                             map->path, index, f->width, f->height, (long long)f->width * f->height,
                             f->vertex_count);
    uint64_t across = (uint64_t)(f->width - 1) / 2, down = (uint64_t)(f->height - 1) / 2, level = map->level;
    totals->subpatches += across * down;
    totals->patch_vertices += (across * level + 1) * (down * level + 1);
    totals->triangles += across * down * 2 * level * level;
    return true;
}

static bool check_faces(const bsp_map *map, bsp_totals *totals, rtt_error *err)
{
    memset(totals, 0, sizeof *totals);
    for (uint32_t i = 0; i < map->face_count; i++) {
        bsp_face f = read_face(map, i);
        if (f.type == FACE_BILLBOARD) continue;
        if (f.type != FACE_POLYGON && f.type != FACE_MESH && f.type != FACE_PATCH)
            return rtt_error_set(err, "%s: face %u: unknown face type %d", map->path, i, f.type);
        if (!check_vertex_range(map, i, &f, err)) return false;
        bool ok = f.type == FACE_PATCH ? check_patch_face(map, i, &f, totals, err)
                                       : check_triangle_face(map, i, &f, totals, err);
        if (!ok) return false;
        /* The budgets that keep output proportional to the file (see the top). */
        if (totals->list_triangles > BSP_TRIANGLES_PER_VERTEX * (uint64_t)map->vertex_count)
            return rtt_error_set(err, "%s: face %u: polygons and meshes have more than %u triangles per vertex",
                                 map->path, i, BSP_TRIANGLES_PER_VERTEX);
        if (totals->subpatches > map->vertex_count)
            return rtt_error_set(err, "%s: face %u: patches have more sub-patches than the map has vertices (%u)",
                                 map->path, i, map->vertex_count);
        if (totals->triangles > BSP_MAX_TRIANGLES)
            return rtt_error_set(err, "%s: face %u: more than %u triangles at bezier level %u", map->path, i,
                                 BSP_MAX_TRIANGLES, map->level);
    }
    if (totals->triangles == 0) return rtt_error_set(err, "%s: the map has no triangles", map->path);
    return true;
}

/* ---- building the mesh ---- */

typedef struct bsp_mesh {
    rtt_vec3 *positions, *normals;
    float *texcoords;              /* (u, v) per vertex, v up */
    uint32_t *indices;
    uint32_t *triangle_texture;    /* the face's texture per triangle */
    uint32_t vertex_count, triangle_count;
} bsp_mesh;

static void emit_triangle(bsp_mesh *mesh, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t *t = &mesh->indices[3 * (size_t)mesh->triangle_count++];
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

/* Quake winds front faces clockwise (its polygons' normals point against
 * their triangles' right-handed normals); rtt's front faces are
 * counter-clockwise, so the second and third corners swap. */
static void emit_triangle_face(const bsp_map *map, const bsp_face *f, bsp_mesh *mesh)
{
    for (int32_t k = 0; k < f->meshvert_count; k += 3) {
        uint32_t base = (uint32_t)f->vertex, first = (uint32_t)f->meshvert + (uint32_t)k;
        emit_triangle(mesh, base + meshvert(map, first), base + meshvert(map, first + 2),
                      base + meshvert(map, first + 1));
    }
}

/* Quadratic Bernstein weights and their derivatives at t. */
static void bernstein2(double t, double w[3], double dw[3])
{
    w[0] = (1.0 - t) * (1.0 - t);
    w[1] = 2.0 * t * (1.0 - t);
    w[2] = t * t;
    dw[0] = -2.0 * (1.0 - t);
    dw[1] = 2.0 - 4.0 * t;
    dw[2] = 2.0 * t;
}

static double length3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* Position and normal (Quake coordinates) of one 3x3 sub-patch at (s, t);
 * first is the vertex index of its corner control point, stride the patch
 * width.  The normal is orientation * (dP/ds x dP/dt), or the interpolated
 * control normals where the derivative degenerates; the return value is the
 * derivative normal's agreement with the control normals (positive when they
 * point the same way, 0 where it degenerates). */
static double eval_subpatch(const bsp_map *map, uint32_t first, uint32_t stride, double s, double t,
                            float orientation, rtt_vec3 *position, rtt_vec3 *normal)
{
    double ws[3], dws[3], wt[3], dwt[3], p[3] = {0}, ds[3] = {0}, dt[3] = {0}, n[3] = {0};
    bernstein2(s, ws, dws);
    bernstein2(t, wt, dwt);
    for (uint32_t j = 0; j < 3; j++)
        for (uint32_t i = 0; i < 3; i++) {
            uint32_t v = first + j * stride + i;
            rtt_vec3 c = vertex_position(map, v), cn = vertex_normal(map, v);
            double xyz[3] = {c.x, c.y, c.z}, nxyz[3] = {cn.x, cn.y, cn.z};
            for (int a = 0; a < 3; a++) {
                p[a] += ws[i] * wt[j] * xyz[a];
                ds[a] += dws[i] * wt[j] * xyz[a];
                dt[a] += ws[i] * dwt[j] * xyz[a];
                n[a] += ws[i] * wt[j] * nxyz[a];
            }
        }
    double cross[3] = {ds[1] * dt[2] - ds[2] * dt[1], ds[2] * dt[0] - ds[0] * dt[2], ds[0] * dt[1] - ds[1] * dt[0]};
    double len = length3(cross);
    *position = rtt_v3((float)p[0], (float)p[1], (float)p[2]);
    /* relative test: the derivatives scale with the patch */
    if (!(len > 0.0 && len > 1e-9 * length3(ds) * length3(dt))) {
        *normal = rtt_v3_normalize(rtt_v3((float)n[0], (float)n[1], (float)n[2]));
        return 0.0;
    }
    double to_unit = orientation / len;
    *normal = rtt_v3((float)(cross[0] * to_unit), (float)(cross[1] * to_unit), (float)(cross[2] * to_unit));
    return (cross[0] * n[0] + cross[1] * n[1] + cross[2] * n[2]) / len;
}

/* Evaluates the patch's vertex grid (shared by its sub-patches) at
 * mesh->vertex_count onwards with the given orientation; returns the summed
 * agreement of derivative and control normals. */
static double eval_patch_grid(const bsp_map *map, const bsp_face *f, float orientation, bsp_mesh *mesh)
{
    const uint32_t level = map->level, width = (uint32_t)f->width;
    const uint32_t across = (width - 1) / 2, down = ((uint32_t)f->height - 1) / 2;
    const uint32_t columns = across * level + 1, rows = down * level + 1;
    double agreement = 0.0;
    for (uint32_t row = 0; row < rows; row++)
        for (uint32_t column = 0; column < columns; column++) {
            uint32_t px = column / level < across ? column / level : across - 1;
            uint32_t py = row / level < down ? row / level : down - 1;
            double s = (double)(column - px * level) / level, t = (double)(row - py * level) / level;
            uint32_t first = (uint32_t)f->vertex + 2 * py * width + 2 * px;
            uint32_t v = mesh->vertex_count + row * columns + column;
            agreement += eval_subpatch(map, first, width, s, t, orientation, &mesh->positions[v], &mesh->normals[v]);
        }
    return agreement;
}

/* The file's texture coordinate (s, t) of vertex i as (u, v) with v up. */
static void vertex_texcoord(const bsp_map *map, uint32_t i, float uv[2])
{
    const uint8_t *p = map->vertex_lump + (size_t)i * BSP_VERTEX_SIZE + 12;
    float s = read_f32(p), t = read_f32(p + 4);
    uv[0] = isfinite(s) ? s : 0.0f;
    uv[1] = isfinite(t) ? 1.0f - t : 0.0f;
}

/* Texture coordinates of the patch's vertex grid, the Bezier
 * interpolation of its control points' (as eval_patch_grid's positions). */
static void eval_patch_texcoords(const bsp_map *map, const bsp_face *f, bsp_mesh *mesh)
{
    const uint32_t level = map->level, width = (uint32_t)f->width;
    const uint32_t across = (width - 1) / 2, down = ((uint32_t)f->height - 1) / 2;
    const uint32_t columns = across * level + 1, rows = down * level + 1;
    for (uint32_t row = 0; row < rows; row++)
        for (uint32_t column = 0; column < columns; column++) {
            uint32_t px = column / level < across ? column / level : across - 1;
            uint32_t py = row / level < down ? row / level : down - 1;
            double ws[3], wt[3], unused[3], uv[2] = {0.0, 0.0};
            bernstein2((double)(column - px * level) / level, ws, unused);
            bernstein2((double)(row - py * level) / level, wt, unused);
            uint32_t first = (uint32_t)f->vertex + 2 * py * width + 2 * px;
            for (uint32_t j = 0; j < 3; j++)
                for (uint32_t i = 0; i < 3; i++) {
                    float c[2];
                    vertex_texcoord(map, first + j * width + i, c);
                    uv[0] += ws[i] * wt[j] * c[0];
                    uv[1] += ws[i] * wt[j] * c[1];
                }
            float *out = &mesh->texcoords[2 * ((size_t)mesh->vertex_count + row * columns + column)];
            out[0] = (float)uv[0];
            out[1] = (float)uv[1];
        }
}

/* Quake's patches have dP/du x dP/dv along their control normals; a patch
 * inverted in the editor has it against them, and is wound the other way so
 * that geometric and shading normals still agree. */
static void emit_patch_face(const bsp_map *map, const bsp_face *f, bsp_mesh *mesh)
{
    const uint32_t level = map->level, width = (uint32_t)f->width;
    const uint32_t across = (width - 1) / 2, down = ((uint32_t)f->height - 1) / 2;
    const uint32_t columns = across * level + 1, rows = down * level + 1, grid = mesh->vertex_count;
    const bool inverted = eval_patch_grid(map, f, 1.0f, mesh) < 0.0;
    if (inverted) eval_patch_grid(map, f, -1.0f, mesh);
    eval_patch_texcoords(map, f, mesh);
    mesh->vertex_count += rows * columns;
    for (uint32_t py = 0; py < down; py++)
        for (uint32_t px = 0; px < across; px++)
            for (uint32_t b = 0; b < level; b++)
                for (uint32_t a = 0; a < level; a++) {
                    uint32_t v00 = grid + (py * level + b) * columns + px * level + a;
                    uint32_t v10 = v00 + 1, v01 = v00 + columns, v11 = v01 + 1;
                    if (inverted) {
                        emit_triangle(mesh, v00, v01, v10);
                        emit_triangle(mesh, v10, v01, v11);
                    } else {
                        emit_triangle(mesh, v00, v10, v01);
                        emit_triangle(mesh, v10, v11, v01);
                    }
                }
}

static bool build_mesh(const bsp_map *map, const bsp_totals *totals, bsp_mesh *mesh, rtt_error *err)
{
    size_t vertices = (size_t)map->vertex_count + (size_t)totals->patch_vertices;
    mesh->positions = malloc(vertices * sizeof *mesh->positions + 1);
    mesh->normals = malloc(vertices * sizeof *mesh->normals + 1);
    mesh->indices = malloc((size_t)totals->triangles * 3 * sizeof *mesh->indices + 1);
    mesh->texcoords = malloc(vertices * 2 * sizeof *mesh->texcoords + 1);
    mesh->triangle_texture = malloc((size_t)totals->triangles * sizeof *mesh->triangle_texture + 1);
    if (!mesh->positions || !mesh->normals || !mesh->indices || !mesh->texcoords || !mesh->triangle_texture)
        return rtt_error_set(err, "%s: out of memory for %llu triangles", map->path,
                             (unsigned long long)totals->triangles);
    for (uint32_t i = 0; i < map->vertex_count; i++) {
        mesh->positions[i] = vertex_position(map, i);
        mesh->normals[i] = vertex_normal(map, i);
        vertex_texcoord(map, i, &mesh->texcoords[2 * (size_t)i]);
    }
    mesh->vertex_count = map->vertex_count;
    for (uint32_t i = 0; i < map->face_count; i++) {
        bsp_face f = read_face(map, i);
        uint32_t first = mesh->triangle_count;
        if (f.type == FACE_PATCH)
            emit_patch_face(map, &f, mesh);
        else if (f.type == FACE_POLYGON || f.type == FACE_MESH)
            emit_triangle_face(map, &f, mesh);
        for (uint32_t t = first; t < mesh->triangle_count; t++)
            mesh->triangle_texture[t] = f.texture >= 0 ? (uint32_t)f.texture : UINT32_MAX;
    }
    for (uint32_t i = 0; i < mesh->vertex_count; i++) {
        mesh->positions[i] = z_up_to_y_up(mesh->positions[i]);
        mesh->normals[i] = z_up_to_y_up(mesh->normals[i]);
    }
    return true;
}

static uint32_t map_material(rtt_scene *scene, const bsp_map *map, uint32_t material_override, rtt_error *err)
{
    if (material_override != UINT32_MAX) return material_override;
    rtt_material grey = rtt_material_default();
    snprintf(grey.name, sizeof grey.name, "q3bsp");
    uint32_t index = rtt_scene_add_material(scene, &grey);
    if (index == UINT32_MAX) rtt_error_set(err, "%s: out of memory for a material", map->path);
    return index;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

bool rtt_import_q3bsp(rtt_scene *scene, const char *path, const double transform[16], uint32_t material_override,
                      uint32_t bezier_level, rtt_error *err)
{
    bsp_map map = {.path = path, .level = bezier_level ? bezier_level : RTT_DEFAULT_BEZIER_LEVEL};
    if (map.level > BSP_MAX_BEZIER_LEVEL)
        return rtt_error_set(err, "%s: bezier level %u is above the maximum %u", path, map.level,
                             BSP_MAX_BEZIER_LEVEL);
    bsp_totals totals;
    bsp_mesh mesh = {0};
    bool ok = read_map(path, &map, err) && check_vertices(&map, err) && check_faces(&map, &totals, err) &&
              rtt_scene_budget_reserve(scene, path, totals.triangles, 0, err) && build_mesh(&map, &totals, &mesh, err);
    uint32_t *materials = NULL;
    bool textured = false;
    if (ok && material_override == UINT32_MAX)
        ok = rtt_q3_map_materials(scene, path, map.texture_lump, map.texture_count, BSP_TEXTURE_SIZE,
                                  mesh.triangle_texture, mesh.triangle_count, &materials, &textured, err);
    uint32_t material = ok && !materials ? map_material(scene, &map, material_override, err) : 0;
    const uint32_t first_vertex = scene->vertex_count;
    ok = ok && material != UINT32_MAX &&
         rtt_scene_add_mesh(scene, path, base_name(path), mesh.positions, mesh.normals, mesh.vertex_count,
                            mesh.indices, mesh.triangle_count, materials, material, transform, err);
    if (ok && textured) ok = rtt_scene_set_texcoords(scene, first_vertex, mesh.texcoords, mesh.vertex_count, err);
    free(materials);
    free(mesh.texcoords);
    free(mesh.triangle_texture);
    free(mesh.positions);
    free(mesh.normals);
    free(mesh.indices);
    free(map.vertex_lump);
    free(map.meshvert_lump);
    free(map.face_lump);
    free(map.texture_lump);
    return ok;
}

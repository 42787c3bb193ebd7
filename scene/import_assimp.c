/* Mesh files through Assimp's C API: OBJ/MTL, PLY, OFF, 3DS, glTF, STL and
 * whatever else Assimp reads.
 *
 * Global triangle order (docs/ARCHITECTURE.md).  No post-processing step is requested:
 * aiProcess_Triangulate cuts quads at a concave corner and larger polygons by
 * ear clipping, FindDegenerates and SortByPType drop or regroup faces, and
 * PreTransformVertices merges meshes by material, so each would break the
 * order.  Instead:
 *   - nodes are walked depth first, a node before its children, children in
 *     their order, and each node's meshes in the order it lists them (an
 *     instanced mesh is appended once per node that references it); for
 *     OBJ, PLY, OFF and STL that is the file order;
 *   - every node's accumulated transform (parent * child) is applied, then
 *     the caller's transform;
 *   - faces keep Assimp's order, which is the file order for these formats,
 *     and a polygon of n corners becomes the fan (0,1,2), (0,2,3), ...,
 *     (0,n-2,n-1) in that order;
 *   - faces of fewer than 3 corners (points, lines) make no triangle;
 *     degenerate triangles are kept (they never hit).
 * What Assimp itself regroups, we cannot undo.  Checked with Assimp 5.2:
 * its OBJ importer starts a new mesh at each `usemtl`, `o` or `g` and keeps
 * the file order even when a name repeats (tests/data/import/materials.obj);
 * its 3DS importer splits a mesh into one mesh per material, so a 3DS mesh
 * whose faces interleave materials comes out grouped by material (file order
 * within each group), and turns 3DS's Z-up into Y-up through its root node.
 * Assimp duplicates vertices per face corner for OBJ, which keeps flat
 * shading flat; JoinIdenticalVertices is not used (scene.c decides
 * closedness by position).
 *
 * Materials (unless material_override names a scene material for every
 * triangle): each file material a triangle uses is mapped once, in order of
 * first use, onto the five types of rtt_material_type:
 *   reflective  = MTL illum 3, 5 or 7, or $mat.reflectivity > 0 (3DS)
 *   transparent = opacity (MTL d, or 1 - Tr; 3DS transparency) < 1,
 *                 or MTL illum 4, 6, 7 or 9
 *   both              -> TRANSPARENT_REFLECTIVE
 *   transparent only  -> TRANSPARENT
 *   reflective only   -> REFLECTIVE
 *   else Ks non-black -> SPECULAR
 *   else              -> DIFFUSE
 * diffuse = Kd; specular = the largest Ks channel; shininess = Ns (default
 * 32 when absent or 0); reflection = reflectivity when > 0, else the largest
 * Ks channel when non-zero (MTL weights reflection by Ks), else 0.5;
 * transparency = 1 - opacity when opacity < 1, else 0.8 (illum asks for
 * glass but d says opaque); ior = Ni when finite and > 0 (Assimp reports 1
 * when the MTL has none), else 1.5.  For TRANSPARENT_REFLECTIVE the two
 * weights are scaled down to sum to at most 1.  Formats without materials
 * (OFF, PLY, STL: Assimp invents one, white and for PLY even specular) and
 * Assimp's placeholder for files that name none ("DefaultMaterial", e.g. an
 * OBJ without MTL) get rtt's grey diffuse default (docs/ARCHITECTURE.md: no material
 * -> grey diffuse).  Texture maps: assimp_textures.c; a mesh whose material
 * has one brings its first texture coordinate set.
 *
 * Errors are one line, "path: what is wrong": Assimp's message reduced to
 * one line, or ours.  An empty file and a file without triangles are errors.
 * Positions are checked for NaN and infinity per face before anything is
 * appended, so the message names the face as the file counts faces (from 0,
 * like every rtt message): OBJ vertex numbers mean nothing after Assimp's
 * per-corner duplication.
 * Note: aiGetErrorString is Assimp's global; concurrent imports from several
 * threads may see each other's messages (never a crash).  */
#include <assimp/cimport.h>
#include <cjson/cJSON.h>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "assimp_io.h"
#include "assimp_textures.h"
#include "file_kind.h"
#include "file_read.h"
#include "mesh_header_check.h"
#include "rtt/memory_budget.h"
#include "scene_build.h"
#include "textures.h"
#include "transform.h"

#define MTL_DEFAULT_MATERIAL_NAME "DefaultMaterial" /* AI_DEFAULT_MATERIAL_NAME */

typedef struct import_state {
    rtt_scene *scene;
    const char *path;
    const struct aiScene *ai;
    uint32_t material_override;
    uint32_t *material_map; /* file material -> scene material, UINT32_MAX until used */
    uint32_t faces_seen;    /* faces before the current mesh, for messages */
    uint32_t *indices;      /* scratch, reused across meshes */
    size_t indices_capacity;
} import_state;

/* ---- materials ---- */

static float channel_max(struct aiColor4D c) { return fmaxf(c.r, fmaxf(c.g, c.b)); }

/* key, type, index: what an AI_MATKEY_* macro expands to. */
static bool get_float(const struct aiMaterial *m, const char *key, unsigned type, unsigned index, float *out)
{
    ai_real value;
    unsigned int count = 1;
    if (aiGetMaterialFloatArray(m, key, type, index, &value, &count) != aiReturn_SUCCESS || count < 1) return false;
    if (!isfinite((float)value)) return false;
    *out = (float)value;
    return true;
}

static bool get_color(const struct aiMaterial *m, const char *key, unsigned type, unsigned index,
                      struct aiColor4D *out)
{
    if (aiGetMaterialColor(m, key, type, index, out) != aiReturn_SUCCESS) return false;
    return isfinite(out->r) && isfinite(out->g) && isfinite(out->b);
}

static bool illum_is(int illum, const int *models, size_t count)
{
    for (size_t i = 0; i < count; i++)
        if (illum == models[i]) return true;
    return false;
}

static bool has_no_materials(const char *path)
{
    static const char *const formats[] = {"off", "ply", "stl"};
    const char *ext = rtt_file_extension(path);
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++)
        if (strcasecmp(ext, formats[i]) == 0) return true;
    return false;
}

/* The mapping documented at the top of the file. */
static rtt_material map_material(const struct aiMaterial *m, bool placeholder)
{
    rtt_material out = rtt_material_default();
    struct aiString name;
    if (placeholder) return out;
    if (aiGetMaterialString(m, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS) {
        if (strcmp(name.data, MTL_DEFAULT_MATERIAL_NAME) == 0) return out;
        snprintf(out.name, sizeof out.name, "%.63s", name.data);
    }
    struct aiColor4D kd, ks = {0, 0, 0, 0};
    if (get_color(m, AI_MATKEY_COLOR_DIFFUSE, &kd))
        out.diffuse = rtt_v3(fmaxf(kd.r, 0.0f), fmaxf(kd.g, 0.0f), fmaxf(kd.b, 0.0f));
    get_color(m, AI_MATKEY_COLOR_SPECULAR, &ks);
    const float specular = fmaxf(channel_max(ks), 0.0f);
    float shininess = 0.0f, opacity = 1.0f, reflectivity = 0.0f, ior = 0.0f;
    get_float(m, AI_MATKEY_SHININESS, &shininess);
    get_float(m, AI_MATKEY_OPACITY, &opacity);
    get_float(m, AI_MATKEY_REFLECTIVITY, &reflectivity);
    get_float(m, AI_MATKEY_REFRACTI, &ior);
    int illum = -1;
    unsigned int one = 1;
    aiGetMaterialIntegerArray(m, "$mat.illum", 0, 0, &illum, &one); /* AI_MATKEY_OBJ_ILLUM */

    static const int reflective_models[] = {3, 5, 7}, transparent_models[] = {4, 6, 7, 9};
    const bool reflective = illum_is(illum, reflective_models, 3) || reflectivity > 0.0f;
    const bool transparent = opacity < 1.0f || illum_is(illum, transparent_models, 4);
    if (specular > 0.0f) out.specular = specular;
    if (shininess > 0.0f) out.shininess = shininess;
    if (reflectivity > 0.0f)
        out.reflection = fminf(reflectivity, 1.0f);
    else if (specular > 0.0f)
        out.reflection = fminf(specular, 1.0f);
    if (opacity < 1.0f) out.transparency = fminf(1.0f - fmaxf(opacity, 0.0f), 1.0f);
    if (ior > 0.0f) out.ior = ior;

    if (transparent && reflective) {
        out.type = RTT_MATERIAL_TRANSPARENT_REFLECTIVE;
        float sum = out.reflection + out.transparency;
        if (sum > 1.0f) {
            out.reflection /= sum;
            out.transparency /= sum;
        }
    } else if (transparent) {
        out.type = RTT_MATERIAL_TRANSPARENT;
    } else if (reflective) {
        out.type = RTT_MATERIAL_REFLECTIVE;
    } else if (specular > 0.0f) {
        out.type = RTT_MATERIAL_SPECULAR;
    } else {
        out.type = RTT_MATERIAL_DIFFUSE;
    }
    return out;
}

static uint32_t scene_material(import_state *st, unsigned int file_material, rtt_error *err)
{
    if (st->material_override != UINT32_MAX) return st->material_override;
    if (file_material >= st->ai->mNumMaterials) {
        rtt_error_set(err, "%s: material index %u is out of range (%u materials)", st->path, file_material,
                      st->ai->mNumMaterials);
        return UINT32_MAX;
    }
    if (st->material_map[file_material] == UINT32_MAX) {
        const bool placeholder = has_no_materials(st->path);
        rtt_material m = map_material(st->ai->mMaterials[file_material], placeholder);
        if (!placeholder &&
            !rtt_assimp_material_textures(st->scene, st->path, st->ai, st->ai->mMaterials[file_material], &m, err))
            return UINT32_MAX;
        st->material_map[file_material] = rtt_scene_add_material(st->scene, &m);
        if (st->material_map[file_material] == UINT32_MAX)
            rtt_error_set(err, "%s: out of memory for materials", st->path);
    }
    return st->material_map[file_material];
}

/* ---- geometry ---- */

/* aiMatrix4x4 is row-major, like transform.h's matrices. */
static void mat4_from_ai(const struct aiMatrix4x4 *m, double out[16])
{
    const ai_real in[16] = {m->a1, m->a2, m->a3, m->a4, m->b1, m->b2, m->b3, m->b4,
                            m->c1, m->c2, m->c3, m->c4, m->d1, m->d2, m->d3, m->d4};
    for (int i = 0; i < 16; i++) out[i] = (double)in[i];
}

static uint64_t mesh_triangle_count(const struct aiMesh *mesh)
{
    uint64_t count = 0;
    for (unsigned int f = 0; f < mesh->mNumFaces; f++)
        if (mesh->mFaces[f].mNumIndices >= 3) count += mesh->mFaces[f].mNumIndices - 2;
    return count;
}

static bool check_face(const import_state *st, const struct aiMesh *mesh, unsigned int f, rtt_error *err)
{
    const struct aiFace *face = &mesh->mFaces[f];
    for (unsigned int k = 0; k < face->mNumIndices; k++) {
        unsigned int v = face->mIndices[k];
        if (v >= mesh->mNumVertices)
            return rtt_error_set(err, "%s: face %u: vertex index %u is out of range (%u vertices)", st->path,
                                 st->faces_seen + f, v, mesh->mNumVertices);
        const struct aiVector3D p = mesh->mVertices[v];
        if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z))
            return rtt_error_set(err, "%s: face %u: corner %u has a NaN or infinite coordinate (%g, %g, %g)",
                                 st->path, st->faces_seen + f, k + 1, (double)p.x, (double)p.y, (double)p.z);
    }
    return true;
}

/* Fan-triangulates the faces of one mesh into st->indices. */
static bool fan_triangulate(import_state *st, const struct aiMesh *mesh, uint32_t triangles, rtt_error *err)
{
    size_t needed = (size_t)triangles * 3;
    if (needed > st->indices_capacity) {
        uint32_t *p = realloc(st->indices, needed * sizeof *p);
        if (!p) return rtt_error_set(err, "%s: out of memory for %u triangles", st->path, triangles);
        st->indices = p;
        st->indices_capacity = needed;
    }
    size_t n = 0;
    for (unsigned int f = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (!check_face(st, mesh, f, err)) return false;
        for (unsigned int k = 2; k < face->mNumIndices; k++) {
            st->indices[n++] = face->mIndices[0];
            st->indices[n++] = face->mIndices[k - 1];
            st->indices[n++] = face->mIndices[k];
        }
    }
    return true;
}

/* The mesh's first texture coordinate set (u, v; Assimp's v is up). */
static bool set_texcoords(import_state *st, const struct aiMesh *mesh, uint32_t first_vertex, rtt_error *err)
{
    float *uv = malloc((size_t)mesh->mNumVertices * 2 * sizeof *uv + 1);
    if (!uv) return rtt_error_set(err, "%s: out of memory for texture coordinates", st->path);
    for (unsigned int i = 0; i < mesh->mNumVertices; i++) {
        uv[2 * (size_t)i] = (float)mesh->mTextureCoords[0][i].x;
        uv[2 * (size_t)i + 1] = (float)mesh->mTextureCoords[0][i].y;
    }
    bool ok = rtt_scene_set_texcoords(st->scene, first_vertex, uv, mesh->mNumVertices, err);
    free(uv);
    return ok;
}

static bool append_mesh(import_state *st, const struct aiMesh *mesh, const double transform[16], rtt_error *err)
{
    uint64_t triangles = mesh_triangle_count(mesh);
    if (triangles > UINT32_MAX / 3)
        return rtt_error_set(err, "%s: mesh \"%s\" has too many triangles", st->path, mesh->mName.data);
    if (triangles == 0) {
        st->faces_seen += mesh->mNumFaces;
        return true;
    }
    uint32_t material = scene_material(st, mesh->mMaterialIndex, err);
    if (material == UINT32_MAX || !fan_triangulate(st, mesh, (uint32_t)triangles, err)) return false;
    _Static_assert(sizeof(struct aiVector3D) == sizeof(rtt_vec3), "aiVector3D is three floats (ai_real = float)");
    const char *name = mesh->mName.length ? mesh->mName.data : NULL;
    const uint32_t first_vertex = st->scene->vertex_count;
    bool ok = rtt_scene_add_mesh(st->scene, st->path, name, (const rtt_vec3 *)mesh->mVertices,
                                 (const rtt_vec3 *)mesh->mNormals, mesh->mNumVertices, st->indices,
                                 (uint32_t)triangles, NULL, material, transform, err);
    st->faces_seen += mesh->mNumFaces;
    const rtt_material *m = &st->scene->materials[material];
    if (ok && (m->diffuse_map || m->normal_map) && mesh->mTextureCoords[0])
        ok = set_texcoords(st, mesh, first_vertex, err);
    return ok;
}

/* What the scene will hold of a format without counts in its header, once
 * Assimp has read it: instanced meshes count once per node using them. */
static uint64_t node_triangles(const struct aiScene *ai, const struct aiNode *node, unsigned depth)
{
    uint64_t count = 0;
    for (unsigned int i = 0; node && depth <= 1024 && i < node->mNumMeshes; i++)
        if (node->mMeshes[i] < ai->mNumMeshes) count += mesh_triangle_count(ai->mMeshes[node->mMeshes[i]]);
    for (unsigned int c = 0; node && depth <= 1024 && c < node->mNumChildren; c++)
        count += node_triangles(ai, node->mChildren[c], depth + 1);
    return count;
}

static uint64_t imported_triangles(const struct aiScene *ai) { return node_triangles(ai, ai->mRootNode, 0); }

/* Depth first: the node's own meshes, then its children, in order. */
static bool append_node(import_state *st, const struct aiNode *node, const double parent[16], unsigned depth,
                        rtt_error *err)
{
    if (depth > 1024) return rtt_error_set(err, "%s: node hierarchy deeper than 1024", st->path);
    double local[16], world[16];
    mat4_from_ai(&node->mTransformation, local);
    rtt_transform_multiply(parent, local, world);
    for (unsigned int i = 0; i < node->mNumMeshes; i++) {
        unsigned int m = node->mMeshes[i];
        if (m >= st->ai->mNumMeshes)
            return rtt_error_set(err, "%s: node \"%s\": mesh index %u is out of range", st->path, node->mName.data, m);
        if (!append_mesh(st, st->ai->mMeshes[m], world, err)) return false;
    }
    for (unsigned int c = 0; c < node->mNumChildren; c++)
        if (!append_node(st, node->mChildren[c], world, depth + 1, err)) return false;
    return true;
}

/* Assimp's message, reduced to one line without trailing punctuation noise. */
static bool assimp_error(const char *path, rtt_error *err)
{
    char line[400];
    const char *message = aiGetErrorString();
    snprintf(line, sizeof line, "%s", message && *message ? message : "Assimp could not read the file");
    for (char *c = line; *c; c++)
        if (*c == '\n' || *c == '\r' || *c == '\t') *c = ' ';
    size_t n = strlen(line);
    while (n > 0 && line[n - 1] == ' ') line[--n] = '\0';
    return rtt_error_set(err, "%s: %s", path, line);
}

static bool check_file(const char *path, rtt_error *err)
{
    FILE *f = rtt_file_open_regular(path, err);
    if (!f) return false;
    struct stat info;
    bool empty = fstat(fileno(f), &info) == 0 && info.st_size == 0;
    fclose(f);
    if (empty) return rtt_error_set(err, "%s: the file is empty", path);
    return true;
}

/* Assimp falls back from the extension's importer to every importer that
 * claims the content, and some of its parsers read past their buffers on
 * input that is not their format (libassimp 5.2: a heap overflow on a
 * ".gltf" that is not JSON, fuzz/regressions/assimp/gltf_not_json_heap_overflow).
 * So a file must look like its extension's format before Assimp sees it:
 * .gltf a JSON object (cJSON), .glb the "glTF" magic, .ply the "ply" magic. */
static bool check_signature(const char *path, rtt_error *err)
{
    const char *ext = rtt_file_extension(path);
    if (strcasecmp(ext, "gltf") == 0) {
        size_t size = 0;
        char *text = rtt_file_read(path, RTT_FILE_TEXT_MAX, &size, err);
        if (!text) return false;
        cJSON *json = cJSON_ParseWithLengthOpts(text, size + 1u, NULL, true); /* the whole file, NUL included */
        bool object = cJSON_IsObject(json);
        cJSON_Delete(json);
        free(text);
        if (!object) return rtt_error_set(err, "%s: not a glTF file (not a JSON object)", path);
        return true;
    }
    static const struct { const char *ext, *magic; } magics[] = { { "glb", "glTF" }, { "ply", "ply" } };
    for (size_t i = 0; i < sizeof magics / sizeof magics[0]; i++) {
        if (strcasecmp(ext, magics[i].ext) != 0) continue;
        char head[8] = { 0 };
        FILE *f = rtt_file_open_regular(path, err);
        if (!f) return false;
        size_t n = f ? fread(head, 1, strlen(magics[i].magic), f) : 0;
        if (f) fclose(f);
        if (n != strlen(magics[i].magic) || memcmp(head, magics[i].magic, n) != 0)
            return rtt_error_set(err, "%s: not a %s file (it does not start with \"%s\")", path, magics[i].ext,
                                 magics[i].magic);
    }
    return true;
}

bool rtt_import_assimp(rtt_scene *scene, const char *path, const double transform[16], uint32_t material_override,
                       rtt_error *err)
{
    if (!check_file(path, err) || !check_signature(path, err)) return false;
    if (material_override != UINT32_MAX && material_override >= scene->material_count)
        return rtt_error_set(err, "%s: material index %u is out of range", path, material_override);
    rtt_mesh_header header;
    if (!rtt_mesh_header_check_file(path, &header, err) ||
        !rtt_scene_budget_reserve(scene, path, header.triangles, header.bytes, err))
        return false;
    rtt_assimp_io io;
    rtt_assimp_io_init(&io);
    const struct aiScene *ai = aiImportFileEx(path, 0, &io.io);
    if (io.refused) {
        aiReleaseImport(ai);
        *err = io.error;
        return false;
    }
    if (!ai) return assimp_error(path, err);
    if (!rtt_mesh_header_check_import(path, &header, ai, err) ||
        (!header.counted && !rtt_scene_budget_reserve(scene, path, imported_triangles(ai), 0, err))) {
        aiReleaseImport(ai);
        return false;
    }
    if (!ai->mRootNode) {
        aiReleaseImport(ai);
        return rtt_error_set(err, "%s: the file has no meshes", path);
    }
    import_state st = {.scene = scene, .path = path, .ai = ai, .material_override = material_override};
    st.material_map = malloc(((size_t)ai->mNumMaterials + 1) * sizeof *st.material_map);
    if (!st.material_map) {
        aiReleaseImport(ai);
        return rtt_error_set(err, "%s: out of memory", path);
    }
    for (unsigned int i = 0; i < ai->mNumMaterials; i++) st.material_map[i] = UINT32_MAX;
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const uint32_t triangles_before = scene->triangle_count;
    bool ok = append_node(&st, ai->mRootNode, transform ? transform : identity, 0, err);
    if (ok && scene->triangle_count == triangles_before) ok = rtt_error_set(err, "%s: the file has no triangles", path);
    free(st.material_map);
    free(st.indices);
    aiReleaseImport(ai);
    return ok;
}

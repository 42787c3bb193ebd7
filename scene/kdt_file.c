/* The baked kd-tree file (.kdt; layout in kdt_format.h): the writer used by
 * `rtt bake` and the reader behind rtt_scene_load("x.kdt").
 *
 * The reader is a fuzz target: it checks the header, then the
 * checksum, then every section's place and size against the file, then
 * every count, index and float before anything uses them, and refuses a bad
 * file with one line "file.kdt: what is wrong (where)".  It allocates only
 * what the file's size justifies: the file itself, copies of its sections
 * (whose sizes were checked against the file) and one byte per node for the
 * structure check. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "file_read.h"
#include "kdt_format.h"
#include "rtt/atomic_file.h"
#include "scene_build.h"

_Static_assert(sizeof(rtt_vec3) == 12, "vertices are written as 3 float32");
_Static_assert(sizeof(rtt_triangle) == 12, "triangles are written as 3 uint32");

static const char *const section_names[KDT_SECTION_COUNT] = {
    "settings", "vertices", "normals", "triangles", "triangle materials", "triangle meshes",
    "meshes",   "materials", "lights", "nodes",     "leaves",             "triangle records",
};

static const uint32_t element_sizes[KDT_SECTION_COUNT] = {
    sizeof(kdt_scene_settings), sizeof(rtt_vec3), sizeof(rtt_vec3), sizeof(rtt_triangle), sizeof(uint32_t),
    sizeof(uint32_t), sizeof(kdt_mesh), sizeof(kdt_material), sizeof(kdt_light), sizeof(kdt_node),
    sizeof(kdt_leaf), sizeof(kdt_triangle),
};

static uint64_t align_up(uint64_t x) { return (x + KDT_ALIGN - 1) & ~(uint64_t)(KDT_ALIGN - 1); }

/* ---- writing ------------------------------------------------------------- */

typedef struct kdt_writer {
    FILE *stream;
    uint64_t position, hash;
    bool ok;
} kdt_writer;

/* kdt_light has no attenuation distance: it is folded into the
 * coefficients (l / D, q / D^2), which must stay finite and non-zero where
 * they were (rtt_kdt_write refuses the light otherwise). */
static void kdt_light_attenuation(const rtt_light *l, float out[3])
{
    const double d = l->attenuation_distance > 0.0f ? l->attenuation_distance : 1.0;
    out[0] = l->attenuation[0];
    out[1] = (float)(l->attenuation[1] / d);
    out[2] = (float)(l->attenuation[2] / (d * d));
}

static bool kdt_light_attenuation_fits(const rtt_light *l)
{
    float a[3];
    kdt_light_attenuation(l, a);
    for (int i = 1; i < 3; i++)
        if (!isfinite(a[i]) || (l->attenuation[i] > 0.0f && !(a[i] >= FLT_MIN))) return false;
    return true;
}

static void emit(kdt_writer *w, const void *data, size_t size)
{
    if (!w->ok || size == 0) return;
    const unsigned char *p = data;
    if (w->position + size > KDT_CHECKSUM_START) {
        size_t skip = w->position >= KDT_CHECKSUM_START ? 0 : (size_t)(KDT_CHECKSUM_START - w->position);
        w->hash = rtt_kdt_checksum_update(w->hash, p + skip, size - skip);
    }
    w->ok = fwrite(data, 1, size, w->stream) == size;
    w->position += size;
}

static void emit_padding(kdt_writer *w, uint64_t to)
{
    static const unsigned char zeros[KDT_ALIGN];
    while (w->ok && w->position < to) emit(w, zeros, (size_t)(to - w->position < KDT_ALIGN ? to - w->position
                                                                                             : KDT_ALIGN));
}

/* A uint32 per triangle, zeros when the scene has no array. */
static void emit_u32s(kdt_writer *w, const uint32_t *values, uint32_t count)
{
    if (values) {
        emit(w, values, (size_t)count * sizeof *values);
        return;
    }
    const uint32_t zero = 0;
    for (uint32_t i = 0; i < count; i++) emit(w, &zero, sizeof zero);
}

static void copy_name(char *dst, const char *src)
{
    memset(dst, 0, 64);
    size_t n = strnlen(src, 63);
    memcpy(dst, src, n);
}

static kdt_scene_settings settings_of(const rtt_scene *s)
{
    kdt_scene_settings k;
    memset(&k, 0, sizeof k);
    memcpy(k.eye, &s->camera.eye, sizeof k.eye);
    memcpy(k.look_at, &s->camera.look_at, sizeof k.look_at);
    memcpy(k.up, &s->camera.up, sizeof k.up);
    k.fov_deg = s->camera.fov_deg;
    k.width = s->width, k.height = s->height, k.max_bounces = s->max_bounces;
    k.degenerate_count = s->degenerate_count;
    memcpy(k.background, &s->background, sizeof k.background);
    k.ambient = s->ambient;
    k.has_normals = s->normals != NULL;
    k.collapsed_count = s->collapsed_count;
    memcpy(k.origin, s->origin, sizeof k.origin);
    return k;
}

static void emit_scene_sections(kdt_writer *w, const rtt_scene *s, const kdt_section *table)
{
    kdt_scene_settings settings = settings_of(s);
    emit_padding(w, table[KDT_SECTION_SETTINGS].offset);
    emit(w, &settings, sizeof settings);
    emit_padding(w, table[KDT_SECTION_VERTICES].offset);
    emit(w, s->vertices, (size_t)s->vertex_count * sizeof(rtt_vec3));
    emit_padding(w, table[KDT_SECTION_NORMALS].offset);
    if (s->normals) emit(w, s->normals, (size_t)s->vertex_count * sizeof(rtt_vec3));
    emit_padding(w, table[KDT_SECTION_TRIANGLES].offset);
    emit(w, s->triangles, (size_t)s->triangle_count * sizeof(rtt_triangle));
    emit_padding(w, table[KDT_SECTION_TRIANGLE_MATERIAL].offset);
    emit_u32s(w, s->triangle_material, s->triangle_count);
    emit_padding(w, table[KDT_SECTION_TRIANGLE_MESH].offset);
    emit_u32s(w, s->triangle_mesh, s->triangle_count);
    emit_padding(w, table[KDT_SECTION_MESHES].offset);
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const rtt_mesh *m = &s->meshes[i];
        kdt_mesh k = {.first_triangle = m->first_triangle, .triangle_count = m->triangle_count,
                      .material = m->material, .closed = m->closed};
        copy_name(k.name, m->name);
        emit(w, &k, sizeof k);
    }
    emit_padding(w, table[KDT_SECTION_MATERIALS].offset);
    for (uint32_t i = 0; i < s->material_count; i++) {
        const rtt_material *m = &s->materials[i];
        kdt_material k = {.type = (uint32_t)m->type, .diffuse = {m->diffuse.x, m->diffuse.y, m->diffuse.z},
                          .specular = m->specular, .shininess = m->shininess, .reflection = m->reflection,
                          .transparency = m->transparency, .ior = m->ior, .edge_width_scale = m->edge_width_scale};
        copy_name(k.name, m->name);
        emit(w, &k, sizeof k);
    }
    emit_padding(w, table[KDT_SECTION_LIGHTS].offset);
    for (uint32_t i = 0; i < s->light_count; i++) {
        const rtt_light *l = &s->lights[i];
        float attenuation[3];
        kdt_light_attenuation(l, attenuation);
        kdt_light k = {.type = (uint32_t)l->type,
                       .position = {l->position.x, l->position.y, l->position.z},
                       .color = {l->color.x, l->color.y, l->color.z},
                       .intensity = l->intensity,
                       .attenuation = {attenuation[0], attenuation[1], attenuation[2]},
                       .radius = l->radius};
        emit(w, &k, sizeof k);
    }
}

static void fill_header(kdt_header *h, const rtt_scene *s, const rtt_baked_tree *t, uint64_t file_size)
{
    memset(h, 0, sizeof *h);
    memcpy(h->magic, KDT_MAGIC, 8);
    h->version = KDT_VERSION;
    h->header_size = sizeof *h;
    h->file_size = file_size;
    h->section_count = KDT_SECTION_COUNT;
    h->vertex_count = s->vertex_count, h->triangle_count = s->triangle_count, h->mesh_count = s->mesh_count;
    h->material_count = s->material_count, h->light_count = s->light_count;
    h->node_count = t->node_count, h->leaf_count = t->leaf_count, h->record_count = t->record_count;
    memcpy(h->tree_lo, &t->bounds.lo, sizeof h->tree_lo);
    memcpy(h->tree_hi, &t->bounds.hi, sizeof h->tree_hi);
    h->max_depth = t->info.max_depth, h->depth = t->info.depth, h->empty_leaf_count = t->info.empty_leaf_count;
    h->reference_cap = t->info.reference_cap;
    h->sah_cost = t->info.sah_cost, h->build_seconds = t->info.build_seconds;
}

/* Section sizes in id order at aligned offsets; returns the file size. */
static uint64_t layout_sections(const rtt_scene *s, const rtt_baked_tree *t, kdt_section table[KDT_SECTION_COUNT])
{
    const uint64_t counts[KDT_SECTION_COUNT] = {
        1, s->vertex_count, s->normals ? s->vertex_count : 0, s->triangle_count, s->triangle_count,
        s->triangle_count, s->mesh_count, s->material_count, s->light_count, t->node_count, t->leaf_count,
        t->record_count,
    };
    uint64_t offset = sizeof(kdt_header) + KDT_SECTION_COUNT * sizeof(kdt_section);
    for (uint32_t i = 0; i < KDT_SECTION_COUNT; i++) {
        offset = align_up(offset);
        table[i] = (kdt_section){.id = i, .element_size = element_sizes[i], .offset = offset,
                                 .size = counts[i] * element_sizes[i]};
        offset += table[i].size;
    }
    return offset;
}

bool rtt_kdt_write(const char *path, const rtt_scene *scene, const rtt_baked_tree *tree, rtt_error *err)
{
    if (scene->texture_count || scene->texcoords) /* images and texture coordinates have no section */
        return rtt_error_set(err, "%s: %s has %u textures: a .kdt does not carry textures (render the scene file "
                                  "itself)", path, scene->path, scene->texture_count);
    for (uint32_t i = 0; i < scene->light_count; i++) /* kdt_light has no edges */
        if (scene->lights[i].type == RTT_LIGHT_QUAD)
            return rtt_error_set(err, "%s: light %u is a quad light: the .kdt format stores point and sphere lights only",
                                 scene->path, i);
    for (uint32_t i = 0; i < scene->light_count; i++)
        if (!kdt_light_attenuation_fits(&scene->lights[i]))
            return rtt_error_set(err, "%s: light %u: its fall-off over attenuation_distance %g does not fit the .kdt "
                                      "format's coefficients per unit length (render the scene file itself)",
                                 scene->path, i, (double)scene->lights[i].attenuation_distance);
    kdt_section table[KDT_SECTION_COUNT];
    const uint64_t file_size = layout_sections(scene, tree, table);
    kdt_header header;
    fill_header(&header, scene, tree, file_size);

    rtt_atomic_file file;
    if (!rtt_atomic_file_open(&file, path, err)) return false;
    kdt_writer w = {.stream = file.stream, .hash = KDT_CHECKSUM_INIT, .ok = true};
    emit(&w, &header, sizeof header);
    emit(&w, table, sizeof table);
    emit_scene_sections(&w, scene, table);
    emit_padding(&w, table[KDT_SECTION_NODES].offset);
    emit(&w, tree->nodes, (size_t)tree->node_count * sizeof(kdt_node));
    emit_padding(&w, table[KDT_SECTION_LEAVES].offset);
    emit(&w, tree->leaves, (size_t)tree->leaf_count * sizeof(kdt_leaf));
    emit_padding(&w, table[KDT_SECTION_RECORDS].offset);
    emit(&w, tree->records, (size_t)tree->record_count * sizeof(kdt_triangle));
    bool ok = w.ok && w.position == file_size;
    header.checksum = w.hash;
    ok = ok && fseek(w.stream, (long)offsetof(kdt_header, checksum), SEEK_SET) == 0 &&
         fwrite(&header.checksum, sizeof header.checksum, 1, w.stream) == 1;
    if (!ok) {
        int saved = errno;
        rtt_atomic_file_abort(&file);
        return rtt_error_set(err, "%s: cannot write: %s", path, strerror(saved ? saved : EIO));
    }
    return rtt_atomic_file_commit(&file, err);
}

/* ---- reading: the file and its section table ----------------------------- */

typedef struct kdt_file {
    const char *path;
    unsigned char *bytes;
    uint64_t size;
    kdt_header header;
    kdt_section table[KDT_SECTION_COUNT];
} kdt_file;

/* No size limit of its own: a baked tree is as large as its scene, and
 * nothing is allocated past the file itself until its sizes have been
 * checked against it. */
static bool read_whole_file(kdt_file *f, rtt_error *err)
{
    size_t size = 0;
    f->bytes = (unsigned char *)rtt_file_read(f->path, SIZE_MAX, &size, err);
    if (!f->bytes) return false;
    f->size = size;
    if (size < sizeof(kdt_header))
        return rtt_error_set(err, "%s: truncated: %zu bytes, shorter than the %zu-byte .kdt header", f->path, size,
                             sizeof(kdt_header));
    memcpy(&f->header, f->bytes, sizeof f->header);
    return true;
}

static bool check_header(const kdt_file *f, rtt_error *err)
{
    const kdt_header *h = &f->header;
    if (memcmp(h->magic, KDT_MAGIC, 8) != 0)
        return rtt_error_set(err, "%s: not a .kdt file (bad magic)", f->path);
    if (h->version != KDT_VERSION)
        return rtt_error_set(err, "%s: unsupported .kdt version %u (this build reads version %u)", f->path,
                             h->version, KDT_VERSION);
    if (h->header_size != sizeof(kdt_header))
        return rtt_error_set(err, "%s: header size %u, expected %zu (header)", f->path, h->header_size,
                             sizeof(kdt_header));
    if (h->file_size > f->size)
        return rtt_error_set(err, "%s: truncated: %llu bytes, the header says %llu", f->path,
                             (unsigned long long)f->size, (unsigned long long)h->file_size);
    if (h->file_size < f->size)
        return rtt_error_set(err, "%s: %llu bytes, the header says %llu (trailing data)", f->path,
                             (unsigned long long)f->size, (unsigned long long)h->file_size);
    uint64_t sum = rtt_kdt_checksum_update(KDT_CHECKSUM_INIT, f->bytes + KDT_CHECKSUM_START,
                                           (size_t)(f->size - KDT_CHECKSUM_START));
    if (sum != h->checksum) return rtt_error_set(err, "%s: checksum mismatch: the file is corrupt", f->path);
    if (h->section_count != KDT_SECTION_COUNT || h->flags != 0)
        return rtt_error_set(err, "%s: %u sections with flags %u, expected %u and 0 (header)", f->path,
                             h->section_count, h->flags, KDT_SECTION_COUNT);
    return true;
}

static uint64_t expected_count(const kdt_header *h, uint32_t id)
{
    switch (id) {
    case KDT_SECTION_SETTINGS: return 1;
    case KDT_SECTION_VERTICES: case KDT_SECTION_NORMALS: return h->vertex_count;
    case KDT_SECTION_TRIANGLES: case KDT_SECTION_TRIANGLE_MATERIAL: case KDT_SECTION_TRIANGLE_MESH:
        return h->triangle_count;
    case KDT_SECTION_MESHES: return h->mesh_count;
    case KDT_SECTION_MATERIALS: return h->material_count;
    case KDT_SECTION_LIGHTS: return h->light_count;
    case KDT_SECTION_NODES: return h->node_count;
    case KDT_SECTION_LEAVES: return h->leaf_count;
    default: return h->record_count;
    }
}

static bool check_sections(kdt_file *f, rtt_error *err)
{
    uint64_t end = sizeof(kdt_header) + sizeof f->table;
    if (end > f->size) return rtt_error_set(err, "%s: truncated: no room for the section table", f->path);
    memcpy(f->table, f->bytes + sizeof(kdt_header), sizeof f->table);
    for (uint32_t i = 0; i < KDT_SECTION_COUNT; i++) {
        const kdt_section *s = &f->table[i];
        const char *name = section_names[i];
        if (s->id != i || s->element_size != element_sizes[i])
            return rtt_error_set(err, "%s: section %u is not the %s section of %u-byte records (section table)",
                                 f->path, i, name, element_sizes[i]);
        if (s->offset % KDT_ALIGN != 0 || s->offset < end || s->offset > f->size || s->size > f->size - s->offset)
            return rtt_error_set(err, "%s: %s section at %llu, %llu bytes, lies outside the file or overlaps "
                                      "(section table)",
                                 f->path, name, (unsigned long long)s->offset, (unsigned long long)s->size);
        uint64_t want = expected_count(&f->header, i) * element_sizes[i];
        bool normals_absent = i == KDT_SECTION_NORMALS && s->size == 0;
        if (s->size != want && !normals_absent)
            return rtt_error_set(err, "%s: %s section has %llu bytes, the counts say %llu (section table)", f->path,
                                 name, (unsigned long long)s->size, (unsigned long long)want);
        end = s->offset + s->size;
    }
    return true;
}

/* A malloc'd copy of section id (at least one byte so NULL means failure). */
static void *section_copy(const kdt_file *f, uint32_t id)
{
    const kdt_section *s = &f->table[id];
    void *p = malloc(s->size ? (size_t)s->size : 1);
    if (p && s->size) memcpy(p, f->bytes + s->offset, (size_t)s->size);
    return p;
}

/* ---- reading: the scene -------------------------------------------------- */

static bool all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

static bool check_settings(const kdt_file *f, const kdt_scene_settings *k, rtt_error *err)
{
    if (!all_finite(k->eye, 9) || !all_finite(k->background, 4))
        return rtt_error_set(err, "%s: camera or background is not finite (settings section)", f->path);
    if (!(k->fov_deg >= 1.0f && k->fov_deg <= 179.0f))
        return rtt_error_set(err, "%s: fov %g must be between 1 and 179 (settings section)", f->path, k->fov_deg);
    if (k->width == 0 || k->height == 0 || k->width > 65536u || k->height > 65536u)
        return rtt_error_set(err, "%s: image size %ux%u must be 1 to 65536 a side (settings section)", f->path,
                             k->width, k->height);
    if (k->max_bounces > RTT_MAX_BOUNCES)
        return rtt_error_set(err, "%s: max bounces %u over %u (settings section)", f->path, k->max_bounces,
                             RTT_MAX_BOUNCES);
    if (k->degenerate_count > f->header.triangle_count || k->has_normals > 1u)
        return rtt_error_set(err, "%s: degenerate count %u or normals flag %u out of range (settings section)",
                             f->path, k->degenerate_count, k->has_normals);
    if (!isfinite(k->origin[0]) || !isfinite(k->origin[1]) || !isfinite(k->origin[2]) ||
        k->collapsed_count > k->degenerate_count)
        return rtt_error_set(err, "%s: origin not finite or collapsed count %u over the degenerate count "
                                  "(settings section)", f->path, k->collapsed_count);
    if ((k->has_normals != 0) != (f->table[KDT_SECTION_NORMALS].size != 0 || f->header.vertex_count == 0))
        return rtt_error_set(err, "%s: normals flag disagrees with the normals section (settings section)", f->path);
    return true;
}

static bool check_geometry(const kdt_file *f, const rtt_scene *s, rtt_error *err)
{
    for (uint32_t i = 0; i < s->vertex_count; i++)
        if (!rtt_v3_is_finite(s->vertices[i]))
            return rtt_error_set(err, "%s: vertex %u is not finite (vertices section)", f->path, i);
    for (uint32_t i = 0; s->normals && i < s->vertex_count; i++)
        if (!rtt_v3_is_finite(s->normals[i]))
            return rtt_error_set(err, "%s: normal %u is not finite (normals section)", f->path, i);
    for (uint32_t i = 0; i < s->triangle_count; i++) {
        for (int c = 0; c < 3; c++)
            if (s->triangles[i].v[c] >= s->vertex_count)
                return rtt_error_set(err, "%s: triangle %u: vertex index %u out of range (%u vertices) "
                                          "(triangles section)",
                                     f->path, i, s->triangles[i].v[c], s->vertex_count);
        if (s->triangle_material[i] >= s->material_count)
            return rtt_error_set(err, "%s: triangle %u: material %u out of range (%u materials) "
                                      "(triangle materials section)",
                                 f->path, i, s->triangle_material[i], s->material_count);
        if (s->triangle_mesh[i] >= s->mesh_count)
            return rtt_error_set(err, "%s: triangle %u: mesh %u out of range (%u meshes) (triangle meshes section)",
                                 f->path, i, s->triangle_mesh[i], s->mesh_count);
    }
    return true;
}

static bool read_meshes(const kdt_file *f, rtt_scene *s, rtt_error *err)
{
    const kdt_mesh *in = (const kdt_mesh *)(f->bytes + f->table[KDT_SECTION_MESHES].offset);
    uint32_t next = 0; /* meshes tile the global triangle order, in order (scene.h) */
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        kdt_mesh k;
        memcpy(&k, &in[i], sizeof k);
        if (k.first_triangle != next || (uint64_t)k.first_triangle + k.triangle_count > s->triangle_count ||
            k.material >= s->material_count || k.closed > 1u)
            return rtt_error_set(err, "%s: mesh %u: triangles %u+%u, material %u or closed flag out of range "
                                      "(meshes section)",
                                 f->path, i, k.first_triangle, k.triangle_count, k.material);
        next += k.triangle_count;
        rtt_mesh *m = &s->meshes[i];
        memset(m, 0, sizeof *m);
        memcpy(m->name, k.name, 63);
        m->first_triangle = k.first_triangle, m->triangle_count = k.triangle_count;
        m->material = k.material, m->closed = k.closed != 0;
    }
    if (s->mesh_count > 0 && next != s->triangle_count)
        return rtt_error_set(err, "%s: meshes cover %u of %u triangles (meshes section)", f->path, next,
                             s->triangle_count);
    return true;
}

static bool read_materials(const kdt_file *f, rtt_scene *s, rtt_error *err)
{
    const kdt_material *in = (const kdt_material *)(f->bytes + f->table[KDT_SECTION_MATERIALS].offset);
    for (uint32_t i = 0; i < s->material_count; i++) {
        kdt_material k;
        memcpy(&k, &in[i], sizeof k);
        if (k.type > (uint32_t)RTT_MATERIAL_TRANSPARENT_REFLECTIVE || !all_finite(k.diffuse, 9))
            return rtt_error_set(err, "%s: material %u: type %u or a value out of range (materials section)", f->path,
                                 i, k.type);
        rtt_material *m = &s->materials[i];
        memset(m, 0, sizeof *m);
        memcpy(m->name, k.name, 63);
        m->type = (rtt_material_type)k.type;
        m->diffuse = rtt_v3(k.diffuse[0], k.diffuse[1], k.diffuse[2]);
        m->specular = k.specular, m->shininess = k.shininess, m->reflection = k.reflection;
        m->transparency = k.transparency, m->ior = k.ior, m->edge_width_scale = k.edge_width_scale;
    }
    return true;
}

static bool read_lights(const kdt_file *f, rtt_scene *s, rtt_error *err)
{
    const kdt_light *in = (const kdt_light *)(f->bytes + f->table[KDT_SECTION_LIGHTS].offset);
    for (uint32_t i = 0; i < s->light_count; i++) {
        kdt_light k;
        memcpy(&k, &in[i], sizeof k);
        if (k.type > (uint32_t)RTT_LIGHT_SPHERE || !all_finite(k.position, 11) || k.radius < 0.0f)
            return rtt_error_set(err, "%s: light %u: type %u or a value out of range (lights section)", f->path, i,
                                 k.type);
        rtt_light *l = &s->lights[i];
        memset(l, 0, sizeof *l);
        l->type = (rtt_light_type)k.type;
        l->position = rtt_v3(k.position[0], k.position[1], k.position[2]);
        l->color = rtt_v3(k.color[0], k.color[1], k.color[2]);
        l->intensity = k.intensity;
        memcpy(l->attenuation, k.attenuation, sizeof l->attenuation);
        l->radius = k.radius;
    }
    return true;
}

static void apply_settings(rtt_scene *s, const kdt_scene_settings *k)
{
    s->camera.eye = rtt_v3(k->eye[0], k->eye[1], k->eye[2]);
    s->camera.look_at = rtt_v3(k->look_at[0], k->look_at[1], k->look_at[2]);
    s->camera.up = rtt_v3(k->up[0], k->up[1], k->up[2]);
    s->camera.fov_deg = k->fov_deg;
    s->width = k->width, s->height = k->height, s->max_bounces = k->max_bounces;
    s->degenerate_count = k->degenerate_count;
    s->collapsed_count = k->collapsed_count;
    memcpy(s->origin, k->origin, sizeof s->origin);
    s->background = rtt_v3(k->background[0], k->background[1], k->background[2]);
    s->ambient = k->ambient;
    s->bounds = rtt_bounds_empty();
    for (uint32_t i = 0; i < s->triangle_count; i++)
        for (int c = 0; c < 3; c++) s->bounds = rtt_bounds_grow(s->bounds, s->vertices[s->triangles[i].v[c]]);
}

static bool read_scene_part(const kdt_file *f, rtt_scene *s, rtt_error *err)
{
    const kdt_header *h = &f->header;
    kdt_scene_settings settings;
    memcpy(&settings, f->bytes + f->table[KDT_SECTION_SETTINGS].offset, sizeof settings);
    if (!check_settings(f, &settings, err)) return false;
    if (h->material_count == 0 || h->light_count == 0)
        return rtt_error_set(err, "%s: %u materials and %u lights: a scene has at least one of each (header)",
                             f->path, h->material_count, h->light_count);
    s->vertex_count = h->vertex_count, s->triangle_count = h->triangle_count, s->mesh_count = h->mesh_count;
    s->material_count = h->material_count, s->light_count = h->light_count;
    s->vertices = section_copy(f, KDT_SECTION_VERTICES);
    s->normals = settings.has_normals ? section_copy(f, KDT_SECTION_NORMALS) : NULL;
    s->triangles = section_copy(f, KDT_SECTION_TRIANGLES);
    s->triangle_material = section_copy(f, KDT_SECTION_TRIANGLE_MATERIAL);
    s->triangle_mesh = section_copy(f, KDT_SECTION_TRIANGLE_MESH);
    s->meshes = malloc((h->mesh_count ? h->mesh_count : 1) * sizeof *s->meshes);
    s->materials = malloc(h->material_count * sizeof *s->materials);
    s->lights = malloc(h->light_count * sizeof *s->lights);
    if (!s->vertices || (settings.has_normals && !s->normals) || !s->triangles || !s->triangle_material ||
        !s->triangle_mesh || !s->meshes || !s->materials || !s->lights)
        return rtt_error_set(err, "%s: out of memory reading the scene", f->path);
    if (!read_meshes(f, s, err) || !read_materials(f, s, err) || !read_lights(f, s, err) ||
        !check_geometry(f, s, err))
        return false;
    apply_settings(s, &settings);
    return true;
}

/* ---- reading: the tree --------------------------------------------------- */

static bool box_ok(const float lo[3], const float hi[3], bool may_be_empty)
{
    if (may_be_empty && lo[0] == INFINITY && lo[1] == INFINITY && lo[2] == INFINITY && hi[0] == -INFINITY &&
        hi[1] == -INFINITY && hi[2] == -INFINITY)
        return true;
    return all_finite(lo, 3) && all_finite(hi, 3) && lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2];
}

/* Children after their parent (so no cycle), every node but the root the
 * child of exactly one node, every leaf index used by one leaf node, depth
 * within KDT_DEPTH_LIMIT.  depth[] is one byte per node. */
static bool check_nodes(const kdt_file *f, const rtt_baked_tree *t, uint8_t *depth, uint8_t *leaf_used,
                        uint32_t *deepest_leaf, rtt_error *err)
{
    const uint32_t n = t->node_count;
    memset(depth, 0, n);
    memset(leaf_used, 0, t->leaf_count);
    uint32_t deepest = 0;
    for (uint32_t i = 0; i < n; i++) {
        const kdt_node *node = &t->nodes[i];
        if (i > 0 && depth[i] == 0)
            return rtt_error_set(err, "%s: node %u is not reachable from the root (nodes section)", f->path, i);
        uint32_t d = i == 0 ? 0 : depth[i] - 1u, axis = node->bits & 3u, index = node->bits >> 2;
        if (axis == 3u) {
            if (node->leaf >= t->leaf_count || index != 0)
                return rtt_error_set(err, "%s: node %u: leaf index %u out of range (%u leaves) (nodes section)",
                                     f->path, i, node->leaf, t->leaf_count);
            if (leaf_used[node->leaf]++)
                return rtt_error_set(err, "%s: node %u: leaf %u used twice (nodes section)", f->path, i, node->leaf);
            if (d > deepest) deepest = d;
            continue;
        }
        if (!isfinite(node->split))
            return rtt_error_set(err, "%s: node %u: split plane is not finite (nodes section)", f->path, i);
        if (index <= i || index >= n - 1u)
            return rtt_error_set(err, "%s: node %u: child index %u out of range (%u nodes, children follow "
                                      "their parent) (nodes section)",
                                 f->path, i, index, n);
        if (depth[index] != 0 || depth[index + 1] != 0)
            return rtt_error_set(err, "%s: node %u: child %u has two parents (nodes section)", f->path, i, index);
        if (d + 1u > KDT_DEPTH_LIMIT)
            return rtt_error_set(err, "%s: node %u: deeper than %u (nodes section)", f->path, i, KDT_DEPTH_LIMIT);
        depth[index] = depth[index + 1] = (uint8_t)(d + 2u); /* depth + 1, so 0 means "no parent yet" */
    }
    for (uint32_t i = 0; i < t->leaf_count; i++)
        if (!leaf_used[i])
            return rtt_error_set(err, "%s: leaf %u is in no node (leaves section)", f->path, i);
    if (deepest > f->header.max_depth || f->header.max_depth > KDT_DEPTH_LIMIT)
        return rtt_error_set(err, "%s: tree depth %u over its maximum %u (header)", f->path, deepest,
                             f->header.max_depth);
    *deepest_leaf = deepest;
    return true;
}

static bool check_leaves_and_records(const kdt_file *f, const rtt_baked_tree *t, uint32_t *empty_leaves,
                                     rtt_error *err)
{
    const bool no_records = t->record_count == 0;
    uint32_t empty = 0;
    for (uint32_t i = 0; i < t->leaf_count; i++) {
        const kdt_leaf *l = &t->leaves[i];
        if ((uint64_t)l->first + l->count > t->record_count)
            return rtt_error_set(err, "%s: leaf %u: records %u+%u out of range (%u records) (leaves section)",
                                 f->path, i, l->first, l->count, t->record_count);
        if (!box_ok(l->lo, l->hi, no_records))
            return rtt_error_set(err, "%s: leaf %u: box is not finite or inverted (leaves section)", f->path, i);
        empty += l->count == 0;
    }
    for (uint32_t i = 0; i < t->record_count; i++) {
        const kdt_triangle *r = &t->records[i];
        if (r->prim >= f->header.triangle_count)
            return rtt_error_set(err, "%s: record %u: prim %u out of range (%u triangles) (triangle records section)",
                                 f->path, i, r->prim, f->header.triangle_count);
        if (r->k > 2u || r->pad != 0 || !all_finite(&r->n_u, 9))
            return rtt_error_set(err, "%s: record %u: axis %u or a coefficient out of range (triangle records "
                                      "section)",
                                 f->path, i, r->k);
    }
    *empty_leaves = empty;
    return true;
}

static rtt_baked_tree *read_tree(const kdt_file *f, rtt_error *err)
{
    const kdt_header *h = &f->header;
    if (h->node_count == 0 || h->leaf_count == 0 || (uint64_t)h->node_count != 2ull * h->leaf_count - 1u)
        return rtt_error_set(err, "%s: %u nodes and %u leaves do not make a binary tree (header)", f->path,
                             h->node_count, h->leaf_count),
               NULL;
    if (!box_ok(h->tree_lo, h->tree_hi, h->record_count == 0) || !isfinite(h->sah_cost) ||
        !isfinite(h->build_seconds))
        return rtt_error_set(err, "%s: tree bounds or statistics are not finite (header)", f->path), NULL;
    rtt_baked_tree *t = calloc(1, sizeof *t);
    uint8_t *scratch = malloc((size_t)h->node_count + h->leaf_count);
    if (t) {
        t->nodes = section_copy(f, KDT_SECTION_NODES);
        t->leaves = section_copy(f, KDT_SECTION_LEAVES);
        t->records = section_copy(f, KDT_SECTION_RECORDS);
        t->node_count = h->node_count, t->leaf_count = h->leaf_count, t->record_count = h->record_count;
    }
    if (!t || !scratch || !t->nodes || !t->leaves || !t->records) {
        free(scratch);
        rtt_kdt_baked_free(t);
        return rtt_error_set(err, "%s: out of memory reading the tree", f->path), NULL;
    }
    uint32_t empty = 0, deepest = 0;
    bool ok = check_nodes(f, t, scratch, scratch + h->node_count, &deepest, err) &&
              check_leaves_and_records(f, t, &empty, err);
    free(scratch);
    if (!ok) {
        rtt_kdt_baked_free(t);
        return NULL;
    }
    /* what the header reports of the build must agree with the tree */
    if (t->record_count > h->reference_cap) {
        rtt_kdt_baked_free(t);
        return rtt_error_set(err, "%s: %u triangle references over the cap %llu (header)", f->path, h->record_count,
                             (unsigned long long)h->reference_cap), NULL;
    }
    if (!(isfinite(h->sah_cost) && h->sah_cost >= 0.0 && isfinite(h->build_seconds) && h->build_seconds >= 0.0)) {
        rtt_kdt_baked_free(t);
        return rtt_error_set(err, "%s: SAH cost or build time is not a finite number >= 0 (header)", f->path), NULL;
    }
    t->bounds.lo = rtt_v3(h->tree_lo[0], h->tree_lo[1], h->tree_lo[2]);
    t->bounds.hi = rtt_v3(h->tree_hi[0], h->tree_hi[1], h->tree_hi[2]);
    rtt_tree_info *info = &t->info;
    info->depth = deepest;
    info->max_depth = h->max_depth;
    info->node_count = t->node_count, info->leaf_count = t->leaf_count, info->empty_leaf_count = empty;
    info->references = t->record_count;
    info->reference_cap = h->reference_cap;
    info->sah_cost = h->sah_cost, info->build_seconds = h->build_seconds;
    info->memory_bytes = (uint64_t)t->node_count * sizeof(kdt_node) + (uint64_t)t->leaf_count * sizeof(kdt_leaf) +
                         (uint64_t)t->record_count * sizeof(kdt_triangle);
    return t;
}

void rtt_kdt_baked_free(rtt_baked_tree *tree)
{
    if (!tree) return;
    free(tree->nodes);
    free(tree->leaves);
    free(tree->records);
    free(tree);
}

rtt_scene *rtt_kdt_read_scene(const char *path, rtt_error *err)
{
    kdt_file f = {.path = path};
    rtt_scene *scene = NULL;
    bool ok = read_whole_file(&f, err) && check_header(&f, err) && check_sections(&f, err);
    if (ok) {
        scene = rtt_scene_new(path, err);
        ok = scene != NULL;
    }
    ok = ok && read_scene_part(&f, scene, err);
    if (ok) {
        scene->baked = read_tree(&f, err);
        scene->baked_free = rtt_kdt_baked_free;
        ok = scene->baked != NULL;
    }
    free(f.bytes);
    if (!ok) {
        rtt_scene_free(scene);
        return NULL;
    }
    return scene;
}

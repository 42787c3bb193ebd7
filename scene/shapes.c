/* Built-in procedural shapes (see shapes.h and scene/README.md). */
#include "shapes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const float pi = 3.14159265358979323846f;

static bool shape_alloc(rtt_shape_mesh *out, uint32_t vertex_count, uint32_t triangle_count, bool with_normals)
{
    memset(out, 0, sizeof *out);
    out->positions = malloc(sizeof *out->positions * vertex_count);
    out->normals = with_normals ? malloc(sizeof *out->normals * vertex_count) : NULL;
    out->indices = malloc(sizeof *out->indices * 3u * triangle_count);
    if (!out->positions || !out->indices || (with_normals && !out->normals)) {
        rtt_shape_mesh_free(out);
        return false;
    }
    out->vertex_count = vertex_count;
    out->triangle_count = triangle_count;
    return true;
}

void rtt_shape_mesh_free(rtt_shape_mesh *mesh)
{
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->indices);
    memset(mesh, 0, sizeof *mesh);
}

static void set_triangle(rtt_shape_mesh *m, uint32_t t, uint32_t a, uint32_t b, uint32_t c)
{
    m->indices[3u * t + 0u] = a;
    m->indices[3u * t + 1u] = b;
    m->indices[3u * t + 2u] = c;
}

bool rtt_shape_quad(const rtt_vec3 corners[4], rtt_shape_mesh *out)
{
    if (!shape_alloc(out, 4, 2, true)) return false;
    memcpy(out->positions, corners, sizeof *out->positions * 4u);
    /* Newell's normal: right for any planar quad, sensible for a warped one */
    rtt_vec3 normal = rtt_v3(0, 0, 0);
    for (uint32_t i = 0; i < 4; i++)
        normal = rtt_v3_add(normal, rtt_v3_cross(corners[i], corners[(i + 1u) % 4u]));
    normal = rtt_v3_normalize(normal);
    for (uint32_t i = 0; i < 4; i++) out->normals[i] = normal;
    set_triangle(out, 0, 0, 1, 2);
    set_triangle(out, 1, 0, 2, 3);
    return true;
}

bool rtt_shape_box(rtt_vec3 lo, rtt_vec3 hi, rtt_shape_mesh *out)
{
    /* corner i has x from bit 0, y from bit 1, z from bit 2; each face is a
     * quad wound counter-clockwise seen from outside, with its own four
     * vertices so that it carries its face normal */
    static const uint8_t faces[6][4] = {
        {0, 4, 6, 2}, {1, 3, 7, 5}, /* -x, +x */
        {0, 1, 5, 4}, {2, 6, 7, 3}, /* -y, +y */
        {0, 2, 3, 1}, {4, 5, 7, 6}, /* -z, +z */
    };
    if (!shape_alloc(out, 24, 12, true)) return false;
    for (uint32_t f = 0; f < 6; f++) {
        rtt_vec3 normal = rtt_v3(0, 0, 0);
        rtt_v3_set(&normal, (int)(f / 2u), f % 2u ? 1.0f : -1.0f);
        for (uint32_t k = 0; k < 4; k++) {
            uint32_t i = faces[f][k];
            out->positions[4u * f + k] = rtt_v3(i & 1u ? hi.x : lo.x, i & 2u ? hi.y : lo.y, i & 4u ? hi.z : lo.z);
            out->normals[4u * f + k] = normal;
        }
        set_triangle(out, 2u * f, 4u * f, 4u * f + 1u, 4u * f + 2u);
        set_triangle(out, 2u * f + 1u, 4u * f, 4u * f + 2u, 4u * f + 3u);
    }
    return true;
}

/* Midpoints of the current level's edges, so that the two triangles sharing
 * an edge share its midpoint vertex (the sphere stays closed). */
typedef struct edge_midpoints {
    uint64_t *keys; /* (min << 32 | max) + 1; 0 marks an empty slot */
    uint32_t *vertex;
    size_t mask;
} edge_midpoints;

static uint32_t midpoint(edge_midpoints *table, rtt_shape_mesh *m, uint32_t a, uint32_t b)
{
    uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t key = (lo << 32 | hi) + 1u;
    size_t slot = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & table->mask;
    while (table->keys[slot] && table->keys[slot] != key) slot = (slot + 1u) & table->mask;
    if (!table->keys[slot]) {
        rtt_vec3 p = rtt_v3_normalize(rtt_v3_scale(rtt_v3_add(m->positions[a], m->positions[b]), 0.5f));
        table->keys[slot] = key;
        table->vertex[slot] = m->vertex_count;
        m->positions[m->vertex_count++] = p;
    }
    return table->vertex[slot];
}

/* One subdivision of a unit icosphere in place: each triangle into four. */
static bool subdivide(rtt_shape_mesh *m, uint32_t *scratch)
{
    size_t edges = 3u * (size_t)m->triangle_count / 2u, size = 1;
    while (size < 2u * edges) size <<= 1;
    edge_midpoints table = {calloc(size, sizeof(uint64_t)), malloc(size * sizeof(uint32_t)), size - 1u};
    if (!table.keys || !table.vertex) {
        free(table.keys);
        free(table.vertex);
        return false;
    }
    uint32_t count = m->triangle_count;
    memcpy(scratch, m->indices, sizeof *scratch * 3u * count);
    for (uint32_t t = 0; t < count; t++) {
        uint32_t a = scratch[3u * t], b = scratch[3u * t + 1u], c = scratch[3u * t + 2u];
        uint32_t ab = midpoint(&table, m, a, b), bc = midpoint(&table, m, b, c), ca = midpoint(&table, m, c, a);
        set_triangle(m, 4u * t + 0u, a, ab, ca);
        set_triangle(m, 4u * t + 1u, b, bc, ab);
        set_triangle(m, 4u * t + 2u, c, ca, bc);
        set_triangle(m, 4u * t + 3u, ab, bc, ca);
    }
    m->triangle_count = 4u * count;
    free(table.keys);
    free(table.vertex);
    return true;
}

bool rtt_shape_sphere(rtt_vec3 center, float radius, uint32_t subdivisions, rtt_shape_mesh *out)
{
    static const uint8_t faces[20][3] = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1},
    };
    const float g = (1.0f + sqrtf(5.0f)) * 0.5f;
    const rtt_vec3 corners[12] = {
        {-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
        {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1},
    };
    if (subdivisions > RTT_SHAPE_MAX_SUBDIVISIONS) subdivisions = RTT_SHAPE_MAX_SUBDIVISIONS;
    uint32_t triangles = 20u << (2u * subdivisions), vertices = 10u * (1u << (2u * subdivisions)) + 2u;
    uint32_t *scratch = malloc(sizeof *scratch * 3u * triangles / 4u + sizeof *scratch * 3u);
    if (!scratch || !shape_alloc(out, vertices, triangles, true)) {
        free(scratch);
        return false;
    }
    out->vertex_count = 12;
    out->triangle_count = 20;
    for (uint32_t i = 0; i < 12; i++) out->positions[i] = rtt_v3_normalize(corners[i]);
    for (uint32_t t = 0; t < 20; t++) set_triangle(out, t, faces[t][0], faces[t][1], faces[t][2]);
    for (uint32_t s = 0; s < subdivisions; s++) {
        if (!subdivide(out, scratch)) {
            free(scratch);
            rtt_shape_mesh_free(out);
            return false;
        }
    }
    free(scratch);
    for (uint32_t i = 0; i < out->vertex_count; i++) {
        out->normals[i] = out->positions[i];
        out->positions[i] = rtt_v3_madd(center, out->positions[i], radius);
    }
    return true;
}

bool rtt_shape_cylinder(rtt_vec3 base, float radius, float height, uint32_t segments, rtt_shape_mesh *out)
{
    uint32_t n = segments;
    /* side: bottom ring 0..n-1 and top ring n..2n-1 with radial normals;
     * caps: bottom ring 2n..3n-1, top ring 3n..4n-1, centres 4n and 4n+1,
     * with axial normals (same positions as the side's rings, bit for bit) */
    if (!shape_alloc(out, 4u * n + 2u, 4u * n, true)) return false;
    for (uint32_t i = 0; i < n; i++) {
        float a = 2.0f * pi * (float)i / (float)n;
        rtt_vec3 radial = rtt_v3(cosf(a), 0.0f, sinf(a));
        rtt_vec3 p = rtt_v3_madd(base, radial, radius);
        out->positions[i] = out->positions[2u * n + i] = p;
        out->positions[n + i] = out->positions[3u * n + i] = rtt_v3(p.x, p.y + height, p.z);
        out->normals[i] = out->normals[n + i] = radial;
        out->normals[2u * n + i] = rtt_v3(0, -1, 0);
        out->normals[3u * n + i] = rtt_v3(0, 1, 0);
    }
    out->positions[4u * n] = base;
    out->positions[4u * n + 1u] = rtt_v3(base.x, base.y + height, base.z);
    out->normals[4u * n] = rtt_v3(0, -1, 0);
    out->normals[4u * n + 1u] = rtt_v3(0, 1, 0);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (i + 1u) % n;
        set_triangle(out, 4u * i + 0u, i, n + i, j);
        set_triangle(out, 4u * i + 1u, j, n + i, n + j);
        set_triangle(out, 4u * i + 2u, 4u * n, 2u * n + i, 2u * n + j);
        set_triangle(out, 4u * i + 3u, 4u * n + 1u, 3u * n + j, 3u * n + i);
    }
    return true;
}

bool rtt_shape_torus(rtt_vec3 center, float major_radius, float minor_radius, uint32_t around, uint32_t tube,
                     rtt_shape_mesh *out)
{
    if (!shape_alloc(out, around * tube, 2u * around * tube, true)) return false;
    for (uint32_t i = 0; i < around; i++) {
        float u = 2.0f * pi * (float)i / (float)around;
        rtt_vec3 radial = rtt_v3(cosf(u), 0.0f, sinf(u));
        for (uint32_t j = 0; j < tube; j++) {
            float v = 2.0f * pi * (float)j / (float)tube;
            rtt_vec3 n = rtt_v3_add(rtt_v3_scale(radial, cosf(v)), rtt_v3(0.0f, sinf(v), 0.0f));
            out->normals[i * tube + j] = n;
            out->positions[i * tube + j] =
                rtt_v3_add(center, rtt_v3_add(rtt_v3_scale(radial, major_radius), rtt_v3_scale(n, minor_radius)));
        }
    }
    for (uint32_t i = 0; i < around; i++) {
        uint32_t i1 = (i + 1u) % around;
        for (uint32_t j = 0; j < tube; j++) {
            uint32_t j1 = (j + 1u) % tube, t = 2u * (i * tube + j);
            set_triangle(out, t, i * tube + j, i * tube + j1, i1 * tube + j);
            set_triangle(out, t + 1u, i1 * tube + j, i * tube + j1, i1 * tube + j1);
        }
    }
    return true;
}

uint64_t rtt_shape_triangle_count(const char *type, uint32_t subdivisions, uint32_t segments, uint32_t around,
                                  uint32_t tube)
{
    if (strcmp(type, "quad") == 0) return 2;
    if (strcmp(type, "box") == 0) return 12;
    if (strcmp(type, "sphere") == 0) return (uint64_t)20 << (2 * (subdivisions > 30 ? 30 : subdivisions));
    if (strcmp(type, "cylinder") == 0) return 4 * (uint64_t)segments;
    if (strcmp(type, "torus") == 0) return 2 * (uint64_t)around * tube;
    return 0;
}

/* A scene's closed, consistently oriented meshes and the outward side of
 * each of their parts (pgrid_solids.h). */
#include "pgrid_solids.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sorts 64-bit keys (least-significant-digit radix, 16 bits a pass, as
 * many passes as `largest` needs); the result is in keys.  False when out
 * of memory. */
static bool sort_u64(uint64_t *keys, uint64_t *spare, size_t count, uint64_t largest)
{
    enum { BITS = 16, BUCKETS = 1 << BITS };
    uint32_t *histogram = malloc(BUCKETS * sizeof *histogram);
    if (!histogram) return false;
    for (uint32_t shift = 0; shift < 64 && (largest >> shift) != 0; shift += BITS) {
        memset(histogram, 0, BUCKETS * sizeof *histogram);
        for (size_t i = 0; i < count; i++) histogram[(keys[i] >> shift) & (BUCKETS - 1)]++;
        for (uint32_t b = 0, sum = 0; b < BUCKETS; b++) {
            const uint32_t k = histogram[b];
            histogram[b] = sum, sum += k;
        }
        for (size_t i = 0; i < count; i++) spare[histogram[(keys[i] >> shift) & (BUCKETS - 1)]++] = keys[i];
        memcpy(keys, spare, count * sizeof *keys);
    }
    free(histogram);
    return true;
}

/* Six times the signed volume of the tetrahedron from o to the triangle of
 * corners v (in double, relative to o). */
static double signed_volume6(const rtt_scene *scene, const uint32_t v[3], rtt_vec3 o)
{
    double p[3][3];
    for (int k = 0; k < 3; k++) {
        const rtt_vec3 q = scene->vertices[v[k]];
        p[k][0] = (double)q.x - o.x, p[k][1] = (double)q.y - o.y, p[k][2] = (double)q.z - o.z;
    }
    return p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
           p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
}

/* Every directed edge, by vertex index, used once and its reverse once,
 * and a non-zero volume. */
bool pgrid_mesh_oriented(const rtt_scene *scene, const uint8_t *degenerate, const rtt_mesh *mesh, int8_t *outward)
{
    const size_t most = (size_t)mesh->triangle_count * 3;
    uint64_t *edges = malloc(4 * most * sizeof *edges + 8);
    if (!edges) return false;
    uint64_t *reverse = edges + most, *spare = edges + 2 * most;
    size_t count = 0;
    uint64_t largest = 0;
    double volume = 0.0;
    const rtt_vec3 o = scene->vertices[scene->triangles[mesh->first_triangle].v[0]];
    for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++) {
        if (degenerate && degenerate[t]) continue;
        const uint32_t *v = scene->triangles[t].v;
        for (int k = 0; k < 3; k++) {
            const uint64_t a = v[k], b = v[(k + 1) % 3];
            edges[count] = a << 32 | b, reverse[count] = b << 32 | a;
            if (edges[count] > largest) largest = edges[count];
            if (reverse[count] > largest) largest = reverse[count];
            count++;
        }
        volume += signed_volume6(scene, v, o);
    }
    bool ok = sort_u64(edges, spare, count, largest) && sort_u64(reverse, spare, count, largest) && count > 0 &&
              volume != 0.0 && isfinite(volume);
    for (size_t i = 0; ok && i < count; i++) ok = edges[i] == reverse[i] && (i == 0 || edges[i] != edges[i - 1]);
    free(edges);
    *outward = volume > 0.0 ? 1 : -1;
    return ok;
}

void pgrid_mesh_box(const rtt_scene *scene, const rtt_mesh *mesh, float box[6])
{
    for (int a = 0; a < 3; a++) box[a] = INFINITY, box[3 + a] = -INFINITY;
    for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const float *q = &scene->vertices[scene->triangles[t].v[k]].x;
            for (int a = 0; a < 3; a++) box[a] = fminf(box[a], q[a]), box[3 + a] = fmaxf(box[3 + a], q[a]);
        }
}

/* The root of vertex v's part (path halving). */
static uint32_t part_of(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/* The outward side of every triangle of qualifying mesh m: its part (the
 * triangles linked through shared vertex indices) and the sign of that
 * part's signed volume.  parent and volume: scratch per vertex. */
static void parts_outward(const rtt_scene *scene, const uint8_t *degenerate, const rtt_mesh *mesh, uint32_t *parent,
                          double *volume, int8_t *outward)
{
    const uint32_t first = mesh->first_triangle, end = first + mesh->triangle_count;
    for (uint32_t t = first; t < end; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t v = scene->triangles[t].v[k];
            parent[v] = v, volume[v] = 0.0;
        }
    for (uint32_t t = first; t < end; t++) {
        if (degenerate && degenerate[t]) continue;
        const uint32_t *v = scene->triangles[t].v;
        for (int k = 1; k < 3; k++) {
            const uint32_t a = part_of(parent, v[0]), b = part_of(parent, v[k]);
            if (a != b) parent[a] = b;
        }
    }
    /* each part's volume about the mesh's first corner (any point will do: every part is closed) */
    const rtt_vec3 o = scene->vertices[scene->triangles[first].v[0]];
    for (uint32_t t = first; t < end; t++) {
        if (degenerate && degenerate[t]) continue;
        const uint32_t *v = scene->triangles[t].v;
        volume[part_of(parent, v[0])] += signed_volume6(scene, v, o);
    }
    for (uint32_t t = first; t < end; t++) {
        const double w = volume[part_of(parent, scene->triangles[t].v[0])];
        outward[t] = (degenerate && degenerate[t]) || !(w != 0.0) || !isfinite(w) ? 0 : (w > 0.0 ? 1 : -1);
    }
}

bool pgrid_solids_find(pgrid_solids *solids, const rtt_scene *scene, const uint8_t *degenerate)
{
    memset(solids, 0, sizeof *solids);
    solids->triangle_outward = calloc((size_t)scene->triangle_count + 1, 1);
    solids->mesh_solid = calloc((size_t)scene->mesh_count + 1, 1);
    solids->mesh_box = calloc((size_t)scene->mesh_count + 1, sizeof *solids->mesh_box);
    uint32_t *parent = malloc(((size_t)scene->vertex_count + 1) * sizeof *parent);
    double *volume = malloc(((size_t)scene->vertex_count + 1) * sizeof *volume);
    bool ok = solids->triangle_outward && solids->mesh_solid && solids->mesh_box && parent && volume;
    for (uint32_t m = 0; ok && m < scene->mesh_count; m++) {
        const rtt_mesh *mesh = &scene->meshes[m];
        int8_t whole;
        if (!mesh->closed || !mesh->triangle_count || !pgrid_mesh_oriented(scene, degenerate, mesh, &whole)) continue;
        pgrid_mesh_box(scene, mesh, solids->mesh_box[m]);
        parts_outward(scene, degenerate, mesh, parent, volume, solids->triangle_outward);
        solids->mesh_solid[m] = 1;
        solids->solid_count++;
    }
    free(parent);
    free(volume);
    if (!ok) pgrid_solids_free(solids);
    return ok;
}

void pgrid_solids_free(pgrid_solids *solids)
{
    free(solids->triangle_outward);
    free(solids->mesh_solid);
    free(solids->mesh_box);
    memset(solids, 0, sizeof *solids);
}

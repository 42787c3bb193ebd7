/* A scene's closed, consistently oriented meshes and the outward side of
 * each of their parts (solids.h). */
#include "solids.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sorts a vertex's short list of neighbours (insertion sort; qsort past 32). */
static int compare_u32(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static void sort_neighbours(uint32_t *list, uint32_t n)
{
    if (n > 32) {
        qsort(list, n, sizeof *list, compare_u32);
        return;
    }
    for (uint32_t i = 1; i < n; i++) {
        const uint32_t x = list[i];
        uint32_t j = i;
        for (; j > 0 && list[j - 1] > x; j--) list[j] = list[j - 1];
        list[j] = x;
    }
}

/* Whether b is in the sorted list. */
static bool has_neighbour(const uint32_t *list, uint32_t n, uint32_t b)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (list[mid] < b) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && list[lo] == b;
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

/* Every directed edge, by vertex index, used once and its reverse once.
 * The edges are listed by their first vertex (a counting sort over the
 * mesh's vertex range), each vertex's list sorted: no neighbour twice (an
 * edge used twice) and, for every edge a -> b, a in b's list (its
 * reverse). */
static bool edges_paired(const rtt_scene *scene, const uint8_t *degenerate, const rtt_mesh *mesh)
{
    const uint32_t first = mesh->first_triangle, end = first + mesh->triangle_count;
    uint32_t lowest = UINT32_MAX, highest = 0;
    for (uint32_t t = first; t < end; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t v = scene->triangles[t].v[k];
            lowest = v < lowest ? v : lowest;
            highest = v > highest ? v : highest;
        }
    if (lowest > highest) return false;
    const size_t span = (size_t)highest - lowest + 1, most = (size_t)mesh->triangle_count * 3;
    uint32_t *start = calloc(span + 1, sizeof *start), *fill = malloc(span * sizeof *fill);
    uint32_t *to = malloc((most ? most : 1) * sizeof *to);
    bool ok = start && fill && to;
    for (uint32_t t = first; ok && t < end; t++) {
        if (degenerate && degenerate[t]) continue;
        const uint32_t *v = scene->triangles[t].v;
        for (int k = 0; k < 3; k++) start[v[k] - lowest + 1]++;
    }
    if (ok) {
        for (size_t i = 0; i < span; i++) start[i + 1] += start[i], fill[i] = start[i];
        for (uint32_t t = first; t < end; t++) {
            if (degenerate && degenerate[t]) continue;
            const uint32_t *v = scene->triangles[t].v;
            for (int k = 0; k < 3; k++) to[fill[v[k] - lowest]++] = v[(k + 1) % 3] - lowest;
        }
        for (size_t a = 0; a < span; a++) sort_neighbours(to + start[a], start[a + 1] - start[a]);
        ok = start[span] > 0;
        for (size_t a = 0; ok && a < span; a++)
            for (uint32_t i = start[a]; ok && i < start[a + 1]; i++) {
                const uint32_t b = to[i];
                ok = (i == start[a] || to[i - 1] != b) && has_neighbour(to + start[b], start[b + 1] - start[b], (uint32_t)a);
            }
    }
    free(start), free(fill), free(to);
    return ok;
}

/* Edges paired and a non-zero volume (the whole mesh's: its outward side). */
bool scene_mesh_oriented(const rtt_scene *scene, const uint8_t *degenerate, const rtt_mesh *mesh, int8_t *outward)
{
    double volume = 0.0;
    const rtt_vec3 o = scene->vertices[scene->triangles[mesh->first_triangle].v[0]];
    for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++)
        if (!degenerate || !degenerate[t]) volume += signed_volume6(scene, scene->triangles[t].v, o);
    *outward = volume > 0.0 ? 1 : -1;
    return volume != 0.0 && isfinite(volume) && edges_paired(scene, degenerate, mesh);
}

void scene_mesh_box(const rtt_scene *scene, const rtt_mesh *mesh, float box[6])
{
    for (int a = 0; a < 3; a++) box[a] = INFINITY, box[3 + a] = -INFINITY;
    for (uint32_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const float *q = &scene->vertices[scene->triangles[t].v[k]].x;
            for (int a = 0; a < 3; a++) { /* NaN corners leave the box as it was, as fminf and fmaxf would */
                box[a] = q[a] < box[a] ? q[a] : box[a];
                box[3 + a] = q[a] > box[3 + a] ? q[a] : box[3 + a];
            }
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

bool scene_solids_find(scene_solids *solids, const rtt_scene *scene, const uint8_t *degenerate)
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
        if (!mesh->closed || !mesh->triangle_count || !edges_paired(scene, degenerate, mesh)) continue;
        scene_mesh_box(scene, mesh, solids->mesh_box[m]);
        parts_outward(scene, degenerate, mesh, parent, volume, solids->triangle_outward);
        solids->mesh_solid[m] = 1;
        solids->solid_count++;
    }
    free(parent);
    free(volume);
    if (!ok) scene_solids_free(solids);
    return ok;
}

void scene_solids_free(scene_solids *solids)
{
    free(solids->triangle_outward);
    free(solids->mesh_solid);
    free(solids->mesh_box);
    memset(solids, 0, sizeof *solids);
}

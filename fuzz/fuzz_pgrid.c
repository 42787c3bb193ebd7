/* Fuzz harness for the light grids of --shadows pgrid
 * (optimized/pgrid/pgrid_light.h): bytes → triangles (palette coordinates
 * with shared vertices, signed zeros, tiny, denormal and huge values, or raw
 * float bits; scaled and moved away from the origin), a light (at a vertex,
 * on an edge's midpoint or at a palette point), a grid resolution, and
 * shadow-ray origins (at vertices, on triangles, at palette points).  The
 * grid is built and its invariants checked (references in range and
 * ascending per cell, the near list in range); then every shadow ray the
 * shader proxy would make from those origins to the light (epsilon to
 * distance - epsilon) is traced through the grid at every instruction set
 * this CPU runs and must answer exactly as the brute force: any
 * non-degenerate triangle the reference's watertight test
 * (rtt_reference_intersect_triangle) finds on it.
 *
 * Then the same for --shadows pgrid:N's 3D grid (pgrid_soft.h) around a
 * sphere light at the same place (radius from the mode byte, 1 to 8 slices):
 * its invariants, and from every origin its 4 multi:4 sample rays
 * (rtt_light_sample, the shader proxy's segment), the ray to the centre and
 * the segment to the next origin (a ray nowhere near the light), each
 * through the slice traverser at every instruction set against the brute
 * force.
 *
 * Input: [count - 1] [mode] [offset] [res] then 3 * count vertex controls (a
 * byte < 48 repeats an earlier vertex, else three coordinates), the light
 * as a point (control byte: vertex, surface, edge midpoint or palette
 * point, and its operands), then the origins as points the same way. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "pgrid_eye.h"
#include "pgrid_light.h"
#include "pgrid_soft.h"
#include "rtt/reference.h"
#include "rtt/rtt.h"

#define MAX_TRIANGLES 40u
#define MAX_ORIGINS 64u

typedef struct byte_reader {
    const uint8_t *data;
    size_t size, at;
} byte_reader;

static uint8_t next_byte(byte_reader *in) { return in->at < in->size ? in->data[in->at++] : 0; }

static float next_raw_float(byte_reader *in)
{
    uint32_t bits = 0;
    for (int k = 0; k < 4; k++) bits |= (uint32_t)next_byte(in) << (8 * k);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static float palette_float(uint8_t b)
{
    static const float specials[] = {0.0f, -0.0f, 0.5f, -0.5f, 0.25f, 1e-3f, 1e-20f, -1e-20f,
                                     1e-40f, FLT_MIN, 1e10f, -1e10f, 1e20f, 3.3e6f, 0.1f, 0.3f};
    if (b < 16) return specials[b];
    if (b < 16 + 33) return (float)((int)b - 32);
    return (float)((int)b - 152) / 8.0f;
}

static const float scales[8] = {1.0f, 1e-20f, 1e20f, 1e-6f, 1e6f, 1.0f, 1e-3f, 1e3f};
static const float offsets[4] = {0.0f, 1e4f, -1e7f, 3e5f};

static float coordinate(byte_reader *in, bool raw, float scale, float offset)
{
    return raw ? next_raw_float(in) : palette_float(next_byte(in)) * scale + offset;
}

static rtt_vec3 palette_point(byte_reader *in, const rtt_scene *scene, float scale, float offset)
{
    const double p[3] = {palette_float(next_byte(in)) * scale + offset, palette_float(next_byte(in)) * scale + offset,
                         palette_float(next_byte(in)) * scale + offset};
    return rtt_scene_point_to_stored(scene, p);
}

/* A point on triangle b % count at barycentrics from two bytes (its index in *prim). */
static rtt_vec3 surface_point(byte_reader *in, const rtt_scene *scene, uint32_t *prim)
{
    rtt_vec3 c[3];
    *prim = next_byte(in) % scene->triangle_count;
    rtt_scene_triangle(scene, *prim, c);
    float u = (float)next_byte(in) / 255.0f, v = (float)next_byte(in) / 255.0f;
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    return rtt_v3_add(c[0], rtt_v3_add(rtt_v3_scale(rtt_v3_sub(c[1], c[0]), u), rtt_v3_scale(rtt_v3_sub(c[2], c[0]), v)));
}

/* *prim: the triangle the point lies on, RTT_MISS when none is known. */
static rtt_vec3 decode_point(byte_reader *in, const rtt_scene *scene, float scale, float offset, uint32_t *prim)
{
    const uint8_t control = next_byte(in);
    *prim = RTT_MISS;
    switch (control % 4) {
    case 0: return scene->vertices[next_byte(in) % scene->vertex_count];
    case 1: return surface_point(in, scene, prim);
    case 2: {
        const rtt_vec3 a = scene->vertices[next_byte(in) % scene->vertex_count];
        const rtt_vec3 b = scene->vertices[next_byte(in) % scene->vertex_count];
        return rtt_v3_scale(rtt_v3_add(a, b), 0.5f);
    }
    default: return palette_point(in, scene, scale, offset);
    }
}

static uint8_t brute_force(const rtt_scene *scene, const uint8_t *degenerate, const rtt_ray *ray)
{
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        if (degenerate[i]) continue;
        rtt_vec3 c[3];
        rtt_scene_triangle(scene, i, c);
        float t, u, v;
        if (rtt_reference_intersect_triangle(ray, c, &t, &u, &v)) return 1;
    }
    return 0;
}

static void check_invariants(const pgrid_shadows *grids, const pgrid_light *light)
{
    const size_t face_cells = (size_t)light->res * light->res, cells = PGRID_LIGHT_FACES * face_cells;
    if (light->cell_first[cells] != light->ref_count) fuzz_fail("light grid: the cell ranges do not cover the references");
    /* the kept cells' ranges tile the references in face order; the others hold none */
    for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
        const uint32_t *kept = light->kept_cells[face];
        if ((light->faces >> face & 1u) != (kept[0] < kept[1]))
            fuzz_fail("light grid: face %u's kept cells disagree with its bit", face);
        if (kept[0] < kept[1] && (kept[0] % light->res || kept[1] % light->res || kept[0] < face * face_cells ||
                                  kept[1] > (face + 1) * face_cells))
            fuzz_fail("light grid: face %u's kept cells are not rows of it", face);
    }
    uint32_t covered = 0;
    for (size_t c = 0; c < cells; c++) {
        const uint32_t *kept = light->kept_cells[c / face_cells];
        if (c < kept[0] || c >= kept[1]) continue;
        if (light->cell_first[c] != covered) fuzz_fail("light grid: cell %zu's range does not follow the last", c);
        covered = light->cell_first[c + 1];
        if (light->cell_front[c] < light->cell_first[c] || light->cell_front[c] > light->cell_first[c + 1])
            fuzz_fail("light grid: cell %zu's front references lie outside its range", c);
        if (light->cell_first[c] > light->cell_first[c + 1]) fuzz_fail("light grid: cell %zu's range is reversed", c);
        for (uint32_t r = light->cell_first[c]; r < light->cell_first[c + 1]; r++) {
            if (light->refs[r] >= grids->corner_count) fuzz_fail("light grid: cell %zu names triangle %u", c, light->refs[r]);
            if (r > light->cell_first[c] && light->refs[r] <= light->refs[r - 1])
                fuzz_fail("light grid: cell %zu's list is not ascending", c);
        }
    }
    if (covered != light->ref_count) fuzz_fail("light grid: the kept faces' cells do not cover the references");
    for (uint32_t i = 0; i < grids->corner_count; i++) {
        if (light->face_mask[i] & ~light->faces) fuzz_fail("light grid: triangle %u has a footprint on a face not kept", i);
        for (uint32_t face = 0; face < PGRID_LIGHT_FACES; face++) {
            if (!(light->face_mask[i] >> face & 1u)) continue;
            const pgrid_footprint f = light->prints[(size_t)face * grids->corner_count + i];
            const size_t first = ((size_t)face * light->res + f.y0) * light->res, end = ((size_t)face * light->res + f.y1 + 1) * light->res;
            if (first < light->kept_cells[face][0] || end > light->kept_cells[face][1])
                fuzz_fail("light grid: triangle %u's footprint on face %u meets rows not kept", i, face);
        }
    }
    for (uint32_t i = 0; i < light->near_count; i++)
        if (light->near[i] >= grids->corner_count) fuzz_fail("light grid: the near list names triangle %u", light->near[i]);
}

static void check_soft_invariants(const pgrid_soft *grids, const pgrid_soft_light *light)
{
    const size_t cells = (size_t)light->slices * PGRID_LIGHT_FACES * light->res * light->res;
    if (light->cell_first[0] != 0 || light->cell_first[cells] != light->ref_count)
        fuzz_fail("soft grid: the cell ranges do not cover the references");
    for (size_t c = 0; c < cells; c++) {
        if (light->cell_first[c] > light->cell_first[c + 1]) fuzz_fail("soft grid: cell %zu's range is reversed", c);
        for (uint32_t r = light->cell_first[c]; r < light->cell_first[c + 1]; r++) {
            if (light->refs[r] >= grids->tri_count) fuzz_fail("soft grid: cell %zu names triangle %u", c, light->refs[r]);
            if (r > light->cell_first[c] && light->refs[r] <= light->refs[r - 1])
                fuzz_fail("soft grid: cell %zu's list is not ascending", c);
        }
    }
    for (uint32_t i = 0; i < light->near_count; i++)
        if (light->near_list[i] >= grids->tri_count) fuzz_fail("soft grid: the near list names triangle %u", light->near_list[i]);
    for (uint32_t k = 0; k < light->slices; k++)
        if (!(light->bound[k] < light->bound[k + 1])) fuzz_fail("soft grid: slice %u's bounds are not increasing", k);
}

/* The soft rays from the origins (see the header) through the 3D grid. */
static void check_soft(const rtt_scene *scene, const uint8_t *degenerate, rtt_vec3 at, float radius, uint32_t res,
                       uint32_t slices, const rtt_ray *hard, uint32_t n)
{
    pgrid_soft grids;
    rtt_error err = {""};
    if (!pgrid_soft_prepare(&grids, scene, degenerate, &err)) fuzz_fail("soft grid: %s", err.message);
    rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = at, .radius = radius, .intensity = 1.0f};
    const float position[3] = {at.x, at.y, at.z};
    if (!pgrid_soft_light_build(&grids.lights[0], &grids, position, pgrid_soft_light_extent(&light), res, slices))
        fuzz_fail("soft grid: out of memory");
    grids.light_count = 1;
    check_soft_invariants(&grids, &grids.lights[0]);
    enum { PER = 6 };
    rtt_ray rays[MAX_ORIGINS * PER];
    uint8_t expected[MAX_ORIGINS * PER], ours[MAX_ORIGINS * PER];
    uint32_t m = 0;
    const float epsilon = rtt_scene_ray_epsilon(scene);
    for (uint32_t i = 0; i < n; i++) {
        const rtt_vec3 p = {hard[i].org[0], hard[i].org[1], hard[i].org[2]};
        for (uint32_t k = 0; k <= 5; k++) {
            const rtt_vec3 target = k < 4 ? rtt_light_sample(&light, p, k, 4, i)
                                  : k == 4 ? at
                                           : rtt_v3(hard[(i + 1) % n].org[0], hard[(i + 1) % n].org[1],
                                                    hard[(i + 1) % n].org[2]);
            const rtt_vec3 to = rtt_v3_sub(target, p);
            const float distance = rtt_v3_length(to);
            if (!isfinite(distance) || !(distance > 2.0f * epsilon)) continue;
            const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / distance);
            rays[m] = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, epsilon, distance - epsilon};
            expected[m] = brute_force(scene, degenerate, &rays[m]);
            m++;
        }
    }
    for (rtt_isa isa = RTT_ISA_SSE4; isa < RTT_ISA_COUNT; isa = (rtt_isa)(isa + 1)) {
        if (!rtt_isa_supported(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        k->soft_occluded(&grids, 0, rays, m, ours, NULL);
        for (uint32_t i = 0; i < m; i++)
            if (ours[i] != expected[i])
                fuzz_fail("soft grid (%s, res %u x %u slices, radius %a): ray %u org (%a %a %a) dir (%a %a %a) tnear "
                          "%a tfar %a: grid %u, brute force %u",
                          rtt_isa_name(isa), grids.lights[0].res, grids.lights[0].slices, (double)radius, i,
                          (double)rays[i].org[0], (double)rays[i].org[1], (double)rays[i].org[2],
                          (double)rays[i].dir[0], (double)rays[i].dir[1], (double)rays[i].dir[2],
                          (double)rays[i].tnear, (double)rays[i].tfar, ours[i], expected[i]);
    }
    pgrid_soft_free(&grids);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    byte_reader in = {data, size, 0};
    const uint32_t triangle_count = 1 + next_byte(&in) % MAX_TRIANGLES;
    const uint8_t mode = next_byte(&in);
    const bool raw = mode & 1;
    const float scale = scales[(mode >> 1) % 8], offset = offsets[next_byte(&in) % 4];
    static const uint32_t resolutions[] = {0, 1, 2, 5, 16, 64, 200, 333};
    const uint32_t res = resolutions[next_byte(&in) % 8];
    float xyz[MAX_TRIANGLES * 9];
    for (uint32_t v = 0; v < triangle_count * 3; v++) {
        const uint8_t control = next_byte(&in);
        if (control < 48 && v > 0)
            memcpy(&xyz[v * 3], &xyz[(control % v) * 3], 3 * sizeof(float));
        else
            for (int k = 0; k < 3; k++) xyz[v * 3 + k] = coordinate(&in, raw, scale, offset);
    }
    for (size_t i = 0; i < (size_t)triangle_count * 9; i++)
        if (!isfinite(xyz[i])) return 0; /* refused by rtt_scene_from_triangles (fuzz_kd_build checks how) */
    rtt_error err = {""};
    rtt_scene *scene = rtt_scene_from_triangles(xyz, triangle_count, &err);
    if (!scene) fuzz_fail("rtt_scene_from_triangles refused finite input: %s", err.message);
    uint8_t degenerate[MAX_TRIANGLES];
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 c[3];
        rtt_scene_triangle(scene, i, c);
        degenerate[i] = rtt_triangle_is_degenerate(c);
    }
    uint32_t light_prim;
    const rtt_vec3 light_at = decode_point(&in, scene, scale, offset, &light_prim);
    if (!isfinite(light_at.x) || !isfinite(light_at.y) || !isfinite(light_at.z)) {
        rtt_scene_free(scene);
        return 0;
    }
    pgrid_shadows grids;
    if (!pgrid_shadows_build(&grids, scene, degenerate, 0, &err)) fuzz_fail("light grids: %s", err.message);
    pgrid_light light;
    const float position[3] = {light_at.x, light_at.y, light_at.z};
    if (!pgrid_light_build(&light, &grids, scene, position, res)) fuzz_fail("light grid: out of memory");
    check_invariants(&grids, &light);
    /* every instruction set's footprint stage (vectors of doubles) builds the scalar stage's grid, bit for bit */
    for (rtt_isa isa = RTT_ISA_SSE4; isa < RTT_ISA_COUNT; isa = (rtt_isa)(isa + 1)) {
        if (!rtt_isa_supported(isa)) continue;
        pgrid_shadows vector = grids;
        vector.prints = pgrid_kernel_find("", isa)->light_prints;
        pgrid_light other;
        if (!pgrid_light_build(&other, &vector, scene, position, res)) fuzz_fail("light grid: out of memory");
        const size_t n = grids.corner_count;
        bool cells_differ = other.faces != light.faces || memcmp(other.kept_cells, light.kept_cells, sizeof light.kept_cells);
        for (uint32_t face = 0; face < PGRID_LIGHT_FACES && !cells_differ; face++) {
            const size_t at = light.kept_cells[face][0], kept = light.kept_cells[face][1] - at;
            if (kept)
                cells_differ = memcmp(other.cell_first + at, light.cell_first + at, (kept + 1) * sizeof *light.cell_first) ||
                               memcmp(other.cell_front + at, light.cell_front + at, kept * sizeof *light.cell_front) ||
                               memcmp(other.cell_min + at, light.cell_min + at, kept * sizeof *light.cell_min);
        }
        if (cells_differ || other.ref_count != light.ref_count || other.near_count != light.near_count ||
            (light.ref_count && memcmp(other.refs, light.refs, light.ref_count * sizeof *light.refs)) ||
            !pgrid_light_prints_equal(&light, &other, (uint32_t)n))
            fuzz_fail("light grid (%s, res %u): the vector footprint stage's grid differs from the scalar one's",
                      rtt_isa_name(isa), light.res);
        pgrid_light_free(&other);
    }
    pgrid_shadows one = grids;
    one.lights = &light, one.light_count = 1;

    const float epsilon = rtt_scene_ray_epsilon(scene);
    rtt_ray rays[MAX_ORIGINS];
    uint8_t expected[MAX_ORIGINS], ours[MAX_ORIGINS];
    uint32_t prims[MAX_ORIGINS], n = 0;
    while (in.at < in.size && n < MAX_ORIGINS) {
        const rtt_vec3 p = decode_point(&in, scene, scale, offset, &prims[n]);
        const rtt_vec3 to = rtt_v3_sub(light_at, p);
        const float distance = rtt_v3_length(to);
        if (!isfinite(distance) || !(distance > 2.0f * epsilon)) continue;
        const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / distance);
        rays[n] = (rtt_ray){{p.x, p.y, p.z}, {dir.x, dir.y, dir.z}, epsilon, distance - epsilon};
        expected[n] = brute_force(scene, degenerate, &rays[n]);
        n++;
    }
    for (rtt_isa isa = RTT_ISA_SSE4; isa < RTT_ISA_COUNT; isa = (rtt_isa)(isa + 1)) {
        if (!rtt_isa_supported(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("", isa);
        if (!k) fuzz_fail("no pgrid kernel for %s", rtt_isa_name(isa));
        if (!k->shadow_occluded(&one, 0, rays, prims, n, ours)) fuzz_fail("light grid: out of memory tracing");
        for (uint32_t i = 0; i < n; i++)
            if (ours[i] != expected[i])
                fuzz_fail("light grid (%s, res %u): ray %u org (%a %a %a) dir (%a %a %a) tnear %a tfar %a: grid %u, "
                          "brute force %u", rtt_isa_name(isa), light.res, i, (double)rays[i].org[0],
                          (double)rays[i].org[1], (double)rays[i].org[2], (double)rays[i].dir[0],
                          (double)rays[i].dir[1], (double)rays[i].dir[2], (double)rays[i].tnear,
                          (double)rays[i].tfar, ours[i], expected[i]);
    }
    static const float radii[4] = {0.0f, 0.05f, 1.0f, 20.0f};
    check_soft(scene, degenerate, light_at, radii[(mode >> 4) % 4] * scale, res, 1 + (mode >> 6) * 2, rays, n);
    pgrid_light_free(&light);
    pgrid_shadows_free(&grids);
    rtt_scene_free(scene);
    return 0;
}

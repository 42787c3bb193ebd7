/* Lights for a Quake III map whose light entities are gone: q3map2 removes
 * them when it compiles a map (unless told to keep them), and so almost
 * every OpenArena map has none.  What the map keeps of its lighting is the
 * light grid (lump 15), which the game uses to light moving models: one
 * sample per grid point of the world model's bounds, 8 bytes each (ambient
 * RGB, directed RGB, and the directed light's direction), on a grid of
 * "gridsize" units (worldspawn's key, default 64 64 128) laid out as the
 * engine lays it out (origin = size * ceil(mins / size), points up to
 * size * floor(maxs / size), x fastest).
 *
 * The rule: a grid point whose directed light is a local maximum over its 26
 * neighbours, at least a quarter of the map's brightest, stands for a light
 * next to it.  Up to 64 such points, brightest first, no two within two grid
 * steps of each other, become sphere lights of the point's directed colour
 * (its largest component scaled to 1), with the entity lights' inverse-square
 * fall-off 1 / (256 + d^2) and an intensity that gives the point's directed
 * brightness (directed / 255 of white) at one grid step (64 units) away; the
 * radius is that of the default entity light, 8.7 units.  The map's ambient
 * becomes the median ambient brightness of the lit grid points (ambient / 255
 * of white), at least the default 0.05 and at most 0.5.  A map without a
 * grid, or with one that does not match its bounds, gets none of this. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_build.h"

#define BSP_HEADER_SIZE 144u
#define LUMP_MODELS 7u
#define LUMP_LIGHTGRID 15u
#define MODEL_SIZE 40u
#define CELL_SIZE 8u
#define GRID_POINTS_MAX ((uint32_t)1 << 24)
#define GRID_LIGHTS_MAX 64u
#define GRID_LIGHT_SPACING 2
#define FALL_OFF_CONSTANT 256.0f
#define REFERENCE_DISTANCE 64.0f
#define GRID_LIGHT_RADIUS 8.66f
#define AMBIENT_MAX 0.25f
#define AMBIENT_SHARE 0.5f

typedef struct light_grid {
    float origin[3], size[3];
    int32_t count[3];
    const uint8_t *cells;
} light_grid;

typedef struct grid_candidate {
    uint32_t index, directed;
} grid_candidate;

static uint32_t read_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float read_f32(const uint8_t *p)
{
    uint32_t bits = read_u32(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* Lump `lump` of the open map, or NULL (absent, or outside the file). */
static uint8_t *read_lump(FILE *file, long file_size, const uint8_t *header, uint32_t lump, uint32_t *bytes)
{
    uint32_t offset = read_u32(header + 8 + 8 * lump);
    *bytes = read_u32(header + 12 + 8 * lump);
    if (*bytes == 0 || (uint64_t)offset + *bytes > (uint64_t)file_size) return NULL;
    uint8_t *data = malloc(*bytes);
    if (data && (fseek(file, (long)offset, SEEK_SET) != 0 || fread(data, 1, *bytes, file) != *bytes)) {
        free(data);
        return NULL;
    }
    return data;
}

static uint32_t directed_of(const uint8_t *cell) { return (uint32_t)cell[3] + cell[4] + cell[5]; }
static uint32_t ambient_of(const uint8_t *cell) { return (uint32_t)cell[0] + cell[1] + cell[2]; }

/* No neighbour brighter, and brighter by a quarter than the mean of the lit
 * ones (points in solid or outside the level are black, and do not count):
 * light that falls off around the point (a sun's, even everywhere, does not). */
static bool is_peak(const light_grid *g, int32_t x, int32_t y, int32_t z, uint32_t directed)
{
    uint32_t sum = 0, neighbours = 0;
    for (int32_t dz = -1; dz <= 1; dz++)
        for (int32_t dy = -1; dy <= 1; dy++)
            for (int32_t dx = -1; dx <= 1; dx++) {
                int32_t nx = x + dx, ny = y + dy, nz = z + dz;
                if ((!dx && !dy && !dz) || nx < 0 || ny < 0 || nz < 0 || nx >= g->count[0] || ny >= g->count[1] ||
                    nz >= g->count[2])
                    continue;
                size_t n = ((size_t)nz * (size_t)g->count[1] + (size_t)ny) * (size_t)g->count[0] + (size_t)nx;
                uint32_t d = directed_of(g->cells + n * CELL_SIZE);
                if (d > directed) return false;
                sum += d;
                neighbours += d > 0;
            }
    return neighbours && 5u * sum <= 4u * directed * neighbours;
}

static int by_directed_then_index(const void *a, const void *b)
{
    const grid_candidate *p = a, *q = b;
    if (p->directed != q->directed) return p->directed > q->directed ? -1 : 1;
    return p->index < q->index ? -1 : p->index > q->index;
}

static int by_value(const void *a, const void *b)
{
    uint32_t p = *(const uint32_t *)a, q = *(const uint32_t *)b;
    return (p > q) - (p < q);
}

static void grid_point(const light_grid *g, uint32_t index, int32_t xyz[3])
{
    xyz[0] = (int32_t)(index % (uint32_t)g->count[0]);
    xyz[1] = (int32_t)(index / (uint32_t)g->count[0] % (uint32_t)g->count[1]);
    xyz[2] = (int32_t)(index / ((uint32_t)g->count[0] * (uint32_t)g->count[1]));
}

static bool add_grid_light(rtt_scene *scene, const light_grid *g, uint32_t index, rtt_error *err)
{
    const uint8_t *cell = g->cells + (size_t)index * CELL_SIZE;
    int32_t xyz[3];
    grid_point(g, index, xyz);
    float q[3];
    for (int k = 0; k < 3; k++) q[k] = g->origin[k] + (float)xyz[k] * g->size[k];
    float largest = fmaxf((float)cell[3], fmaxf((float)cell[4], (float)cell[5]));
    float brightness = (float)directed_of(cell) / (3.0f * 255.0f);
    rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = rtt_v3(q[0], q[2], -q[1]),
                       .color = rtt_v3(cell[3] / largest, cell[4] / largest, cell[5] / largest),
                       .intensity = brightness * (FALL_OFF_CONSTANT + REFERENCE_DISTANCE * REFERENCE_DISTANCE),
                       .attenuation = {FALL_OFF_CONSTANT, 0.0f, 1.0f}, .radius = GRID_LIGHT_RADIUS};
    if (!rtt_light_is_finite(&light)) return true; /* a grid past float's range lights nothing */
    return rtt_scene_add_light(scene, &light, err);
}

/* The lights and ambient of the rule above from a grid that matches. */
static bool lights_from_grid(rtt_scene *scene, const light_grid *g, rtt_error *err)
{
    const uint32_t points = (uint32_t)g->count[0] * (uint32_t)g->count[1] * (uint32_t)g->count[2];
    uint32_t brightest = 0, lit = 0;
    for (uint32_t i = 0; i < points; i++) {
        uint32_t directed = directed_of(g->cells + (size_t)i * CELL_SIZE);
        if (directed > brightest) brightest = directed;
    }
    if (brightest == 0) return true;
    grid_candidate *candidates = malloc((size_t)points * sizeof *candidates);
    uint32_t *ambient = malloc((size_t)points * sizeof *ambient);
    if (!candidates || !ambient) {
        free(candidates);
        free(ambient);
        return rtt_error_set(err, "%s: light grid: out of memory", scene->path);
    }
    uint32_t count = 0;
    for (uint32_t i = 0; i < points; i++) {
        const uint8_t *cell = g->cells + (size_t)i * CELL_SIZE;
        uint32_t directed = directed_of(cell);
        if (directed || ambient_of(cell)) ambient[lit++] = ambient_of(cell);
        int32_t xyz[3];
        grid_point(g, i, xyz);
        if (4 * directed >= brightest && is_peak(g, xyz[0], xyz[1], xyz[2], directed))
            candidates[count++] = (grid_candidate){i, directed};
    }
    qsort(candidates, count, sizeof *candidates, by_directed_then_index);
    bool ok = true;
    uint32_t chosen[GRID_LIGHTS_MAX], chosen_count = 0;
    for (uint32_t c = 0; ok && c < count && chosen_count < GRID_LIGHTS_MAX; c++) {
        int32_t p[3], q[3];
        grid_point(g, candidates[c].index, p);
        bool apart = true;
        for (uint32_t k = 0; k < chosen_count && apart; k++) {
            grid_point(g, chosen[k], q);
            apart = abs(p[0] - q[0]) > GRID_LIGHT_SPACING || abs(p[1] - q[1]) > GRID_LIGHT_SPACING ||
                    abs(p[2] - q[2]) > GRID_LIGHT_SPACING;
        }
        if (!apart) continue;
        chosen[chosen_count++] = candidates[c].index;
        ok = add_grid_light(scene, g, candidates[c].index, err);
    }
    if (ok && lit) {
        qsort(ambient, lit, sizeof *ambient, by_value);
        float median = (float)ambient[lit / 2] / (3.0f * 255.0f);
        scene->ambient = fminf(AMBIENT_MAX, fmaxf(RTT_DEFAULT_AMBIENT, AMBIENT_SHARE * median));
    }
    free(candidates);
    free(ambient);
    return ok;
}

bool rtt_q3bsp_lights_from_grid(rtt_scene *scene, const char *path, const float grid_size[3], rtt_error *err)
{
    FILE *file = fopen(path, "rb");
    if (!file) return rtt_error_set(err, "%s: cannot open", path);
    uint8_t header[BSP_HEADER_SIZE];
    long size = fseek(file, 0, SEEK_END) == 0 ? ftell(file) : -1;
    bool have_header = size >= (long)BSP_HEADER_SIZE && fseek(file, 0, SEEK_SET) == 0 &&
                       fread(header, 1, sizeof header, file) == sizeof header;
    uint32_t model_bytes = 0, grid_bytes = 0;
    uint8_t *models = have_header ? read_lump(file, size, header, LUMP_MODELS, &model_bytes) : NULL;
    uint8_t *cells = have_header ? read_lump(file, size, header, LUMP_LIGHTGRID, &grid_bytes) : NULL;
    fclose(file);
    light_grid g = {.cells = cells};
    bool matches = models && cells && model_bytes >= MODEL_SIZE;
    uint64_t points = 1;
    for (int k = 0; matches && k < 3; k++) {
        float lo = read_f32(models + 4 * k), hi = read_f32(models + 12 + 4 * k);
        g.size[k] = grid_size[k];
        matches = isfinite(lo) && isfinite(hi) && lo <= hi && g.size[k] >= 1.0f &&
                  fabsf(lo) < 1e7f && fabsf(hi) < 1e7f;
        if (!matches) break;
        g.origin[k] = g.size[k] * ceilf(lo / g.size[k]);
        float top = g.size[k] * floorf(hi / g.size[k]);
        g.count[k] = (int32_t)((top - g.origin[k]) / g.size[k]) + 1;
        matches = g.count[k] >= 1;
        points *= matches ? (uint64_t)g.count[k] : 1u;
    }
    matches = matches && points <= GRID_POINTS_MAX && points * CELL_SIZE == grid_bytes;
    bool ok = matches ? lights_from_grid(scene, &g, err) : true;
    free(models);
    free(cells);
    return ok;
}

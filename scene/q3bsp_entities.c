/* A Quake III map's own camera and lights, from its entity lump (lump 0):
 * what a .bsp loaded with no scene file looks from and is lit by.
 *
 * The lump is text, a run of entities `{ "key" "value" ... }` (Quake's map
 * format has no escapes inside quotes).  Two things are read from it:
 *
 * Camera.  The first `info_player_intermission` (where Quake III shows the
 * scores: the level's own establishing shot), else the first spawn point
 * (`info_player_deathmatch`, `info_player_start`, `team_CTF_redspawn`,
 * `team_CTF_bluespawn`, `team_CTF_redplayer`, `team_CTF_blueplayer`), in file
 * order.  The eye is the entity's origin (a spawn point's plus 26 units, Quake
 * III's DEFAULT_VIEWHEIGHT); it looks at the origin of the entity its
 * "target" names, else along its "angles" (pitch yaw roll, degrees; positive
 * pitch looks down) or "angle" (yaw).  The field of view is 74 degrees
 * vertically: Quake III's 90 degrees across at 4:3.
 *
 * Lights.  Every `light` entity becomes a sphere light, with q3map2's
 * semantics for the point light it is (spotlights, which aim at a "target",
 * are lit as point lights: the cone is not modelled):
 *   intensity I = "_light", else "light", else 300, times "_scale" (default 1);
 *     entities with I <= 0 (q3map2's negative "dark" lights) are skipped;
 *   colour = "_color" scaled so its largest component is 1 (default white);
 *   fall-off: by default inverse square, q3map2's I * 7500 / d^2 in lightmap
 *     units (255 = full brightness) with d held at no less than 16 units; here
 *     I * 7500 / 255 / (256 + d^2), the same curve with the clamp made smooth;
 *     with spawnflags bit 1 (LINEAR) q3map2's I * 7500/8000 - fade * d
 *     ("fade" default 1), here (I * 0.9375 / 255) / (1 + d / (reach / 2)),
 *     reach = I * 0.9375 / fade: equal at the light, half at half the reach;
 *   radius = "_deviance" when given (q3map2 jitters a light's samples over
 *     that radius for soft shadows), else sqrt(I) / 2 units, at most 32: the
 *     default light (300) gets 8.7 units, a bulb or torch's size, and soft
 *     shadows have something to soften.
 * Positions go from Quake's Z-up to rtt's Y-up as the geometry does:
 * (x, y, z) -> (x, z, -y).
 *
 * Hostile input: the lump's offset and length are checked against the file,
 * its size is bounded, numbers must be finite, and a malformed lump is one
 * error line naming the entity and what is wrong.  A map with no camera
 * entity keeps the default camera.  A map with no light entities (q3map2
 * drops them when it compiles a map) is lit from its light grid
 * (q3bsp_lightgrid.c); one with neither gets the default light. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/files.h"
#include "scene_build.h"

#define BSP_HEADER_SIZE 144u
#define BSP_VERSION 46
#define ENTITY_LUMP_MAX ((uint32_t)64 << 20)
#define ENTITY_KEYS_MAX 256
#define SPAWN_VIEW_HEIGHT 26.0f
#define MAP_FOV_DEG 74.0f
#define DEFAULT_LIGHT_INTENSITY 300.0f
#define POINT_SCALE 7500.0f         /* q3map2 pointScale */
#define LINEAR_SCALE (1.0f / 8000)  /* q3map2 linearScale */
#define LIGHTMAP_WHITE 255.0f
#define MIN_DISTANCE 16.0f          /* q3map2 holds d at no less than this */
#define MAX_LIGHT_RADIUS 32.0f

typedef struct entity_pair {
    const char *key, *value;
} entity_pair;

typedef struct entity {
    uint32_t index, pair_count;
    entity_pair pairs[ENTITY_KEYS_MAX];
} entity;

typedef struct entity_reader {
    const char *path;
    char *text; /* the lump, NUL-terminated; strings are cut in place */
    size_t length, at;
    uint32_t index;
    rtt_error *err;
} entity_reader;

static uint32_t read_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* The entity lump of the map at `path`, NUL-terminated. */
static char *read_entity_lump(const char *path, size_t *length, rtt_error *err)
{
    FILE *file = rtt_file_open_regular(path, err);
    if (!file) return NULL;
    uint8_t header[BSP_HEADER_SIZE];
    char *text = NULL;
    long size = fseek(file, 0, SEEK_END) == 0 ? ftell(file) : -1;
    bool ok = size >= (long)BSP_HEADER_SIZE && fseek(file, 0, SEEK_SET) == 0 &&
              fread(header, 1, sizeof header, file) == sizeof header && memcmp(header, "IBSP", 4) == 0 &&
              read_u32(header + 4) == BSP_VERSION;
    if (!ok) {
        rtt_error_set(err, "%s: not a Quake III map (IBSP 46)", path);
    } else {
        uint32_t offset = read_u32(header + 8), bytes = read_u32(header + 12);
        if ((uint64_t)offset + bytes > (uint64_t)size || bytes > ENTITY_LUMP_MAX) {
            ok = rtt_error_set(err, "%s: entities: lump (offset %u, %u bytes) outside the file or too large", path,
                               offset, bytes);
        } else if (!(text = malloc((size_t)bytes + 1))) {
            ok = rtt_error_set(err, "%s: entities: out of memory", path);
        } else if (fseek(file, (long)offset, SEEK_SET) != 0 || fread(text, 1, bytes, file) != bytes) {
            ok = rtt_error_set(err, "%s: entities: cannot read the lump", path);
        } else {
            text[bytes] = '\0';
            *length = strlen(text); /* the lump may end in NULs */
        }
    }
    fclose(file);
    if (!ok) {
        free(text);
        return NULL;
    }
    return text;
}

static void skip_space(entity_reader *r)
{
    while (r->at < r->length && (r->text[r->at] == ' ' || r->text[r->at] == '\t' || r->text[r->at] == '\n' ||
                                 r->text[r->at] == '\r'))
        r->at++;
}

static bool reader_fail(entity_reader *r, const char *what)
{
    int line = 1;
    for (size_t i = 0; i < r->at && i < r->length; i++) line += r->text[i] == '\n';
    return rtt_error_set(r->err, "%s: entities, line %d (entity %u): %s", r->path, line, r->index, what);
}

static bool read_string(entity_reader *r, const char **out)
{
    skip_space(r);
    if (r->at >= r->length || r->text[r->at] != '"') return reader_fail(r, "expected a quoted key or value");
    size_t start = ++r->at;
    while (r->at < r->length && r->text[r->at] != '"' && r->text[r->at] != '\n') r->at++;
    if (r->at >= r->length || r->text[r->at] != '"') return reader_fail(r, "a string without its closing quote");
    r->text[r->at++] = '\0';
    *out = r->text + start;
    return true;
}

/* The next entity into *e; false at the end (r->err untouched) or on an error. */
static bool read_entity(entity_reader *r, entity *e, bool *end)
{
    skip_space(r);
    *end = r->at >= r->length;
    if (*end) return false;
    if (r->text[r->at] != '{') return reader_fail(r, "expected '{'");
    r->at++;
    e->index = r->index;
    e->pair_count = 0;
    for (;;) {
        skip_space(r);
        if (r->at < r->length && r->text[r->at] == '}') {
            r->at++;
            r->index++;
            return true;
        }
        if (e->pair_count == ENTITY_KEYS_MAX) return reader_fail(r, "more than 256 keys");
        entity_pair *pair = &e->pairs[e->pair_count];
        if (!read_string(r, &pair->key) || !read_string(r, &pair->value)) return false;
        e->pair_count++;
    }
}

static const char *value_of(const entity *e, const char *key)
{
    for (uint32_t i = 0; i < e->pair_count; i++)
        if (strcmp(e->pairs[i].key, key) == 0) return e->pairs[i].value;
    return NULL;
}

/* Up to n finite numbers separated by white space; *got how many. */
static bool parse_numbers(const char *text, float *out, int n, int *got)
{
    *got = 0;
    for (const char *p = text; *got < n;) {
        char *end;
        while (*p == ' ' || *p == '\t') p++;
        if (!*p) break;
        double v = strtod(p, &end);
        if (end == p || !isfinite(v) || fabs(v) > 1e30) return false;
        out[(*got)++] = (float)v;
        p = end;
    }
    return true;
}

static bool entity_fail(const entity_reader *r, const entity *e, const char *key, const char *what)
{
    const char *classname = value_of(e, "classname");
    return rtt_error_set(r->err, "%s: entities: entity %u (%s): \"%s\" %s", r->path, e->index,
                         classname ? classname : "no classname", key, what);
}

/* An optional number (NULL: absent, *out untouched). */
static bool number_of(const entity_reader *r, const entity *e, const char *key, float *out)
{
    const char *text = value_of(e, key);
    int got;
    if (!text) return true;
    if (!parse_numbers(text, out, 1, &got) || got != 1) return entity_fail(r, e, key, "must be a number");
    return true;
}

static bool vector_of(const entity_reader *r, const entity *e, const char *key, float out[3], bool *present)
{
    const char *text = value_of(e, key);
    int got;
    *present = text != NULL;
    if (!text) return true;
    if (!parse_numbers(text, out, 3, &got) || got != 3) return entity_fail(r, e, key, "must be three numbers");
    return true;
}

static rtt_vec3 z_up_to_y_up(const float q[3]) { return rtt_v3(q[0], q[2], -q[1]); }

/* ---- the camera ---- */

static int spawn_rank(const char *classname)
{
    static const char *const ranked[] = {"info_player_intermission", "info_player_deathmatch", "info_player_start",
                                         "team_CTF_redspawn", "team_CTF_bluespawn", "team_CTF_redplayer",
                                         "team_CTF_blueplayer"};
    for (int i = 0; classname && i < (int)(sizeof ranked / sizeof *ranked); i++)
        if (strcmp(classname, ranked[i]) == 0) return i == 0 ? 0 : 1;
    return -1;
}

typedef struct map_settings {
    float grid_size[3]; /* worldspawn's "gridsize" */
} map_settings;

typedef struct camera_candidate {
    int rank; /* 0 intermission, 1 spawn point, -1 none yet */
    float origin[3], angles[3];
    bool has_target_point;
    float target_point[3];
    char target[64];
} camera_candidate;

static bool consider_camera(const entity_reader *r, const entity *e, camera_candidate *best)
{
    int rank = spawn_rank(value_of(e, "classname"));
    if (rank < 0 || (best->rank >= 0 && best->rank <= rank)) return true;
    camera_candidate c = {.rank = rank};
    bool has_origin, has_angles;
    if (!vector_of(r, e, "origin", c.origin, &has_origin) || !vector_of(r, e, "angles", c.angles, &has_angles) ||
        !number_of(r, e, "angle", &c.angles[1]))
        return false;
    if (!has_origin) return true; /* an entity with no place cannot be looked from */
    const char *target = value_of(e, "target");
    if (target) snprintf(c.target, sizeof c.target, "%s", target);
    *best = c;
    return true;
}

/* The target's origin, looked up in a second pass (it may come earlier or later). */
static bool consider_target(const entity_reader *r, const entity *e, camera_candidate *best)
{
    const char *name = value_of(e, "targetname");
    if (!best->target[0] || best->has_target_point || !name || strcmp(name, best->target) != 0) return true;
    return vector_of(r, e, "origin", best->target_point, &best->has_target_point);
}

static rtt_camera camera_of(const camera_candidate *c)
{
    float eye[3] = {c->origin[0], c->origin[1], c->origin[2] + (c->rank == 0 ? 0.0f : SPAWN_VIEW_HEIGHT)};
    float at[3];
    if (c->has_target_point &&
        (c->target_point[0] != eye[0] || c->target_point[1] != eye[1] || c->target_point[2] != eye[2])) {
        memcpy(at, c->target_point, sizeof at);
    } else {
        const float to_rad = 3.14159265f / 180.0f;
        float pitch = fmaxf(-89.0f, fminf(89.0f, c->angles[0])) * to_rad, yaw = c->angles[1] * to_rad;
        at[0] = eye[0] + 64.0f * cosf(pitch) * cosf(yaw);
        at[1] = eye[1] + 64.0f * cosf(pitch) * sinf(yaw);
        at[2] = eye[2] - 64.0f * sinf(pitch);
    }
    rtt_camera camera = {.eye = z_up_to_y_up(eye), .look_at = z_up_to_y_up(at), .up = rtt_v3(0, 1, 0),
                         .fov_deg = MAP_FOV_DEG};
    /* straight up or down at a target: any up across the view will do */
    rtt_vec3 view = rtt_v3_normalize(rtt_v3_sub(camera.look_at, camera.eye));
    if (fabsf(view.y) > 0.9999f) camera.up = rtt_v3(0, 0, -1);
    return camera;
}

/* ---- lights ---- */

static bool light_of(const entity_reader *r, const entity *e, rtt_light *out, bool *usable)
{
    float origin[3], color[3] = {1, 1, 1}, intensity = 0.0f, scale = 1.0f, fade = 1.0f, spawnflags = 0.0f,
                     deviance = -1.0f;
    bool has_origin, has_color;
    *usable = false;
    if (!vector_of(r, e, "origin", origin, &has_origin) || !vector_of(r, e, "_color", color, &has_color) ||
        !number_of(r, e, "light", &intensity) || !number_of(r, e, "_light", &intensity) ||
        !number_of(r, e, "_scale", &scale) || !number_of(r, e, "fade", &fade) ||
        !number_of(r, e, "spawnflags", &spawnflags) || !number_of(r, e, "_deviance", &deviance))
        return false;
    if (!has_origin) return entity_fail(r, e, "origin", "is missing: a light needs a place");
    if (intensity == 0.0f) intensity = DEFAULT_LIGHT_INTENSITY;
    intensity *= scale;
    if (!(intensity > 0.0f)) return true;
    float largest = fmaxf(color[0], fmaxf(color[1], color[2]));
    if (!(largest > 0.0f) || color[0] < 0 || color[1] < 0 || color[2] < 0)
        return entity_fail(r, e, "_color", "must be three non-negative numbers, not all zero");
    rtt_light light = {.type = RTT_LIGHT_SPHERE, .position = z_up_to_y_up(origin),
                       .color = rtt_v3(color[0] / largest, color[1] / largest, color[2] / largest)};
    if (((uint32_t)spawnflags & 1u) && fade > 0.0f) {
        float reach = intensity * POINT_SCALE * LINEAR_SCALE / fade;
        light.intensity = intensity * POINT_SCALE * LINEAR_SCALE / LIGHTMAP_WHITE;
        light.attenuation[0] = 1.0f;
        light.attenuation[1] = 2.0f / reach;
    } else {
        light.intensity = intensity * POINT_SCALE / LIGHTMAP_WHITE;
        light.attenuation[0] = MIN_DISTANCE * MIN_DISTANCE;
        light.attenuation[2] = 1.0f;
    }
    light.radius = deviance > 0.0f ? deviance : fminf(0.5f * sqrtf(intensity), MAX_LIGHT_RADIUS);
    *out = light;
    *usable = true;
    return true;
}

/* ---- the lump ---- */

/* Pass 0: camera candidates and lights; pass 1: the camera's target. */
static bool read_pass(entity_reader *r, int pass, rtt_scene *scene, camera_candidate *camera, map_settings *map,
                      entity *e)
{
    r->at = 0;
    r->index = 0;
    bool end = false;
    while (read_entity(r, e, &end)) {
        if (pass == 1) {
            if (!consider_target(r, e, camera)) return false;
            continue;
        }
        if (!consider_camera(r, e, camera)) return false;
        const char *classname = value_of(e, "classname");
        bool present;
        if (classname && strcmp(classname, "worldspawn") == 0 && !vector_of(r, e, "gridsize", map->grid_size, &present))
            return false;
        if (!classname || strcmp(classname, "light") != 0) continue;
        rtt_light light;
        bool usable;
        if (!light_of(r, e, &light, &usable)) return false;
        /* a light whose numbers overflow float (a hostile or broken map) is skipped like a dark one */
        usable = usable && rtt_light_is_finite(&light);
        if (usable && !rtt_scene_add_light(scene, &light, r->err)) return false;
    }
    return end;
}

bool rtt_q3bsp_read_entities(rtt_scene *scene, const char *path, rtt_error *err)
{
    entity_reader r = {.path = path, .err = err};
    char *lump = read_entity_lump(path, &r.length, err);
    if (!lump) return false;
    r.text = malloc(r.length + 1); /* each pass cuts its strings in a fresh copy */
    entity *e = malloc(sizeof *e);
    camera_candidate camera = {.rank = -1};
    map_settings map = {{64.0f, 64.0f, 128.0f}};
    uint32_t lights_before = scene->light_count;
    bool ok = r.text && e ? true : rtt_error_set(err, "%s: entities: out of memory", path);
    for (int pass = 0; ok && pass < (camera.target[0] ? 2 : 1); pass++) {
        memcpy(r.text, lump, r.length + 1);
        ok = read_pass(&r, pass, scene, &camera, &map, e);
    }
    const rtt_camera entity_camera = ok && camera.rank >= 0 ? camera_of(&camera) : scene->camera;
    /* an entity whose numbers overflow float (a broken map) gives no camera: the default frames the map */
    if (ok && camera.rank >= 0 && rtt_v3_is_finite(entity_camera.eye) && rtt_v3_is_finite(entity_camera.look_at) &&
        rtt_v3_is_finite(entity_camera.up) && isfinite(entity_camera.fov_deg)) {
        scene->camera = entity_camera;
        scene->camera_source = camera.rank == 0 ? RTT_CAMERA_INTERMISSION : RTT_CAMERA_SPAWN_POINT;
    }
    if (ok && scene->light_count > lights_before) {
        scene->light_source = RTT_LIGHTS_MAP;
    } else if (ok) {
        ok = rtt_q3bsp_lights_from_grid(scene, path, map.grid_size, err);
        if (ok && scene->light_count > lights_before) scene->light_source = RTT_LIGHTS_MAP_GRID;
    }
    free(e);
    free(r.text);
    free(lump);
    return ok;
}

/* --eye, --look-at, --up, --fov, --view and --lights (camera_options.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "camera_options.h"
#include "cli.h"

const char *const cli_light_choices[] = {"map", "camera", "view", NULL};

/* "X,Y,Z" in double, each finite in float too (what a scene can hold). */
static bool parse_xyz(const char *value, double xyz[3])
{
    const char *p = value;
    for (int k = 0; k < 3; k++) {
        char item[64], *end = NULL;
        size_t n = strcspn(p, ",");
        if (n == 0 || n >= sizeof item || (k < 2 && p[n] != ',') || (k == 2 && p[n] != '\0')) return false;
        memcpy(item, p, n);
        item[n] = '\0';
        xyz[k] = strtod(item, &end);
        if (*end || !isfinite(xyz[k]) || !isfinite((float)xyz[k])) return false;
        p += n + (k < 2);
    }
    return true;
}

bool cli_parse_vec3(const char *value, void *field, rtt_error *why)
{
    double xyz[3];
    if (!parse_xyz(value, xyz)) return rtt_error_set(why, "expected three finite numbers X,Y,Z");
    *(rtt_vec3 *)field = rtt_v3((float)xyz[0], (float)xyz[1], (float)xyz[2]);
    return true;
}

bool cli_parse_point(const char *value, void *field, rtt_error *why)
{
    if (!parse_xyz(value, field)) return rtt_error_set(why, "expected three finite numbers X,Y,Z");
    return true;
}

/* "FILE:NAME" splits at its last colon unless FILE:NAME is itself a file. */
static void split_view(const char *value, char *file, size_t file_size, char *name, size_t name_size,
                       const char *scene_path)
{
    const char *colon = strrchr(value, ':');
    bool split = colon && access(value, F_OK) != 0 && !strchr(colon, '/');
    size_t file_length = split ? (size_t)(colon - value) : strlen(value);
    snprintf(file, file_size, "%.*s", (int)file_length, value);
    if (split) {
        snprintf(name, name_size, "%s", colon + 1);
        return;
    }
    const char *slash = strrchr(scene_path, '/');
    const char *base = slash ? slash + 1 : scene_path;
    snprintf(name, name_size, "%.*s", (int)strcspn(base, "."), base);
}

int cli_camera_check(const cli_parsed *parsed, cli_camera_args *camera, const char *scene_path)
{
    memset(&camera->views, 0, sizeof camera->views);
    camera->chosen = NULL;
    if (cli_given(parsed, "--fov") && camera->fov > 179.0f)
        return cli_refuse(parsed, "--fov", "must be between 1 and 179 degrees");
    if (cli_given(parsed, "--lights") && camera->lights == CLI_LIGHTS_MAP &&
        rtt_file_kind_of(scene_path) != RTT_FILE_Q3BSP)
        return cli_refuse(parsed, "--lights",
                          "only a Quake III map (.bsp) given as SCENE has light entities; %s is not one",
                          scene_path);
    if (cli_given(parsed, "--lights") && camera->lights == CLI_LIGHTS_VIEW && !camera->view)
        return cli_refuse(parsed, "--lights", "view takes the light of --view's view, and no --view is given");
    if (!camera->view) return CLI_CONTINUE;
    static const char *const replaced[] = {"--eye", "--look-at", "--up"};
    for (int i = 0; i < 3; i++)
        if (cli_given(parsed, replaced[i]))
            return cli_refuse(parsed, replaced[i], "does not go with --view, whose camera it would replace");
    char file[512], name[128];
    split_view(camera->view, file, sizeof file, name, sizeof name, scene_path);
    if (!file[0] || !name[0]) return cli_refuse(parsed, "--view", "expected FILE or FILE:NAME");
    rtt_error err = {{0}};
    if (!rtt_views_load(file, &camera->views, &err)) {
        rtt_views_free(&camera->views);
        return cli_fail(&err);
    }
    camera->chosen = rtt_views_find(&camera->views, name);
    if (camera->chosen && cli_given(parsed, "--lights") && camera->lights == CLI_LIGHTS_VIEW &&
        !camera->chosen->has_light) {
        int rc = cli_refuse(parsed, "--lights", "view \"%s\" of %s has no light", name, file);
        cli_camera_free(camera);
        return rc;
    }
    if (camera->chosen) return CLI_CONTINUE;
    char names[256];
    rtt_views_names(&camera->views, names, sizeof names);
    int rc = cli_refuse(parsed, "--view", "%s has no view named \"%s\" (it has %s)", file, name, names);
    cli_camera_free(camera);
    return rc;
}

int cli_camera_apply(const cli_parsed *parsed, const cli_camera_args *camera, rtt_scene *scene)
{
    /* eye and look-at in the scene's own coordinates, in double, until they
     * are moved to the stored frame: checked there, where the scene's
     * precision is */
    rtt_camera c = camera->chosen ? camera->chosen->camera : scene->camera;
    double eye[3], look_at[3];
    if (camera->chosen) {
        memcpy(eye, camera->chosen->eye, sizeof eye);
        memcpy(look_at, camera->chosen->look_at, sizeof look_at);
    } else {
        rtt_scene_point_from_stored(scene, scene->camera.eye, eye);
        rtt_scene_point_from_stored(scene, scene->camera.look_at, look_at);
    }
    static const char *const pieces[] = {"--eye", "--look-at", "--up", "--fov"};
    const char *last = NULL;
    for (int i = 0; i < 4; i++)
        if (cli_given(parsed, pieces[i])) last = pieces[i];
    if (cli_given(parsed, "--eye")) memcpy(eye, camera->eye, sizeof eye);
    if (cli_given(parsed, "--look-at")) memcpy(look_at, camera->look_at, sizeof look_at);
    if (cli_given(parsed, "--up")) c.up = camera->up;
    if (cli_given(parsed, "--fov")) c.fov_deg = camera->fov;
    if (last || camera->chosen) {
        rtt_error why = {{0}};
        rtt_camera stored = c;
        stored.eye = rtt_scene_point_to_stored(scene, eye);
        stored.look_at = rtt_scene_point_to_stored(scene, look_at);
        if (!rtt_camera_check(&stored, &why))
            return cli_refuse(parsed, last ? last : "--view", "%s%s", why.message,
                              last && !camera->chosen ? " (with the rest of the scene's camera)" : "");
        rtt_scene_set_camera_at(scene, &c, eye, look_at);
    }
    if (!cli_given(parsed, "--lights")) return CLI_CONTINUE;
    rtt_error err = {{0}};
    if (camera->lights == CLI_LIGHTS_CAMERA)
        return rtt_scene_use_camera_light(scene, &err) ? CLI_CONTINUE : cli_fail(&err);
    if (camera->lights == CLI_LIGHTS_VIEW) /* cli_camera_check made sure the view has one */
        return rtt_scene_use_view_light(scene, camera->chosen, &err) ? CLI_CONTINUE : cli_fail(&err);
    if (scene->light_source != RTT_LIGHTS_MAP && scene->light_source != RTT_LIGHTS_MAP_GRID) {
        rtt_error_set(&err, "%s: the map has neither light entities nor a light grid to light it with (--lights map)", scene->path);
        return cli_fail(&err);
    }
    return CLI_CONTINUE;
}

void cli_camera_free(cli_camera_args *camera)
{
    rtt_views_free(&camera->views);
    camera->chosen = NULL;
}

static const char *camera_source_name(rtt_camera_source source)
{
    switch (source) {
    case RTT_CAMERA_FRAMING: return "the default, framing the bounds";
    case RTT_CAMERA_INTERMISSION: return "the map's info_player_intermission";
    case RTT_CAMERA_SPAWN_POINT: return "the map's first spawn point";
    case RTT_CAMERA_FROM_OPTIONS: return "the command line";
    default: return "the scene file";
    }
}

static const char *light_source_name(rtt_light_source source)
{
    switch (source) {
    case RTT_LIGHTS_AT_CAMERA: return "one point light at the camera";
    case RTT_LIGHTS_MAP: return "the map's light entities";
    case RTT_LIGHTS_MAP_GRID: return "the brightest points of the map's light grid (it has no light entities)";
    case RTT_LIGHTS_FROM_OPTIONS: return "the command line";
    default: return "the scene file";
    }
}

#define LIGHTS_LISTED 8u

void cli_print_camera_and_lights(const rtt_scene *s)
{
    /* positions in the scene's own coordinates, as the files give them:
     * with the digits a stored float plus a far origin needs */
    const int d = s->origin[0] != 0.0 || s->origin[1] != 0.0 || s->origin[2] != 0.0 ? 9 : 6;
    const rtt_camera *c = &s->camera;
    double eye[3], at[3];
    rtt_scene_point_from_stored(s, c->eye, eye);
    rtt_scene_point_from_stored(s, c->look_at, at);
    printf("  camera      eye (%.*g, %.*g, %.*g), look-at (%.*g, %.*g, %.*g), up (%g, %g, %g), fov %g (%s)\n", d,
           eye[0], d, eye[1], d, eye[2], d, at[0], d, at[1], d, at[2], c->up.x, c->up.y, c->up.z, (double)c->fov_deg,
           camera_source_name(s->camera_source));
    uint32_t spheres = 0, quads = 0;
    for (uint32_t i = 0; i < s->light_count; i++) {
        spheres += s->lights[i].type == RTT_LIGHT_SPHERE;
        quads += s->lights[i].type == RTT_LIGHT_QUAD;
    }
    printf("  lights      %u (%u sphere, %u quad, %u point) from %s\n", s->light_count, spheres, quads,
           s->light_count - spheres - quads, light_source_name(s->light_source));
    for (uint32_t i = 0; i < s->light_count && i < LIGHTS_LISTED; i++) {
        const rtt_light *l = &s->lights[i];
        double at[3];
        rtt_scene_point_from_stored(s, l->position, at);
        printf("    %-6s at (%.*g, %.*g, %.*g), colour (%g, %g, %g), intensity %g, attenuation [%g, %g, %g]",
               l->type == RTT_LIGHT_SPHERE ? "sphere" : l->type == RTT_LIGHT_QUAD ? "quad" : "point", d, at[0], d,
               at[1], d, at[2],
               l->color.x, l->color.y, l->color.z, (double)l->intensity, (double)l->attenuation[0],
               (double)l->attenuation[1], (double)l->attenuation[2]);
        if (l->attenuation_distance > 0.0f) printf(" over %g", (double)l->attenuation_distance);
        if (l->type == RTT_LIGHT_SPHERE) printf(", radius %g", (double)l->radius);
        if (l->type == RTT_LIGHT_QUAD)
            printf(", edges (%g, %g, %g) and (%g, %g, %g)", l->edge_u.x, l->edge_u.y, l->edge_u.z, l->edge_v.x,
                   l->edge_v.y, l->edge_v.z);
        printf("\n");
    }
    if (s->light_count > LIGHTS_LISTED) printf("    ... and %u more\n", s->light_count - LIGHTS_LISTED);
}

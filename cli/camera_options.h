/* The camera and light options of every command that renders or traces from
 * the scene's camera (render, bench, conform, info): --eye, --look-at, --up,
 * --fov, --view FILE[:NAME] and --lights map|camera|view.
 *
 * cli_camera_check runs before the scene is loaded: it refuses what does not
 * go together (exit 2), reads the views file (exit 1 on a bad file) and picks
 * the view.  cli_camera_apply puts the camera and lights into the loaded
 * scene: the view's camera (or the scene's) with the given pieces replaced. */
#ifndef RTT_CLI_CAMERA_OPTIONS_H
#define RTT_CLI_CAMERA_OPTIONS_H

#include "options.h"
#include "rtt/views.h"

typedef enum cli_lights { CLI_LIGHTS_MAP = 0, CLI_LIGHTS_CAMERA = 1, CLI_LIGHTS_VIEW = 2 } cli_lights;

typedef struct cli_camera_args {
    double eye[3], look_at[3]; /* in the scene's own coordinates, in double */
    rtt_vec3 up;
    float fov;
    const char *view;        /* FILE[:NAME] */
    int lights;              /* cli_lights, when --lights is given */
    /* filled by cli_camera_check */
    rtt_view_list views;
    const rtt_view *chosen;  /* the view --view names, or NULL */
} cli_camera_args;

bool cli_parse_vec3(const char *value, void *field, rtt_error *why);
/* The same into a double[3]: positions keep their precision until the scene
 * moves them to its stored frame. */
bool cli_parse_point(const char *value, void *field, rtt_error *why);
extern const char *const cli_light_choices[];

#define CLI_OPTIONS_CAMERA(type, member)                                                                        \
    {.name = "--eye", .value_name = "X,Y,Z", .help = "the camera's position (default: the scene's camera)",      \
     .kind = CLI_CUSTOM, CLI_FIELD(type, member.eye), .parse = cli_parse_point},                                 \
        {.name = "--look-at", .value_name = "X,Y,Z", .help = "the point the camera looks at",                   \
         .kind = CLI_CUSTOM, CLI_FIELD(type, member.look_at), .parse = cli_parse_point},                         \
        {.name = "--up", .value_name = "X,Y,Z", .help = "the camera's up direction (default: the scene's)",     \
         .kind = CLI_CUSTOM, CLI_FIELD(type, member.up), .parse = cli_parse_vec3},                              \
        {.name = "--fov", .value_name = "DEG", .help = "vertical field of view, 1 to 179 degrees",              \
         .kind = CLI_FLOAT, CLI_FIELD(type, member.fov), .min = 1.0f},                                          \
        {.name = "--view", .value_name = "FILE[:NAME]",                                                         \
         .help = "the camera of view NAME of a views file such as bench/views.json (default NAME: the scene "   \
                 "file's base name); --fov still applies, --eye, --look-at, --up do not go with it",            \
         .kind = CLI_STRING, CLI_FIELD(type, member.view)},                                                     \
        {.name = "--lights", .value_name = "map|camera|view",                                                   \
         .help = "map: a Quake III map's own light entities (the default for a .bsp); camera: one point "       \
                 "light at the camera (the default for a scene with no lights); view: the light of --view's "   \
                 "view (as rtt bench lights it)",                                                               \
         .kind = CLI_CHOICE, CLI_FIELD(type, member.lights), .choices = cli_light_choices}

/* Before loading SCENE: CLI_CONTINUE, or the exit code. */
int cli_camera_check(const cli_parsed *parsed, cli_camera_args *camera, const char *scene_path);
/* After loading: CLI_CONTINUE, or the exit code (the message printed). */
int cli_camera_apply(const cli_parsed *parsed, const cli_camera_args *camera, rtt_scene *scene);
void cli_camera_free(cli_camera_args *camera);

/* What `rtt info` prints about the scene's camera and lights. */
void cli_print_camera_and_lights(const rtt_scene *scene);

#endif

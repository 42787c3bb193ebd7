/* `rtt view`: the SDL2 window (viewer.c).  The driver (cli/cmd_view.c)
 * parses the command line into rtt_viewer_options and calls rtt_viewer_run. */
#ifndef RTT_VIEWER_VIEWER_H
#define RTT_VIEWER_VIEWER_H

#include "rtt/render.h"
#include "rtt/scene.h"

typedef struct rtt_viewer_options {
    const char *engine;            /* a registered engine ("optimized") */
    const char *shadows_text;      /* --shadows as typed; NULL: the default */
    rtt_render_options render;     /* the starting settings; width/height 0: the scene's */
    const char *script_path;       /* NULL: interactive */
    const char *screenshot_path;   /* written when the script ends; NULL: none */
} rtt_viewer_options;

/* Opens the window on `scene` (which the viewer may re-aim: it owns the
 * camera while it runs) and renders until the window closes or the script
 * ends.  False + one line in err when something fails. */
bool rtt_viewer_run(rtt_scene *scene, const rtt_viewer_options *opt, rtt_error *err);

#endif

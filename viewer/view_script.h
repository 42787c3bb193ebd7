/* Scripts for `rtt view --script FILE` (view_script.c): a camera path and
 * key presses played without a user, so the viewer runs headless (under
 * Xvfb) in tests and benchmarks.  One command per line; '#' starts a
 * comment:
 *
 *   frames N            render N frames as things are (keys held stay held)
 *   key NAME [FRAMES]   press key NAME (an SDL key name: w, t, Home, F12,
 *                       Left, ...); with FRAMES, hold it that many frames
 *   drag DX DY          move the mouse DX, DY pixels with the left button
 *                       held (looks around), then render one frame
 *   resize W H          resize the window to W x H, then render one frame
 *   set WHAT VALUE      choose as the keys do: set traversal mft, set shadows
 *                       multi:16, set isa sse4 (an offered choice; a
 *                       traversal may name its accel: kd:mft), then
 *                       render one frame
 *   converge            render until the image has all its samples
 *   bench N             render N frames, print their mean fps and Mrays/s
 *   print-overlay       print the overlay line on stdout
 *   print-camera        print the camera as a views.json entry on stdout
 *   print-choices       print what T, G and I cycle: "traversals: kd:mono ...",
 *                       "shadows: none hard ...", "isas: sse4 ..." 
 *   screenshot FILE     write the image shown (.png or .exr)
 *
 * Frames advance the camera by a fixed 1/30 s when scripted, so a script
 * gives the same pictures on every machine. */
#ifndef RTT_VIEWER_VIEW_SCRIPT_H
#define RTT_VIEWER_VIEW_SCRIPT_H

#include <stdint.h>

#include "rtt/error.h"

#define VIEW_SCRIPT_TEXT_MAX 512u

typedef enum view_command_kind {
    VIEW_CMD_FRAMES,
    VIEW_CMD_KEY,
    VIEW_CMD_DRAG,
    VIEW_CMD_RESIZE,
    VIEW_CMD_SET,
    VIEW_CMD_CONVERGE,
    VIEW_CMD_BENCH,
    VIEW_CMD_PRINT_OVERLAY,
    VIEW_CMD_PRINT_CAMERA,
    VIEW_CMD_PRINT_CHOICES,
    VIEW_CMD_SCREENSHOT,
} view_command_kind;

typedef struct view_command {
    view_command_kind kind;
    uint32_t line;                    /* in the script, for messages */
    int32_t a, b;                     /* frames; hold frames; dx, dy; width, height */
    char text[VIEW_SCRIPT_TEXT_MAX];  /* key name; screenshot path; set: the value */
    int32_t what;                     /* set: a view_choice (view_choices.h) */
} view_command;

typedef struct view_script {
    view_command *commands;
    uint32_t count;
} view_script;

/* Reads and checks a whole script; false + "FILE:LINE: what is wrong". */
bool view_script_load(const char *path, view_script *out, rtt_error *err);
/* Parses script text (path only names it in messages). */
bool view_script_parse(const char *path, const char *text, view_script *out, rtt_error *err);
void view_script_free(view_script *script);

#endif

/* The frames of `rtt render`: one (the scene's camera, the outputs as
 * named) or a camera path's, each written to outputs named by a pattern
 * with one frame number in it (frame_%04d.png: frame_0000.png, ...). */
#ifndef RTT_CLI_FRAME_OUTPUTS_H
#define RTT_CLI_FRAME_OUTPUTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/camera_path.h"
#include "rtt/image.h"

typedef struct cli_frames {
    rtt_scene *scene;               /* its camera changes per frame */
    const rtt_camera_path *path;    /* NULL: one frame, the scene's camera, outputs as named */
    bool fov_given;                 /* --fov replaces every frame's */
    float fov;
    const char *const *outputs;
    uint32_t output_count;
    double write_seconds;           /* summed over the frames written (--stats) */
} cli_frames;

/* A pattern holds exactly one %d, %Nd or %0Nd (N 1..9) and no other % but
 * %%.  false + why otherwise. */
bool cli_frame_pattern_check(const char *pattern, rtt_error *why);
/* The pattern with the frame number in it; false when it does not fit. */
bool cli_frame_name(const char *pattern, uint32_t frame, char *out, size_t size);

/* rtt_dist_frames' callbacks over a cli_frames. */
void cli_frames_prepare(void *frames, uint32_t frame);
bool cli_frames_write(void *frames, uint32_t frame, const rtt_image *image, rtt_error *err);

#endif

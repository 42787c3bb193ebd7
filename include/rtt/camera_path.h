/* A camera path: the cameras of a sequence's frames, from a views file
 * (rtt/views.h), for `rtt render --camera-path FILE`.
 *
 * Without a frame count, each view is one frame, in file order.  With a
 * frame count N, the views are key frames: frame 0 looks through the first,
 * frame N-1 through the last, and the frames between move at an even pace
 * in the key frames' index (frame i sits at s = i (K-1) / (N-1) for K keys),
 * eye, look_at, up and fov each interpolated linearly between the two keys
 * around s.  Only the cameras come from the file: the views' lights and
 * sizes are not part of a path. */
#ifndef RTT_CAMERA_PATH_H
#define RTT_CAMERA_PATH_H

#include <stdint.h>

#include "rtt/views.h"

typedef struct rtt_camera_path {
    uint32_t count;
    rtt_camera *cameras;     /* one per frame */
} rtt_camera_path;

/* frames 0: one frame per view; else 1..RTT_MAX_PATH_FRAMES frames through
 * the views as key frames.  Every frame's camera passes rtt_camera_check
 * (err names the frame).  `path` names the file in messages. */
#define RTT_MAX_PATH_FRAMES 1000000u
bool rtt_camera_path_make(const rtt_view_list *keys, uint32_t frames, const char *path, rtt_camera_path *out,
                          rtt_error *err);
void rtt_camera_path_free(rtt_camera_path *path);

#endif

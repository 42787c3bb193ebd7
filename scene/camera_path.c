/* Camera paths (rtt/camera_path.h): the views of a file as frames, or as
 * key frames interpolated linearly. */
#include <stdlib.h>

#include "rtt/camera_path.h"

static rtt_vec3 lerp3(rtt_vec3 a, rtt_vec3 b, float t)
{
    return rtt_v3(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t);
}

/* Frame i of n through k keys: the key before it and how far on to the next. */
static rtt_camera frame_camera(const rtt_view_list *keys, uint32_t i, uint32_t n)
{
    if (n == 1 || keys->count == 1) return keys->views[0].camera;
    double s = (double)i * (keys->count - 1) / (n - 1);
    uint32_t key = (uint32_t)s;
    if (key >= keys->count - 1) return keys->views[keys->count - 1].camera;
    const rtt_camera *a = &keys->views[key].camera, *b = &keys->views[key + 1].camera;
    float t = (float)(s - key);
    return (rtt_camera){.eye = lerp3(a->eye, b->eye, t), .look_at = lerp3(a->look_at, b->look_at, t),
                        .up = lerp3(a->up, b->up, t), .fov_deg = a->fov_deg + (b->fov_deg - a->fov_deg) * t};
}

bool rtt_camera_path_make(const rtt_view_list *keys, uint32_t frames, const char *path, rtt_camera_path *out,
                          rtt_error *err)
{
    out->count = 0;
    out->cameras = NULL;
    if (keys->count == 0) return rtt_error_set(err, "%s: the camera path has no views", path);
    if (frames > RTT_MAX_PATH_FRAMES)
        return rtt_error_set(err, "%s: %u frames is more than %u", path, frames, RTT_MAX_PATH_FRAMES);
    uint32_t n = frames ? frames : keys->count;
    out->cameras = malloc((size_t)n * sizeof *out->cameras);
    if (!out->cameras) return rtt_error_set(err, "%s: out of memory for %u cameras", path, n);
    for (uint32_t i = 0; i < n; i++) {
        out->cameras[i] = frames ? frame_camera(keys, i, n) : keys->views[i].camera;
        rtt_error why = {{0}};
        if (!rtt_camera_check(&out->cameras[i], &why)) {
            rtt_camera_path_free(out);
            if (frames) return rtt_error_set(err, "%s: frame %u of the path: %s", path, i, why.message);
            return rtt_error_set(err, "%s: view %s: %s", path, keys->views[i].name, why.message);
        }
    }
    out->count = n;
    return true;
}

void rtt_camera_path_free(rtt_camera_path *path)
{
    free(path->cameras);
    path->cameras = NULL;
    path->count = 0;
}

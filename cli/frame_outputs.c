/* Frame outputs (frame_outputs.h). */
#include <stdio.h>
#include <string.h>

#include "frame_outputs.h"
#include "progress.h"
#include "rtt/atomic_file.h"
#include "rtt/views.h"

/* The conversion in `pattern`: where it starts, its length and width, and
 * whether it pads with zeros; false unless there is exactly one. */
static bool find_conversion(const char *pattern, size_t *at, size_t *length, int *width, bool *zeros,
                            rtt_error *why)
{
    uint32_t found = 0;
    for (size_t i = 0; pattern[i]; i++) {
        if (pattern[i] != '%') continue;
        if (pattern[i + 1] == '%') {
            i++;
            continue;
        }
        size_t j = i + 1;
        bool pad = pattern[j] == '0';
        if (pad) j++;
        int w = 0;
        while (pattern[j] >= '0' && pattern[j] <= '9' && w < 100) w = w * 10 + (pattern[j++] - '0');
        if (pattern[j] != 'd' || w > 9)
            return rtt_error_set(why, "\"%s\": only %%d, %%Nd or %%0Nd (N 1..9) and %%%% may follow a %%", pattern);
        found++;
        *at = i;
        *length = j + 1 - i;
        *width = w;
        *zeros = pad;
        i = j;
    }
    if (found != 1)
        return rtt_error_set(why, "\"%s\" must hold one frame number (such as frame_%%04d.png), not %u", pattern,
                             found);
    return true;
}

bool cli_frame_pattern_check(const char *pattern, rtt_error *why)
{
    size_t at, length;
    int width;
    bool zeros;
    return find_conversion(pattern, &at, &length, &width, &zeros, why);
}

/* Appends text[0..n) to out, with %% as %. */
static bool append_literal(char *out, size_t size, size_t *used, const char *text, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (text[i] == '%' && i + 1 < n && text[i + 1] == '%') i++;
        if (*used + 1 >= size) return false;
        out[(*used)++] = text[i];
    }
    out[*used] = '\0';
    return true;
}

bool cli_frame_name(const char *pattern, uint32_t frame, char *out, size_t size)
{
    size_t at, length, used = 0;
    int width;
    bool zeros;
    if (size == 0 || !find_conversion(pattern, &at, &length, &width, &zeros, NULL)) return false;
    out[0] = '\0';
    if (!append_literal(out, size, &used, pattern, at)) return false;
    int n = snprintf(out + used, size - used, zeros ? "%0*u" : "%*u", width, frame);
    if (n < 0 || (size_t)n >= size - used) return false;
    used += (size_t)n;
    const char *rest = pattern + at + length;
    return append_literal(out, size, &used, rest, strlen(rest));
}

void cli_frames_prepare(void *opaque, uint32_t frame)
{
    cli_frames *frames = opaque;
    if (!frames->path) return;
    rtt_camera camera = frames->path->cameras[frame];
    if (frames->fov_given) camera.fov_deg = frames->fov;
    rtt_scene_set_camera(frames->scene, &camera);
}

bool cli_frames_write(void *opaque, uint32_t frame, const rtt_image *image, rtt_error *err)
{
    cli_frames *frames = opaque;
    bool ok = true;
    const double start = cli_seconds();
    rtt_atomic_files_hold(); /* a frame's outputs all or none */
    for (uint32_t i = 0; ok && i < frames->output_count; i++) {
        char name[4096];
        const char *path = frames->outputs[i];
        if (frames->path && !cli_frame_name(path, frame, name, sizeof name))
            ok = rtt_error_set(err, "%s: frame %u: the name is too long", path, frame);
        else
            ok = rtt_image_write(image, frames->path ? name : path, err);
    }
    ok = rtt_atomic_files_release(ok, err) && ok;
    frames->write_seconds += cli_seconds() - start;
    return ok;
}

/* A view of bench/views.json applied as the benchmarks define it: camera,
 * light and size (the file itself is read by scene/'s rtt_views_load). */
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "bench_internal.h"
#include "rtt/views.h"

void bench_base_name(const char *path, char out[64])
{
    const char *slash = strrchr(path, '/');
    const char *start = slash ? slash + 1 : path;
    size_t n = strcspn(start, ".");
    if (n > 63) n = 63;
    memcpy(out, start, n);
    out[n] = '\0';
}

bool rtt_bench_apply_view(rtt_scene *scene, const rtt_view *view, rtt_error *err)
{
    rtt_scene_set_camera_at(scene, &view->camera, view->eye, view->look_at);
    if (view->has_light && !rtt_scene_use_view_light(scene, view, err)) return false;
    if (view->width) {
        scene->width = view->width;
        scene->height = view->height;
    }
    return true;
}

/* The kernel timers' shared set-up (kerneltime.h). */
#include "kerneltime.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_internal.h"
#include "rtt/views.h"

bool kerneltime_isa(const char *tool, rtt_isa *isa)
{
    *isa = RTT_ISA_AVX512;
    const char *name = getenv("RTT_ISA");
    if (name && name[0] && !rtt_isa_parse(name, isa)) {
        fprintf(stderr, "%s: RTT_ISA=%s: not an instruction set\n", tool, name);
        return false;
    }
    *isa = rtt_isa_resolve(*isa);
    return true;
}

rtt_scene *kerneltime_scene(const char *tool, const char *path, const char *views_path, char name[256])
{
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(path, NULL, &err);
    if (!scene) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        return NULL;
    }
    rtt_view_list views;
    if (!rtt_views_load(views_path, &views, &err)) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        rtt_scene_free(scene);
        return NULL;
    }
    const char *base = strrchr(path, '/');
    snprintf(name, 256, "%s", base ? base + 1 : path);
    char *dot = strchr(name, '.');
    if (dot) *dot = '\0';
    const rtt_view *view = rtt_views_find(&views, name);
    const bool ok = !view || rtt_bench_apply_view(scene, view, &err);
    rtt_views_free(&views);
    if (!ok) {
        fprintf(stderr, "%s: %s\n", tool, err.message);
        rtt_scene_free(scene);
        return NULL;
    }
    return scene;
}

double kerneltime_thread_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

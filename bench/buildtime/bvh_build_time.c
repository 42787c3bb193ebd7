/* bvh_build_time: the optimized engine's BVH build (bvh_build_sah, one
 * thread) against Embree's high-quality build (rtcCommitScene,
 * RTC_BUILD_QUALITY_HIGH, RTC_SCENE_FLAG_ROBUST, device threads=1), each
 * the best of --runs, in the calling thread's CPU time
 * (CLOCK_THREAD_CPUTIME_ID), with the process's CPU time and the wall
 * clock beside it (Embree's build thread could be another thread).  Our
 * time is the whole build (records, boxes, tree, compaction); Embree's is
 * the commit alone (its triangles are attached before the clock starts).
 *
 *   bvh_build_time [--runs N] [--threads T] [--sphere U V] [SCENE...]
 *
 * --sphere U V adds a generated wavy UV sphere of U x V quads (2UV
 * triangles; 1000 500 is the million-triangle input of
 * bench/results/bvh-build.md).  --threads T times our build on T threads
 * too (wall clock; Embree stays at one).  One Markdown table row per scene
 * on stdout: triangles, our best thread CPU, Embree's, their ratio, our
 * tree's SAH cost, depth and inner nodes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bvh_build.h"
#include "engine/clock.h"
#include "rtt/scene.h"
#ifdef RTT_HAVE_EMBREE
#include "embree_engine.h"
#endif

typedef struct times {
    double thread, process, wall;
} times;

static double clock_of(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static times times_now(void)
{
    return (times){clock_of(CLOCK_THREAD_CPUTIME_ID), clock_of(CLOCK_PROCESS_CPUTIME_ID), rtt_clock_seconds()};
}

/* best = the per-clock minimum of best and (end - start) */
static void times_keep_best(times *best, times start, times end)
{
    const times d = {end.thread - start.thread, end.process - start.process, end.wall - start.wall};
    if (d.thread < best->thread) best->thread = d.thread;
    if (d.process < best->process) best->process = d.process;
    if (d.wall < best->wall) best->wall = d.wall;
}

/* A UV sphere of u x v quads whose radius waves (so no two rings are alike). */
static rtt_scene *wavy_sphere(uint32_t u, uint32_t v, rtt_error *err)
{
    const double pi = 3.14159265358979323846;
    const size_t tris = 2u * (size_t)u * v;
    if (tris > 100000000u) {
        rtt_error_set(err, "--sphere %u %u: more than 1e8 triangles", u, v);
        return NULL;
    }
    float *xyz = malloc(tris * 9u * sizeof *xyz);
    if (!xyz) {
        rtt_error_set(err, "out of memory generating a %ux%u sphere", u, v);
        return NULL;
    }
    size_t k = 0;
    for (uint32_t j = 0; j < v; j++)
        for (uint32_t i = 0; i < u; i++) {
            float p[4][3];
            for (int c = 0; c < 4; c++) {
                const double phi = 2.0 * pi * (double)(i + (c & 1)) / u, theta = pi * (double)(j + (c >> 1)) / v;
                const double r = 1.0 + 0.05 * sin(13.0 * phi) * sin(7.0 * theta);
                p[c][0] = (float)(r * sin(theta) * cos(phi));
                p[c][1] = (float)(r * cos(theta));
                p[c][2] = (float)(r * sin(theta) * sin(phi));
            }
            static const int order[6] = {0, 2, 1, 1, 2, 3};
            for (int t = 0; t < 6; t++)
                for (int a = 0; a < 3; a++) xyz[k++] = p[order[t]][a];
        }
    rtt_scene *scene = rtt_scene_from_triangles(xyz, (uint32_t)tris, err);
    free(xyz);
    return scene;
}

#ifdef RTT_HAVE_EMBREE
static bool embree_best(const rtt_scene *scene, uint32_t runs, times *best)
{
    RTCDevice device = rtcNewDevice("threads=1,verbose=0");
    if (!device) return false;
    bool ok = true;
    for (uint32_t r = 0; r < runs && ok; r++) {
        RTCScene s = rtcNewScene(device);
        ok = s != NULL;
        if (!ok) break;
        rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_HIGH);
        ok = scene->triangle_count == 0 || rtt_embree_attach_triangles(device, s, scene);
        if (ok) {
            const times start = times_now();
            rtcCommitScene(s);
            times_keep_best(best, start, times_now());
            ok = rtcGetDeviceError(device) == RTC_ERROR_NONE;
        }
        rtcReleaseScene(s);
    }
    rtcReleaseDevice(device);
    return ok;
}
#endif

static float split_share; /* --split-share */

static bool ours_best(const rtt_scene *scene, uint32_t threads, uint32_t runs, times *best, rtt_tree_info *info)
{
    const bvh_build_options options = {.threads = threads, .split_share = split_share};
    for (uint32_t r = 0; r < runs; r++) {
        bvh_tree tree;
        rtt_error err = {{0}};
        const times start = times_now();
        const bool ok = bvh_build_sah(scene, &options, &tree, &err);
        times_keep_best(best, start, times_now());
        if (!ok) {
            fprintf(stderr, "bvh_build_time: %s\n", err.message);
            return false;
        }
        *info = tree.info;
        bvh_tree_free(&tree);
    }
    return true;
}

static bool report(const char *name, const rtt_scene *scene, uint32_t runs, uint32_t threads)
{
    const times none = {INFINITY, INFINITY, INFINITY};
    times ours = none, many = none, theirs = none;
    rtt_tree_info info = {0};
    if (!ours_best(scene, 1, runs, &ours, &info)) return false;
    rtt_tree_info info_many = info;
    if (threads > 1 && !ours_best(scene, threads, runs, &many, &info_many)) return false;
#ifdef RTT_HAVE_EMBREE
    if (!embree_best(scene, runs, &theirs)) {
        fprintf(stderr, "bvh_build_time: %s: Embree's build failed\n", name);
        return false;
    }
#endif
    printf("| %s | %u | %.4f | %.4f | %.4f | %.4f | %.4f | %.2fx | %.2fx |", name, scene->triangle_count,
           ours.thread, ours.wall, theirs.thread, theirs.process, theirs.wall, ours.thread / theirs.thread,
           ours.thread / theirs.process);
    printf(" %.3f | %u | %llu |", info.sah_cost, info.depth,
           (unsigned long long)(info.node_count - info.leaf_count));
    if (threads > 1) printf(" %.4f (same SAH: %s) |", many.wall, info_many.sah_cost == info.sah_cost ? "yes" : "NO");
    printf("\n");
    fflush(stdout);
    return true;
}

static void usage(FILE *to)
{
    fprintf(to, "usage: bvh_build_time [--runs N] [--threads T] [--split-share S] [--sphere U V] [SCENE...]\n"
                "  our BVH build (one thread) against Embree's high-quality build (threads=1),\n"
                "  best of N runs (default 5) in thread CPU time; --threads T adds our build's wall\n"
                "  time on T threads; --split-share S the pre-splitting's share of extra references\n"
                "  (default the builder's, negative none); --sphere U V adds a generated wavy sphere\n"
                "  of 2UV triangles\n");
}

static bool parse_count(const char *s, uint32_t *out)
{
    char *end;
    const unsigned long v = strtoul(s, &end, 10);
    if (*s == '\0' || *end != '\0' || v == 0 || v > 100000) return false;
    *out = (uint32_t)v;
    return true;
}

int main(int argc, char **argv)
{
    uint32_t runs = 5, threads = 1, sphere_u = 0, sphere_v = 0;
    int first_scene = argc;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(argv[a], "--runs") == 0 && a + 1 < argc) {
            if (!parse_count(argv[++a], &runs)) return fprintf(stderr, "bvh_build_time: bad --runs %s\n", argv[a]), 2;
        } else if (strcmp(argv[a], "--threads") == 0 && a + 1 < argc) {
            if (!parse_count(argv[++a], &threads))
                return fprintf(stderr, "bvh_build_time: bad --threads %s\n", argv[a]), 2;
        } else if (strcmp(argv[a], "--split-share") == 0 && a + 1 < argc) {
            char *end;
            split_share = strtof(argv[++a], &end);
            if (*argv[a] == '\0' || *end != '\0' || !(split_share <= BVH_SPLIT_SHARE_MAX))
                return fprintf(stderr, "bvh_build_time: bad --split-share %s\n", argv[a]), 2;
        } else if (strcmp(argv[a], "--sphere") == 0 && a + 2 < argc) {
            if (!parse_count(argv[a + 1], &sphere_u) || !parse_count(argv[a + 2], &sphere_v))
                return fprintf(stderr, "bvh_build_time: bad --sphere %s %s\n", argv[a + 1], argv[a + 2]), 2;
            a += 2;
        } else if (argv[a][0] == '-') {
            usage(stderr);
            return 2;
        } else {
            first_scene = a;
            break;
        }
    }
    if (first_scene == argc && sphere_u == 0) {
        usage(stderr);
        return 2;
    }
#ifndef RTT_HAVE_EMBREE
    fprintf(stderr, "bvh_build_time: built without Embree: its columns are inf\n");
#endif
    printf("| scene | triangles | ours thread CPU s | ours wall s | Embree HQ thread CPU s | Embree process CPU s | "
           "Embree wall s | ours / Embree (thread) | ours / Embree (process) | SAH cost | depth | inner nodes |%s\n",
           threads > 1 ? " ours wall s, more threads |" : "");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|%s\n", threads > 1 ? "---|" : "");
    int status = 0;
    if (sphere_u > 0) {
        rtt_error err = {{0}};
        rtt_scene *scene = wavy_sphere(sphere_u, sphere_v, &err);
        if (!scene) {
            fprintf(stderr, "bvh_build_time: %s\n", err.message);
            return 1;
        }
        char name[64];
        snprintf(name, sizeof name, "wavy sphere %ux%u", sphere_u, sphere_v);
        if (!report(name, scene, runs, threads)) status = 1;
        rtt_scene_free(scene);
    }
    for (int a = first_scene; a < argc; a++) {
        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_load(argv[a], NULL, &err);
        if (!scene) {
            fprintf(stderr, "bvh_build_time: %s\n", err.message);
            status = 1;
            continue;
        }
        const char *slash = strrchr(argv[a], '/');
        if (!report(slash ? slash + 1 : argv[a], scene, runs, threads)) status = 1;
        rtt_scene_free(scene);
    }
    return status;
}

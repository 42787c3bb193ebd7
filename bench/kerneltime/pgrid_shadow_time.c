/* pgrid_shadow_time: frames of hard-shadow rays through the light grid
 * alone (--shadows pgrid: light 0's grid rebuilt, then every pixel's shadow
 * ray traced, batched per eye-ray cell in pixel order, as rtt bench's shadow
 * row does, the batches made once before the frames), on rtt bench's camera and shadow rays for the scene (every
 * primary hit of the optimized engine towards light 0's centre), in the
 * thread's CPU time, the best of FRAMES for the build and for the whole
 * frame, with a checksum of the answers (equal checksums: equal occlusion)
 * and the share of rays occluded.  THREADS (default 1) above one builds
 * the grid and traces the batches on the pool, as rtt bench's row at that
 * many threads, and times the frame in wall-clock time.
 *
 *   pgrid_shadow_time SCENE WIDTH HEIGHT LIGHT_RES FRAMES VIEWS [THREADS]
 *
 * LIGHT_RES the light grid's cells per face side (0: pgrid_light_res_rule);
 * RTT_ISA (sse4, avx2, avx512) narrows the kernel.  One line on stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_internal.h"
#include "engine/clock.h"
#include "engine_optimized.h"
#include "kerneltime.h"
#include "pgrid_eye.h"
#include "rtt/rtt.h"

int main(int argc, char **argv)
{
    if (argc != 7 && argc != 8) {
        fprintf(stderr, "usage: pgrid_shadow_time SCENE WIDTH HEIGHT LIGHT_RES FRAMES VIEWS [THREADS]\n");
        return 2;
    }
    const char *path = argv[1], *views_path = argv[6];
    const int width = atoi(argv[2]), height = atoi(argv[3]), res = atoi(argv[4]), frames = atoi(argv[5]);
    const int threads = argc == 8 ? atoi(argv[7]) : 1;
    if (width < 8 || width > 16384 || height < 8 || height > 16384 || res < 0 || res > (int)PGRID_LIGHT_RES_MAX ||
        frames < 1 || threads < 1 || threads > 256) {
        fprintf(stderr, "pgrid_shadow_time: WIDTH and HEIGHT 8..16384, LIGHT_RES 0..%u, FRAMES >= 1, THREADS 1..256\n",
                PGRID_LIGHT_RES_MAX);
        return 2;
    }
    rtt_isa isa;
    if (!kerneltime_isa("pgrid_shadow_time", &isa)) return 2;
    const pgrid_kernel *kernel = pgrid_kernel_find("pgrid", isa);
    rtt_error err = {{0}};
    if (!rtt_builtin_engines_register(&err)) {
        fprintf(stderr, "pgrid_shadow_time: %s\n", err.message);
        return 1;
    }
    char scene_name[256];
    rtt_scene *scene = kerneltime_scene("pgrid_shadow_time", path, views_path, scene_name);
    if (!scene) return 1;
    if (!scene->light_count) {
        fprintf(stderr, "pgrid_shadow_time: %s: the scene has no light\n", path);
        rtt_scene_free(scene);
        return 1;
    }
    int status = 1;
    const size_t pixels = (size_t)width * (size_t)height;
    rtt_engine *engine = rtt_engine_create("optimized", scene, NULL, &err);
    bench_rays primary = {0}, shadow = {0};
    rtt_hit *hits = malloc(pixels * sizeof *hits);
    uint32_t *prim = malloc(pixels * sizeof *prim);
    float *t = malloc(pixels * sizeof *t);
    uint8_t *occluded = malloc(pixels);
    uint8_t *answers = malloc(pixels);
    bench_shadow_batches batches = {0};
    pgrid_shadows grids = {0};
    if (!engine) {
        fprintf(stderr, "pgrid_shadow_time: %s\n", err.message);
    } else if (!hits || !prim || !t || !occluded || !answers ||
               !bench_rays_primary(scene, (uint32_t)width, (uint32_t)height, &primary)) {
        fprintf(stderr, "pgrid_shadow_time: out of memory\n");
    } else {
        rtt_engine_intersect(engine, primary.rays, hits, pixels);
        for (size_t i = 0; i < pixels; i++) prim[i] = hits[i].prim, t[i] = hits[i].t;
        const rtt_vec3 at = scene->lights[0].position;
        const float position[3] = {at.x, at.y, at.z};
        if (!bench_rays_shadow(scene, &primary, prim, t, &shadow) || !bench_shadow_batches_make(&batches, &shadow, prim, PGRID_EYE_CELL_DEFAULT) ||
            !pgrid_shadows_prepare(&grids, scene, optimized_engine_degenerate(engine), &err)) {
            fprintf(stderr, "pgrid_shadow_time: out of memory\n");
        } else {
            double best_frame = 1e30, best_build = 1e30;
            grids.prints = kernel->light_prints;
            status = 0;
            /* one thread: its CPU time; on the pool: the wall clock */
            double (*const seconds)(void) = threads > 1 ? rtt_clock_seconds : kerneltime_thread_seconds;
            for (int f = 0; f < frames && status == 0; f++) {
                const double t0 = seconds();
                const bool built =
                    pgrid_light_rebuild(&grids.lights[0], &grids, scene, position, (uint32_t)res, (uint32_t)threads);
                grids.light_count = 1;
                const double t1 = seconds();
                if (!built || !bench_shadow_batches_trace(&batches, kernel, &grids, answers, (uint32_t)threads)) {
                    fprintf(stderr, "pgrid_shadow_time: out of memory\n");
                    status = 1;
                }
                const double frame = seconds() - t0;
                if (frame < best_frame) best_frame = frame;
                if (t1 - t0 < best_build) best_build = t1 - t0;
            }
            memset(occluded, 0, pixels);
            for (uint32_t k = 0; k < batches.first[batches.cells]; k++) occluded[batches.pixel[k]] = answers[k];
            uint64_t sum = 0, blocked = 0;
            for (size_t i = 0; i < pixels; i++) sum = sum * 31u + occluded[i] + 1u, blocked += occluded[i];
            if (status == 0)
                printf("%s %dx%d %s light %u: frame %.3f ms (%.1f Mrays/s), build %.3f ms (best), "
                       "%llu rays, %.1f%% occluded, %zu refs, %u near, checksum %016llx\n",
                       scene_name, width, height, rtt_isa_name(kernel->isa), grids.lights[0].res, 1e3 * best_frame,
                       1e-6 * (double)shadow.active / best_frame, 1e3 * best_build,
                       (unsigned long long)shadow.active, 100.0 * (double)blocked / (double)(shadow.active ? shadow.active : 1),
                       grids.lights[0].ref_count, grids.lights[0].near_count, (unsigned long long)sum);
        }
    }
    pgrid_shadows_free(&grids);
    bench_rays_free(&primary);
    bench_rays_free(&shadow);
    bench_shadow_batches_free(&batches);
    free(hits), free(prim), free(t), free(occluded), free(answers);
    if (engine) rtt_engine_destroy(engine);
    rtt_scene_free(scene);
    return status;
}

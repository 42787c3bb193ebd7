/* pgrid_frame_time: frames of eye rays through the perspective grid alone
 * (pgrid_eye_trace_frame: the per-frame build, every cell traced, every
 * pixel's hit resolved), on rtt bench's camera for the scene, in the thread's
 * CPU time (CLOCK_THREAD_CPUTIME_ID: steadier than the wall clock on a
 * loaded machine), the best of FRAMES for the build and for the whole frame,
 * with a checksum of the hits (equal checksums: equal hits).  One thread: the
 * build and the cells run on the calling thread.  THREADS (default 1) above
 * one runs them on the pool and times the frame in wall-clock time.
 *
 *   pgrid_frame_time SCENE WIDTH HEIGHT CELL FRAMES VIEWS [THREADS]
 *
 * CELL the grid's cell side (0: the default); RTT_ISA (sse4, avx2, avx512)
 * narrows the kernel.  The scene's degenerate triangles are not flagged (the
 * build sets them up like any other).  One line on stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_internal.h"
#include "engine/clock.h"
#include "kerneltime.h"
#include "pgrid_eye.h"

int main(int argc, char **argv)
{
    if (argc != 7 && argc != 8) {
        fprintf(stderr, "usage: pgrid_frame_time SCENE WIDTH HEIGHT CELL FRAMES VIEWS [THREADS]\n");
        return 2;
    }
    const int threads = argc == 8 ? atoi(argv[7]) : 1;
    const char *path = argv[1], *views_path = argv[6];
    const int width = atoi(argv[2]), height = atoi(argv[3]), cell = atoi(argv[4]), frames = atoi(argv[5]);
    if (width < 8 || width > 16384 || height < 8 || height > 16384 || cell < 0 || frames < 1 || threads < 1 ||
        threads > 256) {
        fprintf(stderr, "pgrid_frame_time: WIDTH and HEIGHT 8..16384, CELL >= 0, FRAMES >= 1, THREADS 1..256\n");
        return 2;
    }
    rtt_isa isa;
    if (!kerneltime_isa("pgrid_frame_time", &isa)) return 2;
    const pgrid_kernel *kernel = pgrid_kernel_find("pgrid", isa);
    char scene_name[256];
    rtt_scene *scene = kerneltime_scene("pgrid_frame_time", path, views_path, scene_name);
    if (!scene) return 1;
    rtt_error err = {{0}};
    int status = 1;
    rtt_hit *hits = aligned_alloc(64, ((size_t)width * (size_t)height * sizeof *hits + 63) & ~(size_t)63); /* as the bench's */
    pgrid_eye grid = {0};
    if (!hits) {
        fprintf(stderr, "pgrid_frame_time: out of memory\n");
    } else {
        const rtt_camera_frame camera = rtt_camera_frame_make(&scene->camera, (uint32_t)width, (uint32_t)height);
        double best_frame = 1e30, best_build = 1e30;
        /* one thread: its CPU time; on the pool: the wall clock */
        double (*const seconds)(void) = threads > 1 ? rtt_clock_seconds : kerneltime_thread_seconds;
        status = 0;
        for (int f = 0; f < frames && status == 0; f++) {
            double build = 0.0;
            const double t0 = seconds();
            if (!pgrid_eye_trace_frame(&grid, kernel, scene, NULL, &camera, (uint32_t)width, (uint32_t)height,
                                       (uint32_t)cell, (uint32_t)threads, hits, &build, &err)) {
                fprintf(stderr, "pgrid_frame_time: %s\n", err.message);
                status = 1;
            }
            const double frame = seconds() - t0;
            if (frame < best_frame) best_frame = frame;
            if (build < best_build) best_build = build;
        }
        uint64_t sum = 0;
        for (size_t i = 0; i < (size_t)width * (size_t)height; i++) {
            uint32_t t;
            memcpy(&t, &hits[i].t, sizeof t);
            sum = sum * 31u + hits[i].prim + ((uint64_t)t << 7);
        }
        if (status == 0)
            printf("%s %dx%d %s threads %d cell %u: frame %.3f ms (%.1f Mrays/s), build %.3f ms (wall, best), "
                   "%u triangles kept, %u back faces dropped, %zu refs, checksum %016llx\n",
                   scene_name, width, height, rtt_isa_name(kernel->isa), threads, grid.cell, 1e3 * best_frame,
                   1e-6 * width * height / best_frame, 1e3 * best_build, grid.triangle_count, grid.culled_count, grid.ref_count,
                   (unsigned long long)sum);
    }
    pgrid_eye_free(&grid);
    free(hits);
    rtt_scene_free(scene);
    return status;
}

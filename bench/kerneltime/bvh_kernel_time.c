/* bvh_kernel_time: one BVH kernel alone on rtt bench's rays, one thread, in
 * the thread's CPU time (CLOCK_THREAD_CPUTIME_ID: steadier than the wall
 * clock on a loaded machine), the best of FRAMES, with the counters of one
 * extra frame and a checksum of the answers (equal checksums: equal hits).
 * bench/results/bvh-mft.md and frusta.md quote it.
 *
 *   bvh_kernel_time SCENE KERNEL SIZE LEAF DEPTH FRAMES VIEWS [NODE_COST]
 *
 * SCENE a scene rtt bench takes, with the view of VIEWS (bench/views.json)
 * named as its file (without the extension) when there is one; KERNEL
 *   bvh-mono, bvh-packet, bvh-mft   the kernel on the primary rays, in rtt
 *                                   bench's order (16x16 tiles of 4x4 blocks);
 *   bvh-mft-camera                  bvh-mft making the primary rays itself
 *                                   from the camera frame (trace_camera),
 *                                   per 16x16 tile;
 *   soft                            frusta:16 on rtt bench's soft-shadow
 *                                   points (its kind "soft" rows), per tile;
 * SIZE the image side; LEAF and DEPTH the BVH's leaf size and depth bound
 * (0: the defaults), NODE_COST the SAH's node cost in triangle tests
 * (absent or 0: the default, BVH_DEFAULT_NODE_COST).  RTT_ISA (sse4, avx2, avx512) narrows the kernel.  One
 * line on stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_internal.h"
#include "bvh_build.h"
#include "bvh_kernels.h"
#include "kerneltime.h"

#define TILE 16u

/* The checksum of answers: order-dependent, over prim and t's bits. */
static uint64_t checksum_hits(const rtt_hit *hits, size_t n)
{
    uint64_t sum = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t t;
        memcpy(&t, &hits[i].t, sizeof t);
        sum = sum * 31u + hits[i].prim + ((uint64_t)t << 7);
    }
    return sum;
}

/* What a timed pass runs, and its last answers. */
typedef struct kernel_run {
    const bvh_tree *tree;
    const bvh_kernel *kernel;
    const bvh_shadow_kernel *soft;
    bool camera;
    const bench_rays *primary;
    const rtt_ray *ordered;              /* primary rays in tile order */
    rtt_hit *hits;                       /* tile order (camera: each tile's rows) */
    const bench_soft *soft_points;
    const bvh_shadow_point *points;      /* soft: tile order */
    const uint32_t *first;               /* soft: per tile, its first point */
    uint32_t *masks;
    uint32_t tiles_x, tiles_y;
} kernel_run;

static void run_pass(const kernel_run *r, bvh_counters *counters)
{
    const uint32_t w = r->primary->width, h = r->primary->height, tiles = r->tiles_x * r->tiles_y;
    const rtt_camera_frame *c = &r->primary->camera;
    bvh_camera_block block = {{c->eye.x, c->eye.y, c->eye.z}, {c->corner.x, c->corner.y, c->corner.z},
                              {c->du.x, c->du.y, c->du.z}, {c->dv.x, c->dv.y, c->dv.z}, 0, 0, 0, 0, true};
    for (uint32_t t = 0; t < tiles; t++) {
        rtt_hit *hits = r->hits ? &r->hits[(size_t)t * TILE * TILE] : NULL;
        if (r->soft) {
            r->soft->trace(r->tree, &(bvh_shadow_query){.points = r->points + r->first[t],
                                                        .count = r->first[t + 1] - r->first[t],
                                                        .sets = &r->soft_points->sets,
                                                        .epsilon = r->soft_points->epsilon,
                                                        .occluded = r->masks + r->first[t], .counters = counters});
        } else if (r->camera) {
            block.x0 = (t % r->tiles_x) * TILE, block.y0 = (t / r->tiles_x) * TILE;
            block.x1 = block.x0 + TILE < w ? block.x0 + TILE : w, block.y1 = block.y0 + TILE < h ? block.y0 + TILE : h;
            r->kernel->trace_camera(r->tree, &block, hits, counters);
        } else {
            r->kernel->trace(r->tree, &(bvh_query){.rays = r->ordered + (size_t)t * TILE * TILE, .count = TILE * TILE,
                                                   .hits = hits, .counters = counters});
        }
    }
}

/* The primary rays' closest hits (bvh-packet), for the soft points. */
static bool soft_points_make(const rtt_scene *scene, const bench_rays *primary, const bvh_tree *tree, bench_soft *soft)
{
    const size_t n = (size_t)primary->width * primary->height;
    rtt_hit *hits = malloc(n * sizeof *hits);
    uint32_t *prim = malloc(n * sizeof *prim);
    float *t = malloc(n * sizeof *t);
    rtt_error err = {{0}};
    bool ok = hits && prim && t;
    if (ok) {
        bvh_kernel_find("bvh-packet", RTT_ISA_AVX512)->trace(tree, &(bvh_query){.rays = primary->rays, .count = n,
                                                                               .hits = hits});
        for (size_t i = 0; i < n; i++) prim[i] = hits[i].prim, t[i] = hits[i].t;
        ok = bench_soft_make(scene, primary, prim, t, soft, &err);
        if (!ok) fprintf(stderr, "bvh_kernel_time: %s\n", err.message[0] ? err.message : "out of memory");
    }
    free(hits), free(prim), free(t);
    return ok;
}

int main(int argc, char **argv)
{
    if (argc < 8 || argc > 10) {
        fprintf(stderr, "usage: bvh_kernel_time SCENE bvh-mono|bvh-packet|bvh-mft|bvh-mft-camera|soft SIZE LEAF DEPTH "
                        "FRAMES VIEWS [NODE_COST [SPLIT_SHARE]]\n");
        return 2;
    }
    const char *path = argv[1], *name = argv[2], *views_path = argv[7];
    const int size = atoi(argv[3]), leaf = atoi(argv[4]), depth = atoi(argv[5]), frames = atoi(argv[6]);
    const double node_cost = argc >= 9 ? atof(argv[8]) : 0.0, split_share = argc == 10 ? atof(argv[9]) : 0.0;
    if (size < 8 || size > 16384 || leaf < 0 || depth < 0 || frames < 1 ||
        !(node_cost >= 0.0 && node_cost <= BVH_NODE_COST_MAX) || !(split_share <= BVH_SPLIT_SHARE_MAX)) {
        fprintf(stderr,
                "bvh_kernel_time: SIZE 8..16384, LEAF and DEPTH >= 0, FRAMES >= 1, NODE_COST 0..%g (0: default), "
                "SPLIT_SHARE at most %g (0: default, negative: none)\n",
                (double)BVH_NODE_COST_MAX, (double)BVH_SPLIT_SHARE_MAX);
        return 2;
    }
    rtt_isa isa;
    if (!kerneltime_isa("bvh_kernel_time", &isa)) return 2;
    char scene_name[256];
    rtt_scene *scene = kerneltime_scene("bvh_kernel_time", path, views_path, scene_name);
    if (!scene) return 1;
    rtt_error err = {{0}};
    bench_rays primary;
    if (!bench_rays_primary(scene, (uint32_t)size, (uint32_t)size, &primary)) {
        fprintf(stderr, "bvh_kernel_time: out of memory\n");
        return 1;
    }
    bvh_tree tree;
    memset(&tree, 0, sizeof tree);
    const bvh_build_options build = {
        .leaf_size = (uint32_t)leaf, .max_depth = (uint32_t)depth, .node_cost = (float)node_cost,
        .split_share = (float)split_share, .threads = 1};
    const double build_start = kerneltime_thread_seconds();
    if (!bvh_build_sah(scene, &build, &tree, &err)) {
        fprintf(stderr, "bvh_kernel_time: %s\n", err.message);
        return 1;
    }
    const double build_seconds = kerneltime_thread_seconds() - build_start;
    const double solids_start = kerneltime_thread_seconds();
    if (!bvh_tree_mark_solids(&tree, scene, &err)) { /* as the engine does: bvh-mft's back-face culling */
        fprintf(stderr, "bvh_kernel_time: %s\n", err.message);
        return 1;
    }
    const double solids_seconds = kerneltime_thread_seconds() - solids_start;
    tree.watertight = true; /* the engine's default test */

    kernel_run run = {.tree = &tree, .primary = &primary, .tiles_x = ((uint32_t)size + TILE - 1) / TILE,
                      .tiles_y = ((uint32_t)size + TILE - 1) / TILE};
    const uint32_t tiles = run.tiles_x * run.tiles_y;
    const size_t slots = (size_t)tiles * TILE * TILE;
    bench_soft soft = {0};
    bvh_shadow_point *points = NULL;
    uint32_t *first = NULL, point_count = 0;
    rtt_ray *ordered = NULL;
    double rays;
    if (strcmp(name, "soft") == 0) {
        if (!soft_points_make(scene, &primary, &tree, &soft)) return 1;
        run.soft = bvh_shadow_kernel_find(isa);
        points = malloc((size_t)soft.width * soft.height * sizeof *points);
        first = malloc(((size_t)tiles + 1) * sizeof *first);
        run.masks = calloc((size_t)soft.width * soft.height, sizeof *run.masks);
        if (!points || !first || !run.masks) return 1;
        /* each tile's points in 4x4 blocks, as the bench and the renderer order them */
        for (uint32_t t = 0; t < tiles; t++) {
            first[t] = point_count;
            for (uint32_t in = 0; in < TILE * TILE; in++) {
                const uint32_t block = in / 16u, lane = in % 16u;
                const uint32_t x = (t % run.tiles_x) * TILE + (block % 4u) * 4u + lane % 4u;
                const uint32_t y = (t / run.tiles_x) * TILE + (block / 4u) * 4u + lane / 4u;
                if (x < soft.width && y < soft.height && soft.has[(size_t)y * soft.width + x])
                    points[point_count++] = soft.points[(size_t)y * soft.width + x];
            }
        }
        first[tiles] = point_count;
        run.soft_points = &soft, run.points = points, run.first = first;
        rays = (double)soft.rays.active;
    } else {
        run.camera = strcmp(name, "bvh-mft-camera") == 0;
        run.kernel = bvh_kernel_find(run.camera ? "bvh-mft" : name, isa);
        if (!run.kernel || (run.camera && !run.kernel->trace_camera)) {
            fprintf(stderr, "bvh_kernel_time: no BVH kernel named %s\n", name);
            return 2;
        }
        ordered = malloc(slots * sizeof *ordered);
        run.hits = aligned_alloc(64, slots * sizeof *run.hits); /* a tile's rows on 64-byte lines: streamed */
        if (!ordered || !run.hits) return 1;
        const rtt_ray off_image = {{0, 0, 0}, {1, 0, 0}, INFINITY, -INFINITY};
        for (size_t i = 0; i < slots; i++) {
            const uint32_t t = (uint32_t)(i / (TILE * TILE)), in = (uint32_t)(i % (TILE * TILE));
            const uint32_t block = in / 16u, lane = in % 16u;
            const uint32_t x = (t % run.tiles_x) * TILE + (block % 4u) * 4u + lane % 4u;
            const uint32_t y = (t / run.tiles_x) * TILE + (block / 4u) * 4u + lane / 4u;
            ordered[i] = x < primary.width && y < primary.height ? primary.rays[(size_t)y * primary.width + x] : off_image;
        }
        run.ordered = ordered;
        rays = (double)primary.active;
    }
    bvh_counters counters = {0};
    run_pass(&run, &counters);
    uint64_t sum = 0;
    if (run.soft) {
        for (uint32_t i = 0; i < point_count; i++) sum = sum * 31u + run.masks[i];
    } else if (run.camera) { /* each tile's rows, as the stream kernels' tile order would give them */
        rtt_hit *image = malloc((size_t)primary.width * primary.height * sizeof *image);
        if (!image) return 1;
        for (uint32_t t = 0; t < tiles; t++) {
            const uint32_t x0 = (t % run.tiles_x) * TILE, y0 = (t / run.tiles_x) * TILE;
            const uint32_t tw = primary.width - x0 < TILE ? primary.width - x0 : TILE;
            const uint32_t th = primary.height - y0 < TILE ? primary.height - y0 : TILE;
            for (uint32_t i = 0; i < tw * th; i++)
                image[(size_t)(y0 + i / tw) * primary.width + x0 + i % tw] = run.hits[(size_t)t * TILE * TILE + i];
        }
        sum = checksum_hits(image, (size_t)primary.width * primary.height);
        free(image);
    } else {
        rtt_hit *image = malloc((size_t)primary.width * primary.height * sizeof *image);
        if (!image) return 1;
        for (size_t i = 0; i < slots; i++) {
            const uint32_t t = (uint32_t)(i / (TILE * TILE)), in = (uint32_t)(i % (TILE * TILE));
            const uint32_t block = in / 16u, lane = in % 16u;
            const uint32_t x = (t % run.tiles_x) * TILE + (block % 4u) * 4u + lane % 4u;
            const uint32_t y = (t / run.tiles_x) * TILE + (block / 4u) * 4u + lane / 4u;
            if (x < primary.width && y < primary.height) image[(size_t)y * primary.width + x] = run.hits[i];
        }
        sum = checksum_hits(image, (size_t)primary.width * primary.height);
        free(image);
    }
    double best = INFINITY;
    for (int f = 0; f < frames; f++) {
        const double start = kerneltime_thread_seconds();
        run_pass(&run, NULL);
        const double seconds = kerneltime_thread_seconds() - start;
        best = seconds < best ? seconds : best;
    }
    /* per 2x2 packet of rays, as the bench's kd rows count N and I */
    const double quads = rays / 4.0;
    printf("%s %s %s leaf %d depth %d: tree depth %u, %u nodes; %.2f Mrays/s (best thread CPU %.4f s of %d); "
           "N %.3f I %.3f tris %.0fK isect %.0fK; build %.3f s, solids %.3f s; checksum %016llx\n",
           scene_name, name, rtt_isa_name(run.soft ? run.soft->isa : run.kernel->isa), leaf, depth, tree.info.depth,
           tree.node_count, rays / best / 1e6, best, frames, (double)counters.aabb_tests / quads,
           (double)counters.isect_tests / quads, (double)counters.triangles / 1e3, (double)counters.isect_tests / 1e3,
           build_seconds, solids_seconds, (unsigned long long)sum);
    free(points), free(first), free(run.masks), free(ordered), free(run.hits);
    bench_soft_free(&soft);
    bench_rays_free(&primary);
    bvh_tree_free(&tree);
    rtt_scene_free(scene);
    return 0;
}

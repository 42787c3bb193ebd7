/* Fuzz target: the kd-tree builders, the BVH builder and every traversal
 * kernel of both.
 *
 * Bytes become triangles and rays at the numerical extremes (docs/ARCHITECTURE.md
 * "Extremes"): NaN, inf, denormals, huge, tiny, degenerate and duplicate
 * triangles, meshes far from the origin, rays aimed exactly at vertices and
 * edges, axis-parallel rays with -0.0.  Then:
 *
 *  1. rtt_scene_from_triangles must refuse non-finite input with one line
 *     and accept finite input;
 *  2. the reference and the optimized engine (kd-tree and BVH) are built;
 *     their tree info must hold its bounds (depth <= max_depth, references
 *     <= reference_cap);
 *  3. the rays go through the reference and every optimized traversal mode
 *     of both structures (the kd and BVH kernels with the watertight test,
 *     or the projected one when flag bit 3 is set) and each answer is
 *     checked against brute force
 *     (fuzz_oracle.h: strict for the reference and the watertight test,
 *     which is the reference's arithmetic; lenient near edges for the
 *     projected test);
 *  4. the perspective grid (optimized/pgrid/) is built for a camera at the
 *     bundle's eye looking at the scene's centre, and its eye rays, at
 *     every instruction set and two cell sizes, are checked the same way;
 *  5. the BVH's shadow frusta: from the rays' hit points to a sphere and a
 *     quad light at the eye, the soft-shadow frusta kernel (frusta:16, rays
 *     made on demand) and bvh-mft's hard shadows bounded from the light
 *     (bvh_query.toward), at every instruction set, must answer each ray
 *     exactly as bvh-packet does on the same rays (the frusta cull only);
 *  6. bvh-mft's primary rays made from the same camera's frame
 *     (trace_camera), every instruction set, in one block and in 5 x 3
 *     blocks: without back-face culling each pixel's hit is bvh-packet's
 *     on rtt_camera_ray's ray; with it (the scene's solids) each passes
 *     the brute force strictly.
 *
 * Layout of an input (missing bytes read as 0):
 *   [0] triangle count - 1 (mod 48)   [1] bit 0: raw float bits, bits 1-3: scale
 *   [2] offset choice                 [3] max tree depth (0 = default), [4] flags
 *   (bit 0 leaf culling, bits 1-2 tile, bit 3 the projected test, bit 4
 *   corners at one position welded into one vertex: closed meshes become
 *   solids, whose back faces pgrid and bvh-mft's camera path cull)
 *   triangles: per vertex 1 control byte (< 48 and a vertex exists: repeat
 *     vertex ctrl % count) then 3 coordinates (1 palette byte each, or 4 raw
 *     bytes in raw mode)
 *   rays: per ray 1 control byte then its operands (see decode_ray). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "rtt/rtt.h"
#include "fuzz_oracle.h"
#include "bvh_kernels.h"
#include "engine_optimized.h"
#include "pgrid_eye.h"
#include "rtt/interleaved.h"
#include "rtt/engine.h"
#include "rtt/shade.h"

#define MAX_TRIANGLES 48u
#define MAX_RAYS 48u
#define GRID 8u   /* a coherent GRID x GRID pinhole bundle for the packet kernels */

typedef struct byte_reader {
    const uint8_t *data;
    size_t size, at;
} byte_reader;

static uint8_t next_byte(byte_reader *in)
{
    return in->at < in->size ? in->data[in->at++] : 0;
}

static float next_raw_float(byte_reader *in)
{
    uint32_t bits = 0;
    for (int k = 0; k < 4; k++)
        bits |= (uint32_t)next_byte(in) << (8 * k);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* Coordinates worth trying: small integers and halves (shared edges, split
 * planes on vertices), signed zeros, tiny, denormal and huge values. */
static float palette_float(uint8_t b)
{
    static const float specials[] = { 0.0f, -0.0f, 0.5f, -0.5f, 0.25f, 1e-3f, 1e-20f, -1e-20f,
                                      1e-40f /* denormal */, FLT_MIN, 1e10f, -1e10f, 1e20f, 3.3e6f, 0.1f, 0.3f };
    if (b < 16)
        return specials[b];
    if (b < 16 + 33)
        return (float)((int)b - 16 - 16);   /* -16 .. 16 */
    return (float)((int)b - 152) / 8.0f;    /* eighths in [-13, 12.9] */
}

static const float scales[8] = { 1.0f, 1e-20f, 1e20f, 1e-6f, 1e6f, 1.0f, 1e-3f, 1e3f };
static const float offsets[4] = { 0.0f, 1e4f, -1e7f, 3e5f };

static float coordinate(byte_reader *in, bool raw, float scale, float offset)
{
    if (raw)
        return next_raw_float(in);
    return palette_float(next_byte(in)) * scale + offset;
}

static uint32_t decode_triangles(byte_reader *in, float *xyz, uint32_t count, bool raw, float scale, float offset)
{
    uint32_t vertices = 0;
    for (uint32_t v = 0; v < count * 3; v++) {
        uint8_t control = next_byte(in);
        if (control < 48 && vertices > 0) {
            memcpy(&xyz[v * 3], &xyz[(control % vertices) * 3], 3 * sizeof(float));   /* shared/duplicate */
        } else {
            for (int k = 0; k < 3; k++)
                xyz[v * 3 + k] = coordinate(in, raw, scale, offset);
        }
        vertices++;
    }
    return count;
}

/* Each triangle corner made the first vertex at its exact position (the
 * soup's vertex per corner otherwise): a closed mesh's edges are then
 * shared by vertex index, as the solids (optimized/solids.h) ask. */
static void weld_vertices(rtt_scene *scene)
{
    for (uint32_t t = 0; t < scene->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t v = scene->triangles[t].v[k];
            for (uint32_t w = 0; w < v; w++)
                if (!memcmp(&scene->vertices[w], &scene->vertices[v], sizeof scene->vertices[v])) {
                    scene->triangles[t].v[k] = w;
                    break;
                }
        }
}

static rtt_vec3 scene_vertex(const rtt_scene *scene, uint8_t b)
{
    return scene->vertex_count ? scene->vertices[b % scene->vertex_count] : rtt_v3(0, 0, 0);
}

static rtt_vec3 palette_point(byte_reader *in, float scale, float offset)
{
    float x = palette_float(next_byte(in)) * scale + offset;
    float y = palette_float(next_byte(in)) * scale + offset;
    float z = palette_float(next_byte(in)) * scale + offset;
    return rtt_v3(x, y, z);
}

/* A palette point placed like the triangles: the scene stores its vertices
 * relative to its origin (rtt/scene.h), so eyes and ray origins go there
 * too, and a mesh far from the origin is seen from near it. */
static rtt_vec3 stored_point(const rtt_scene *scene, rtt_vec3 p)
{
    const double file[3] = {p.x, p.y, p.z};
    return rtt_scene_point_to_stored(scene, file);
}

static void aim(rtt_ray *ray, rtt_vec3 org, rtt_vec3 target)
{
    rtt_vec3 d = rtt_v3_sub(target, org);
    *ray = (rtt_ray){ { org.x, org.y, org.z }, { d.x, d.y, d.z }, 0.0f, INFINITY };
}

/* One ray: control % 5 picks the kind, control / 5 the [tnear, tfar]. */
static rtt_ray decode_ray(byte_reader *in, const rtt_scene *scene, float scale, float offset)
{
    uint8_t control = next_byte(in);
    rtt_ray ray;
    rtt_vec3 org = stored_point(scene, palette_point(in, scale, offset));
    switch (control % 5) {
    case 0:   /* exactly at a vertex */
        aim(&ray, org, scene_vertex(scene, next_byte(in)));
        break;
    case 1: { /* at a point of an edge */
        rtt_vec3 a = scene_vertex(scene, next_byte(in)), b = scene_vertex(scene, next_byte(in));
        float s = (float)next_byte(in) / 255.0f;
        aim(&ray, org, rtt_v3_add(rtt_v3_scale(a, 1.0f - s), rtt_v3_scale(b, s)));
        break;
    }
    case 2: { /* axis-parallel, other components +0 or -0 */
        uint8_t b = next_byte(in);
        float d[3] = { (b & 8) ? -0.0f : 0.0f, (b & 16) ? -0.0f : 0.0f, (b & 32) ? -0.0f : 0.0f };
        d[b % 3] = (b & 64) ? -1.0f : 1.0f;
        ray = (rtt_ray){ { org.x, org.y, org.z }, { d[0], d[1], d[2] }, 0.0f, INFINITY };
        break;
    }
    case 3: { /* anything, including NaN and inf from raw bits */
        ray.org[0] = org.x, ray.org[1] = org.y, ray.org[2] = org.z;
        for (int k = 0; k < 3; k++)
            ray.dir[k] = next_raw_float(in);
        ray.tnear = 0.0f;
        ray.tfar = INFINITY;
        break;
    }
    default: { /* from a vertex along a palette direction (origins on surfaces) */
        rtt_vec3 from = scene_vertex(scene, next_byte(in));
        rtt_vec3 d = palette_point(in, 1.0f, 0.0f);
        ray = (rtt_ray){ { from.x, from.y, from.z }, { d.x, d.y, d.z }, 0.0f, INFINITY };
        break;
    }
    }
    switch ((control / 5) % 6) {
    case 1: ray.tfar = 1.0f; break;            /* ends exactly at the target */
    case 2: ray.tnear = 1e-3f; break;
    case 3: ray.tnear = 0.5f; ray.tfar = 2.0f; break;
    case 4: ray.tnear = -INFINITY; break;
    default: break;
    }
    return ray;
}

/* A pinhole bundle aimed at the scene's centre: coherent packets, so the
 * frustum, MFT and cone kernels take their fast paths. */
static void camera_grid(const rtt_scene *scene, rtt_vec3 eye, rtt_ray *rays)
{
    rtt_vec3 centre = rtt_v3_add(rtt_v3_scale(scene->bounds.lo, 0.5f), rtt_v3_scale(scene->bounds.hi, 0.5f));
    rtt_vec3 extent = rtt_v3_sub(scene->bounds.hi, scene->bounds.lo);
    float size = fmaxf(extent.x, fmaxf(extent.y, extent.z));
    for (uint32_t y = 0; y < GRID; y++)
        for (uint32_t x = 0; x < GRID; x++) {
            float sx = ((float)x + 0.5f) / GRID - 0.5f, sy = ((float)y + 0.5f) / GRID - 0.5f;
            rtt_vec3 target = rtt_v3_add(centre, rtt_v3(sx * size, sy * size, 0.0f));
            aim(&rays[y * GRID + x], eye, target);
        }
}

static void check_engines(const rtt_scene *scene, const rtt_ray *rays, size_t ray_count, uint8_t depth_byte,
                          uint8_t flags)
{
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.threads = 1;
    opt.max_tree_depth = depth_byte % 40;   /* 0: builder default; 1.. tiny trees */
    opt.leaf_culling = flags & 1;
    static const uint32_t tiles[4] = { 4, 8, 16, 32 };
    opt.tile = tiles[(flags >> 1) % 4];
    const bool projected = flags >> 3 & 1;
    fuzz_oracle *oracle = fuzz_oracle_create(scene, rays, ray_count);
    rtt_error err = { "" };

    rtt_engine *reference = rtt_engine_create("reference", scene, &opt, &err);
    if (!reference)
        fuzz_fail("reference engine refused a valid scene: %s", err.message);
    fuzz_check_tree_info(reference, "reference", scene, false);
    fuzz_oracle_check(oracle, reference, "reference", false);
    rtt_engine_destroy(reference);

    const char *kernel;
    static const rtt_accel accels[] = {RTT_ACCEL_KD, RTT_ACCEL_BVH};
    for (size_t a = 0; a < sizeof accels / sizeof accels[0]; a++) {
        opt.accel = accels[a];
        const bool lenient = projected;
        for (uint32_t mode = 0; (kernel = rtt_optimized_engine_class.kernel(accels[a], mode)); mode++) {
            snprintf(opt.traversal, sizeof opt.traversal, "%s", kernel);
            opt.isect = projected ? RTT_ISECT_PROJECTED : RTT_ISECT_WATERTIGHT;
            rtt_engine *optimized = rtt_engine_create("optimized", scene, &opt, &err);
            if (!optimized)
                fuzz_fail("optimized engine (%s) refused a valid scene: %s", kernel, err.message);
            char label[64];
            snprintf(label, sizeof label, "optimized/%s/%s", kernel, lenient ? "projected" : "watertight");
            if (mode == 0)
                fuzz_check_tree_info(optimized, label, scene, true);
            fuzz_oracle_check(oracle, optimized, label, lenient);
            rtt_engine_destroy(optimized);
        }
    }
    fuzz_oracle_free(oracle);
}

/* The perspective grid's eye rays as an engine for the oracle: its hits
 * were traced before, for exactly these rays in this order. */
typedef struct pgrid_answers {
    rtt_engine base;
    const rtt_hit *hits;
} pgrid_answers;

static void answers_intersect(rtt_engine *e, const rtt_ray *rays, rtt_hit *hits, size_t n)
{
    (void)rays;
    memcpy(hits, ((pgrid_answers *)e)->hits, n * sizeof *hits);
}

static void answers_occluded(rtt_engine *e, const rtt_ray *rays, uint8_t *occluded, size_t n)
{
    (void)rays;
    for (size_t i = 0; i < n; i++) occluded[i] = ((pgrid_answers *)e)->hits[i].prim != RTT_MISS;
}

static const rtt_engine_vtable answers_vtable = {.name = "pgrid", .intersect = answers_intersect,
                                                 .occluded = answers_occluded};

#define PGRID_W 20u
#define PGRID_H 12u

/* The perspective grid's build and cell kernels (every instruction set,
 * two cell sizes) on the eye rays of a camera at `eye` looking at the
 * scene's centre, against brute force (lenient: its edge test is not the
 * reference's). */
static void check_pgrid(rtt_scene *scene, rtt_vec3 eye, uint8_t fov_byte)
{
    scene->camera.eye = eye;
    scene->camera.look_at = rtt_v3_add(rtt_v3_scale(scene->bounds.lo, 0.5f), rtt_v3_scale(scene->bounds.hi, 0.5f));
    scene->camera.fov_deg = 10.0f + (float)(fov_byte % 160);
    rtt_camera_frame frame = rtt_camera_frame_make(&scene->camera, PGRID_W, PGRID_H);
    rtt_ray rays[PGRID_W * PGRID_H];
    for (uint32_t y = 0; y < PGRID_H; y++)
        for (uint32_t x = 0; x < PGRID_W; x++) rays[y * PGRID_W + x] = rtt_camera_ray(&frame, x, y);
    uint8_t degenerate[MAX_TRIANGLES];
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        rtt_vec3 c[3];
        rtt_scene_triangle(scene, i, c);
        degenerate[i] = rtt_triangle_is_degenerate(c);
    }
    fuzz_oracle *oracle = fuzz_oracle_create(scene, rays, PGRID_W * PGRID_H);
    rtt_hit hits[PGRID_W * PGRID_H];
    static const uint32_t cells[] = {4, 8};
    for (rtt_isa isa = RTT_ISA_SSE4; isa < RTT_ISA_COUNT; isa = (rtt_isa)(isa + 1)) {
        const pgrid_kernel *kernel = pgrid_kernel_find("pgrid", isa);
        if (!kernel || kernel->isa != isa) continue;
        for (size_t c = 0; c < sizeof cells / sizeof cells[0]; c++) {
            pgrid_eye grid = {0};
            rtt_error err = {""};
            if (!pgrid_eye_trace_frame(&grid, kernel, scene, degenerate, &frame, PGRID_W, PGRID_H, cells[c], 1, hits,
                                       NULL, &err))
                fuzz_fail("pgrid refused a valid scene: %s", err.message);
            pgrid_eye_free(&grid);
            for (uint32_t i = 0; i < PGRID_W * PGRID_H; i++)
                if (hits[i].prim != RTT_MISS && hits[i].prim >= scene->triangle_count)
                    fuzz_fail("pgrid reported prim %u of %u", hits[i].prim, scene->triangle_count);
            pgrid_answers answers = {{&answers_vtable, scene}, hits};
            char label[48];
            snprintf(label, sizeof label, "pgrid/%s cell %u", rtt_isa_name(isa), cells[c]);
            fuzz_oracle_check(oracle, &answers.base, label, true);
        }
    }
    fuzz_oracle_free(oracle);
}

/* The optimized engine with --accel bvh on `scene`, one thread (its tree:
 * bvh_engine_tree). */
static rtt_engine *bvh_engine_for(const rtt_scene *scene)
{
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.threads = 1;
    opt.accel = RTT_ACCEL_BVH;
    rtt_error err = {""};
    rtt_engine *engine = rtt_engine_create("optimized", scene, &opt, &err);
    if (!engine) fuzz_fail("optimized engine (bvh) refused a valid scene: %s", err.message);
    return engine;
}

/* bvh-mft's camera-made primary rays (trace_camera, every instruction set)
 * for the scene's camera (check_pgrid's), in one block and in blocks of
 * 5 x 3 pixels into hits. */
static void trace_mft_camera(const bvh_tree *tree, const bvh_kernel *row, const rtt_camera_frame *frame, uint32_t bw,
                             uint32_t bh, rtt_hit *hits)
{
    bvh_camera_block block = {{frame->eye.x, frame->eye.y, frame->eye.z}, {frame->corner.x, frame->corner.y, frame->corner.z},
                              {frame->du.x, frame->du.y, frame->du.z}, {frame->dv.x, frame->dv.y, frame->dv.z}, 0, 0, 0, 0, false};
    rtt_hit part[PGRID_W * PGRID_H];
    for (uint32_t y0 = 0; y0 < PGRID_H; y0 += bh)
        for (uint32_t x0 = 0; x0 < PGRID_W; x0 += bw) {
            block.x0 = x0, block.y0 = y0;
            block.x1 = x0 + bw < PGRID_W ? x0 + bw : PGRID_W, block.y1 = y0 + bh < PGRID_H ? y0 + bh : PGRID_H;
            row->trace_camera(tree, &block, part, NULL);
            for (uint32_t y = y0; y < block.y1; y++)
                for (uint32_t x = x0; x < block.x1; x++)
                    hits[y * PGRID_W + x] = part[(y - y0) * (block.x1 - x0) + (x - x0)];
        }
}

/* Without back-face culling (the tree's solids left out) each pixel's hit
 * must be bvh-packet's on rtt_camera_ray's ray, bit for bit; with it (the
 * engine's tree: back faces of the solids the eye is outside dropped) the
 * hits must pass the brute force strictly (a front face's tie with a
 * dropped back face at one t is a hit within the tolerance). */
static void check_mft_camera(const rtt_scene *scene)
{
    rtt_engine *engine = bvh_engine_for(scene);
    const bvh_tree *tree = bvh_engine_tree(engine);
    bvh_tree plain = *tree; /* the same arrays, no solids: nothing culled */
    plain.solid = NULL, plain.solid_box = NULL, plain.solid_count = 0;
    const rtt_camera_frame frame = rtt_camera_frame_make(&scene->camera, PGRID_W, PGRID_H);
    rtt_ray rays[PGRID_W * PGRID_H];
    for (uint32_t y = 0; y < PGRID_H; y++)
        for (uint32_t x = 0; x < PGRID_W; x++) rays[y * PGRID_W + x] = rtt_camera_ray(&frame, x, y);
    rtt_hit want[PGRID_W * PGRID_H], got[PGRID_W * PGRID_H];
    bvh_kernel_find("bvh-packet", RTT_ISA_SSE4)->trace(tree, &(bvh_query){.rays = rays, .count = PGRID_W * PGRID_H,
                                                                          .hits = want});
    fuzz_oracle *oracle = tree->solid ? fuzz_oracle_create(scene, rays, PGRID_W * PGRID_H) : NULL;
    const bvh_kernel *row;
    for (uint32_t r = 0; (row = bvh_kernel_row_at(r)); r++) {
        if (!row->trace_camera || !rtt_isa_supported(row->isa)) continue;
        static const uint32_t blocks[2][2] = {{PGRID_W, PGRID_H}, {5, 3}};
        for (uint32_t b = 0; b < 2; b++) {
            const uint32_t bw = blocks[b][0], bh = blocks[b][1];
            trace_mft_camera(&plain, row, &frame, bw, bh, got);
            for (uint32_t i = 0; i < PGRID_W * PGRID_H; i++)
                if (memcmp(&got[i], &want[i], sizeof got[i]) != 0)
                    fuzz_fail("bvh-mft camera (%s, %ux%u blocks) pixel %u: prim %u t %a, bvh-packet prim %u t %a",
                              rtt_isa_name(row->isa), bw, bh, i, got[i].prim, (double)got[i].t, want[i].prim,
                              (double)want[i].t);
            if (!oracle) continue;
            trace_mft_camera(tree, row, &frame, bw, bh, got);
            pgrid_answers answers = {{&answers_vtable, scene}, got};
            char label[64];
            snprintf(label, sizeof label, "bvh-mft camera, back faces culled/%s %ux%u", rtt_isa_name(row->isa), bw, bh);
            fuzz_oracle_check(oracle, &answers.base, label, false);
        }
    }
    if (oracle) fuzz_oracle_free(oracle);
    rtt_engine_destroy(engine);
}

static bool all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* Step 5 for one light: hit points `pts` (count of them). */
static void check_shadow_frusta_light(const bvh_tree *tree, const rtt_light *light, const bvh_kernel *packet,
                                      const rtt_vec3 *pts, uint32_t count, float eps)
{
    bvh_shadow_sets sets = {.samples = 16};
    float xy[BVH_SHADOW_MAX_SAMPLES][2];
    for (uint32_t set = 0; set < RTT_INTERLEAVED_SETS; set++) {
        rtt_interleaved_coords(light, set, 16, xy);
        for (uint32_t k = 0; k < 16; k++) sets.x[set][k] = xy[k][0], sets.y[set][k] = xy[k][1];
        rtt_interleaved_bounds(light, set, 16, sets.lo[set], sets.hi[set]);
    }
    bvh_shadow_point points[MAX_RAYS + GRID * GRID];
    static rtt_ray rays[(MAX_RAYS + GRID * GRID) * 16];
    static uint8_t want[(MAX_RAYS + GRID * GRID) * 16];
    uint32_t index[(MAX_RAYS + GRID * GRID) * 16], n = 0;
    for (uint32_t i = 0; i < count; i++) { /* each point's rays as shader_proxy.c's shadow_segment makes them */
        const rtt_light_frame fr = rtt_light_sample_frame(light, pts[i]);
        points[i] = (bvh_shadow_point){{pts[i].x, pts[i].y, pts[i].z}, {fr.base.x, fr.base.y, fr.base.z},
                                       {fr.du.x, fr.du.y, fr.du.z}, {fr.dv.x, fr.dv.y, fr.dv.z}, i % 16};
        for (uint32_t k = 0; k < 16; k++) {
            const rtt_vec3 to = rtt_v3_sub(rtt_light_frame_point(&fr, sets.x[i % 16][k], sets.y[i % 16][k]), pts[i]);
            const float d = rtt_v3_length(to);
            if (!(d > 2.0f * eps)) continue;
            const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / d);
            rays[n] = (rtt_ray){{pts[i].x, pts[i].y, pts[i].z}, {dir.x, dir.y, dir.z}, eps, d - eps};
            index[n++] = i * 16 + k;
        }
    }
    packet->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = want});
    const bvh_shadow_kernel *row;
    uint32_t masks[MAX_RAYS + GRID * GRID];
    for (uint32_t r = 0; (row = bvh_shadow_kernel_row_at(r)); r++) {
        if (!rtt_isa_supported(row->isa)) continue;
        row->trace(tree, &(bvh_shadow_query){.points = points, .count = count, .sets = &sets, .epsilon = eps,
                                             .occluded = masks});
        for (uint32_t j = 0; j < n; j++)
            if ((masks[index[j] / 16] >> index[j] % 16 & 1u) != want[j])
                fuzz_fail("frusta:16 (%s) point %u sample %u: occluded %u, bvh-packet %u", rtt_isa_name(row->isa),
                          index[j] / 16, index[j] % 16, masks[index[j] / 16] >> index[j] % 16 & 1u, want[j]);
    }
    /* hard shadows: one ray per point to the light's centre, bounded from there */
    const float toward[3] = {light->position.x, light->position.y, light->position.z};
    n = 0;
    for (uint32_t i = 0; i < count; i++) {
        const rtt_vec3 to = rtt_v3_sub(light->position, pts[i]);
        const float d = rtt_v3_length(to);
        if (!(d > 2.0f * eps)) continue;
        const rtt_vec3 dir = rtt_v3_scale(to, 1.0f / d);
        rays[n++] = (rtt_ray){{pts[i].x, pts[i].y, pts[i].z}, {dir.x, dir.y, dir.z}, eps, d - eps};
    }
    packet->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = want});
    const bvh_kernel *mft;
    uint8_t got[MAX_RAYS + GRID * GRID];
    for (uint32_t r = 0; (mft = bvh_kernel_row_at(r)); r++) {
        if (strcmp(mft->name, "bvh-mft") != 0 || !rtt_isa_supported(mft->isa)) continue;
        mft->trace(tree, &(bvh_query){.rays = rays, .count = n, .occluded = got, .toward = toward});
        for (uint32_t j = 0; j < n; j++)
            if (got[j] != want[j])
                fuzz_fail("bvh-mft (%s) hard shadow ray %u toward the light: occluded %u, bvh-packet %u",
                          rtt_isa_name(mft->isa), j, got[j], want[j]);
    }
}

static void check_shadow_frusta(const rtt_scene *scene, const rtt_ray *rays, size_t ray_count, rtt_vec3 eye)
{
    rtt_engine *engine = bvh_engine_for(scene);
    const bvh_tree *tree = bvh_engine_tree(engine);
    rtt_hit hits[MAX_RAYS + GRID * GRID];
    rtt_engine_intersect(engine, rays, hits, ray_count);
    rtt_vec3 pts[MAX_RAYS + GRID * GRID];
    uint32_t count = 0;
    for (size_t i = 0; i < ray_count; i++) {
        if (hits[i].prim == RTT_MISS) continue;
        const rtt_ray *r = &rays[i];
        const rtt_vec3 p = rtt_v3(r->org[0] + hits[i].t * r->dir[0], r->org[1] + hits[i].t * r->dir[1],
                                  r->org[2] + hits[i].t * r->dir[2]);
        if (isfinite(p.x) && isfinite(p.y) && isfinite(p.z)) pts[count++] = p;
    }
    const rtt_vec3 extent = rtt_v3_sub(scene->bounds.hi, scene->bounds.lo);
    const float size = fmaxf(extent.x, fmaxf(extent.y, extent.z));
    const rtt_light sphere = {.type = RTT_LIGHT_SPHERE, .position = eye, .radius = 0.1f * size};
    const rtt_light quad = {.type = RTT_LIGHT_QUAD, .position = eye, .edge_u = {0.2f * size, 0.0f, 0.0f},
                            .edge_v = {0.0f, 0.05f * size, 0.15f * size}};
    const float eps = rtt_scene_ray_epsilon(scene);
    const bvh_kernel *packet = bvh_kernel_find("bvh-packet", RTT_ISA_SSE4);
    if (count && isfinite(size) && size > 0.0f) {
        check_shadow_frusta_light(tree, &sphere, packet, pts, count, eps);
        check_shadow_frusta_light(tree, &quad, packet, pts, count, eps);
    }
    rtt_engine_destroy(engine);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!rtt_builtin_engines_register(NULL)) fuzz_fail("cannot register the built-in engines");
    byte_reader in = { data, size, 0 };
    uint32_t triangle_count = 1 + next_byte(&in) % MAX_TRIANGLES;
    uint8_t mode = next_byte(&in);
    bool raw = mode & 1;
    float scale = scales[(mode >> 1) % 8];
    float offset = offsets[next_byte(&in) % 4];
    uint8_t depth_byte = next_byte(&in);
    uint8_t flags = next_byte(&in);
    float xyz[MAX_TRIANGLES * 9];
    decode_triangles(&in, xyz, triangle_count, raw, scale, offset);

    rtt_error err = { "" };
    rtt_scene *scene = rtt_scene_from_triangles(xyz, triangle_count, &err);
    bool finite = all_finite(xyz, (size_t)triangle_count * 9);
    if (!finite) {
        if (scene)
            fuzz_fail("rtt_scene_from_triangles accepted a non-finite vertex");
        if (!err.message[0] || strchr(err.message, '\n'))
            fuzz_fail("non-finite input refused without a one-line message");
        return 0;
    }
    if (!scene)
        fuzz_fail("rtt_scene_from_triangles refused finite input: %s", err.message);
    fuzz_check_scene(scene);
    if (flags & 16) weld_vertices(scene);

    rtt_ray rays[MAX_RAYS + GRID * GRID];
    size_t ray_count = 0;
    const rtt_vec3 eye = stored_point(scene, palette_point(&in, scale, offset));
    camera_grid(scene, eye, rays);
    ray_count = GRID * GRID;
    while (in.at < in.size && ray_count < MAX_RAYS + GRID * GRID)
        rays[ray_count++] = decode_ray(&in, scene, scale, offset);
    check_engines(scene, rays, ray_count, depth_byte, flags);
    check_pgrid(scene, eye, depth_byte);
    check_mft_camera(scene);
    check_shadow_frusta(scene, rays, ray_count, eye);
    rtt_scene_free(scene);
    return 0;
}

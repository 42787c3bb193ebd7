/* The perspective grid's eye rays (optimized/pgrid/) against the reference
 * engine and a double-precision brute force, at every instruction set this
 * CPU runs and at several cell sizes; every copy bit for bit equal to the
 * SSE4.1 one; every cell's depth and triangle buffers bit for bit a plain
 * Z-buffer's (no row spans, no hierarchical depth test); the renderer's
 * --accel pgrid images against the reference renderer's; bad cell sizes
 * refused.  demo.json's camera stands inside the
 * room, so its floor, walls and ceiling cross the eye's plane: the build's
 * near-plane clipping is checked there.
 *
 * Hits: the same prim as the reference, with t within 1e-5 (|t| + S) (S the
 * scene's extent seen from the eye).  A different prim (or a hit against a
 * miss) is accepted only as a tie: the double-precision test puts the ray
 * within 1e-4 (barycentric) of an edge of the triangle(s) involved, at the
 * same t; at most 1% of the pixels may be ties. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "engine_optimized.h"
#include "pgrid_eye.h"
#include "rtt/image.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "rtt/shade.h"
#include "test_fixtures_pgrid.h"
#include "test_isa.h"
#include "test_double_crossing.h"
#include "test_scenes_solids.h"
#include "test_tempdir.h"

#define EDGE_MARGIN 1e-4
#define MAX_TIE_SHARE 0.01

static float scene_extent(const rtt_scene *s)
{
    rtt_vec3 mid = rtt_v3_scale(rtt_v3_add(s->bounds.lo, s->bounds.hi), 0.5f);
    return rtt_v3_length(rtt_v3_sub(s->bounds.hi, s->bounds.lo)) + rtt_v3_length(rtt_v3_sub(mid, s->camera.eye));
}

/* Our hit against the reference's for one ray; returns 1 for a tie. */
static int check_hit(const rtt_scene *s, const rtt_ray *ray, const rtt_hit *ref, const rtt_hit *ours, float extent,
                     uint32_t pixel)
{
    const double tol = 1e-5 * (fabs((double)ref->t) + extent);
    if (ref->prim == ours->prim) {
        if (ref->prim != RTT_MISS && fabs((double)ref->t - ours->t) > tol)
            fail_msg("pixel %u prim %u: t %.9g, reference %.9g", pixel, ours->prim, ours->t, ref->t);
        return 0;
    }
    for (int k = 0; k < 2; k++) {
        const rtt_hit *h = k ? ours : ref;
        if (h->prim == RTT_MISS) continue;
        double t = INFINITY, inside = crossing(s, h->prim, ray, &t);
        bool other_hits = (k ? ref : ours)->prim != RTT_MISS;
        /* both hit: a tie at the same t, each (nearly) inside; one misses: the hit grazes an edge */
        if (other_hits ? inside < -EDGE_MARGIN || fabs(t - h->t) > tol : inside > EDGE_MARGIN)
            fail_msg("pixel %u: prim %u (t %.9g) against the reference's %u (t %.9g): not a tie (%g)", pixel,
                     ours->prim, ours->t, ref->prim, ref->t, inside);
    }
    if (ref->prim != RTT_MISS && ours->prim != RTT_MISS && fabs((double)ref->t - ours->t) > tol)
        fail_msg("pixel %u: tie at different t %.9g, %.9g", pixel, ours->t, ref->t);
    return 1;
}

/* One frame into hits (w x h records). */
static void trace_pgrid_into(const rtt_scene *s, const uint8_t *degenerate, const pgrid_kernel *k, uint32_t w,
                             uint32_t h, uint32_t cell, uint32_t threads, rtt_hit *hits)
{
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    pgrid_eye grid = {0};
    rtt_error err = {{0}};
    if (!pgrid_eye_trace_frame(&grid, k, s, degenerate, &frame, w, h, cell, threads, hits, NULL, &err))
        fail_msg("pgrid: %s", err.message);
    pgrid_eye_free(&grid);
}

/* ...into a new 64-byte aligned buffer (where the frame's rows of four
 * start on a line, they are streamed: pgrid_resolve_fn). */
static rtt_hit *trace_pgrid(const rtt_scene *s, const uint8_t *degenerate, const pgrid_kernel *k, uint32_t w,
                            uint32_t h, uint32_t cell, uint32_t threads)
{
    rtt_hit *hits = aligned_alloc(64, ((size_t)w * h * sizeof *hits + 63) & ~(size_t)63);
    assert_non_null(hits);
    trace_pgrid_into(s, degenerate, k, w, h, cell, threads, hits);
    return hits;
}

/* Every scene, size, cell and instruction set against the reference; 256
 * the cell pgrid_eye_cell_rule takes on a large L2 (here one cell larger
 * than the image). */
static void test_pgrid_hits_match_reference(void **state)
{
    (void)state;
    static const char *const scenes[] = {"demo.json", "mesh_obj.json", "mat_transparent.json",
                                         "shadow_thin_plate.json", "shadow_on_shadow.json"};
    static const uint32_t sizes[][2] = {{61, 47}, {128, 128}, {203, 97}};
    static const uint32_t cells[] = {4, 16, 0, 256};
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_non_null(ref);
        const float extent = scene_extent(s);
        for (size_t z = 0; z < sizeof sizes / sizeof sizes[0]; z++) {
            const uint32_t w = sizes[z][0], h = sizes[z][1];
            rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
            rtt_ray *rays = malloc((size_t)w * h * sizeof *rays);
            rtt_hit *expect = malloc((size_t)w * h * sizeof *expect);
            assert_non_null(rays);
            assert_non_null(expect);
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) rays[y * w + x] = rtt_camera_ray(&frame, x, y);
            rtt_engine_intersect(ref, rays, expect, (size_t)w * h);
            for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
                if (!isa_runs(isa)) continue;
                const pgrid_kernel *k = pgrid_kernel_find("pgrid", isa);
                assert_int_equal(k->isa, isa);
                for (size_t c = 0; c < sizeof cells / sizeof cells[0]; c++) {
                    rtt_hit *hits = trace_pgrid(s, NULL, k, w, h, cells[c], 2);
                    uint32_t ties = 0;
                    for (uint32_t i = 0; i < w * h; i++) ties += check_hit(s, &rays[i], &expect[i], &hits[i], extent, i);
                    if (ties > MAX_TIE_SHARE * w * h)
                        fail_msg("%s %ux%u cell %u %s: %u ties", scenes[sc], w, h, cells[c], rtt_isa_name(isa), ties);
                    free(hits);
                }
            }
            free(rays);
            free(expect);
        }
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

static int setup_scratch(void **state) { return scratch_create(state, "pgrid"); }

/* An indexed UV sphere (shared vertices: closed), its corners and
 * triangles (OFF's, vertices numbered from `base`) appended to the two
 * files, its winding reversed when `inverted`. */
enum { SPHERE_SEGMENTS = 24, SPHERE_RINGS = 12 };
enum { SPHERE_VERTICES = 2 + (SPHERE_RINGS - 1) * SPHERE_SEGMENTS, SPHERE_TRIANGLES = 2 * SPHERE_SEGMENTS * (SPHERE_RINGS - 1) };
static void off_sphere(FILE *corners, FILE *faces, uint32_t base, const double centre[3], double radius, double scale,
                       bool inverted)
{
    const double pi = 3.14159265358979323846;
    fprintf(corners, "%.9g %.9g %.9g\n", scale * centre[0], scale * (centre[1] + radius), scale * centre[2]);
    for (int r = 1; r < SPHERE_RINGS; r++)
        for (int k = 0; k < SPHERE_SEGMENTS; k++) {
            const double phi = pi * r / SPHERE_RINGS, theta = 2.0 * pi * k / SPHERE_SEGMENTS;
            fprintf(corners, "%.9g %.9g %.9g\n", scale * (centre[0] + radius * sin(phi) * cos(theta)),
                    scale * (centre[1] + radius * cos(phi)), scale * (centre[2] + radius * sin(phi) * sin(theta)));
        }
    fprintf(corners, "%.9g %.9g %.9g\n", scale * centre[0], scale * (centre[1] - radius), scale * centre[2]);
    const uint32_t south = SPHERE_VERTICES - 1;
#define RING(r, k) (1 + (uint32_t)(r) * SPHERE_SEGMENTS + (uint32_t)((k) % SPHERE_SEGMENTS))
    for (int k = 0; k < SPHERE_SEGMENTS; k++) {
        uint32_t tri[2 * SPHERE_RINGS][3], n = 0;
        tri[n][0] = 0, tri[n][1] = RING(0, k + 1), tri[n][2] = RING(0, k), n++;
        for (int r = 0; r + 1 < SPHERE_RINGS - 1; r++) {
            tri[n][0] = RING(r, k), tri[n][1] = RING(r, k + 1), tri[n][2] = RING(r + 1, k + 1), n++;
            tri[n][0] = RING(r, k), tri[n][1] = RING(r + 1, k + 1), tri[n][2] = RING(r + 1, k), n++;
        }
        tri[n][0] = RING(SPHERE_RINGS - 2, k), tri[n][1] = RING(SPHERE_RINGS - 2, k + 1), tri[n][2] = south, n++;
        for (uint32_t i = 0; i < n; i++)
            fprintf(faces, "3 %u %u %u\n", base + tri[i][0], base + tri[i][inverted ? 2 : 1], base + tri[i][inverted ? 1 : 2]);
    }
#undef RING
}

/* The back faces the grid of s's camera (96 x 80, cells of 16) drops, after
 * checking every instruction set's hits against the reference's. */
static uint32_t back_faces_checked(const rtt_scene *s)
{
    const uint32_t w = 96, h = 80;
    rtt_error err = {{0}};
    rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
    assert_non_null(ref);
    const rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    rtt_ray *rays = malloc((size_t)w * h * sizeof *rays);
    rtt_hit *expect = malloc((size_t)w * h * sizeof *expect);
    assert_true(rays && expect);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) rays[y * w + x] = rtt_camera_ray(&frame, x, y);
    rtt_engine_intersect(ref, rays, expect, (size_t)w * h);
    uint32_t seen = 0;
    for (uint32_t i = 0; i < w * h; i++) seen += expect[i].prim != RTT_MISS;
    assert_true(seen > w * h / 10);
    pgrid_eye grid = {0};
    assert_true(pgrid_eye_build(&grid, s, NULL, &frame, w, h, 16, &err));
    const uint32_t culled = grid.culled_count;
    pgrid_eye_free(&grid);
    const float extent = scene_extent(s);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        rtt_hit *hits = trace_pgrid(s, NULL, pgrid_kernel_find("pgrid", isa), w, h, 16, 2);
        uint32_t ties = 0;
        for (uint32_t i = 0; i < w * h; i++) ties += check_hit(s, &rays[i], &expect[i], &hits[i], extent, i);
        if (ties > MAX_TIE_SHARE * w * h) fail_msg("%s: %u ties", rtt_isa_name(isa), ties);
        free(hits);
    }
    free(rays);
    free(expect);
    rtt_engine_destroy(ref);
    return culled;
}

/* Back faces: one mesh of two parts, a sphere and a smaller one wound
 * inside out beside it (each part's own outward side must be used), at
 * scales 1 (the float test) and 1e15 and 1e-15 (the double path), seen from
 * outside both (back faces dropped) and from inside the big one (its box
 * holds the eye: none dropped), every instruction set against the
 * reference. */
static void test_back_faces_dropped_only_where_no_eye_ray_meets_them_first(void **state)
{
    static const double scales[] = {1.0, 1e15, 1e-15};
    for (size_t z = 0; z < sizeof scales / sizeof scales[0]; z++) {
        const char *path = scratch_path(state, "spheres.off");
        FILE *corners = tmpfile(), *faces = tmpfile(), *f = fopen(path, "w");
        assert_true(corners && faces && f);
        const double big[3] = {0.0, 0.0, 0.0}, small[3] = {2.2, 0.3, -0.4};
        off_sphere(corners, faces, 0, big, 1.0, scales[z], false);
        off_sphere(corners, faces, SPHERE_VERTICES, small, 0.6, scales[z], true);
        fprintf(f, "OFF\n%d %d 0\n", 2 * SPHERE_VERTICES, 2 * SPHERE_TRIANGLES);
        for (FILE *part = corners; part; part = part == corners ? faces : NULL) {
            rewind(part);
            for (int c; (c = fgetc(part)) != EOF;) fputc(c, f);
            fclose(part);
        }
        assert_int_equal(fclose(f), 0);
        rtt_error err = {{0}};
        rtt_scene *s = rtt_scene_load(path, NULL, &err);
        if (!s) fail_msg("%s: %s", path, err.message);
        assert_int_equal(s->mesh_count, 1);
        assert_true(s->meshes[0].closed);
        static const double eyes[][3] = {{0.6, 1.9, 4.5}, {3.5, -1.0, 2.0}, {0.1, 0.2, 0.3}};
        for (size_t e = 0; e < sizeof eyes / sizeof eyes[0]; e++) {
            const float k = (float)scales[z];
            s->camera = (rtt_camera){rtt_v3((float)eyes[e][0] * k, (float)eyes[e][1] * k, (float)eyes[e][2] * k),
                                     rtt_v3(1.0f * k, 0.0f, 0.0f), rtt_v3(0.0f, 1.0f, 0.0f), e == 2 ? 100.0f : 50.0f};
            const uint32_t culled = back_faces_checked(s);
            /* dropped from outside, kept from within the big sphere's box */
            if (e < 2)
                assert_true(culled > s->triangle_count / 4);
            else
                assert_int_equal(culled, 0);
        }
        rtt_scene_free(s);
    }
}

/* Back faces, mesh by mesh: two solid spheres (two meshes of one scene),
 * the eye inside the first one's box (which keeps both faces: the eye sees
 * its inner side) and outside the second's (whose back faces are dropped). */
static void test_back_faces_kept_for_the_mesh_whose_box_holds_the_eye(void **state)
{
    const char *path = scratch_path(state, "two_spheres.json");
    rtt_error err = {{0}};
    rtt_scene *s = two_spheres_scene(path, &err);
    if (!s) fail_msg("%s: not two closed spheres (%s)", path, err.message);
    /* the small sphere's back faces only: about half of its triangles */
    const uint32_t culled = back_faces_checked(s);
    assert_true(culled > s->meshes[1].triangle_count / 4);
    assert_true(culled < s->meshes[1].triangle_count);
    rtt_scene_free(s);
}

/* One cell as a plain Z-buffer would fill it: every pixel of every listed
 * triangle's rectangle, in list order, with the kernel's operations in its
 * order (pgrid_cell.c: w_e = (c_e + b_e fy) + a_e fx, inside when all three
 * are >= 0 or all <= 0, t_D = det / ((c_3 + b_3 fy) + a_3 fx), kept when
 * 0 < t_D < the kept one), no row spans and no hierarchical depth test. */
static void plain_z_buffer(const pgrid_eye *g, uint32_t cell, uint32_t lanes, float *depth, uint32_t *triangle)
{
    const uint32_t side = g->cell, X0 = (cell % g->cells_x) * side, Y0 = (cell / g->cells_x) * side;
    for (size_t i = 0; i < (size_t)side * side; i++) depth[i] = INFINITY, triangle[i] = PGRID_NO_TRIANGLE;
    for (uint32_t r = g->cell_first[cell]; r < g->cell_first[cell + 1]; r++) {
        const pgrid_triangle *t = &g->triangles[g->refs[r]];
        for (uint32_t y = t->y0 > Y0 ? t->y0 : Y0; y <= t->y1 && y < Y0 + side && y < g->height; y++)
            for (uint32_t x = t->x0 > X0 ? t->x0 : X0; x <= t->x1 && x < X0 + side && x < g->width; x++) {
                const float fx = (float)x + 0.5f, fy = (float)y + 0.5f;
                float w[4];
                for (int e = 0; e < 4; e++) w[e] = (t->c[e] + t->b[e] * fy) + t->a[e] * fx;
                const bool inside = (w[0] >= 0.0f && w[1] >= 0.0f && w[2] >= 0.0f) ||
                                    (w[0] <= 0.0f && w[1] <= 0.0f && w[2] <= 0.0f);
                const float tv = t->det / w[3];
                const size_t at = pgrid_cell_offset(side, lanes, x - X0, y - Y0);
                if (inside && tv > 0.0f && tv < depth[at]) depth[at] = tv, triangle[at] = g->refs[r];
            }
    }
}

/* The kernel's cell buffers (its row spans and hierarchical depth test
 * skip blocks) bit for bit those of the plain Z-buffer, every cell, at every
 * instruction set and several cell sizes, on scenes deep in overdraw: the
 * triangle soup (big triangles at random depths in random order), the demo
 * room and, when cached, a Quake III map seen from inside; and after the
 * cell's resolve, cleared again for the next. */
static void test_cell_buffers_equal_a_plain_z_buffer(void **state)
{
    (void)state;
    rtt_scene *scenes[3] = {NULL, load_scene("demo.json"), NULL};
    uint32_t seed = 5;
    scenes[0] = triangle_soup(&seed);
    char path[600];
    const char *home = getenv("HOME");
    snprintf(path, sizeof path, "%s/.cache/rtt-data/maps/czest3ctf.bsp", home ? home : "");
    rtt_error err = {{0}};
    scenes[2] = rtt_scene_load(path, NULL, &err);
    if (!scenes[2]) print_message("%s not cached (bench/fetch-scenes.sh): only the soup and the demo\n", path);
    static const uint32_t cells[] = {8, 32, 0, 256};
    for (int sc = 0; sc < 3 && scenes[sc]; sc++) {
        const uint32_t w = 160, h = 120;
        rtt_camera_frame frame = rtt_camera_frame_make(&scenes[sc]->camera, w, h);
        for (size_t c = 0; c < sizeof cells / sizeof cells[0]; c++) {
            pgrid_eye g = {0};
            g.threads = 1;
            assert_true(pgrid_eye_build(&g, scenes[sc], NULL, &frame, w, h, cells[c], &err));
            const size_t entries = (size_t)g.cell * g.cell;
            float *depth = malloc(entries * sizeof *depth);
            uint32_t *triangle = malloc(entries * sizeof *triangle);
            rtt_hit *cell_hits = malloc(entries * sizeof *cell_hits);
            pgrid_cell_buffers b;
            assert_true(depth && triangle && cell_hits && pgrid_cell_buffers_alloc(&b, g.cell));
            uint64_t won = 0;
            for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
                if (!isa_runs(isa)) continue;
                const pgrid_kernel *k = pgrid_kernel_find("pgrid", isa);
                for (uint32_t cell = 0; cell < pgrid_eye_cell_count(&g); cell++) {
                    plain_z_buffer(&g, cell, k->lanes, depth, triangle);
                    k->trace_cell(&g, cell, &b);
                    for (size_t i = 0; i < entries; i++) {
                        if (triangle[i] != b.triangle[i] || memcmp(&depth[i], &b.depth[i], sizeof(float)) != 0)
                            fail_msg("scene %d cell %u of %u px %s: entry %zu: triangle %u t %.9g, plain %u t %.9g",
                                     sc, cell, g.cell, rtt_isa_name(isa), i, b.triangle[i], (double)b.depth[i],
                                     triangle[i], (double)depth[i]);
                        won += triangle[i] != PGRID_NO_TRIANGLE;
                    }
                    /* the resolve leaves the buffers cleared for the next cell's trace */
                    k->resolve_cell(&g, cell, &b, cell_hits, g.cell, false);
                    for (size_t i = 0; i < entries; i++)
                        if (b.triangle[i] != PGRID_NO_TRIANGLE || b.depth[i] != INFINITY)
                            fail_msg("scene %d cell %u of %u px %s: entry %zu left %u t %.9g by the resolve", sc, cell,
                                     g.cell, rtt_isa_name(isa), i, b.triangle[i], (double)b.depth[i]);
                }
            }
            assert_true(won > 0);
            pgrid_cell_buffers_free(&b);
            free(cell_hits);
            free(depth);
            free(triangle);
            pgrid_eye_free(&g);
        }
        rtt_scene_free(scenes[sc]);
    }
}

/* Every copy gives the SSE4.1 copy's hits bit for bit, for any thread count, its rows streamed (a
 * 64-byte aligned buffer, rows of a multiple of four) or not. */
static void test_pgrid_isa_bit_identical(void **state)
{
    (void)state;
    rtt_scene *s = load_scene("demo.json");
    const uint32_t sizes[][2] = {{150, 90}, {152, 90}}; /* 152: every row of four starts on a line */
    for (size_t z = 0; z < 2; z++) {
        const uint32_t w = sizes[z][0], h = sizes[z][1];
        /* the SSE4.1 copy into a buffer 16 bytes off a line (plain stores everywhere) */
        rtt_hit *block = aligned_alloc(64, ((size_t)w * h * sizeof *block + 16 + 63) & ~(size_t)63), *base = block + 1;
        assert_non_null(block);
        trace_pgrid_into(s, NULL, pgrid_kernel_find("pgrid", RTT_ISA_SSE4), w, h, 32, 1, base);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            rtt_hit *hits = trace_pgrid(s, NULL, pgrid_kernel_find("pgrid", isa), w, h, 32, 2);
            assert_memory_equal(hits, base, (size_t)w * h * sizeof *hits);
            free(hits);
        }
        free(block);
    }
    rtt_scene_free(s);
}

/* Frames one after the other on one grid (its cell buffers kept from frame
 * to frame, left cleared by each cell's resolve, or made again for another
 * cell size or more threads) give a fresh grid's hits, bit for bit, at
 * every instruction set; 256 a cell larger than the image. */
static void test_pgrid_frames_on_one_grid_equal_fresh_ones(void **state)
{
    (void)state;
    rtt_scene *s = load_scene("demo.json");
    const uint32_t w = 152, h = 90, runs[][2] = {{32, 1}, {32, 1}, {32, 2}, {16, 2}, {256, 1}, {32, 2}, {0, 1}};
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
        if (!isa_runs(isa)) continue;
        const pgrid_kernel *k = pgrid_kernel_find("pgrid", isa);
        pgrid_eye grid = {0};
        rtt_error err = {{0}};
        rtt_hit *hits = aligned_alloc(64, (size_t)w * h * sizeof *hits);
        assert_non_null(hits);
        for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
            assert_true(pgrid_eye_trace_frame(&grid, k, s, NULL, &frame, w, h, runs[r][0], runs[r][1], hits, NULL, &err));
            rtt_hit *fresh = trace_pgrid(s, NULL, k, w, h, runs[r][0], runs[r][1]);
            if (memcmp(hits, fresh, (size_t)w * h * sizeof *hits) != 0)
                fail_msg("%s: frame %zu (cell %u, %u threads) on the kept grid differs from a fresh grid's",
                         rtt_isa_name(isa), r, runs[r][0], runs[r][1]);
            free(fresh);
        }
        free(hits);
        pgrid_eye_free(&grid);
    }
    rtt_scene_free(s);
}

/* The build on 1 and 3 threads (the set-up by chunks of 4096 triangles):
 * the same grid, byte for byte, on the bunny (75k triangles, when cached). */
static void test_pgrid_build_same_at_any_thread_count(void **state)
{
    (void)state;
    char path[600];
    const char *home = getenv("HOME");
    snprintf(path, sizeof path, "%s/.cache/rtt-data/meshes/bunny00.off", home ? home : "");
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_load(path, NULL, &err);
    if (!s) {
        print_message("%s not cached (bench/fetch-scenes.sh): skipped\n", path);
        skip();
    }
    const uint32_t w = 300, h = 200;
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, w, h);
    pgrid_eye one = {0}, three = {0};
    one.threads = 1, three.threads = 3;
    assert_true(pgrid_eye_build(&one, s, NULL, &frame, w, h, 32, &err));
    assert_true(pgrid_eye_build(&three, s, NULL, &frame, w, h, 32, &err));
    assert_true(one.triangle_count > 8192); /* more than two chunks */
    assert_true(three.culled_count > 0);    /* back faces dropped: three threads bin by chunks (bin_by_chunks) */
    assert_int_equal(one.triangle_count, three.triangle_count);
    assert_int_equal(one.near_count, three.near_count);
    assert_int_equal(one.ref_count, three.ref_count);
    /* each chunk's kept triangles at its slots (pgrid_eye) */
    uint32_t kept = 0;
    for (uint32_t c = 0; c * PGRID_SETUP_CHUNK < s->triangle_count; c++) {
        const uint32_t first = c * PGRID_SETUP_CHUNK, n = one.chunk_kept[PGRID_CHUNK_FIELDS * c];
        assert_int_equal(n, three.chunk_kept[PGRID_CHUNK_FIELDS * c]);
        assert_memory_equal(one.triangles + first, three.triangles + first, n * sizeof *one.triangles);
        assert_memory_equal(one.surfaces + first, three.surfaces + first, n * sizeof *one.surfaces);
        kept += n;
    }
    assert_int_equal(kept, one.triangle_count);
    assert_memory_equal(one.cell_first, three.cell_first, ((size_t)pgrid_eye_cell_count(&one) + 1) * sizeof(uint32_t));
    assert_memory_equal(one.refs, three.refs, one.ref_count * sizeof *one.refs);
    pgrid_eye_free(&one);
    pgrid_eye_free(&three);
    rtt_scene_free(s);
}

/* The cell rule: 256 when its buffers fit in a quarter of the L2; in half
 * of it only when 256 cuts the references to four fifths or fewer; never
 * with fewer than 4 big cells a thread.  bytes_per_pixel is chosen so that
 * a 256-pixel cell's buffers take an eighth of this machine's L2 (eighth),
 * between a quarter and a half of it (mid), more than half (3 mid). */
static void test_pgrid_cell_rule_by_references(void **state)
{
    (void)state;
    const size_t l2 = rtt_cpu_l2_bytes(), cell_pixels = 256u * 256u;
    const uint32_t mid = (uint32_t)(l2 * 3u / 8u / cell_pixels), eighth = (uint32_t)(l2 / 8u / cell_pixels);
    if (eighth == 0 || mid * cell_pixels <= l2 / 4u) {
        print_message("L2 of %zu bytes: too small to place a 256-pixel cell's bytes: skipped\n", l2);
        skip();
    }
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 1, eighth, 100, 100), 256);      /* a quarter: always */
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 1, mid, 100, 80), 256);          /* half, refs cut by a fifth */
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 1, mid, 100, 81), PGRID_EYE_CELL_DEFAULT);
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 1, 3u * mid, 100, 10), PGRID_EYE_CELL_DEFAULT); /* over half */
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 5, eighth, 100, 10), PGRID_EYE_CELL_DEFAULT);   /* 16 cells */
    assert_int_equal(pgrid_eye_cell_rule(1024, 1024, 4, eighth, 100, 10), 256);
}

/* A degenerate triangle never hits, even where it would cover the view. */
static void test_pgrid_skips_degenerate(void **state)
{
    (void)state;
    /* a big triangle in front of the default camera and a zero-area one nearer */
    const float xyz[] = {-5, -5, 0, 5, -5, 0, 0, 5, 0, -5, -5, 1, 5, 5, 1, 0, 0, 1};
    rtt_error err = {{0}};
    rtt_scene *s = rtt_scene_from_triangles(xyz, 2, &err);
    assert_non_null(s);
    assert_int_equal(s->degenerate_count, 1);
    rtt_engine_options opt;
    rtt_engine_options_default(&opt);
    opt.accel = RTT_ACCEL_PGRID;
    rtt_engine *e = rtt_optimized_engine_create(s, &opt, &err);
    assert_non_null(e);
    const uint8_t *degenerate = optimized_engine_degenerate(e);
    assert_non_null(degenerate);
    rtt_hit *hits = trace_pgrid(s, degenerate, pgrid_kernel_find("", RTT_ISA_SSE4), 16, 16, 8, 1);
    for (uint32_t i = 0; i < 256; i++) assert_true(hits[i].prim != 1u);
    free(hits);
    rtt_engine_destroy(e);
    rtt_scene_free(s);
}

static void test_pgrid_refuses_bad_cells(void **state)
{
    (void)state;
    rtt_scene *s = load_scene("mesh_obj.json");
    rtt_camera_frame frame = rtt_camera_frame_make(&s->camera, 32, 32);
    pgrid_eye grid = {0};
    rtt_error err = {{0}};
    assert_false(pgrid_eye_build(&grid, s, NULL, &frame, 32, 32, 6, &err));
    assert_non_null(strstr(err.message, "multiple of 4"));
    assert_false(pgrid_eye_build(&grid, s, NULL, &frame, 32, 32, PGRID_EYE_CELL_MAX + 4, &err));
    assert_false(pgrid_eye_build(&grid, s, NULL, &frame, PGRID_IMAGE_MAX + 1, 32, 0, &err));
    pgrid_eye_free(&grid);
    rtt_scene_free(s);
}

/* The renderer with --accel pgrid against the reference renderer (both
 * shade the same hits with the same formulas; shadows and secondary rays
 * go through the kd-tree). */
static void test_pgrid_render_matches_reference(void **state)
{
    (void)state;
    static const char *const scenes[] = {"demo.json", "mat_transparent.json", "light_sphere.json"};
    static const rtt_shadow_method shadows[] = {RTT_SHADOWS_NONE, RTT_SHADOWS_HARD};
    for (size_t sc = 0; sc < sizeof scenes / sizeof scenes[0]; sc++) {
        rtt_scene *s = load_scene(scenes[sc]);
        rtt_error err = {{0}};
        rtt_engine_options eo;
        rtt_engine_options_default(&eo);
        eo.accel = RTT_ACCEL_PGRID;
        rtt_engine *opt_engine = rtt_optimized_engine_create(s, &eo, &err);
        rtt_engine *ref = rtt_reference_engine_create(s, NULL, &err);
        assert_non_null(opt_engine);
        assert_non_null(ref);
        for (rtt_isa isa = TEST_ISA_FIRST; isa < RTT_ISA_COUNT; isa = isa_next(isa)) {
            if (!isa_runs(isa)) continue;
            for (size_t m = 0; m < 2; m++) {
                rtt_render_options ro;
                rtt_render_options_default(&ro);
                ro.width = 96, ro.height = 72, ro.threads = 2, ro.shadows = shadows[m];
                ro.engine.accel = RTT_ACCEL_PGRID;
                ro.engine.isa = isa;
                if (m) snprintf(ro.engine.traversal, sizeof ro.engine.traversal, "pgrid"); /* named or default */
                rtt_image *a = rtt_image_create(96, 72, 0, &err), *b = rtt_image_create(96, 72, 0, &err);
                assert_non_null(a);
                assert_non_null(b);
                if (!rtt_optimized_render(opt_engine, &ro, a, NULL, &err)) fail_msg("pgrid render: %s", err.message);
                ro.engine.accel = RTT_ACCEL_DEFAULT;
                ro.engine.isa = RTT_ISA_AUTO;
                ro.engine.traversal[0] = '\0';
                if (!rtt_reference_render(s, ref, &ro, b, NULL, &err)) fail_msg("reference: %s", err.message);
                rtt_image_metrics mt;
                assert_true(rtt_image_compare(a, b, &mt, &err));
                if (mt.rmse > 2e-3 || mt.share_over_1_255 > 0.005)
                    fail_msg("%s %s %s: RMSE %g, %.3f%% over 1/255", scenes[sc], rtt_shadow_method_name(shadows[m]),
                             rtt_isa_name(isa), mt.rmse, 100.0 * mt.share_over_1_255);
                rtt_image_free(a);
                rtt_image_free(b);
            }
        }
        rtt_engine_destroy(opt_engine);
        rtt_engine_destroy(ref);
        rtt_scene_free(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pgrid_hits_match_reference),
        cmocka_unit_test(test_pgrid_isa_bit_identical),
        cmocka_unit_test_setup_teardown(test_back_faces_dropped_only_where_no_eye_ray_meets_them_first, setup_scratch,
                                        remove_scratch),
        cmocka_unit_test_setup_teardown(test_back_faces_kept_for_the_mesh_whose_box_holds_the_eye, setup_scratch,
                                        remove_scratch),
        cmocka_unit_test(test_cell_buffers_equal_a_plain_z_buffer),
        cmocka_unit_test(test_pgrid_frames_on_one_grid_equal_fresh_ones),
        cmocka_unit_test(test_pgrid_build_same_at_any_thread_count),
        cmocka_unit_test(test_pgrid_cell_rule_by_references),
        cmocka_unit_test(test_pgrid_skips_degenerate),
        cmocka_unit_test(test_pgrid_refuses_bad_cells),
        cmocka_unit_test(test_pgrid_render_matches_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

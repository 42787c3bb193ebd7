/* Hunt & Mark 2008, sections 4 and 5.1: the perspective grid of the eye
 * rays, rebuilt every frame.  A 2D grid over the image with no depth
 * splits: cell (cx, cy) holds every triangle whose projected bounds meet
 * its cell-by-cell pixel square, but the back faces of the solids the eye
 * is outside (pgrid_eye.solids, below), in the frame's drawing order (the
 * global triangle order, or nearest first when no back face is dropped).  The eye
 * rays are never stored: a cell's rays are the pixel formula of
 * rtt_camera_ray (scene/shade.c), so a cell is processed like a tiled
 * Z-buffer, in object order (pgrid_cell.c).
 *
 * The triangle test is per triangle an edge function of the pixel centre
 * (fx, fy) = (px + 0.5, py + 0.5): with A, B, C the corners relative to the
 * eye and D(fx, fy) = corner + du fx + dv fy the unnormalised direction of
 * rtt_camera_frame,
 *
 *     w_A = (B x C) . D,  w_B = (C x A) . D,  w_C = (A x B) . D,
 *
 * each w_e = (c_e + b_e fy) + a_e fx with a_e = n_e . du, b_e = n_e . dv,
 * c_e = n_e . corner computed once per frame.  The ray through the pixel
 * hits the triangle when the three have one sign (zeros included).  Its
 * distance comes from the plane, not from the sum of the w_e (which
 * cancels: each w_e is the edge's length times the distance larger than
 * their sum): t_D = det / (N . D) along D, with N = (B - A) x (C - A) and
 * det = N . A, N . D evaluated like an edge function (index 3 of a, b, c).
 * Watertight on shared edges: the neighbour computes the shared edge's
 * normal as q x p = -(p x q) exactly, and every later operation negates
 * exactly with it, so a pixel centre is inside one of two triangles sharing
 * an edge, or on it and inside both.  The barycentrics u, v of vertices 1
 * and 2 are computed in world space from the hit point p = t_D D relative
 * to vertex 0 (u = (p - A) . m_u, v = (p - A) . m_v, pgrid_surface), so they
 * need no perspective correction: they never pass through perspective
 * space.  (The edge functions would give them as w_B / (N . D), but those
 * cancel: errors of 1e-3 on the demo scene's spheres against 1e-5.) */
#ifndef RTT_OPTIMIZED_PGRID_EYE_H
#define RTT_OPTIMIZED_PGRID_EYE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/error.h"
#include "rtt/shade.h"

#include "pgrid_light.h"
#include "pgrid_soft.h"
#include "solids.h"

#define PGRID_NO_TRIANGLE UINT32_MAX
/* The cell side in pixels when the caller gives none and the cache rule
 * (pgrid_eye_cell_rule) does not choose a larger one (bench/results/pgrid.md,
 * "Cell size": the sweeps on a 1 MiB and a 2 MiB L2 per core). */
#define PGRID_EYE_CELL_DEFAULT 128u
#define PGRID_EYE_CELL_MAX 512u
/* the build's set-up: scene triangles per task (pgrid_eye's triangle slots) */
#define PGRID_SETUP_CHUNK 4096u

/* One triangle set up for one frame (64 bytes: one cache line, read once
 * per pixel block of its rectangle; pixel indices in 16 bits, so images
 * are at most PGRID_IMAGE_MAX wide and high). */
typedef struct pgrid_triangle {
    float a[4], b[4], c[4];    /* edge functions of the edges opposite vertices 0, 1, 2; [3]: N . D */
    float det;                 /* N . A */
    uint32_t prim;             /* global triangle order */
    uint16_t x0, y0, x1, y1;   /* pixels whose centre may lie in its projection, inclusive */
} pgrid_triangle;
#define PGRID_IMAGE_MAX 65535u

/* What the hits of a triangle need beyond the test (48 bytes, read only
 * for the pixels it wins): vertex 0 relative to the eye and the two rows of
 * the barycentric map, m_u = (e2 x N) / |N|^2, m_v = (N x e1) / |N|^2. */
typedef struct pgrid_surface {
    float origin[3], m_u[3], m_v[3];
    uint32_t prim;             /* the triangle's, beside its map: the resolve reads one record per hit */
    float pad[2];
} pgrid_surface;
/* what the resolve reads of it, as floats: origin, m_u, m_v, prim */
#define PGRID_SURFACE_FLOATS 10
_Static_assert(sizeof(pgrid_surface) == 48, "pgrid_surface: three rows of 16 bytes");
_Static_assert(sizeof(pgrid_triangle) == 64, "pgrid_triangle is one cache line");

#define PGRID_CHUNK_FIELDS 5u

/* The grid of one frame.  Arrays grow and are kept from frame to frame. */
typedef struct pgrid_eye {
    uint32_t width, height, cell, cells_x, cells_y;
    rtt_camera_frame frame;
    /* The triangles whose rectangle is not empty, in global order, by
     * chunks of the scene's (PGRID_SETUP_CHUNK): chunk c's kept ones at
     * [c * PGRID_SETUP_CHUNK, + chunk_kept[PGRID_CHUNK_FIELDS c]), the rest of its slots
     * unused (left where the parallel set-up wrote them, not moved
     * together: that copy was a third of a mesh's serial build) */
    pgrid_triangle *triangles;
    pgrid_surface *surfaces;   /* the same triangles' barycentric maps, in the same slots */
    uint32_t triangle_count, triangle_capacity; /* count: how many kept, in all chunks */
    uint32_t *cell_first;      /* cells_x * cells_y + 1: cell c's references are refs[cell_first[c] ..) */
    uint32_t cell_capacity;
    uint32_t *refs;            /* indices into triangles */
    size_t ref_count, ref_capacity;
    uint32_t near_count;       /* triangles reaching in front of the near plane: every cell holds them */
    float inv_scale;           /* the build works on corners scaled by 1 / inv_scale (a power of two) */
    uint32_t threads;          /* the build's threads, set by the caller (0 or 1: the caller's alone) */
    /* set by the caller: with cell 0, the build takes pgrid_eye_cell_rule's
     * cell for cells keeping this many bytes a pixel, from its set-up's
     * references; 0: PGRID_EYE_CELL_DEFAULT */
    uint32_t cell_rule_bytes;
    uint32_t *chunk_kept;      /* the build's: per chunk of triangles (PGRID_CHUNK_FIELDS each), how many it
                                * kept, how many are near, how many it dropped as back faces, and its kept
                                * ones' references in cells of PGRID_EYE_CELL_DEFAULT and of twice that */
    uint32_t chunk_capacity;
    uint32_t *chunk_cells;     /* the build's: per chunk and cell, its references' count, then first slot */
    size_t chunk_cells_capacity;
    /* Back-face culling (solids.h): a triangle of a solid whose
     * mesh's box the eye is outside, with the eye on the inner side of its
     * plane by a margin, is dropped: an eye ray meets an entering face of
     * that solid first (or ties with one at a silhouette).  The solids are
     * the scene's last built for (worked out again when the scene, its
     * counts or the degenerate flags differ); mesh_culled is the frame's. */
    scene_solids solids;
    const rtt_scene *solids_scene;
    const uint8_t *solids_degenerate;
    uint32_t solids_triangles, solids_vertices, solids_meshes;
    uint8_t *mesh_culled;      /* per mesh: 1 when this frame drops its back faces */
    uint32_t culled_count;     /* back faces dropped this frame */
    /* the drawing order (pgrid_build.c, drawing_order): per kept triangle
     * its nearest corner's depth, the order (each cell's list follows it)
     * and its sort's keys */
    float *nearest;
    uint32_t *order;
    uint64_t *order_keys;
    uint32_t order_capacity;
    /* pgrid_eye_trace_frame's cell buffers, a set per thread, kept from
     * frame to frame (cleared, as the resolve leaves them) for cells of
     * frame_buffer_cell */
    struct pgrid_cell_buffers *frame_buffers;
    uint32_t frame_buffer_count, frame_buffer_cell;
} pgrid_eye;

/* Builds the grid of `frame` at width x height in cells of `cell` pixels
 * (a multiple of 4, 4 .. PGRID_EYE_CELL_MAX; 0 → the default) over the
 * triangles not flagged in `degenerate` (one byte per triangle, 1 = never
 * hits; NULL: none), the set-up on grid->threads (the same grid at any
 * count).  False (err filled) when out of memory. */
bool pgrid_eye_build(pgrid_eye *grid, const rtt_scene *scene, const uint8_t *degenerate,
                     const rtt_camera_frame *frame, uint32_t width, uint32_t height, uint32_t cell, rtt_error *err);
void pgrid_eye_free(pgrid_eye *grid);

static inline uint32_t pgrid_eye_cell_count(const pgrid_eye *grid) { return grid->cells_x * grid->cells_y; }

/* A cell's depth and triangle buffers, cell x cell entries each, in blocks
 * of 4 x (lanes / 4) pixels (one vector each, row-major blocks), the layout
 * of the kernel that fills them. */
static inline size_t pgrid_cell_offset(uint32_t cell, uint32_t lanes, uint32_t x, uint32_t y)
{
    const uint32_t block_h = lanes / 4u;
    return ((size_t)(y / block_h) * (cell / 4u) + x / 4u) * lanes + (y % block_h) * 4u + x % 4u;
}

/* One thread's buffers for the cell it traces: per pixel the closest t_D
 * and its triangle (pgrid_cell_offset's layout), per block the largest t_D
 * it keeps (the hierarchical depth test of pgrid_cell.c); sized for cells
 * of `cell` pixels at any width. */
typedef struct pgrid_cell_buffers {
    float *depth;           /* cell * cell */
    uint32_t *triangle;     /* cell * cell */
    float *block_max;       /* cell * cell / 4: a block per vector, 4 lanes or more */
} pgrid_cell_buffers;
/* Cleared (depth +inf, PGRID_NO_TRIANGLE), as the trace wants them and
 * the resolve leaves them; false (nothing held) when out of memory. */
bool pgrid_cell_buffers_alloc(pgrid_cell_buffers *b, uint32_t cell);
void pgrid_cell_buffers_free(pgrid_cell_buffers *b);
/* The grid's pgrid_eye_trace_frame buffers (pgrid_eye_free frees them too). */
void pgrid_eye_frame_buffers_free(pgrid_eye *grid);

/* The per-cell kernel (pgrid_cell.c, one copy per instruction set): fills
 * the buffers of cell `cell`, cleared, with the closest triangle per pixel
 * and its t_D (PGRID_NO_TRIANGLE and +inf where none). */
typedef void (*pgrid_cell_fn)(const pgrid_eye *grid, uint32_t cell, pgrid_cell_buffers *buffers);
/* ...and the hits of the cell's pixels from them: pixel (X0 + x, Y0 + y)
 * of the cell with corner (X0, Y0) into hits[y * stride + x]; t along
 * rtt_camera_ray's normalised direction, u, v, prim (a miss where none).
 * With `stream`, when hits and the stride are whole 64-byte lines, the
 * rows of 4 pixels are written with non-temporal stores (past the caches, without reading the
 * lines first): for a whole frame of hits, many times the caches, that no
 * one reads before it has left them; a tile about to be shaded wants
 * plain stores.  The buffers are left cleared for the next cell's trace:
 * each block as it is read, while its lines are in the cache (a clear at
 * the trace's start missed on every line: 5% of oa_dm4's frame). */
typedef void (*pgrid_resolve_fn)(const pgrid_eye *grid, uint32_t cell, pgrid_cell_buffers *buffers,
                                 rtt_hit *hits, size_t stride, bool stream);

/* The perspective grid's kernel descriptor table (pgrid_table.c): one row
 * per instruction set. */
typedef struct pgrid_kernel {
    const char *name;          /* what --traversal calls it */
    const char *implements;
    pgrid_cell_fn trace_cell;
    pgrid_resolve_fn resolve_cell;
    pgrid_occluded_fn shadow_occluded; /* --shadows pgrid: shadow rays through the light grids (pgrid_light.h) */
    pgrid_soft_occluded_fn soft_occluded; /* --shadows pgrid:N: the slice traverser (pgrid_soft.h) */
    pgrid_prints_fn light_prints;  /* the light grids' footprint stage (pgrid_light_prints.c), for pgrid_shadows.prints */
    uint32_t lanes;            /* pixels per packet: 16 (AVX-512), 8 (AVX2), 4 (SSE4.1) */
    rtt_isa isa;
} pgrid_kernel;

/* The row for `name` ("" → "pgrid") of the widest instruction set not
 * wider than `isa` (resolved) that this CPU runs; NULL for an unknown name. */
const pgrid_kernel *pgrid_kernel_find(const char *name, rtt_isa isa);
const char *pgrid_kernel_name_at(uint32_t i);
const pgrid_kernel *pgrid_kernel_row_at(uint32_t i);

/* The cell side for a frame of width x height on `threads` threads whose
 * cells keep `bytes_per_pixel` each in the cache while they are traced,
 * its kept triangles making refs_default references in cells of
 * PGRID_EYE_CELL_DEFAULT and refs_big in cells of twice that: the big cell
 * when the image has 4 of them a thread or more (the threads' balance) and
 * a cell's bytes fit in a quarter of the L2 (rtt_cpu_l2_bytes; the rest
 * for the triangle records and the surfaces the resolve reads), or in half
 * of it when the big cells cut the references by a fifth or more (a map's
 * large triangles set up again in every cell they straddle: 5-15% of
 * their frame on a 1 MiB L2, bench/results/pgrid.md, eighteenth session;
 * a mesh's small ones straddle few); else PGRID_EYE_CELL_DEFAULT.  A frame
 * whose hits are streamed keeps 8 bytes a pixel (depth, triangle); a tile
 * shaded next keeps its 16-byte hits too (24). */
uint32_t pgrid_eye_cell_rule(uint32_t width, uint32_t height, uint32_t threads, uint32_t bytes_per_pixel,
                             uint64_t refs_default, uint64_t refs_big);

/* One frame of eye rays alone (the bench and the tests): build, every cell
 * through `kernel` on `threads` threads, each pixel's hit into hits[py *
 * width + px], streamed (pgrid_resolve_fn: a whole frame of hits; give a
 * 64-byte aligned buffer to get it).  `cell` 0 takes pgrid_eye_cell_rule's
 * for streamed hits (grid->cell_rule_bytes 8).  build_seconds (may be NULL) gets the build's share. */
bool pgrid_eye_trace_frame(pgrid_eye *grid, const pgrid_kernel *kernel, const rtt_scene *scene,
                           const uint8_t *degenerate, const rtt_camera_frame *frame, uint32_t width,
                           uint32_t height, uint32_t cell, uint32_t threads, rtt_hit *hits, double *build_seconds,
                           rtt_error *err);

#endif

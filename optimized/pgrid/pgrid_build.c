/* Hunt & Mark 2008, section 4 and 5.1: the per-frame build of the eye
 * rays' perspective grid (pgrid_eye.h).  Each triangle is transformed to
 * the camera's perspective space (depth along the view axis, pixel-centre
 * coordinates), its projected bounds widened by a pixel and binned into
 * the cells they meet by a counting sort, so each cell lists its triangles
 * in the global order (ties then go to the smaller prim by keeping the
 * first of equal depths).
 *
 * Corners are taken relative to the eye and scaled by a power of two that
 * brings the scene's extent seen from the eye to about 1 (exact), so the
 * products of the edge functions neither underflow at 1e-20 nor overflow
 * at 1e20; t is scaled back when hits are resolved.
 *
 * The near plane, and what it trades against the paper: the paper clips
 * geometry to a near plane and loses what lies in front of it.  Here a
 * triangle with every corner beyond the near plane (depth >= z_near, a
 * 2^-20 fraction of the scene's extent seen from the eye) is binned by its
 * projected corners, which bound its projection exactly; one with every
 * corner behind the eye (depth < -z_near) is dropped, as no eye ray meets
 * it at t > 0; one in between is clipped to a plane that no eye ray
 * meets it in front of (from the distance of its plane, triangle_rect) and
 * binned by the clipped polygon; only one whose plane passes within about
 * z_near of the eye is kept in every cell (its projection is unbounded),
 * counted in near_count.  Exact for every scene.
 *
 * Speed: the set-up runs on the thread pool by chunks, four triangles at a
 * time in SSE4.1 where every corner lies beyond the near plane (setup_four:
 * the scalar functions' operations in their order, lane by lane, so the
 * grid is the same bit for bit), its records streamed past the cache on
 * more than one thread (setup_group); the binning's two passes by chunks
 * on the pool when the drawing order is the global one (bin_by_chunks),
 * else serial (by pieces of the sorted order on two threads was slower:
 * ctf_inyard's build 0.67 -> 0.77 ms). */
#include <immintrin.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "engine/threads.h"
#include "pgrid_eye.h"
#include "pgrid_sort.h"

static bool grow(void **array, size_t *capacity, size_t need, size_t element)
{
    if (need <= *capacity) return true;
    size_t cap = *capacity ? *capacity : 1024;
    while (cap < need) cap *= 2;
    void *p = aligned_alloc(64, (cap * element + 63) / 64 * 64);
    if (!p) return false;
    free(*array);
    *array = p;
    *capacity = cap;
    return true;
}

void pgrid_eye_free(pgrid_eye *grid)
{
    free(grid->triangles);
    free(grid->surfaces);
    free(grid->cell_first);
    free(grid->refs);
    free(grid->chunk_kept);
    free(grid->mesh_culled);
    free(grid->nearest);
    free(grid->order);
    free(grid->order_keys);
    scene_solids_free(&grid->solids);
    free(grid->chunk_cells);
    pgrid_eye_frame_buffers_free(grid);
    memset(grid, 0, sizeof *grid);
}

/* The pixel-centre coordinate range [lo, hi] of a projected extent, as
 * pixel indices 0 .. size-1; false when it misses the image.  The centre
 * of pixel p is p + 0.5; one pixel of margin covers the rounding of the
 * projection and of the triangle test. */
static inline float min_float(float a, float b) { return b < a ? b : a; }
static inline float max_float(float a, float b) { return b > a ? b : a; }

static bool pixel_range(float lo, float hi, uint32_t size, uint16_t *first, uint16_t *last)
{
    const float margin = 1.0f;
    float a = lo - margin - 0.5f, b = hi + margin - 0.5f;
    if (!(b >= 0.0f) || !(a <= (float)size - 1.0f)) return false; /* NaN is outside too */
    a = a < 0.0f ? 0.0f : ceilf(a);
    b = b > (float)size - 1.0f ? (float)size - 1.0f : floorf(b);
    if (a > b) return false;
    *first = (uint16_t)a;
    *last = (uint16_t)b;
    return true;
}

/* What the build needs of the frame: the view axis and the projection of
 * a point relative to the eye onto pixel-centre coordinates. */
typedef struct projection {
    rtt_vec3 forward, du, dv;
    float corner_du, corner_dv, inv_du2, inv_dv2;   /* corner . du, corner . dv, 1 / |du|^2, 1 / |dv|^2 */
    float corner_length;                            /* |corner|: 1 / the smallest cosine of an eye ray */
    float z_near;
    float scale;        /* a power of two bringing the scene's extent seen from the eye to about 1 */
} projection;

static projection projection_make(const rtt_camera_frame *f, const rtt_scene *scene)
{
    projection p;
    p.forward = rtt_v3_normalize(rtt_v3_cross(f->du, f->dv));
    p.du = f->du;
    p.dv = f->dv;
    p.corner_du = rtt_v3_dot(f->corner, f->du);
    p.corner_dv = rtt_v3_dot(f->corner, f->dv);
    p.inv_du2 = 1.0f / rtt_v3_dot(f->du, f->du);
    p.inv_dv2 = 1.0f / rtt_v3_dot(f->dv, f->dv);
    p.corner_length = rtt_v3_length(f->corner);
    rtt_vec3 lo = scene->bounds.lo, hi = scene->bounds.hi;
    float extent = rtt_v3_length(rtt_v3_sub(hi, lo)) +
                   rtt_v3_length(rtt_v3_sub(rtt_v3_scale(rtt_v3_add(lo, hi), 0.5f), f->eye));
    const bool usable = isfinite(extent) && extent > 0.0f;
    p.scale = usable ? ldexpf(1.0f, -ilogbf(extent)) : 1.0f;
    p.z_near = usable ? extent * p.scale * 0x1p-20f : 0x1p-100f;
    return p;
}

/* The edge functions of one triangle relative to the eye (pgrid_eye.h). */
static void triangle_setup(pgrid_triangle *t, pgrid_surface *surface, const rtt_camera_frame *f,
                           const rtt_vec3 rel[3])
{
    const rtt_vec3 e1 = rtt_v3_sub(rel[1], rel[0]), e2 = rtt_v3_sub(rel[2], rel[0]);
    const rtt_vec3 normal = rtt_v3_cross(e1, e2);
    const float inv_n2 = 1.0f / rtt_v3_dot(normal, normal);
    const rtt_vec3 m_u = rtt_v3_scale(rtt_v3_cross(e2, normal), inv_n2);
    const rtt_vec3 m_v = rtt_v3_scale(rtt_v3_cross(normal, e1), inv_n2);
    *surface = (pgrid_surface){{rel[0].x, rel[0].y, rel[0].z}, {m_u.x, m_u.y, m_u.z}, {m_v.x, m_v.y, m_v.z}, 0, {0}};
    for (int e = 0; e < 4; e++) {
        rtt_vec3 n = e < 3 ? rtt_v3_cross(rel[(e + 1) % 3], rel[(e + 2) % 3]) : normal;
        t->a[e] = rtt_v3_dot(n, f->du);
        t->b[e] = rtt_v3_dot(n, f->dv);
        t->c[e] = rtt_v3_dot(n, f->corner);
    }
    t->det = rtt_v3_dot(normal, rel[0]);
}

/* The pixel-centre bounds of points relative to the eye, all at depth
 * >= z_near (z their depths). */
static void project_bounds(const projection *p, const rtt_vec3 *rel, const float *z, int count, float box[4])
{
    box[0] = box[2] = INFINITY;
    box[1] = box[3] = -INFINITY;
    for (int i = 0; i < count; i++) {
        const float inv_z = 1.0f / z[i];
        float fx = (rtt_v3_dot(rel[i], p->du) * inv_z - p->corner_du) * p->inv_du2;
        float fy = (rtt_v3_dot(rel[i], p->dv) * inv_z - p->corner_dv) * p->inv_dv2;
        box[0] = min_float(box[0], fx);
        box[1] = max_float(box[1], fx);
        box[2] = min_float(box[2], fy);
        box[3] = max_float(box[3], fy);
    }
}

/* The triangle clipped to depth >= z_clip (Sutherland-Hodgman, one plane):
 * at most four corners. */
static int clip_near(float z_clip, const rtt_vec3 rel[3], const float z[3], rtt_vec3 out[4], float zout[4])
{
    int n = 0;
    for (int i = 0; i < 3; i++) {
        const int j = (i + 1) % 3;
        const bool in_i = z[i] >= z_clip, in_j = z[j] >= z_clip;
        if (in_i) out[n] = rel[i], zout[n++] = z[i];
        if (in_i != in_j) {
            const float s = (z_clip - z[i]) / (z[j] - z[i]);
            out[n] = rtt_v3_add(rel[i], rtt_v3_scale(rtt_v3_sub(rel[j], rel[i]), s));
            zout[n++] = z_clip; /* on the plane up to rounding: the bounds are widened for it */
        }
    }
    return n;
}

/* The pixel rectangle of a triangle; false when no eye ray can hit it. */
static bool triangle_rect(const projection *p, const rtt_vec3 rel[3], uint32_t width, uint32_t height,
                          pgrid_triangle *t, bool *near)
{
    float z[3], zmin = INFINITY, zmax = -INFINITY;
    for (int i = 0; i < 3; i++) {
        z[i] = rtt_v3_dot(rel[i], p->forward);
        zmin = min_float(zmin, z[i]);
        zmax = max_float(zmax, z[i]);
    }
    *near = false;
    if (zmax < -p->z_near) return false;
    float box[4];
    if (zmin >= p->z_near) {
        project_bounds(p, rel, z, 3, box);
    } else {
        /* Crossing the near plane.  Every point of the triangle's plane is
         * at least its distance h from the eye, and an eye ray's depth is
         * at least its length / |corner| (|corner| = 1 / the smallest cosine
         * of an eye ray with the view axis), so no eye ray meets the plane
         * at a depth below h / |corner|: the triangle clipped to half that
         * bounds every hit.  When that clip plane would lie nearer than
         * z_near, the triangle is kept in every cell. */
        const rtt_vec3 normal = rtt_v3_cross(rtt_v3_sub(rel[1], rel[0]), rtt_v3_sub(rel[2], rel[0]));
        const float h = fabsf(rtt_v3_dot(normal, rel[0])) / rtt_v3_length(normal);
        const float z_clip = 0.5f * h / p->corner_length;
        if (!(z_clip >= p->z_near && zmax > z_clip)) {
            *near = true;
            t->x0 = t->y0 = 0;
            t->x1 = (uint16_t)(width - 1);
            t->y1 = (uint16_t)(height - 1);
            return true;
        }
        rtt_vec3 clipped[4];
        float zc[4];
        const int n = clip_near(z_clip, rel, z, clipped, zc);
        project_bounds(p, clipped, zc, n, box);
        /* a crossing is off the plane by a few ulps of the corners' size:
         * over z_clip, 2^-18 of that in the projection, in pixels */
        float size = 0.0f;
        for (int i = 0; i < 3; i++) size = max_float(size, rtt_v3_length(rel[i]));
        const float widen = size / z_clip * 0x1p-18f * sqrtf(p->inv_du2 > p->inv_dv2 ? p->inv_du2 : p->inv_dv2);
        box[0] -= widen, box[1] += widen, box[2] -= widen, box[3] += widen;
    }
    return pixel_range(box[0], box[1], width, &t->x0, &t->x1) && pixel_range(box[2], box[3], height, &t->y0, &t->y1);
}

/* A pixel index's cell without a division: pixel indices are below 2^16 and
 * cells at most 2^9 pixels, so x * ceil(2^32 / cell) / 2^32 is off x / cell
 * by less than 2^-16 and floors to the quotient (the binning's two passes
 * divide every rectangle's four bounds). */
_Static_assert(PGRID_EYE_CELL_MAX <= 512u && PGRID_IMAGE_MAX < 65536u, "cell_of's bound: pixels < 2^16, cells <= 2^9");
static inline uint64_t cell_reciprocal(uint32_t cell) { return ((UINT64_C(1) << 32) + cell - 1) / cell; }
static inline uint32_t cell_of(uint32_t pixel, uint64_t reciprocal) { return (uint32_t)((pixel * reciprocal) >> 32); }

enum { SETUP_CHUNK = PGRID_SETUP_CHUNK };

/* ---- four triangles at once (SSE4.1, the baseline) ----
 * The common case, every corner beyond the near plane, for four triangles
 * in the lanes of one vector: the same operations in the same order as
 * triangle_rect's projection and triangle_setup, lane by lane, so the
 * same bits (min_float(a, b) is _mm_min_ps(b, a), NaN included); a lane
 * crossing the near plane or behind the eye takes the scalar path. */
typedef struct v3x4 {
    __m128 x, y, z;
} v3x4;

static inline v3x4 v4_sub(v3x4 a, v3x4 b) { return (v3x4){_mm_sub_ps(a.x, b.x), _mm_sub_ps(a.y, b.y), _mm_sub_ps(a.z, b.z)}; }
static inline v3x4 v4_scale(v3x4 a, __m128 s) { return (v3x4){_mm_mul_ps(a.x, s), _mm_mul_ps(a.y, s), _mm_mul_ps(a.z, s)}; }
static inline v3x4 v4_splat(rtt_vec3 a) { return (v3x4){_mm_set1_ps(a.x), _mm_set1_ps(a.y), _mm_set1_ps(a.z)}; }
static inline __m128 v4_dot(v3x4 a, v3x4 b)
{
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(a.x, b.x), _mm_mul_ps(a.y, b.y)), _mm_mul_ps(a.z, b.z));
}
static inline v3x4 v4_cross(v3x4 a, v3x4 b)
{
    return (v3x4){_mm_sub_ps(_mm_mul_ps(a.y, b.z), _mm_mul_ps(a.z, b.y)), _mm_sub_ps(_mm_mul_ps(a.z, b.x), _mm_mul_ps(a.x, b.z)),
                  _mm_sub_ps(_mm_mul_ps(a.x, b.y), _mm_mul_ps(a.y, b.x))};
}

/* What triangle_setup writes, for four triangles (row k, lane i). */
typedef struct setup4 {
    _Alignas(16) float a[4][4], b[4][4], c[4][4], det[4];
    _Alignas(16) float origin[3][4], m_u[3][4], m_v[3][4];
    _Alignas(16) float box[4][4];   /* the projected corners' fx lo, hi, fy lo, hi */
    _Alignas(16) float zmin[4], zmax[4];
} setup4;

static void setup_four(const projection *p, const rtt_camera_frame *f, const v3x4 rel[3], setup4 *out)
{
    /* triangle_rect: depths, and the projection of the corners */
    __m128 zmin = _mm_set1_ps(INFINITY), zmax = _mm_set1_ps(-INFINITY), z[3];
    const v3x4 forward = v4_splat(p->forward), du = v4_splat(p->du), dv = v4_splat(p->dv);
    for (int k = 0; k < 3; k++) {
        z[k] = v4_dot(rel[k], forward);
        zmin = _mm_min_ps(z[k], zmin);
        zmax = _mm_max_ps(z[k], zmax);
    }
    _mm_store_ps(out->zmin, zmin);
    _mm_store_ps(out->zmax, zmax);
    __m128 box0 = _mm_set1_ps(INFINITY), box1 = _mm_set1_ps(-INFINITY), box2 = box0, box3 = box1;
    const __m128 corner_du = _mm_set1_ps(p->corner_du), corner_dv = _mm_set1_ps(p->corner_dv);
    const __m128 inv_du2 = _mm_set1_ps(p->inv_du2), inv_dv2 = _mm_set1_ps(p->inv_dv2);
    for (int k = 0; k < 3; k++) {
        const __m128 inv_z = _mm_div_ps(_mm_set1_ps(1.0f), z[k]);
        const __m128 fx = _mm_mul_ps(_mm_sub_ps(_mm_mul_ps(v4_dot(rel[k], du), inv_z), corner_du), inv_du2);
        const __m128 fy = _mm_mul_ps(_mm_sub_ps(_mm_mul_ps(v4_dot(rel[k], dv), inv_z), corner_dv), inv_dv2);
        box0 = _mm_min_ps(fx, box0);
        box1 = _mm_max_ps(fx, box1);
        box2 = _mm_min_ps(fy, box2);
        box3 = _mm_max_ps(fy, box3);
    }
    _mm_store_ps(out->box[0], box0);
    _mm_store_ps(out->box[1], box1);
    _mm_store_ps(out->box[2], box2);
    _mm_store_ps(out->box[3], box3);
    /* triangle_setup */
    const v3x4 e1 = v4_sub(rel[1], rel[0]), e2 = v4_sub(rel[2], rel[0]);
    const v3x4 normal = v4_cross(e1, e2);
    const __m128 inv_n2 = _mm_div_ps(_mm_set1_ps(1.0f), v4_dot(normal, normal));
    const v3x4 m_u = v4_scale(v4_cross(e2, normal), inv_n2), m_v = v4_scale(v4_cross(normal, e1), inv_n2);
    _mm_store_ps(out->origin[0], rel[0].x);
    _mm_store_ps(out->origin[1], rel[0].y);
    _mm_store_ps(out->origin[2], rel[0].z);
    _mm_store_ps(out->m_u[0], m_u.x);
    _mm_store_ps(out->m_u[1], m_u.y);
    _mm_store_ps(out->m_u[2], m_u.z);
    _mm_store_ps(out->m_v[0], m_v.x);
    _mm_store_ps(out->m_v[1], m_v.y);
    _mm_store_ps(out->m_v[2], m_v.z);
    const v3x4 fdu = v4_splat(f->du), fdv = v4_splat(f->dv), fcorner = v4_splat(f->corner);
    for (int e = 0; e < 4; e++) {
        const v3x4 n = e < 3 ? v4_cross(rel[(e + 1) % 3], rel[(e + 2) % 3]) : normal;
        _mm_store_ps(out->a[e], v4_dot(n, fdu));
        _mm_store_ps(out->b[e], v4_dot(n, fdv));
        _mm_store_ps(out->c[e], v4_dot(n, fcorner));
    }
    _mm_store_ps(out->det, v4_dot(normal, rel[0]));
}

/* What the set-up's tasks share. */
typedef struct setup_job {
    pgrid_eye *g;
    const rtt_scene *scene;
    const uint8_t *degenerate;
    const rtt_camera_frame *frame;
    projection p;
    /* the solids' outward sides per triangle and, per mesh, whether this
     * frame drops its back faces (the eye outside its box); outward NULL:
     * no back face is dropped this frame */
    const int8_t *outward;
    const uint8_t *mesh_culled;
    bool stream;            /* the records streamed: the set-up runs on more than one thread (setup_group) */
} setup_job;

/* ---- back faces ----
 * A triangle of a solid (pgrid_eye.h) is dropped when the eye lies on the
 * inner side of its plane: s det > 0 for det = ((B - A) x (C - A)) . (A - E)
 * and s its outward side, by a margin that covers det's rounding.  From the
 * float corners, e1 = B - A, e2 = C - A, w = A - E and det each carry a
 * relative error of 2^-24 per operation; the cross product and the dot then
 * err by at most about 17 2^-24 |e1| |e2| |w| < 2^-19 |e1| |e2| |w|, so
 * s det > 2^-16 |e1| |e2| |w| (compared squared: det^2 > 2^-32 |e1|^2
 * |e2|^2 |w|^2) has the exact sign.  Those squares stay normal floats while
 * each lies in [2^-30, 2^30]; a triangle outside that range is decided in
 * double (margin 2^-40: double's own rounding is 2^-29 times float's). */
static bool facing_away1(const rtt_vec3 c[3], rtt_vec3 eye, int8_t side)
{
    double e1[3], e2[3], w[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)rtt_v3_get(c[1], a) - rtt_v3_get(c[0], a);
        e2[a] = (double)rtt_v3_get(c[2], a) - rtt_v3_get(c[0], a);
        w[a] = (double)rtt_v3_get(c[0], a) - rtt_v3_get(eye, a);
    }
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double det = (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) * side;
    const double bound = (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]) * (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]) *
                         (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    return det > 0.0 && det * det > 0x1p-80 * bound && isfinite(bound);
}

/* The lanes of four triangles (corners c, one per lane; lane l's also in
 * tri[l]; outward sides in `side`, 0: never) that face away from the eye;
 * the lanes whose squares leave float's safe range are decided by
 * facing_away1. */
static uint32_t facing_away4(const v3x4 c[3], const rtt_vec3 (*tri)[3], rtt_vec3 eye, const int8_t side[4], uint32_t n)
{
    const v3x4 e1 = v4_sub(c[1], c[0]), e2 = v4_sub(c[2], c[0]), w = v4_sub(c[0], v4_splat(eye));
    const __m128 sign = _mm_setr_ps(side[0], side[1], side[2], side[3]);
    const __m128 det = _mm_mul_ps(v4_dot(v4_cross(e1, e2), w), sign);
    const __m128 a = v4_dot(e1, e1), b = v4_dot(e2, e2), q = v4_dot(w, w);
    const __m128 lo = _mm_set1_ps(0x1p-30f), hi = _mm_set1_ps(0x1p30f);
    const __m128 safe = _mm_and_ps(_mm_and_ps(_mm_and_ps(_mm_cmpge_ps(a, lo), _mm_cmple_ps(a, hi)),
                                              _mm_and_ps(_mm_cmpge_ps(b, lo), _mm_cmple_ps(b, hi))),
                                   _mm_and_ps(_mm_cmpge_ps(q, lo), _mm_cmple_ps(q, hi)));
    const __m128 away = _mm_and_ps(_mm_cmpgt_ps(det, _mm_setzero_ps()),
                                   _mm_cmpgt_ps(_mm_mul_ps(det, det),
                                                _mm_mul_ps(_mm_set1_ps(0x1p-32f), _mm_mul_ps(_mm_mul_ps(a, b), q))));
    const uint32_t lanes = (1u << n) - 1u, sided = lanes & (uint32_t)_mm_movemask_ps(_mm_cmpneq_ps(sign, _mm_setzero_ps()));
    uint32_t result = sided & (uint32_t)_mm_movemask_ps(_mm_and_ps(safe, away));
    for (uint32_t odd = sided & ~(uint32_t)_mm_movemask_ps(safe); odd; odd &= odd - 1) {
        const uint32_t l = (uint32_t)__builtin_ctz(odd);
        if (facing_away1(tri[l], eye, side[l])) result |= 1u << l;
    }
    return result;
}

/* Four triangles' corners (tri[l], one per lane) as vectors, put together
 * in registers: no vector load of scalar stores. */
static inline void corners_of(const rtt_vec3 (*tri)[3], v3x4 corners[3])
{
    for (int k = 0; k < 3; k++)
        corners[k] = (v3x4){_mm_setr_ps(tri[0][k].x, tri[1][k].x, tri[2][k].x, tri[3][k].x),
                            _mm_setr_ps(tri[0][k].y, tri[1][k].y, tri[2][k].y, tri[3][k].y),
                            _mm_setr_ps(tri[0][k].z, tri[1][k].z, tri[2][k].z, tri[3][k].z)};
}

/* A kept triangle's references (pixel rectangle x0..x1, y0..y1) in cells
 * of PGRID_EYE_CELL_DEFAULT (refs[0]) and of twice that (refs[1]), for
 * the cell rule (pgrid_eye_cell_rule). */
static inline void refs_in_cells(uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1, uint32_t refs[2])
{
    const uint32_t small = PGRID_EYE_CELL_DEFAULT, big = 2u * PGRID_EYE_CELL_DEFAULT;
    refs[0] += (x1 / small - x0 / small + 1u) * (y1 / small - y0 / small + 1u);
    refs[1] += (x1 / big - x0 / big + 1u) * (y1 / big - y0 / big + 1u);
}

/* The four lanes of rows r[0..3] (lane-major: r[i][l]) as four rows
 * (r[l] = (r0[l], r1[l], r2[l], r3[l])): records written whole. */
static inline void lanes_to_rows(__m128 r[4])
{
    _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
}
_Static_assert(offsetof(pgrid_triangle, a) == 0 && offsetof(pgrid_triangle, b) == 16 &&
                   offsetof(pgrid_triangle, c) == 32 && offsetof(pgrid_triangle, det) == 48 &&
                   offsetof(pgrid_triangle, prim) == 52 && offsetof(pgrid_triangle, x0) == 56 &&
                   offsetof(pgrid_triangle, y0) == 58 && offsetof(pgrid_triangle, x1) == 60 &&
                   offsetof(pgrid_triangle, y1) == 62,
               "setup_group writes pgrid_triangle as rows a, b, c and det, prim, x0 y0, x1 y1");
_Static_assert(offsetof(pgrid_surface, origin) == 0 && offsetof(pgrid_surface, m_u) == 12 &&
                   offsetof(pgrid_surface, m_v) == 24 && offsetof(pgrid_surface, prim) == 36,
               "setup_group writes pgrid_surface as three rows");

/* Up to four triangles (prim, their corners tri) transformed, clipped and
 * set up, the kept ones written from slot *kept on, the common lanes'
 * records as whole 16-byte rows.  Streamed (non-temporal) when the set-up
 * runs on more than one thread: the slots' lines were last read by the
 * other core, in the frame before's cells, and a plain store's ownership
 * request for each took as long as the set-up (the same set-up run twice
 * in one frame took half as long the second time: bench/results/pgrid.md,
 * eighteenth session); the caller fences.  On one thread they are stored
 * (still in this core's cache for the binning and the cells). */
static inline void put_row(void *record, size_t offset, __m128 row, bool stream)
{
    float *to = (float *)((char *)record + offset); /* the record's bytes, not one member's array */
    if (stream)
        _mm_stream_ps(to, row);
    else
        _mm_store_ps(to, row);
}

static void setup_group(const setup_job *job, const uint32_t prim[4], const rtt_vec3 (*tri)[3], uint32_t n,
                        uint32_t *kept, uint32_t *near_count, uint32_t refs[2])
{
    pgrid_eye *g = job->g;
    const v3x4 eye = v4_splat(job->frame->eye);
    const __m128 scale = _mm_set1_ps(job->p.scale);
    /* the corners, a triangle per lane (lanes past n zero) */
    v3x4 rel[3];
    corners_of(tri, rel);
    for (int k = 0; k < 3; k++) rel[k] = v4_scale(v4_sub(rel[k], eye), scale);
    setup4 four;
    setup_four(&job->p, job->frame, rel, &four);
    /* each lane's pgrid_triangle rows a, b, c and pgrid_surface's three rows */
    __m128 ta[4], tb[4], tc[4], s0[4], s1[4], s2[4];
    for (int e = 0; e < 4; e++)
        ta[e] = _mm_load_ps(four.a[e]), tb[e] = _mm_load_ps(four.b[e]), tc[e] = _mm_load_ps(four.c[e]);
    s0[0] = _mm_load_ps(four.origin[0]), s0[1] = _mm_load_ps(four.origin[1]), s0[2] = _mm_load_ps(four.origin[2]);
    s0[3] = _mm_load_ps(four.m_u[0]);
    s1[0] = _mm_load_ps(four.m_u[1]), s1[1] = _mm_load_ps(four.m_u[2]), s1[2] = _mm_load_ps(four.m_v[0]);
    s1[3] = _mm_load_ps(four.m_v[1]);
    s2[0] = _mm_load_ps(four.m_v[2]), s2[1] = _mm_castsi128_ps(_mm_setr_epi32((int)prim[0], (int)prim[1], (int)prim[2],
                                                                               (int)prim[3]));
    s2[2] = s2[3] = _mm_setzero_ps(); /* the surface's pad */
    lanes_to_rows(ta), lanes_to_rows(tb), lanes_to_rows(tc), lanes_to_rows(s0), lanes_to_rows(s1), lanes_to_rows(s2);
    for (uint32_t l = 0; l < n; l++) {
        pgrid_triangle *t = &g->triangles[*kept];
        pgrid_surface *sf = &g->surfaces[*kept];
        if (four.zmin[l] >= job->p.z_near) {
            /* beyond the near plane: the vector lane's projection and set-up */
            uint16_t x0, x1, y0, y1;
            if (!pixel_range(four.box[0][l], four.box[1][l], g->width, &x0, &x1) ||
                !pixel_range(four.box[2][l], four.box[3][l], g->height, &y0, &y1))
                continue;
            float det = four.det[l];
            int32_t det_bits;
            memcpy(&det_bits, &det, sizeof det_bits);
            const __m128 last = _mm_castsi128_ps(_mm_setr_epi32(det_bits, (int)prim[l], (int)(x0 | (uint32_t)y0 << 16),
                                                                (int)(x1 | (uint32_t)y1 << 16)));
            refs_in_cells(x0, x1, y0, y1, refs);
            const bool stream = job->stream;
            put_row(t, 0, ta[l], stream), put_row(t, 16, tb[l], stream), put_row(t, 32, tc[l], stream);
            put_row(t, 48, last, stream);
            put_row(sf, 0, s0[l], stream), put_row(sf, 16, s1[l], stream), put_row(sf, 32, s2[l], stream);
            g->nearest[*kept] = four.zmin[l];
        } else {
            /* behind the eye or crossing the near plane: the scalar path */
            rtt_vec3 r[3];
            for (int k = 0; k < 3; k++) r[k] = rtt_v3_scale(rtt_v3_sub(tri[l][k], job->frame->eye), job->p.scale);
            bool near;
            if (!triangle_rect(&job->p, r, g->width, g->height, t, &near)) continue;
            refs_in_cells(t->x0, t->x1, t->y0, t->y1, refs);
            triangle_setup(t, sf, job->frame, r);
            *near_count += near;
            float nearest = INFINITY;
            for (int k = 0; k < 3; k++) nearest = min_float(nearest, rtt_v3_dot(r[k], job->p.forward));
            g->nearest[*kept] = nearest;
            t->prim = sf->prim = prim[l];
        }
        (*kept)++;
    }
}

/* Task: the triangles of chunk `task` transformed, clipped and set up, the
 * kept ones packed from the chunk's first slot in global order; the
 * chunk's kept, near and dropped counts and its references in cells of
 * two sizes in chunk_kept[PGRID_CHUNK_FIELDS task ..].
 * The back faces are found four at a time first and the rest gathered
 * into groups of four for the set-up, so a dropped face costs no set-up
 * (a solid seen from outside drops about half its triangles). */
static void setup_chunk(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    const setup_job *job = context;
    const rtt_scene *scene = job->scene;
    const uint32_t first = task * SETUP_CHUNK,
                   end = first + SETUP_CHUNK < scene->triangle_count ? first + SETUP_CHUNK : scene->triangle_count;
    uint32_t kept = first, near_count = 0, culled = 0, refs[2] = {0, 0};
    uint32_t group_prim[4], grouped = 0;
    rtt_vec3 group_tri[4][3] = {{{0}}};
    for (uint32_t i = first; i < end;) {
        /* the next four triangles not flagged degenerate */
        uint32_t prim[4], n = 0;
        for (; i < end && n < 4; i++)
            if (!job->degenerate || !job->degenerate[i]) prim[n++] = i;
        if (n == 0) break;
        rtt_vec3 tri[4][3] = {{{0}}};
        for (uint32_t l = 0; l < n; l++) rtt_scene_triangle(scene, prim[l], tri[l]);
        uint32_t away = 0;
        if (job->outward) {
            int8_t side[4] = {0, 0, 0, 0};
            for (uint32_t l = 0; l < n; l++)
                side[l] = job->mesh_culled[scene->triangle_mesh[prim[l]]] ? job->outward[prim[l]] : 0;
            if (side[0] | side[1] | side[2] | side[3]) {
                v3x4 corners[3];
                corners_of((const rtt_vec3(*)[3])tri, corners);
                away = facing_away4(corners, (const rtt_vec3(*)[3])tri, job->frame->eye, side, n);
            }
        }
        if (!away && !grouped) { /* the common case without culling: the four as they are */
            setup_group(job, prim, (const rtt_vec3(*)[3])tri, n, &kept, &near_count, refs);
            continue;
        }
        for (uint32_t l = 0; l < n; l++) {
            if (away >> l & 1u) {
                culled++;
                continue;
            }
            group_prim[grouped] = prim[l];
            memcpy(group_tri[grouped], tri[l], sizeof group_tri[0]);
            if (++grouped == 4) {
                setup_group(job, group_prim, (const rtt_vec3(*)[3])group_tri, 4, &kept, &near_count, refs);
                grouped = 0;
            }
        }
    }
    if (grouped) {
        for (uint32_t l = grouped; l < 4; l++) memset(group_tri[l], 0, sizeof group_tri[0]); /* lanes past n zero */
        setup_group(job, group_prim, (const rtt_vec3(*)[3])group_tri, grouped, &kept, &near_count, refs);
    }
    if (job->stream) _mm_sfence(); /* setup_group's streamed records before the chunk is done */
    uint32_t *counts = job->g->chunk_kept + (size_t)PGRID_CHUNK_FIELDS * task;
    counts[0] = kept - first, counts[1] = near_count, counts[2] = culled, counts[3] = refs[0], counts[4] = refs[1];
}

/* The end of chunk c's kept slots (pgrid_eye: they start at c * SETUP_CHUNK). */
static inline uint32_t chunk_end(const pgrid_eye *g, uint32_t c)
{
    return c * SETUP_CHUNK + g->chunk_kept[PGRID_CHUNK_FIELDS * c];
}

/* The frame's side of the culling: the scene's solids (worked out once per
 * scene) and the meshes whose box the eye is outside (g->mesh_culled);
 * outward NULL when no triangle can be dropped.  False when out of memory. */
static bool frame_outward(pgrid_eye *g, const rtt_scene *scene, const uint8_t *degenerate, rtt_vec3 eye,
                          const int8_t **outward)
{
    *outward = NULL;
    if (g->solids_scene != scene || g->solids_degenerate != degenerate || g->solids_triangles != scene->triangle_count ||
        g->solids_vertices != scene->vertex_count || g->solids_meshes != scene->mesh_count) {
        scene_solids_free(&g->solids);
        free(g->mesh_culled);
        g->mesh_culled = calloc((size_t)scene->mesh_count + 1, 1);
        g->solids_scene = NULL;
        if (!g->mesh_culled || !scene_solids_find(&g->solids, scene, degenerate)) return false;
        g->solids_scene = scene, g->solids_degenerate = degenerate, g->solids_triangles = scene->triangle_count;
        g->solids_vertices = scene->vertex_count, g->solids_meshes = scene->mesh_count;
    }
    if (!g->solids.solid_count || !scene->triangle_mesh) return true;
    /* a mesh whose box holds the eye keeps both faces (the eye may be inside its solid) */
    bool any = false;
    for (uint32_t m = 0; m < scene->mesh_count; m++) {
        const float *box = g->solids.mesh_box[m];
        g->mesh_culled[m] = g->solids.mesh_solid[m] && (eye.x < box[0] || eye.y < box[1] || eye.z < box[2] ||
                                                         eye.x > box[3] || eye.y > box[4] || eye.z > box[5]);
        any |= g->mesh_culled[m];
    }
    if (any) *outward = g->solids.triangle_outward;
    return true;
}

/* The order the cells draw the kept triangles in (g->order).  Nearest
 * first (by their nearest corner's depth, ties by index: a stable radix
 * sort on the float's bits made monotone) when the frame dropped no back
 * face: open surfaces overlap deeply (a map's depth complexity is 2 to 10),
 * and near ones drawn first let the hierarchical depth test skip the
 * blocks of those behind (czest3ctf -20%, ctf_inyard -10% a frame's
 * cells).  Otherwise the global order: solids seen from outside overlap
 * little once their back faces are gone, and neighbours in a mesh's order
 * are neighbours on screen (the bunny's cells took 18% longer sorted).
 * The same order at any thread count. */
static void drawing_order(pgrid_eye *g, uint32_t chunks)
{
    const uint32_t n = g->triangle_count;
    if (g->culled_count || n < 2) {
        for (uint32_t c = 0, i = 0; c < chunks; c++)
            for (uint32_t k = c * SETUP_CHUNK; k < chunk_end(g, c); k++) g->order[i++] = k;
        return;
    }
    uint64_t *keys = g->order_keys, *spare = keys + n;
    for (uint32_t c = 0, i = 0; c < chunks; c++)
        for (uint32_t k = c * SETUP_CHUNK; k < chunk_end(g, c); k++) {
            uint32_t bits;
            memcpy(&bits, &g->nearest[k], sizeof bits);
            bits ^= (bits >> 31) ? 0xFFFFFFFFu : 0x80000000u; /* NaN sorts last */
            keys[i++] = (uint64_t)bits << 32 | k;
        }
    const uint64_t *sorted = pgrid_sort_keys(keys, spare, n, 0, UINT32_MAX);
    for (uint32_t k = 0; k < n; k++) g->order[k] = (uint32_t)sorted[k];
}

/* The cells (inclusive) a set-up triangle's rectangle covers. */
static inline void triangle_cells(const pgrid_triangle *t, uint64_t inv_cell, uint32_t *cx0, uint32_t *cx1,
                                  uint32_t *cy0, uint32_t *cy1)
{
    *cx0 = cell_of(t->x0, inv_cell), *cx1 = cell_of(t->x1, inv_cell);
    *cy0 = cell_of(t->y0, inv_cell), *cy1 = cell_of(t->y1, inv_cell);
}

/* The binning by chunks on the pool (bin_job): when the drawing order is
 * the global one, each chunk's references per cell are counted on its own
 * row of chunk_cells, turned into that row's first slots per cell (the
 * chunks in order within each cell, as the one-thread fill leaves them),
 * and placed; while the table stays small (BIN_TABLE_MOST entries). */
enum { BIN_TABLE_MOST = 1 << 20 };
typedef struct bin_job {
    pgrid_eye *g;
    uint64_t inv_cell;
    uint32_t cells;
    bool fill;
} bin_job;

static void bin_chunk(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    const bin_job *job = context;
    pgrid_eye *g = job->g;
    uint32_t *row = g->chunk_cells + (size_t)task * job->cells;
    const uint32_t from = task * SETUP_CHUNK, end = chunk_end(g, task);
    if (!job->fill) memset(row, 0, job->cells * sizeof *row);
    for (uint32_t k = from; k < end; k++) {
        uint32_t cx0, cx1, cy0, cy1;
        triangle_cells(&g->triangles[k], job->inv_cell, &cx0, &cx1, &cy0, &cy1);
        for (uint32_t cy = cy0; cy <= cy1; cy++)
            for (uint32_t cx = cx0; cx <= cx1; cx++) {
                const uint32_t c = cy * g->cells_x + cx;
                if (job->fill)
                    g->refs[row[c]++] = k;
                else
                    row[c]++;
            }
    }
}

/* Bins the kept triangles by chunks on the pool (bin_job); false when it
 * does not apply (then the caller's loops do it) or memory runs out. */
static bool bin_by_chunks(pgrid_eye *g, uint32_t chunks, uint32_t cells, uint64_t inv_cell)
{
    if (g->threads < 2 || !g->culled_count || (uint64_t)chunks * cells > BIN_TABLE_MOST) return false;
    size_t cap = g->chunk_cells_capacity;
    if (!grow((void **)&g->chunk_cells, &cap, (size_t)chunks * cells, sizeof(uint32_t))) return false;
    g->chunk_cells_capacity = cap;
    bin_job job = {g, inv_cell, cells, false};
    rtt_parallel_run(chunks, g->threads, bin_chunk, &job);
    size_t refs = 0;
    for (uint32_t c = 0; c < cells; c++) {
        g->cell_first[c] = (uint32_t)refs;
        for (uint32_t k = 0; k < chunks; k++) {
            uint32_t *slot = &g->chunk_cells[(size_t)k * cells + c];
            const uint32_t n = *slot;
            *slot = (uint32_t)refs, refs += n;
        }
    }
    g->cell_first[cells] = (uint32_t)refs;
    if (!grow((void **)&g->refs, &g->ref_capacity, refs ? refs : 1, sizeof(uint32_t))) return false;
    g->ref_count = refs;
    job.fill = true;
    rtt_parallel_run(chunks, g->threads, bin_chunk, &job);
    return true;
}

bool pgrid_eye_build(pgrid_eye *g, const rtt_scene *scene, const uint8_t *degenerate,
                     const rtt_camera_frame *frame, uint32_t width, uint32_t height, uint32_t cell, rtt_error *err)
{
    const bool by_rule = cell == 0 && g->cell_rule_bytes; /* chosen after the set-up */
    if (cell == 0 && !by_rule) cell = PGRID_EYE_CELL_DEFAULT;
    if (cell % 4u || cell > PGRID_EYE_CELL_MAX || width == 0 || height == 0 || width > PGRID_IMAGE_MAX ||
        height > PGRID_IMAGE_MAX)
        return rtt_error_set(err,
                             "perspective grid: cell %u for %ux%u pixels (cells are 4 .. %u, a multiple of 4; "
                             "images 1 .. %u a side)",
                             cell, width, height, PGRID_EYE_CELL_MAX, PGRID_IMAGE_MAX);
    g->width = width;
    g->height = height;
    g->frame = *frame;
    size_t tcap = g->triangle_capacity, scap = g->triangle_capacity;
    const size_t triangles = scene->triangle_count ? scene->triangle_count : 1;
    if (!grow((void **)&g->triangles, &tcap, triangles, sizeof(pgrid_triangle)) ||
        !grow((void **)&g->surfaces, &scap, triangles, sizeof(pgrid_surface)))
        return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
    size_t ncap = g->order_capacity, ocap = g->order_capacity, kcap = g->order_capacity;
    if (!grow((void **)&g->nearest, &ncap, triangles, sizeof(float)) ||
        !grow((void **)&g->order, &ocap, triangles, sizeof(uint32_t)) ||
        !grow((void **)&g->order_keys, &kcap, 2 * triangles, sizeof(uint64_t)))
        return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
    g->order_capacity = (uint32_t)triangles;
    g->triangle_capacity = (uint32_t)tcap;

    /* transform, clip against the near plane, set up (by chunks on the
     * thread pool, each chunk's kept triangles packed at its own start,
     * where they stay: pgrid_eye's slots), then each cell's references counted */
    const uint32_t chunks = (scene->triangle_count + SETUP_CHUNK - 1) / SETUP_CHUNK;
    if (PGRID_CHUNK_FIELDS * chunks + 1 > g->chunk_capacity) {
        uint32_t *bigger = realloc(g->chunk_kept, (PGRID_CHUNK_FIELDS * (size_t)chunks + 1) * sizeof *bigger);
        if (!bigger) return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
        g->chunk_kept = bigger;
        g->chunk_capacity = PGRID_CHUNK_FIELDS * chunks + 1;
    }
    setup_job job = {g, scene, degenerate, frame, projection_make(frame, scene), NULL, NULL,
                     chunks > 1 && rtt_thread_count(g->threads) > 1};
    if (!frame_outward(g, scene, degenerate, frame->eye, &job.outward))
        return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
    job.mesh_culled = g->mesh_culled; /* allocated there for a new scene */
    rtt_parallel_run(chunks, g->threads, setup_chunk, &job);
    uint32_t kept = 0, near_count = 0;
    uint64_t refs_default = 0, refs_big = 0;
    g->culled_count = 0;
    for (uint32_t c = 0; c < chunks; c++) {
        const uint32_t *counts = g->chunk_kept + (size_t)PGRID_CHUNK_FIELDS * c;
        kept += counts[0], near_count += counts[1], g->culled_count += counts[2];
        refs_default += counts[3], refs_big += counts[4];
    }
    if (by_rule)
        cell = pgrid_eye_cell_rule(width, height, rtt_thread_count(g->threads), g->cell_rule_bytes, refs_default,
                                   refs_big);
    g->cell = cell;
    g->cells_x = (width + cell - 1) / cell;
    g->cells_y = (height + cell - 1) / cell;
    const uint32_t cells = g->cells_x * g->cells_y;
    size_t cap = g->cell_capacity;
    if (!grow((void **)&g->cell_first, &cap, (size_t)cells + 1, sizeof(uint32_t)))
        return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
    g->cell_capacity = (uint32_t)cap;
    const uint64_t inv_cell = cell_reciprocal(cell);
    g->triangle_count = kept;
    g->inv_scale = 1.0f / job.p.scale;
    g->near_count = near_count;
    if (bin_by_chunks(g, chunks, cells, inv_cell)) return true;

    /* on this thread: each cell's references counted, then placed in the drawing order */
    memset(g->cell_first, 0, ((size_t)cells + 1) * sizeof(uint32_t));
    size_t refs = 0;
    for (uint32_t c = 0; c < chunks; c++)
        for (uint32_t k = c * SETUP_CHUNK; k < chunk_end(g, c); k++) {
            uint32_t cx0, cx1, cy0, cy1;
            triangle_cells(&g->triangles[k], inv_cell, &cx0, &cx1, &cy0, &cy1);
            for (uint32_t cy = cy0; cy <= cy1; cy++)
                for (uint32_t cx = cx0; cx <= cx1; cx++) g->cell_first[cy * g->cells_x + cx + 1]++;
            refs += (size_t)(cx1 - cx0 + 1) * (cy1 - cy0 + 1);
        }
    if (!grow((void **)&g->refs, &g->ref_capacity, refs ? refs : 1, sizeof(uint32_t)))
        return rtt_error_set(err, "%s: out of memory building the perspective grid", scene->path);
    g->ref_count = refs;
    drawing_order(g, chunks);
    for (uint32_t c = 0; c < cells; c++) g->cell_first[c + 1] += g->cell_first[c];
    for (uint32_t i = 0; i < kept; i++) {
        const uint32_t k = g->order[i];
        uint32_t cx0, cx1, cy0, cy1;
        triangle_cells(&g->triangles[k], inv_cell, &cx0, &cx1, &cy0, &cy1);
        for (uint32_t cy = cy0; cy <= cy1; cy++)
            for (uint32_t cx = cx0; cx <= cx1; cx++) g->refs[g->cell_first[cy * g->cells_x + cx]++] = k;
    }
    for (uint32_t c = cells; c > 0; c--) g->cell_first[c] = g->cell_first[c - 1];
    g->cell_first[0] = 0;
    return true;
}

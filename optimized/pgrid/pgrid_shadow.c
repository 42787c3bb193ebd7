/* Hunt & Mark 2008, section 5.2: shadow rays through a light's perspective
 * grid (pgrid_light.h).  The batch (one eye-ray cell's shadow rays to one
 * light, as the shader proxy hands them) is sorted by (light cell, dominant
 * axis of the ray's direction); each run is cut into packets of one vector,
 * 16 rays with AVX-512, 8 with AVX2, 4 with SSE4.1, which meet the cell's
 * triangles in object order, after the per-cell distance test, then the
 * near list.
 *
 * The test is Woop, Benthin & Wald's watertight one exactly as
 * ../isect/isect_woop_watertight.h and the reference compute it: the lanes
 * of a packet share kz (the sort), the corners are broadcast, every lane's
 * shear is its own ray's; a lane with an edge function, det or T that is
 * zero, subnormal, infinite or NaN is decided again by wt_decide1 (double).
 * So a lane answers as the reference for each triangle tested. */
#include <float.h>
#include <immintrin.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_simd.h"
#include "isect_woop_watertight.h"
#include "pgrid_isa.h"
#include "pgrid_light.h"

/* the vector vocabulary at this copy's width, shared with the BVH kernels */
#define LANES BVH_W

/* Normal floats: neither zero, subnormal, infinite nor NaN. */
static inline vm vm_normal(vf x)
{
    const vf a = vf_abs(x);
    return vm_and(vf_ge(a, vf_set1(FLT_MIN)), vf_lt(a, vf_set1(INFINITY)));
}

/* One packet: LANES rays of one kz, structure of arrays. */
typedef struct shadow_packet {
    _Alignas(64) float org[3][LANES];
    _Alignas(64) float sx[LANES], sy[LANES], sz[LANES], tnear[LANES], tfar[LANES], reach[LANES];
    uint32_t kx, ky, kz;
} shadow_packet;

/* The lanes of `active` that `tri` occludes (tnear < t < tfar); with
 * `entering` non-NULL, the lanes that cross it at -tnear < t <= tnear are
 * added there (the ray may start inside a culled solid, pgrid_light.h). */
static uint32_t occluded_lanes(const kd_corners *tri, const shadow_packet *p, uint32_t active, uint32_t *entering)
{
    const uint32_t kx = p->kx, ky = p->ky, kz = p->kz;
    const vf ox = vf_load(p->org[kx]), oy = vf_load(p->org[ky]), oz = vf_load(p->org[kz]);
    const vf sx = vf_load(p->sx), sy = vf_load(p->sy);
    const vf akz = vf_sub(vf_set1(tri->a[kz]), oz), bkz = vf_sub(vf_set1(tri->b[kz]), oz),
             ckz = vf_sub(vf_set1(tri->c[kz]), oz);
    const vf ax = vf_sub(vf_sub(vf_set1(tri->a[kx]), ox), vf_mul(sx, akz));
    const vf ay = vf_sub(vf_sub(vf_set1(tri->a[ky]), oy), vf_mul(sy, akz));
    const vf bx = vf_sub(vf_sub(vf_set1(tri->b[kx]), ox), vf_mul(sx, bkz));
    const vf by = vf_sub(vf_sub(vf_set1(tri->b[ky]), oy), vf_mul(sy, bkz));
    const vf cx = vf_sub(vf_sub(vf_set1(tri->c[kx]), ox), vf_mul(sx, ckz));
    const vf cy = vf_sub(vf_sub(vf_set1(tri->c[ky]), oy), vf_mul(sy, ckz));
    const vf u = vf_sub(vf_mul(cx, by), vf_mul(cy, bx));
    const vf v = vf_sub(vf_mul(ax, cy), vf_mul(ay, cx));
    const vf w = vf_sub(vf_mul(bx, ay), vf_mul(by, ax));
    const vf zero = vf_set1(0.0f);
    const vm positive = vm_and(vm_and(vf_gt(u, zero), vf_gt(v, zero)), vf_gt(w, zero));
    const vm negative = vm_and(vm_and(vf_lt(u, zero), vf_lt(v, zero)), vf_lt(w, zero));
    const vm edges_normal = vm_and(vm_and(vm_normal(u), vm_normal(v)), vm_normal(w));
    const vm act = vm_of_bits(active);
    const uint32_t inside = vm_bits(vm_and(act, vm_or(positive, negative)));
    const uint32_t odd = active & ~vm_bits(edges_normal);
    if (!(inside | odd)) return 0;
    const vf sz = vf_load(p->sz);
    const vf az = vf_mul(sz, akz), bz = vf_mul(sz, bkz), cz = vf_mul(sz, ckz);
    const vf det = vf_add(vf_add(u, v), w);
    const vf t_scaled = vf_add(vf_add(vf_mul(u, az), vf_mul(v, bz)), vf_mul(w, cz));
    const vm normal = vm_and(edges_normal, vm_and(vm_normal(det), vm_normal(t_scaled)));
    const vf t = vf_div(t_scaled, det);
    const vf tnear = vf_load(p->tnear);
    const vm in_range = vm_and(vf_gt(t, tnear), vf_lt(t, vf_load(p->tfar)));
    uint32_t hit = inside & vm_bits(vm_and(normal, in_range));
    if (entering) {
        const vm window = vm_and(vf_gt(t, vf_sub(vf_set1(0.0f), tnear)), vf_lt(vf_sub(t, tnear), vf_set1(FLT_MIN)));
        *entering |= inside & vm_bits(vm_and(normal, window));
    }
    const uint32_t slow = active & ~vm_bits(normal);
    if (slow) {
        _Alignas(64) float lane[9][LANES];
        const vf parts[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
        for (int i = 0; i < 9; i++) vf_store(lane[i], parts[i]);
        for (uint32_t l = 0; l < LANES; l++) {
            if (!(slow >> l & 1u)) continue;
            const wt_lane one = {lane[0][l], lane[1][l], lane[2][l], lane[3][l], lane[4][l],
                                 lane[5][l], lane[6][l], lane[7][l], lane[8][l]};
            float tl, ul, vl;
            if (wt_decide1(&one, p->tnear[l], p->tfar[l], &tl, &ul, &vl))
                hit |= 1u << l;
            else
                hit &= ~(1u << l);
            if (entering && wt_decide1(&one, -p->tnear[l], nextafterf(p->tnear[l], INFINITY), &tl, &ul, &vl))
                *entering |= 1u << l;
        }
    }
    return hit;
}

/* The lanes of `active` occluded by one of list[0 .. count); `entering`
 * as occluded_lanes' (complete for the lanes not occluded). */
static uint32_t occluded_list(const pgrid_shadows *g, const pgrid_light *L, const uint32_t *list, uint32_t count,
                              const shadow_packet *p, uint32_t active, uint32_t *entering)
{
    /* the farthest any lane reaches from the light: triangles beyond it are skipped (the per-cell test, per triangle) */
    float reach = 0.0f;
    for (uint32_t l = 0; l < LANES; l++)
        if (active >> l & 1u && p->reach[l] > reach) reach = p->reach[l];
    uint32_t hit = 0;
    for (uint32_t i = 0; i < count && (hit & active) != active; i++)
        if (!(L->bound[list[i]] > reach)) hit |= occluded_lanes(&g->corners[list[i]], p, active & ~hit, entering);
    return hit;
}

/* Must ray r from triangle `prim` (RTT_MISS: unknown) meet the culled
 * meshes' front faces too?  When its own mesh is culled and its triangle
 * does not face the light (the ray goes into the solid) or the ray grazes
 * it (PGRID_GRAZING_COSINE), or its origin lies in the grown box of another
 * culled mesh (it may start inside that solid). */
static bool needs_front_faces(const pgrid_shadows *g, const pgrid_light *L, const rtt_ray *r, uint32_t prim)
{
    const float *org = r->org;
    const uint32_t own = prim != RTT_MISS && g->triangle_mesh ? g->triangle_mesh[prim] : UINT32_MAX;
    if (own != UINT32_MAX && g->mesh_culled[own]) {
        if (!L->front[prim]) return true;
        const float *n = g->outward_normal[prim];
        if (!(n[0] * r->dir[0] + n[1] * r->dir[1] + n[2] * r->dir[2] >= PGRID_GRAZING_COSINE)) return true;
    }
    for (uint32_t i = 0; i < g->culled_count; i++) {
        const uint32_t m = g->culled[i];
        if (m == own) continue;
        const float *box = g->mesh_box[m];
        if (org[0] >= box[0] && org[1] >= box[1] && org[2] >= box[2] && org[0] <= box[3] && org[1] <= box[4] &&
            org[2] <= box[5])
            return true;
    }
    return false;
}

/* Sorts keys (cell * 3 + kz in the high word, the ray's index in the low)
 * by their high word, stably (a batch in pixel order stays so within a
 * cell): least-significant-digit radix, 11 bits a pass, as many passes as
 * the largest key needs.  The result is in keys. */
static void sort_keys(uint64_t *keys, uint64_t *spare, uint32_t count, uint32_t largest)
{
    enum { BITS = 11, BUCKETS = 1 << BITS };
    uint32_t histogram[BUCKETS];
    for (uint32_t shift = 32; shift < 64 && (largest >> (shift - 32)) != 0; shift += BITS) {
        memset(histogram, 0, sizeof histogram);
        for (uint32_t i = 0; i < count; i++) histogram[(keys[i] >> shift) & (BUCKETS - 1)]++;
        for (uint32_t b = 0, sum = 0; b < BUCKETS; b++) {
            const uint32_t n = histogram[b];
            histogram[b] = sum, sum += n;
        }
        for (uint32_t i = 0; i < count; i++) spare[histogram[(keys[i] >> shift) & (BUCKETS - 1)]++] = keys[i];
        memcpy(keys, spare, (size_t)count * sizeof *keys);
    }
}

bool pgrid_shadow_occluded(const pgrid_shadows *grids, uint32_t light, const rtt_ray *rays,
                           const uint32_t *origin_prim, uint32_t count, uint8_t *occluded);

bool pgrid_shadow_occluded(const pgrid_shadows *grids, uint32_t light, const rtt_ray *rays,
                           const uint32_t *origin_prim, uint32_t count, uint8_t *occluded)
{
    if (!count) return true;
    const pgrid_light *L = &grids->lights[light];
    uint64_t *keys = malloc(2 * (size_t)count * sizeof *keys);
    if (!keys) return false;
    uint32_t largest = 0;
    for (uint32_t i = 0; i < count; i++) {
        const rtt_ray *r = &rays[i];
        const uint32_t cell = pgrid_light_cell_of(L->res, r->org[0] - L->position[0], r->org[1] - L->position[1],
                                                  r->org[2] - L->position[2]);
        const float ax = fabsf(r->dir[0]), ay = fabsf(r->dir[1]), az = fabsf(r->dir[2]);
        const uint32_t kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
        keys[i] = (uint64_t)(cell * 3u + kz) << 32 | i;
        if (cell * 3u + kz > largest) largest = cell * 3u + kz;
    }
    sort_keys(keys, keys + count, count, largest);
    shadow_packet p;
    for (uint32_t first = 0; first < count;) {
        const uint32_t key = (uint32_t)(keys[first] >> 32);
        uint32_t n = 0;
        while (n < LANES && first + n < count && (uint32_t)(keys[first + n] >> 32) == key) n++;
        const uint32_t cell = key / 3u, kz = key % 3u;
        p.kz = kz, p.kx = kz == 2 ? 0 : kz + 1, p.ky = kz == 0 ? 2 : kz - 1;
        const float cell_min = L->cell_min[cell];
        uint32_t active = 0, reaching = 0, full = 0, wild = 0;
        for (uint32_t l = 0; l < LANES; l++) {
            const uint32_t index = (uint32_t)keys[first + (l < n ? l : 0)];
            const rtt_ray *r = &rays[index];
            for (int a = 0; a < 3; a++) p.org[a][l] = r->org[a];
            p.sx[l] = r->dir[p.kx] / r->dir[kz];
            p.sy[l] = r->dir[p.ky] / r->dir[kz];
            p.sz[l] = 1.0f / r->dir[kz];
            p.tnear[l] = r->tnear, p.tfar[l] = r->tfar;
            if (l >= n) continue;
            active |= 1u << l;
            /* an origin beyond 2M: every triangle (pgrid_light.h) */
            for (int a = 0; a < 3; a++)
                if (!(fabs((double)r->org[a]) <= L->magnitude)) wild |= 1u << l;
            /* the per-cell distance test: |L - p| is tnear + tfar for the proxy's rays */
            p.reach[l] = r->tnear + r->tfar + L->reach;
            if (!(p.reach[l] < cell_min)) reaching |= 1u << l;
            if (grids->culled_count && needs_front_faces(grids, L, r, origin_prim ? origin_prim[index] : RTT_MISS))
                full |= 1u << l;
        }
        uint32_t hit = 0, entering = 0;
        for (uint32_t t = 0; wild & ~hit && t < grids->corner_count; t++)
            hit |= occluded_lanes(&grids->corners[t], &p, wild & ~hit, NULL);
        active &= ~wild, reaching &= ~wild, full &= ~wild;
        uint32_t *watch = grids->culled_count ? &entering : NULL;
        if (reaching)
            hit |= occluded_list(grids, L, L->refs + L->cell_first[cell], L->cell_front[cell] - L->cell_first[cell], &p,
                                reaching, watch);
        if (L->near_count && (hit & active) != active)
            hit |= occluded_list(grids, L, L->near, L->near_count, &p, active & ~hit, watch);
        /* the front faces, for the lanes that may start inside a culled solid */
        const uint32_t front = (full | entering) & active & ~hit;
        if (front)
            hit |= occluded_list(grids, L, L->refs + L->cell_front[cell], L->cell_first[cell + 1] - L->cell_front[cell],
                                 &p, front, NULL);
        for (uint32_t l = 0; l < n; l++) occluded[(uint32_t)keys[first + l]] = (uint8_t)(hit >> l & 1u);
        first += n;
    }
    free(keys);
    return true;
}

/* Hunt & Mark 2008, section 5.2: shadow rays through a light's perspective
 * grid (pgrid_light.h).  The batch (one eye-ray cell's shadow rays to one
 * light, as the shader proxy hands them) is keyed by (light cell, dominant
 * axis of the ray's direction) one vector of rays at a time, 16 with
 * AVX-512, 8 with AVX2, 4 with SSE4.1: the rays of a vector that share its
 * first ray's key, when three quarters of it do, are a packet at once; the
 * rest are sorted by key and each run cut into packets of one vector.  A
 * packet meets its cell's triangles in object order, after the per-cell
 * distance test, then the near list.
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
#include "bvh_wt_lanes.h"
#include "isect_woop_watertight.h"
#include "pgrid_isa.h"
#include "pgrid_light.h"
#include "pgrid_sort.h"

/* the vector vocabulary at this copy's width, shared with the BVH kernels */
#define LANES BVH_W

/* One packet: LANES rays of one kz, structure of arrays. */
typedef struct shadow_packet {
    _Alignas(64) float org[3][LANES];
    _Alignas(64) float sx[LANES], sy[LANES], sz[LANES], tnear[LANES], tfar[LANES], reach[LANES];
    uint32_t kx, ky, kz;
} shadow_packet;

/* A packet's vectors for its run through a list, loaded once (kept in
 * registers across the list's triangles). */
typedef struct packet_regs {
    vf ox, oy, oz, sx, sy, sz, tnear, tfar;
    uint32_t kx, ky, kz;
} packet_regs;

static inline packet_regs packet_regs_load(const shadow_packet *p)
{
    return (packet_regs){vf_load(p->org[p->kx]), vf_load(p->org[p->ky]), vf_load(p->org[p->kz]),
                         vf_load(p->sx), vf_load(p->sy), vf_load(p->sz), vf_load(p->tnear), vf_load(p->tfar),
                         p->kx, p->ky, p->kz};
}

/* The lanes of `slow` decided by the reference's own decision (double when
 * a value is not a normal float), from the lanes' transformed corners
 * (parts: ax, ay, az, bx, by, bz, cx, cy, cz): `hit` with those lanes set
 * or cleared; `entering` as occluded_lanes'.  Rare: out of line. */
static __attribute__((noinline)) uint32_t decide_slow(const float (*parts)[LANES], const shadow_packet *p, uint32_t slow,
                                                      uint32_t hit, uint32_t *entering)
{
    for (uint32_t l = 0; l < LANES; l++) {
        if (!(slow >> l & 1u)) continue;
        const wt_lane one = {parts[0][l], parts[1][l], parts[2][l], parts[3][l], parts[4][l],
                             parts[5][l], parts[6][l], parts[7][l], parts[8][l]};
        float tl, ul, vl;
        if (wt_decide1(&one, p->tnear[l], p->tfar[l], &tl, &ul, &vl))
            hit |= 1u << l;
        else
            hit &= ~(1u << l);
        if (entering && wt_decide1(&one, -p->tnear[l], nextafterf(p->tnear[l], INFINITY), &tl, &ul, &vl))
            *entering |= 1u << l;
    }
    return hit;
}

/* The lanes of `active` that `tri` occludes (tnear < t < tfar); with
 * `entering` non-NULL, the lanes that cross it at -tnear < t <= tnear are
 * added there (the ray may start inside a culled solid, pgrid_light.h).
 * Inlined into the list's loop, the packet's vectors in registers. */
static inline __attribute__((always_inline)) uint32_t occluded_lanes(const kd_corners *tri, const packet_regs *r,
                                                                     const shadow_packet *p, uint32_t active,
                                                                     uint32_t *entering)
{
    const uint32_t kx = r->kx, ky = r->ky, kz = r->kz;
    const vf ox = r->ox, oy = r->oy, oz = r->oz, sx = r->sx, sy = r->sy;
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
    /* all three positive or all negative, by their least and greatest
     * (exact for the lanes without a NaN; a NaN lane is not normal, so
     * decided below by the reference's own decision whatever this says) */
    const vm positive = vf_gt(vf_min(vf_min(u, v), w), zero), negative = vf_lt(vf_max(vf_max(u, v), w), zero);
    const vm edges_normal = bvh_wt_normal3(u, v, w);
    const vm act = vm_of_bits(active);
    const uint32_t inside = vm_bits(vm_and(act, vm_or(positive, negative)));
    const uint32_t odd = active & ~vm_bits(edges_normal);
    if (!(inside | odd)) return 0;
    const vf sz = r->sz, tnear = r->tnear;
    const vf az = vf_mul(sz, akz), bz = vf_mul(sz, bkz), cz = vf_mul(sz, ckz);
    const vf det = vf_add(vf_add(u, v), w);
    const vf t_scaled = vf_add(vf_add(vf_mul(u, az), vf_mul(v, bz)), vf_mul(w, cz));
    const vm normal = vm_and(edges_normal, vm_and(bvh_wt_normal(det), bvh_wt_normal(t_scaled)));
    const vf t = vf_div(t_scaled, det);
    const vm in_range = vm_and(vf_gt(t, tnear), vf_lt(t, r->tfar));
    uint32_t hit = inside & vm_bits(vm_and(normal, in_range));
    if (entering) {
        const vm window = vm_and(vf_gt(t, vf_sub(vf_set1(0.0f), tnear)), vf_lt(vf_sub(t, tnear), vf_set1(FLT_MIN)));
        *entering |= inside & vm_bits(vm_and(normal, window));
    }
    uint32_t slow = active & ~vm_bits(normal);
    /* the flat and short lanes' answer is no, without asking the
     * reference's test (unless `entering` wants the window around 0) */
    if (!entering) slow = bvh_wt_undecided(slow, ax, ay, az, bx, by, bz, cx, cy, cz, det, t_scaled, tnear);
    if (slow) {
        _Alignas(64) float parts[9][LANES];
        const vf values[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
        for (int i = 0; i < 9; i++) vf_store(parts[i], values[i]);
        hit = decide_slow((const float (*)[LANES])parts, p, slow, hit, entering);
    }
    return hit;
}

/* The lanes of `active` occluded by one of list[0 .. count); `entering`
 * as occluded_lanes' (complete for the lanes not occluded). */
static uint32_t occluded_list(const pgrid_shadows *g, const pgrid_light *L, const uint32_t *list, uint32_t count,
                              const shadow_packet *p, uint32_t active, uint32_t *entering)
{
    /* the farthest any lane reaches from the light: triangles beyond it are skipped (the per-cell test, per triangle) */
    const vf zero = vf_set1(0.0f), lanes = vf_load(p->reach);
    const float reach = vf_hmax(vf_blend(vm_and(vm_of_bits(active), vf_gt(lanes, zero)), zero, lanes)); /* NaN: none */
    const packet_regs r = packet_regs_load(p);
    uint32_t hit = 0;
    for (uint32_t i = 0; i < count && (hit & active) != active; i++)
        if (!(L->bound[list[i]] > reach)) hit |= occluded_lanes(&g->corners[list[i]], &r, p, active & ~hit, entering);
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
    /* one byte per triangle (the light's class of it), not its mesh's entries: a frame reads it once a ray */
    const uint8_t side = prim != RTT_MISS ? L->front[prim] : PGRID_PRIM_OPEN;
    if (side == PGRID_PRIM_AWAY) return true;
    if (side == PGRID_PRIM_FACING) {
        const float *n = g->outward_normal[prim];
        if (!(n[0] * r->dir[0] + n[1] * r->dir[1] + n[2] * r->dir[2] >= PGRID_GRAZING_COSINE)) return true;
    }
    if (side >= PGRID_PRIM_FACING && g->culled_count == 1) return false; /* its own mesh is the one culled */
    const uint32_t own = side != PGRID_PRIM_OPEN ? g->triangle_mesh[prim] : UINT32_MAX;
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

/* The dominant axis of (x, y, z) per lane, by the reference's tie rule
 * (|x| >= |y|, |x| >= |z| → 0, else |y| >= |z| → 1, else 2): the masks of
 * axes 0 and 1 (the latter meaningful outside the former's lanes). */
static inline void major_axis(vf x, vf y, vf z, vm *axis0, vm *axis1)
{
    const vf ax = vf_abs(x), ay = vf_abs(y), az = vf_abs(z);
    *axis0 = vm_and(vf_ge(ax, ay), vf_ge(ax, az));
    *axis1 = vf_ge(ay, az);
}

/* The keys of rays[first .. first + n) (n <= LANES): cell * 3 + kz, with
 * the cell of the origin's direction d = p - L from the light (the six-face
 * arrangement of pgrid_light.h: face 2 axis + (d[axis] < 0) for d's major
 * axis by the reference's tie rule, coordinates d[axis + 1], d[axis + 2]
 * over |d[axis]| clamped below at -1 (NaN too: any cell, the test
 * decides), res / 2 (s + 1) truncated, at most res - 1) and the
 * direction's dominant axis kz.  The keys as a vector (lanes past n: the
 * first ray's) and stored at keys[first ..]; the rays' words in `ray`
 * (vf_load_records8's: org xyz, dir xyz, tnear, tfar). */
static vi make_keys(const pgrid_light *L, const rtt_ray *rays, uint32_t first, uint32_t n, uint32_t *keys, vf ray[8])
{
    _Alignas(64) rtt_ray tail[LANES];
    const rtt_ray *lanes = rays + first;
    if (n < LANES) { /* the batch's last rays: no reading past them */
        for (uint32_t l = 0; l < LANES; l++) tail[l] = rays[first + (l < n ? l : 0)];
        lanes = tail;
    }
    vf_load_records8((const float *)lanes, ray);
    const vf dx = vf_sub(ray[0], vf_set1(L->position[0])), dy = vf_sub(ray[1], vf_set1(L->position[1])),
             dz = vf_sub(ray[2], vf_set1(L->position[2]));
    vm x_major, y_major;
    major_axis(dx, dy, dz, &x_major, &y_major);
    const vf zero = vf_set1(0.0f), one = vf_set1(1.0f), two = vf_set1(2.0f), minus_one = vf_set1(-1.0f);
    const vf along = vf_blend(x_major, vf_blend(y_major, dz, dy), dx), major = vf_abs(along);
    const vf s_num = vf_blend(x_major, vf_blend(y_major, dx, dz), dy);
    const vf t_num = vf_blend(x_major, vf_blend(y_major, dy, dx), dz);
    const vf axis = vf_blend(x_major, vf_blend(y_major, two, one), zero);
    const vf face = vf_add(vf_add(axis, axis), vf_blend(vf_lt(along, zero), zero, one));
    const vf half = vf_set1(0.5f * (float)L->res);
    vf s = vf_div(s_num, major), t = vf_div(t_num, major);
    s = vf_blend(vf_ge(s, minus_one), minus_one, s); /* also NaN: any cell, the test decides */
    t = vf_blend(vf_ge(t, minus_one), minus_one, t);
    vm dir_x, dir_y;
    major_axis(ray[3], ray[4], ray[5], &dir_x, &dir_y);
    const vf kz = vf_blend(dir_x, vf_blend(dir_y, two, one), zero);
    /* |s|, |t| <= 1 (a coordinate over the largest): the cells 0 .. res, truncated as integers */
    const vi res = vi_set1(L->res), last = vi_set1(L->res - 1u);
    const vi x = vi_min_s(vf_trunc(vf_mul(vf_add(s, one), half)), last);
    const vi y = vi_min_s(vf_trunc(vf_mul(vf_add(t, one), half)), last);
    const vi cell = vi_add(vi_mul(vi_add(vi_mul(vf_trunc(face), res), y), res), x);
    const vi key = vi_add(vi_mul(cell, vi_set1(3u)), vf_trunc(kz));
    _Alignas(64) uint32_t out[LANES];
    vi_store(out, key);
    memcpy(keys + first, out, n * sizeof *keys);
    return key;
}

/* What a chunk's packets share. */
typedef struct packet_context {
    const pgrid_shadows *grids;
    const pgrid_light *L;
    vf within, slack; /* origins within 2M (pgrid_light.h), the distance test's slack */
    uint32_t face_cells;
} packet_context;

/* The lanes `lanes` of the rays in `ray` (vf_load_records8's words; the
 * other lanes hold rays of other keys or repeats, left alone), all of key
 * `key`, traced as one packet; `full`: those of them that may start inside
 * a culled solid.  The lanes occluded. */
static uint32_t trace_packet(const packet_context *ctx, const vf ray[8], uint32_t lanes, uint32_t key, uint32_t full)
{
    const pgrid_shadows *grids = ctx->grids;
    const pgrid_light *L = ctx->L;
    shadow_packet p;
    const uint32_t cell = key / 3u, kz = key % 3u;
    p.kz = kz, p.kx = kz == 2 ? 0 : kz + 1, p.ky = kz == 0 ? 2 : kz - 1;
    for (int a = 0; a < 3; a++) vf_store(p.org[a], ray[a]);
    vf_store(p.tnear, ray[6]), vf_store(p.tfar, ray[7]);
    const vf dkz = ray[3 + kz];
    vf_store(p.sx, vf_div(ray[3 + p.kx], dkz));
    vf_store(p.sy, vf_div(ray[3 + p.ky], dkz));
    vf_store(p.sz, vf_div(vf_set1(1.0f), dkz));
    /* the per-cell distance test: |L - p| is tnear + tfar for the proxy's rays */
    const vf reach = vf_add(vf_add(ray[6], ray[7]), ctx->slack);
    vf_store(p.reach, reach);
    uint32_t active = lanes;
    /* a face keeps the rows of cells its footprints meet: elsewhere nothing but the near list */
    const uint32_t *kept_cells = L->kept_cells[cell / ctx->face_cells];
    const bool kept = cell >= kept_cells[0] && cell < kept_cells[1];
    uint32_t reaching = kept ? active & ~vm_bits(vf_lt(reach, vf_set1(L->cell_min[cell]))) : 0;
    /* an origin beyond 2M: every triangle (pgrid_light.h) */
    const vf within = ctx->within;
    const vm tame = vm_and(vm_and(vf_le(vf_abs(ray[0]), within), vf_le(vf_abs(ray[1]), within)),
                           vf_le(vf_abs(ray[2]), within));
    const uint32_t wild = active & ~vm_bits(tame);
    uint32_t hit = 0, entering = 0;
    if (wild) {
        const packet_regs regs = packet_regs_load(&p);
        for (uint32_t t = 0; wild & ~hit && t < grids->corner_count; t++)
            hit |= occluded_lanes(&grids->corners[t], &regs, &p, wild & ~hit, NULL);
    }
    active &= ~wild, reaching &= ~wild, full &= ~wild;
    /* The front faces, for the lanes that may start inside a culled
     * solid: first for those known now (most start on a face turned
     * from the light, so go into the solid and leave it through a
     * front face), then for those the kept lists find crossing a
     * triangle at the origin (entering).  A lane's answer is whether
     * any triangle it is tested against occludes it, so the order of
     * the lists changes no answer, only how soon a lane is done. */
    const uint32_t front_first = kept ? full & active : 0;
    if (front_first)
        hit |= occluded_list(grids, L, L->refs + L->cell_front[cell], L->cell_first[cell + 1] - L->cell_front[cell], &p,
                             front_first, NULL);
    uint32_t *watch = grids->culled_count ? &entering : NULL;
    if (reaching & ~hit)
        hit |= occluded_list(grids, L, L->refs + L->cell_first[cell], L->cell_front[cell] - L->cell_first[cell], &p,
                             reaching & ~hit, watch);
    if (L->near_count && (hit & active) != active)
        hit |= occluded_list(grids, L, L->near, L->near_count, &p, active & ~hit, watch);
    const uint32_t front = kept ? entering & ~front_first & active & ~hit : 0;
    if (front)
        hit |= occluded_list(grids, L, L->refs + L->cell_front[cell], L->cell_first[cell + 1] - L->cell_front[cell], &p,
                             front, NULL);
    return hit;
}

/* The rays sorted at once: a chunk of the batch (an eye-ray cell of
 * 128 x 128 pixels is four), its scratch on the stack, nothing allocated. */
enum { CHUNK_RAYS = 4096 };
/* LANES rays in a row of which this many share the first's key are a
 * packet at once (the others left for the sort): ctf_inyard, czest3ctf,
 * oa_dm4 best at 12 of 16 against 8 and 16 (bench/results/pgrid.md,
 * fourteenth session) */
#define PACKET_MIN (LANES * 3u / 4u)
/* How many vectors of rays ahead the batch is prefetched: 8 against 4 and
 * 16 on the same three maps (bench/results/pgrid.md, fourteenth session) */
#define PREFETCH_GROUPS 8u
typedef struct chunk_scratch {
    uint32_t keys[CHUNK_RAYS];          /* per ray */
    uint32_t rest[CHUNK_RAYS];          /* the rays left for the sort, in batch order */
    uint32_t run_first[CHUNK_RAYS + 1]; /* per run of equal keys: its first place in rest */
    uint64_t records[CHUNK_RAYS], spare[CHUNK_RAYS];
    uint8_t full[CHUNK_RAYS];           /* per ray: needs_front_faces */
} chunk_scratch;

/* pgrid_shadow_occluded on at most CHUNK_RAYS rays. */
static void occluded_chunk(const pgrid_shadows *grids, const pgrid_light *L, const rtt_ray *rays,
                           const uint32_t *origin_prim, uint32_t count, uint8_t *occluded, chunk_scratch *scratch)
{
    /* the largest float at most 2M: |org| (a float) <= 2M iff |org| <= it */
    float magnitude = (float)L->magnitude;
    if ((double)magnitude > L->magnitude) magnitude = nextafterf(magnitude, 0.0f);
    const packet_context ctx = {grids, L, vf_set1(magnitude), vf_set1(L->reach), L->res * L->res};
    /* which rays may start inside a culled solid, in batch order (their
     * triangles' bytes and normals read in the batch's coherent order, not
     * the packets') */
    uint8_t *full_ray = scratch->full;
    if (grids->culled_count)
        for (uint32_t i = 0; i < count; i++)
            full_ray[i] = needs_front_faces(grids, L, &rays[i], origin_prim ? origin_prim[i] : RTT_MISS);
    /* per ray its key; of LANES rays in a row, those of the first one's
     * key are a packet at once when they are PACKET_MIN or more (a
     * coherent batch's neighbours mostly share a cell: a map's, whose
     * cells are wide, often), from the words the keys were made from; the
     * others are left for the sort */
    uint32_t *keys = scratch->keys, *rest = scratch->rest, *run_first = scratch->run_first;
    uint32_t rests = 0;
    for (uint32_t first = 0; first < count; first += LANES) {
        const uint32_t n = count - first < LANES ? count - first : LANES;
        /* the batch streams in from memory: its lines asked for PREFETCH_GROUPS groups ahead */
        if (first + (PREFETCH_GROUPS + 1u) * LANES <= count) {
            const char *ahead = (const char *)(rays + first + PREFETCH_GROUPS * LANES);
            for (uint32_t b = 0; b < LANES * sizeof *rays; b += 64) __builtin_prefetch(ahead + b);
        }
        vf ray[8];
        const vi key = make_keys(L, rays, first, n, keys, ray);
        const uint32_t same = vm_bits(vi_eq(key, vi_set1(keys[first]))) & (uint32_t)((1ull << n) - 1u);
        uint32_t left = (uint32_t)((1ull << n) - 1u);
        if ((uint32_t)__builtin_popcount(same) >= PACKET_MIN) {
            uint32_t full = 0;
            if (grids->culled_count)
                for (uint32_t l = 0; l < n; l++) full |= (uint32_t)full_ray[first + l] << l;
            const uint32_t hit = trace_packet(&ctx, ray, same, keys[first], full & same);
            for (uint32_t bits = same; bits; bits &= bits - 1u) {
                const uint32_t l = (uint32_t)__builtin_ctz(bits);
                occluded[first + l] = (uint8_t)(hit >> l & 1u);
            }
            left &= ~same;
        }
        for (; left; left &= left - 1u) rest[rests++] = first + (uint32_t)__builtin_ctz(left);
    }
    if (!rests) return;
    /* per run of equal keys in batch order a record and its first place;
     * without a branch per ray: a run's entry is written at every ray and
     * kept by the count moving on only where a run starts (a mesh's rays
     * seen from the light change cells every ray or two, and the branch
     * was mispredicted as often) */
    uint64_t *records = scratch->records;
    uint32_t runs = 0, lo = UINT32_MAX, hi = 0, before = ~keys[rest[0]];
    for (uint32_t j = 0; j < rests; j++) {
        const uint32_t key = keys[rest[j]];
        run_first[runs] = j;
        records[runs] = (uint64_t)key << 32 | runs;
        runs += key != before;
        before = key;
        lo = key < lo ? key : lo;
        hi = key > hi ? key : hi;
    }
    run_first[runs] = rests;
    /* by cell and axis, stably (a batch in pixel order stays so within a
     * cell; an eye-ray cell's rays see a band of the light's cells: one or
     * two passes of a few hundred buckets), so the packets read runs of
     * one key in order */
    const uint64_t *sorted = pgrid_sort_keys(records, scratch->spare, runs, lo, hi);
    _Alignas(64) rtt_ray lane_rays[LANES];
    uint32_t index[LANES];
    for (uint32_t next = 0, taken = 0; next < runs;) {
        /* the next LANES rays of this key, run after run */
        const uint32_t key = (uint32_t)(sorted[next] >> 32);
        uint32_t n = 0;
        while (n < LANES && next < runs && (uint32_t)(sorted[next] >> 32) == key) {
            const uint32_t run = (uint32_t)sorted[next], start = run_first[run] + taken, end = run_first[run + 1];
            const uint32_t take = end - start < LANES - n ? end - start : LANES - n;
            for (uint32_t k = 0; k < take; k++) index[n++] = rest[start + k];
            taken += take;
            if (start + take == end) next++, taken = 0;
        }
        /* the lanes' rays as structure of arrays (lanes past n repeat the first) */
        for (uint32_t l = 0; l < LANES; l++) lane_rays[l] = rays[index[l < n ? l : 0]];
        vf ray[8];
        vf_load_records8((const float *)lane_rays, ray);
        uint32_t full = 0;
        if (grids->culled_count)
            for (uint32_t l = 0; l < n; l++) full |= (uint32_t)full_ray[index[l]] << l;
        const uint32_t hit = trace_packet(&ctx, ray, (uint32_t)((1ull << n) - 1u), key, full);
        for (uint32_t l = 0; l < n; l++) occluded[index[l]] = (uint8_t)(hit >> l & 1u);
    }
}

bool pgrid_shadow_occluded(const pgrid_shadows *grids, uint32_t light, const rtt_ray *rays,
                           const uint32_t *origin_prim, uint32_t count, uint8_t *occluded);

bool pgrid_shadow_occluded(const pgrid_shadows *grids, uint32_t light, const rtt_ray *rays,
                           const uint32_t *origin_prim, uint32_t count, uint8_t *occluded)
{
    chunk_scratch scratch;
    for (uint32_t first = 0; first < count; first += CHUNK_RAYS)
        occluded_chunk(grids, &grids->lights[light], rays + first, origin_prim ? origin_prim + first : NULL,
                       count - first < CHUNK_RAYS ? count - first : CHUNK_RAYS, occluded + first, &scratch);
    return true;
}

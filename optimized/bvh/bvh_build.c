/* Binned SAH BVH construction (Wald 2007, "On fast construction of SAH-based
 * bounding volume hierarchies", section 3: centroid binning, one sweep over
 * the bins per axis), the structure Benthin & Wald 2009 trace with multiple
 * frusta.
 *
 * First, pre-splitting (Karras & Aila 2013, section 5; below, "Pre-splitting"):
 * the few triangles whose boxes dwarf the scene's typical one are cut into
 * parts at the scene's dyadic planes, each part a reference of its own
 * with its part's box, so that one long wall's box does not span the nodes
 * around it.  The builder then works on references (a triangle's, or a
 * part's), and a leaf holds the records of its references: a pre-split
 * triangle's record is in every leaf one of its parts went to.
 *
 * Per node: the references' box centroids are put into bins along each axis
 * of the centroid bounds (min(BVH_BINS, 8 + n / 8) for n triangles: the
 * sweep's fixed cost would dominate small nodes; Embree's 4 + n / 20 is
 * faster still but costs 0.7-0.9% SAH, bench/results/bvh-build.md); a sweep over the bins' counts and boxes
 * gives every plane's cost
 *   C = C_trav + C_isect * (N_L * SA_L + N_R * SA_R) / SA
 * (C_isect = 1, C_trav = options.node_cost, BVH_DEFAULT_NODE_COST), and the
 * cheapest plane splits the node unless a leaf, C_isect * N, is no dearer
 * and N fits in a leaf (options.leaf_size).  A node with more than
 * leaf_size triangles is always split (at the median of its order when
 * every centroid coincides); at options.max_depth a node is a leaf whatever
 * it holds.  Binning runs in SSE lanes, all three axes in one pass over the
 * node's boxes, and the sweep runs the three axes in SSE lanes; surface
 * areas are in float relative to the node's largest extent, so scenes at
 * 1e20 do not overflow them (the tree's reported SAH cost is in double).
 *
 * Threads (engine/threads.h): the top of the tree is split breadth-first on
 * the calling thread until there are BVH_TASKS_PER_THREAD subtrees per
 * thread; the subtrees are then built as independent tasks of
 * rtt_parallel_run.  Subtree i owns the node slots of its reference range
 * (a subtree of n references has at most n - 1 inner nodes), so no slot is
 * shared and the build is the same for any thread count.  A subtree's
 * slots are in depth-first order (a node, its left subtree, its right
 * one), so the layout walks only the top nodes and moves each subtree's
 * block whole into the final array, its node references shifted; one
 * linear pass then widens the boxes and sums the SAH cost, and the records
 * and corners are copied in leaf order (the references' final order) on
 * the thread pool.
 *
 * Memory: every array is fresh, and a cold build touches ~250 bytes a
 * triangle.  On a virtual machine whose page faults go through the
 * hypervisor, 4 KiB faults were half of a one-thread build of the bunny
 * (0.071 s -> 0.034 s, bench/results/bvh-build.md), so the arrays come from
 * rtt_alloc_pages (2 MiB transparent huge pages for the large ones).
 *
 * What it trades: binning rather than a full sweep over sorted centroids
 * (Wald 2007: within a few percent of the full SAH at a fraction of the
 * time); the top levels' binning is serial, and so is pre-splitting;
 * pre-splitting instead of spatial splits decided per node by the SAH
 * (Stich et al. 2009, Embree's high-quality builder): a pass before the
 * build, no change to it (the SAH cost it reports counts each part's
 * record, so the maps' rose 1-4% while their frusta got faster). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <smmintrin.h>

#include "bvh_build.h"
#include "engine/clock.h"
#include "engine/pages.h"
#include "engine/threads.h"
#include "isect_projected_bary.h"
#include "solids.h"

#define BVH_BINS 32u
#define BVH_TASKS_PER_THREAD 8u
/* Nodes smaller than this are not worth a task of their own. */
#define BVH_TASK_MIN_TRIANGLES 4096u

/* The larger of two floats that are not NaN (boxes of finite triangles),
 * without fmaxf's call. */
static inline float max_f(float a, float b) { return a > b ? a : b; }

typedef struct box3 {
    float lo[3], hi[3];
} box3;

/* Half the surface area of the box [lo, hi] in double (0 along an empty axis). */
static double half_area(const double lo[3], const double hi[3])
{
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = hi[k] > lo[k] ? hi[k] - lo[k] : 0.0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static double box_half_area(const box3 *b)
{
    const double lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, hi[3] = {b->hi[0], b->hi[1], b->hi[2]};
    return half_area(lo, hi);
}

/* 32 bytes: a triangle's box in SSE lanes, its record index in the fourth
 * lane of `lo` (bits).  The builder partitions these themselves, so every
 * pass reads them in sequence. */
typedef struct prim_ref {
    __m128 lo, hi;
} prim_ref;

static inline uint32_t ref_record(const prim_ref *r) { return (uint32_t)_mm_extract_ps(r->lo, 3); }
/* `lo` with the record's bits cleared: as a float they are a denormal (any
 * index below 2^23), and an Intel core takes a microcode assist of about a
 * hundred cycles for every denormal operand of a multiply or subtract (AMD
 * cores do not), which made the build 3.5x slower on a Xeon.  Every box and
 * centroid the builder computes from a reference reads this; lane 3 is
 * never part of a cost, so the tree is the same. */
static inline __m128 ref_lo(const prim_ref *r) { return _mm_blend_ps(r->lo, _mm_setzero_ps(), 0x8); }
/* the box's centre, halved before the sum so that no coordinate overflows */
static inline __m128 ref_centroid(const prim_ref *r)
{
    const __m128 half = _mm_set1_ps(0.5f);
    return _mm_add_ps(_mm_mul_ps(ref_lo(r), half), _mm_mul_ps(r->hi, half));
}

/* An SSE box: min xyz and max xyz (the fourth lanes unused). */
typedef struct box4 {
    __m128 lo, hi;
} box4;

static inline void box4_empty(box4 *b) { b->lo = _mm_set1_ps(INFINITY), b->hi = _mm_set1_ps(-INFINITY); }
static inline void box4_grow(box4 *b, __m128 lo, __m128 hi)
{
    b->lo = _mm_min_ps(b->lo, lo);
    b->hi = _mm_max_ps(b->hi, hi);
}
/* Half the surface area of the box scaled by `unit` (0 for an empty box). */
static inline float box4_half_area(const box4 *b, __m128 unit)
{
    const __m128 d = _mm_mul_ps(_mm_max_ps(_mm_sub_ps(b->hi, b->lo), _mm_setzero_ps()), unit);
    const __m128 e = _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)); /* y z x */
    const __m128 p = _mm_mul_ps(d, e);                               /* xy yz zx */
    return _mm_cvtss_f32(p) + _mm_cvtss_f32(_mm_shuffle_ps(p, p, 1)) + _mm_cvtss_f32(_mm_shuffle_ps(p, p, 2));
}

static inline box3 box4_unpack(const box4 *b)
{
    _Alignas(16) float lo[4], hi[4];
    _mm_store_ps(lo, b->lo), _mm_store_ps(hi, b->hi);
    return (box3){{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

typedef struct builder {
    prim_ref *refs;            /* partitioned node by node */
    bvh_node *slots;           /* inner nodes before the layout */
    uint32_t leaf_size, max_depth;
    float node_cost;           /* C_trav in units of C_isect */
} builder;

/* What the builder decided for a range: a leaf, or a split at `mid`. */
typedef struct split_choice {
    bool leaf;
    uint32_t mid;
} split_choice;

/* The bin of each axis for centroid c: (c - lo) * scale, clamped. */
static inline __m128i bins_of(__m128 c, __m128 lo, __m128 scale, __m128 bin_max)
{
    __m128 f = _mm_mul_ps(_mm_sub_ps(c, lo), scale);
    f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), bin_max);
    return _mm_cvttps_epi32(f);
}

/* Bins for a node of n triangles: as many as BVH_BINS_BASE + n / BVH_BINS_PER,
 * at most BVH_BINS (the sweep's fixed cost would dominate small nodes). */
#define BVH_BINS_BASE 8u
#define BVH_BINS_PER 8u
static inline uint32_t bins_for(uint32_t n)
{
    const uint32_t bins = BVH_BINS_BASE + n / BVH_BINS_PER;
    return bins < BVH_BINS ? bins : BVH_BINS;
}

/* A range's box and the box of its centroids. */
typedef struct node_bounds {
    box4 box, cbox;
} node_bounds;

static void range_bounds(const builder *b, uint32_t begin, uint32_t end, node_bounds *out)
{
    box4_empty(&out->box), box4_empty(&out->cbox);
    for (uint32_t i = begin; i < end; i++) {
        const prim_ref *r = &b->refs[i];
        box4_grow(&out->box, ref_lo(r), r->hi);
        const __m128 c = ref_centroid(r);
        box4_grow(&out->cbox, c, c);
    }
}

/* A node's bins: per axis and bin the box of the triangles whose centroid
 * falls there; per bin the three axes' counts in lanes 0..2 (so the sweep
 * reads them as one vector). */
typedef struct bin_set {
    box4 box[3][BVH_BINS];
    _Alignas(16) uint32_t count[BVH_BINS][4];
} bin_set;

static void bin_set_empty(bin_set *s, uint32_t bins_used)
{
    for (uint32_t j = 0; j < bins_used; j++) {
        for (int k = 0; k < 3; k++) box4_empty(&s->box[k][j]);
        _mm_store_si128((__m128i *)s->count[j], _mm_setzero_si128());
    }
}

static inline void bin_set_add(bin_set *s, const prim_ref *r, __m128 lo4, __m128 scale4, __m128 bin_max)
{
    _Alignas(16) int32_t j[4];
    _mm_store_si128((__m128i *)j, bins_of(ref_centroid(r), lo4, scale4, bin_max));
    for (int k = 0; k < 3; k++) {
        s->count[j[k]][k]++;
        box4_grow(&s->box[k][j[k]], ref_lo(r), r->hi);
    }
}

/* Bins [begin, end) on all three axes in one pass.  A large node's
 * triangles alternate between two bin sets, merged at the end: neighbours
 * in a mesh tend to share a bin, and one set would chain each update on the
 * store before it. */
static void bins_bin(const builder *b, uint32_t begin, uint32_t end, uint32_t bins_used, __m128 lo4, __m128 scale4,
                     __m128 bin_max, bin_set *out)
{
    bin_set_empty(out, bins_used);
    if (end - begin < 4u * bins_used) {
        for (uint32_t i = begin; i < end; i++) bin_set_add(out, &b->refs[i], lo4, scale4, bin_max);
        return;
    }
    bin_set other;
    bin_set_empty(&other, bins_used);
    uint32_t i = begin;
    for (; i + 1 < end; i += 2) {
        bin_set_add(out, &b->refs[i], lo4, scale4, bin_max);
        bin_set_add(&other, &b->refs[i + 1], lo4, scale4, bin_max);
    }
    if (i < end) bin_set_add(out, &b->refs[i], lo4, scale4, bin_max);
    for (uint32_t j = 0; j < bins_used; j++) {
        for (int k = 0; k < 3; k++) box4_grow(&out->box[k][j], other.box[k][j].lo, other.box[k][j].hi);
        const __m128i c = _mm_add_epi32(_mm_load_si128((const __m128i *)out->count[j]),
                                        _mm_load_si128((const __m128i *)other.count[j]));
        _mm_store_si128((__m128i *)out->count[j], c);
    }
}

/* Half the areas (scaled by `unit`) of three boxes, in lanes 0..2: the
 * extents transposed so that each lane computes box4_half_area's sum in its
 * order (xy + yz + zx), bit for bit. */
static inline __m128 half_areas3(const __m128 lo[3], const __m128 hi[3], __m128 unit)
{
    const __m128 zero = _mm_setzero_ps();
    __m128 d0 = _mm_mul_ps(_mm_max_ps(_mm_sub_ps(hi[0], lo[0]), zero), unit);
    __m128 d1 = _mm_mul_ps(_mm_max_ps(_mm_sub_ps(hi[1], lo[1]), zero), unit);
    __m128 d2 = _mm_mul_ps(_mm_max_ps(_mm_sub_ps(hi[2], lo[2]), zero), unit);
    __m128 d3 = zero;
    _MM_TRANSPOSE4_PS(d0, d1, d2, d3); /* d0: the x extents of the three boxes, d1 y, d2 z */
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(d0, d1), _mm_mul_ps(d1, d2)), _mm_mul_ps(d2, d0));
}

/* The sweep over the bins, all three axes in SSE lanes: right to left the
 * area-weighted counts, then left to right each plane's cost; the cheapest
 * plane of the axes with a scale (ties: the lower axis, then the lower bin). */
static void bins_sweep(const bin_set *s, uint32_t bins_used, uint32_t n, const float scale[4], __m128 unit,
                       float *best_cost, int *best_axis, uint32_t *best_bin)
{
    _Alignas(16) float right_cost[BVH_BINS][4];
    __m128 lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = _mm_set1_ps(INFINITY), hi[k] = _mm_set1_ps(-INFINITY);
    __m128i count = _mm_setzero_si128();
    for (uint32_t j = bins_used - 1; j > 0; j--) {
        for (int k = 0; k < 3; k++) lo[k] = _mm_min_ps(lo[k], s->box[k][j].lo), hi[k] = _mm_max_ps(hi[k], s->box[k][j].hi);
        count = _mm_add_epi32(count, _mm_load_si128((const __m128i *)s->count[j]));
        _mm_store_ps(right_cost[j], _mm_mul_ps(_mm_cvtepi32_ps(count), half_areas3(lo, hi, unit)));
    }
    for (int k = 0; k < 3; k++) lo[k] = _mm_set1_ps(INFINITY), hi[k] = _mm_set1_ps(-INFINITY);
    count = _mm_setzero_si128();
    const __m128i all = _mm_set1_epi32((int)n), none = _mm_setzero_si128();
    /* lanes of axes without a scale, and lane 3, never offer a plane */
    const __m128i usable = _mm_castps_si128(_mm_cmpgt_ps(_mm_load_ps(scale), _mm_setzero_ps()));
    __m128 best = _mm_set1_ps(INFINITY);
    __m128i best_j = _mm_setzero_si128();
    for (uint32_t j = 0; j + 1 < bins_used; j++) {
        for (int k = 0; k < 3; k++) lo[k] = _mm_min_ps(lo[k], s->box[k][j].lo), hi[k] = _mm_max_ps(hi[k], s->box[k][j].hi);
        count = _mm_add_epi32(count, _mm_load_si128((const __m128i *)s->count[j]));
        const __m128 cost = _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(count), half_areas3(lo, hi, unit)),
                                       _mm_load_ps(right_cost[j + 1]));
        const __m128i split = _mm_andnot_si128(_mm_or_si128(_mm_cmpeq_epi32(count, none), _mm_cmpeq_epi32(count, all)),
                                               usable);
        const __m128 better = _mm_and_ps(_mm_cmplt_ps(cost, best), _mm_castsi128_ps(split));
        best = _mm_blendv_ps(best, cost, better);
        best_j = _mm_blendv_epi8(best_j, _mm_set1_epi32((int)j), _mm_castps_si128(better));
    }
    _Alignas(16) float costs[4];
    _Alignas(16) int32_t js[4];
    _mm_store_ps(costs, best), _mm_store_si128((__m128i *)js, best_j);
    for (int k = 0; k < 3; k++)
        if (costs[k] < *best_cost) *best_cost = costs[k], *best_axis = k, *best_bin = (uint32_t)js[k];
}

/* Grows a child's bounds by one reference. */
static inline void grow_child(node_bounds *child, const prim_ref *r)
{
    const __m128 c = ref_centroid(r);
    box4_grow(&child->box, ref_lo(r), r->hi);
    box4_grow(&child->cbox, c, c);
}

/* The chosen plane: references whose bin on `axis` is above `bin` go right. */
typedef struct axis_split {
    int axis;
    float lo, scale, bin_max;
    uint32_t bin;
} axis_split;

/* bins_of's arithmetic (ref_centroid's too) in one lane, so that a
 * reference goes to the side its bin was counted on. */
static inline bool goes_right(const axis_split *s, const prim_ref *r)
{
    float lo, hi;
    memcpy(&lo, (const char *)&r->lo + sizeof(float) * (size_t)s->axis, sizeof lo);
    memcpy(&hi, (const char *)&r->hi + sizeof(float) * (size_t)s->axis, sizeof hi);
    const __m128 c = _mm_add_ss(_mm_mul_ss(_mm_set_ss(lo), _mm_set_ss(0.5f)), _mm_mul_ss(_mm_set_ss(hi), _mm_set_ss(0.5f)));
    __m128 f = _mm_mul_ss(_mm_sub_ss(c, _mm_set_ss(s->lo)), _mm_set_ss(s->scale));
    f = _mm_min_ss(_mm_max_ss(f, _mm_setzero_ps()), _mm_set_ss(s->bin_max));
    return (uint32_t)_mm_cvttss_si32(f) > s->bin;
}

/* Partitions [begin, end) (bounds `nb`) by the node's choice and says where
 * it split; the children's bounds into `child`, gathered by the partition. */
static split_choice choose_split(const builder *b, uint32_t begin, uint32_t end, uint32_t depth,
                                 const node_bounds *nb, node_bounds child[2])
{
    const uint32_t n = end - begin;
    const box4 box = nb->box, cbox = nb->cbox;
    const box3 unpacked = box4_unpack(&box), *bounds = &unpacked;
    if (n <= 1 || depth >= b->max_depth) return (split_choice){true, 0};

    /* one pass bins all three axes; an axis whose centroids coincide (or
     * whose extent is not finite) gets scale 0 and offers no plane.  Small
     * nodes get fewer bins (the sweep's fixed cost would dominate them). */
    const uint32_t bins_used = bins_for(n);
    _Alignas(16) float clo[4], chi[4], scale[4];
    _mm_store_ps(clo, cbox.lo), _mm_store_ps(chi, cbox.hi);
    bool any_axis = false;
    for (int k = 0; k < 3; k++) {
        const float extent = chi[k] - clo[k];
        scale[k] = extent > 0.0f && isfinite(extent) ? (float)bins_used * (1.0f - 0x1p-20f) / extent : 0.0f;
        if (!(scale[k] > 0.0f) || !isfinite(scale[k])) scale[k] = 0.0f;
        any_axis |= scale[k] > 0.0f;
    }
    scale[3] = 0.0f;
    const __m128 lo4 = cbox.lo, scale4 = _mm_load_ps(scale), bin_max = _mm_set1_ps((float)(bins_used - 1));
    /* areas relative to the node's largest extent: the SAH compares ratios,
     * and relative extents (<= 1) neither overflow nor underflow in float */
    const float largest = max_f(bounds->hi[0] - bounds->lo[0], max_f(bounds->hi[1] - bounds->lo[1], bounds->hi[2] - bounds->lo[2]));
    const __m128 unit = _mm_set1_ps(largest > 0.0f && isfinite(largest) && isfinite(1.0f / largest) ? 1.0f / largest : 1.0f);
    float best_cost = INFINITY;
    int best_axis = -1;
    uint32_t best_bin = 0;
    if (any_axis) {
        bin_set bins;
        bins_bin(b, begin, end, bins_used, lo4, scale4, bin_max, &bins);
        bins_sweep(&bins, bins_used, n, scale, unit, &best_cost, &best_axis, &best_bin);
    }
    const float area = box4_half_area(&box, unit);
    /* C_trav + (N_L SA_L + N_R SA_R) / SA against the leaf's N (in units of C_isect) */
    const bool leaf_cheaper = best_axis < 0 || !(area > 0.0f) || b->node_cost + best_cost / area >= (float)n;
    if (n <= b->leaf_size && leaf_cheaper) return (split_choice){true, 0};

    uint32_t mid;
    if (best_axis < 0) {
        mid = begin + n / 2; /* every centroid coincides: halve the order */
        range_bounds(b, begin, mid, &child[0]);
        range_bounds(b, mid, end, &child[1]);
    } else {
        /* Hoare's partition on the bin of the chosen axis; each scan grows
         * the bounds of the side it keeps */
        for (int c = 0; c < 2; c++) box4_empty(&child[c].box), box4_empty(&child[c].cbox);
        const axis_split split = {best_axis, clo[best_axis], scale[best_axis], (float)(bins_used - 1), best_bin};
        prim_ref *refs = b->refs;
        uint32_t i = begin, j = end;
        for (;;) {
            for (; i < j && !goes_right(&split, &refs[i]); i++) grow_child(&child[0], &refs[i]);
            for (; i < j && goes_right(&split, &refs[j - 1]); j--) grow_child(&child[1], &refs[j - 1]);
            if (i >= j) break;
            const prim_ref right = refs[i];
            refs[i] = refs[j - 1], refs[j - 1] = right;
            grow_child(&child[0], &refs[i++]);
            grow_child(&child[1], &refs[--j]);
        }
        mid = i;
    }
    return (split_choice){false, mid};
}


/* ---- Pre-splitting (Karras & Aila 2013, section 5) ----
 * Before the build, the triangles whose boxes are far larger than the
 * scene's typical triangle box (BVH_SPLIT_AREA_FACTOR times the median's
 * binade or more: a map's long walls, floors and slopes, none of a dense
 * mesh's) are cut into parts, each its own reference with the box of its
 * part: the builder then separates space where one box would have spanned
 * it.  The cuts are the planes of the scene box's dyadic grid, the
 * coarsest crossing the part first (the planes a top-down build is likely
 * to cut at too), in double, each part's box rounded outward to floats.
 * The extra references, a share of the triangles (options.split_share),
 * are spread over the candidates in proportion to the square root of
 * their box areas, none cut into parts smaller than the threshold. */
typedef struct dbox {
    double lo[3], hi[3];
} dbox;

/* A float no greater (lo) or no smaller (hi) than x. */
static float round_down(double x) { float f = (float)x; return (double)f > x ? nextafterf(f, -INFINITY) : f; }
static float round_up(double x) { float f = (float)x; return (double)f < x ? nextafterf(f, INFINITY) : f; }

/* A reference to `record` with box b, rounded outward to floats. */
static prim_ref ref_of(const dbox *b, uint32_t record)
{
    prim_ref r;
    r.lo = _mm_setr_ps(round_down(b->lo[0]), round_down(b->lo[1]), round_down(b->lo[2]), 0.0f);
    r.lo = _mm_insert_ps(r.lo, _mm_castsi128_ps(_mm_cvtsi32_si128((int)record)), 0x30);
    r.hi = _mm_setr_ps(round_up(b->hi[0]), round_up(b->hi[1]), round_up(b->hi[2]), 0.0f);
    return r;
}

/* The most important plane of the scene's dyadic grid crossing box b
 * (the coarsest level of the grid with a plane strictly inside the box,
 * over the three axes: the planes a top-down build cuts first): its axis
 * and position; false when none within 2^-32 of the scene's extent. */
static bool dyadic_plane(const dbox *b, const double scene_lo[3], const double scene_ext[3], int *axis, double *at)
{
    int best = 64;
    for (int k = 0; k < 3; k++) {
        if (!(scene_ext[k] > 0.0)) continue;
        const double scale = 0x1p32 / scene_ext[k];
        const double u0 = (b->lo[k] - scene_lo[k]) * scale, u1 = (b->hi[k] - scene_lo[k]) * scale;
        if (!(u0 >= 0.0) || !(u1 < 0x1p32) || !(u0 < u1)) continue;
        const uint64_t lo = (uint64_t)u0, hi = (uint64_t)u1, differ = lo ^ hi;
        if (!differ) continue;
        const int bit = 63 - __builtin_clzll(differ), level = 32 - bit;
        const uint64_t grid = hi & ~((UINT64_C(1) << bit) - 1u); /* lo < grid <= hi */
        if (level < best && (double)grid > u0 && (double)grid < u1) {
            best = level, *axis = k;
            *at = scene_lo[k] + (double)grid / scale;
        }
    }
    return best < 64;
}

/* A convex polygon (a triangle's part) in double: a triangle cut by
 * axis-aligned planes has at most 9 corners (3 + 2 per axis); room for
 * more, for what rounding may add. */
enum { POLYGON_MAX = 16 };
typedef struct polygon {
    int n;
    double v[POLYGON_MAX][3];
} polygon;

/* The part of `in` on one side of the plane x[axis] = at (`upper`: x >= at)
 * and its box; false (nothing made) when it would not fit: a corner
 * dropped would leave the box short of the part. */
static bool polygon_cut(const polygon *in, int axis, double at, bool upper, polygon *out, dbox *box)
{
    const double sign = upper ? 1.0 : -1.0;
    out->n = 0;
    for (int i = 0; i < in->n; i++) {
        const double *a = in->v[i], *c = in->v[(i + 1) % in->n];
        const double da = sign * (a[axis] - at), dc = sign * (c[axis] - at);
        const bool keep = da >= 0.0, cross = (da < 0.0 && dc > 0.0) || (da > 0.0 && dc < 0.0);
        if (out->n + keep + cross > POLYGON_MAX) return false;
        if (keep) memcpy(out->v[out->n++], a, sizeof out->v[0]);
        if (cross) {
            const double t = da / (da - dc);
            double *q = out->v[out->n++];
            for (int k = 0; k < 3; k++) q[k] = a[k] + t * (c[k] - a[k]);
            q[axis] = at;
        }
    }
    for (int k = 0; k < 3; k++) box->lo[k] = INFINITY, box->hi[k] = -INFINITY;
    for (int i = 0; i < out->n; i++)
        for (int k = 0; k < 3; k++) {
            box->lo[k] = out->v[i][k] < box->lo[k] ? out->v[i][k] : box->lo[k];
            box->hi[k] = out->v[i][k] > box->hi[k] ? out->v[i][k] : box->hi[k];
        }
    return true;
}

/* `pieces` more references for the record's part `poly` (box b) at
 * refs[*at] on: cut at the most important dyadic plane crossing the box,
 * the pieces left shared between the halves by their areas. */
static void split_count(const polygon *poly, const dbox *b, uint32_t pieces, uint32_t record, const double scene_lo[3],
                        const double scene_ext[3], prim_ref *refs, uint32_t *at)
{
    int axis = 0;
    double plane = 0.0;
    if (pieces == 0 || !dyadic_plane(b, scene_lo, scene_ext, &axis, &plane)) {
        refs[(*at)++] = ref_of(b, record);
        return;
    }
    polygon part[2];
    dbox box[2];
    /* no cut when the plane only touches the part, or a part would not fit */
    if (!polygon_cut(poly, axis, plane, false, &part[0], &box[0]) ||
        !polygon_cut(poly, axis, plane, true, &part[1], &box[1]) || part[0].n < 3 || part[1].n < 3) {
        refs[(*at)++] = ref_of(b, record);
        return;
    }
    const double a0 = half_area(box[0].lo, box[0].hi), a1 = half_area(box[1].lo, box[1].hi);
    const uint32_t left = (uint32_t)((double)(pieces - 1u) * (a0 + a1 > 0.0 ? a0 / (a0 + a1) : 0.5) + 0.5);
    split_count(&part[0], &box[0], left, record, scene_lo, scene_ext, refs, at);
    split_count(&part[1], &box[1], pieces - 1u - left, record, scene_lo, scene_ext, refs, at);
}

/* Half the surface area of a reference's box. */
static inline float ref_half_area(const prim_ref *r)
{
    const __m128 d = _mm_max_ps(_mm_sub_ps(r->hi, ref_lo(r)), _mm_setzero_ps());
    _Alignas(16) float e[4];
    _mm_store_ps(e, d);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

/* A triangle to cut: its reference, weight and most extra parts. */
typedef struct split_candidate {
    uint32_t ref;
    float weight;
    uint32_t most;
} split_candidate;

/* Cuts the references refs[0 .. n) (one per record) into parts, appended
 * up to `capacity`; returns the references' count. */
static uint32_t presplit(const rtt_scene *scene, const kd_triangle *records, prim_ref *refs, uint32_t n,
                         uint32_t capacity)
{
    if (capacity <= n || n == 0) return n;
    /* the scene's box and the median box area's binade (a histogram of the areas' exponents) */
    uint32_t histogram[256] = {0};
    __m128 lo4 = _mm_set1_ps(INFINITY), hi4 = _mm_set1_ps(-INFINITY);
    for (uint32_t i = 0; i < n; i++) {
        const float a = ref_half_area(&refs[i]);
        uint32_t bits;
        memcpy(&bits, &a, sizeof bits);
        histogram[bits >> 23 & 255u]++;
        lo4 = _mm_min_ps(lo4, ref_lo(&refs[i])), hi4 = _mm_max_ps(hi4, refs[i].hi);
    }
    uint32_t seen = 0, exponent = 0;
    while (exponent < 255u && (seen += histogram[exponent]) <= n / 2) exponent++;
    const float limit = ldexpf(BVH_SPLIT_AREA_FACTOR, (int)exponent - 126); /* the factor times the binade's top */
    split_candidate *cand = malloc((size_t)n * sizeof *cand);
    if (!cand) return n; /* no parts: the tree is the plain one */
    uint32_t count = 0;
    double x_all = 0.0; /* the X at which every candidate has its most */
    for (uint32_t i = 0; i < n; i++) {
        const float a = ref_half_area(&refs[i]);
        if (!(a > limit) || !(a < INFINITY)) continue;
        const float ratio = a / limit;
        cand[count] = (split_candidate){i, sqrtf(a), ratio < 63.0f ? (uint32_t)ratio : 63u};
        const double x = (cand[count].most + 1.0) / cand[count].weight;
        x_all = x > x_all ? x : x_all;
        count++;
    }
    /* the largest X (bisection) whose parts, floor(X weight) each up to its most, fit the budget */
    const double budget = (double)(capacity - n);
    double lo_x = 0.0, hi_x = x_all;
    for (int it = 0; it < 30 && count; it++) {
        const double mid = 0.5 * (lo_x + hi_x);
        double sum = 0.0;
        for (uint32_t c = 0; c < count; c++) {
            const double k = floor(mid * cand[c].weight);
            sum += k < cand[c].most ? k : cand[c].most;
        }
        if (sum <= budget) lo_x = mid;
        else hi_x = mid;
    }
    _Alignas(16) float slo[4], shi[4];
    _mm_store_ps(slo, lo4), _mm_store_ps(shi, hi4);
    const double scene_lo[3] = {slo[0], slo[1], slo[2]};
    const double scene_ext[3] = {(double)shi[0] - slo[0], (double)shi[1] - slo[1], (double)shi[2] - slo[2]};
    uint32_t at = n;
    for (uint32_t c = 0; c < count; c++) {
        const double k = floor(lo_x * cand[c].weight);
        const uint32_t pieces = k < cand[c].most ? (uint32_t)k : cand[c].most, i = cand[c].ref;
        if (pieces == 0 || at + pieces > capacity) continue;
        const uint32_t record = ref_record(&refs[i]);
        rtt_vec3 v[3];
        rtt_scene_triangle(scene, records[record].prim, v);
        const polygon tri = {3, {{v[0].x, v[0].y, v[0].z}, {v[1].x, v[1].y, v[1].z}, {v[2].x, v[2].y, v[2].z}}};
        _Alignas(16) float lo[4], hi[4];
        _mm_store_ps(lo, ref_lo(&refs[i])), _mm_store_ps(hi, refs[i].hi);
        const dbox b = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
        prim_ref part[64];
        uint32_t made = 0;
        split_count(&tri, &b, pieces, record, scene_lo, scene_ext, part, &made);
        refs[i] = part[0]; /* the first part in the triangle's place, the others appended */
        for (uint32_t j = 1; j < made; j++) refs[at++] = part[j];
    }
    free(cand);
    return at;
}

static void set_box(bvh_child *c, const box3 *bounds)
{
    memcpy(c->lo, bounds->lo, sizeof c->lo);
    memcpy(c->hi, bounds->hi, sizeof c->hi);
}

/* What a subtree's build counts: its next free slot, its leaves, its
 * deepest leaf. */
typedef struct subtree_count {
    uint32_t next, leaves, depth;
} subtree_count;

/* Builds [begin, end) (bounds `nb`) into `out`, inner nodes from slot
 * count->next on, in depth-first order (a node before its left subtree,
 * that before its right one). */
static void build_subtree(const builder *b, uint32_t begin, uint32_t end, uint32_t depth, const node_bounds *nb,
                          bvh_child *out, subtree_count *count)
{
    node_bounds child[2];
    split_choice s = choose_split(b, begin, end, depth, nb, child);
    const box3 bounds = box4_unpack(&nb->box);
    set_box(out, &bounds);
    if (s.leaf) {
        out->index = begin;
        out->count = end - begin;
        count->leaves++;
        if (depth > count->depth) count->depth = depth;
        return;
    }
    const uint32_t slot = count->next++;
    out->index = slot;
    out->count = 0;
    build_subtree(b, begin, s.mid, depth + 1, &child[0], &b->slots[slot].child[0], count);
    build_subtree(b, s.mid, end, depth + 1, &child[1], &b->slots[slot].child[1], count);
}

/* A subtree left for a task: its range, where its reference goes, and
 * (after the build) its slots first .. counted.next. */
typedef struct subtree_task {
    uint32_t begin, end, depth;
    bvh_child *out;
    node_bounds bounds;
    uint32_t first;
    subtree_count counted;
} subtree_task;

typedef struct task_context {
    const builder *b;
    subtree_task *tasks;
} task_context;

static void run_subtree_task(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    const task_context *c = context;
    subtree_task *t = &c->tasks[task];
    t->counted = (subtree_count){.next = t->first, .depth = t->depth};
    build_subtree(c->b, t->begin, t->end, t->depth, &t->bounds, t->out, &t->counted);
}

/* The final layout: depth first, children after their parent.  A task's
 * slots are in that order already, so its block moves as a whole. */
typedef struct layout {
    const builder *b;
    const subtree_task *tasks;
    uint32_t task_count, top_slots;
    bvh_node *nodes;
    uint32_t next;
} layout;

/* Places what `ref` (already in its final place) references at nodes[next]
 * on and points it there; leaves reference their records where they are. */
static void place(layout *l, bvh_child *ref)
{
    if (ref->count > 0) return;
    const uint32_t slot = ref->index, at = l->next;
    if (slot < l->top_slots) { /* a node of the top: copied, its children placed after it */
        l->nodes[l->next++] = l->b->slots[slot];
        ref->index = at;
        place(l, &l->nodes[at].child[0]);
        place(l, &l->nodes[at].child[1]);
        return;
    }
    const subtree_task *t = l->tasks;
    while (t->first != slot) t++; /* the task whose root this is (a subtree's root takes its first slot) */
    const uint32_t count = t->counted.next - t->first;
    for (uint32_t i = 0; i < count; i++) {
        bvh_node node = l->b->slots[t->first + i];
        for (int c = 0; c < 2; c++)
            if (node.child[c].count == 0) node.child[c].index = node.child[c].index - t->first + at;
        l->nodes[at + i] = node;
    }
    ref->index = at;
    l->next += count;
}

/* A stored box is the exact box grown by 1e-4 of its extent and four
 * ulps of its largest coordinate (and FLT_MIN): a flat box gets a thickness,
 * so a ray running in its plane is inside rather than at 0 * inf, and the
 * kernels' rounded slab distances never clip a hit on the box's face. */
static void widen(bvh_child *c)
{
    float scale = 0.0f, extent = 0.0f;
    for (int k = 0; k < 3; k++) {
        scale = max_f(scale, max_f(fabsf(c->lo[k]), fabsf(c->hi[k])));
        extent = max_f(extent, c->hi[k] - c->lo[k]);
    }
    const float margin = extent * 1e-4f + scale * 0x1p-21f + FLT_MIN;
    for (int k = 0; k < 3; k++) c->lo[k] -= margin, c->hi[k] += margin;
}

/* The child's term of the tree's SAH cost (its area relative to the root's,
 * times its records for a leaf), before widen grows its box. */
static double sah_term(const bvh_child *c, double root_area)
{
    box3 box;
    memcpy(box.lo, c->lo, sizeof box.lo);
    memcpy(box.hi, c->hi, sizeof box.hi);
    const double weight = root_area > 0.0 ? box_half_area(&box) / root_area : 1.0;
    return c->count > 0 ? weight * (double)c->count : weight;
}

/* The leaf records in leaf order (the references' order after the build),
 * a block of them per task. */
typedef struct record_copy {
    const rtt_scene *scene;
    const kd_triangle *records;
    const prim_ref *refs;
    bvh_tree *tree;
    uint32_t per_task;
} record_copy;

static void copy_records(void *context, uint32_t thread, uint32_t task)
{
    (void)thread;
    const record_copy *c = context;
    const uint32_t first = task * c->per_task, n = c->tree->triangle_count;
    const uint32_t end = n - first < c->per_task ? n : first + c->per_task;
    for (uint32_t i = first; i < end; i++) {
        const kd_triangle *rec = &c->records[ref_record(&c->refs[i])];
        rtt_vec3 p[3];
        rtt_scene_triangle(c->scene, rec->prim, p);
        bvh_corners *corners = &c->tree->corners[i];
        for (int v = 0; v < 3; v++) corners->v[v][0] = p[v].x, corners->v[v][1] = p[v].y, corners->v[v][2] = p[v].z;
        corners->prim = rec->prim;
        c->tree->triangles[i] = *rec;
    }
}

/* The bytes the records' solids take (bvh_tree.info.memory_bytes counts them). */
static uint64_t solids_bytes(const bvh_tree *tree)
{
    return tree->solid ? (uint64_t)tree->triangle_count * sizeof *tree->solid +
                             (uint64_t)tree->solid_count * sizeof *tree->solid_box
                       : 0;
}

bool bvh_tree_mark_solids(bvh_tree *tree, const rtt_scene *scene, rtt_error *err)
{
    tree->info.memory_bytes -= solids_bytes(tree);
    free(tree->solid), free(tree->solid_box);
    tree->solid = NULL, tree->solid_box = NULL, tree->solid_count = 0;
    if (!scene->triangle_mesh || tree->triangle_count == 0) return true;
    /* the triangles with no record (degenerate, or unrepresentable) are no part of any surface here */
    uint8_t *dropped = malloc((size_t)scene->triangle_count + 1);
    uint32_t *entry = malloc(((size_t)scene->mesh_count + 1) * sizeof *entry);
    scene_solids solids = {0};
    bool ok = dropped && entry;
    if (ok) {
        memset(dropped, 1, scene->triangle_count);
        for (uint32_t i = 0; i < tree->triangle_count; i++) dropped[tree->triangles[i].prim] = 0;
        ok = scene_solids_find(&solids, scene, dropped); /* on failure it keeps nothing */
    }
    if (ok && solids.solid_count) {
        tree->solid = malloc((size_t)tree->triangle_count * sizeof *tree->solid);
        tree->solid_box = malloc((size_t)solids.solid_count * sizeof *tree->solid_box);
        ok = tree->solid && tree->solid_box;
        for (uint32_t m = 0; ok && m < scene->mesh_count; m++)
            if (solids.mesh_solid[m]) {
                entry[m] = tree->solid_count;
                memcpy(tree->solid_box[tree->solid_count++], solids.mesh_box[m], sizeof *tree->solid_box);
            }
        for (uint32_t i = 0; ok && i < tree->triangle_count; i++) {
            const uint32_t prim = tree->triangles[i].prim, m = scene->triangle_mesh[prim];
            const int32_t outward = solids.triangle_outward[prim];
            tree->solid[i] = outward && solids.mesh_solid[m] ? outward * (int32_t)(entry[m] + 1u) : 0;
        }
    }
    scene_solids_free(&solids);
    free(dropped), free(entry);
    if (ok) {
        tree->info.memory_bytes += solids_bytes(tree);
        return true;
    }
    free(tree->solid), free(tree->solid_box);
    tree->solid = NULL, tree->solid_box = NULL, tree->solid_count = 0;
    return rtt_error_set(err, "%s: out of memory finding the solids for back-face culling", scene->path);
}

void bvh_tree_free(bvh_tree *tree)
{
    free(tree->arrays);
    free(tree->solid);
    free(tree->solid_box);
    memset(tree, 0, sizeof *tree);
}

/* Arrays laid out one after another in one allocation, each aligned:
 * where an array of `count` elements goes in a block whose arrays so far
 * end at *bytes (`align` a power of two); *bytes then ends after it.
 * Counts are at most 2^32 and elements a few cache lines, so no sum
 * overflows a 64-bit size. */
static size_t block_array(size_t *bytes, size_t count, size_t element, size_t align)
{
    const size_t at = (*bytes + align - 1) & ~(align - 1);
    *bytes = at + count * element;
    return at;
}

bool bvh_build_sah(const rtt_scene *scene, const bvh_build_options *options, bvh_tree *tree, rtt_error *err)
{
    const double start = rtt_clock_seconds();
    memset(tree, 0, sizeof *tree);
    builder b = {0};
    b.leaf_size = options->leaf_size ? options->leaf_size : BVH_DEFAULT_LEAF_SIZE;
    if (b.leaf_size > BVH_LEAF_SIZE_MAX) b.leaf_size = BVH_LEAF_SIZE_MAX;
    b.max_depth = options->max_depth && options->max_depth < BVH_DEPTH_LIMIT ? options->max_depth : BVH_DEPTH_LIMIT;
    b.node_cost = options->node_cost > 0.0f && options->node_cost <= BVH_NODE_COST_MAX ? options->node_cost
                                                                                        : BVH_DEFAULT_NODE_COST;
    const uint32_t threads = rtt_thread_count(options->threads);

    const uint32_t n_tri = scene->triangle_count;
    const float share = options->split_share == 0.0f ? BVH_DEFAULT_SPLIT_SHARE
                        : options->split_share > 0.0f ? fminf(options->split_share, BVH_SPLIT_SHARE_MAX) : 0.0f;
    /* the references: one per triangle, and the parts pre-splitting may add */
    const uint64_t wanted = (uint64_t)n_tri + (uint64_t)((double)share * n_tri);
    const uint32_t ref_capacity = wanted < UINT32_MAX / 2u ? (uint32_t)wanted : n_tri;
    const uint32_t top_slots = 2u * BVH_TASKS_PER_THREAD * threads + 2u;
    /* the build's own arrays, one allocation: references, records in scene
     * order, inner-node slots (a subtree of n references has at most n - 1) */
    size_t scratch_bytes = 0;
    const size_t refs_at = block_array(&scratch_bytes, ref_capacity, sizeof(prim_ref), 64);
    const size_t slots_at = block_array(&scratch_bytes, (size_t)top_slots + ref_capacity, sizeof(bvh_node), 64);
    const size_t records_at = block_array(&scratch_bytes, n_tri, sizeof(kd_triangle), 64);
    char *scratch = rtt_alloc_pages(scratch_bytes, 64);
    prim_ref *refs = scratch ? (prim_ref *)(scratch + refs_at) : NULL;
    bvh_node *slots = scratch ? (bvh_node *)(scratch + slots_at) : NULL;
    kd_triangle *records = scratch ? (kd_triangle *)(scratch + records_at) : NULL;
    subtree_task *tasks = scratch ? malloc((size_t)(BVH_TASKS_PER_THREAD * threads + 2u) * sizeof *tasks) : NULL;
    if (!tasks) goto out_of_memory;
    uint32_t n = 0;
    for (uint32_t i = 0; i < n_tri; i++) {
        rtt_vec3 p[3];
        rtt_scene_triangle(scene, i, p);
        if (!kd_triangle_record(&records[n], p, i)) continue;
        const __m128 a = _mm_setr_ps(p[0].x, p[0].y, p[0].z, 0.0f), b1 = _mm_setr_ps(p[1].x, p[1].y, p[1].z, 0.0f),
                     c = _mm_setr_ps(p[2].x, p[2].y, p[2].z, 0.0f);
        refs[n].lo = _mm_insert_ps(_mm_min_ps(a, _mm_min_ps(b1, c)), _mm_castsi128_ps(_mm_cvtsi32_si128((int)n)),
                                   0x30); /* record index into lane 3 */
        refs[n].hi = _mm_max_ps(a, _mm_max_ps(b1, c));
        n++;
    }
    const uint32_t triangles = n;
    n = presplit(scene, records, refs, n, n + (ref_capacity - n_tri));
    b.refs = refs, b.slots = slots;

    /* the top, breadth first on this thread, until there are enough subtrees */
    uint32_t task_count = 0, next_top = 0;
    if (n > 0) {
        tasks[task_count] = (subtree_task){.begin = 0, .end = n, .depth = 0, .out = &tree->root};
        range_bounds(&b, 0, n, &tasks[task_count++].bounds);
    }
    const uint32_t want = threads > 1 ? BVH_TASKS_PER_THREAD * threads : 1;
    while (task_count > 0 && task_count < want) {
        uint32_t largest = 0;
        for (uint32_t i = 1; i < task_count; i++)
            if (tasks[i].end - tasks[i].begin > tasks[largest].end - tasks[largest].begin) largest = i;
        subtree_task t = tasks[largest];
        if (t.end - t.begin < BVH_TASK_MIN_TRIANGLES) break;
        node_bounds child[2];
        split_choice s = choose_split(&b, t.begin, t.end, t.depth, &t.bounds, child);
        if (s.leaf) break; /* the largest is a leaf (depth bound): the rest are smaller */
        const box3 bounds = box4_unpack(&t.bounds.box);
        set_box(t.out, &bounds);
        const uint32_t slot = next_top++;
        t.out->index = slot;
        t.out->count = 0;
        tasks[largest] = (subtree_task){.begin = t.begin, .end = s.mid, .depth = t.depth + 1, .out = &slots[slot].child[0], .bounds = child[0]};
        tasks[task_count++] = (subtree_task){.begin = s.mid, .end = t.end, .depth = t.depth + 1, .out = &slots[slot].child[1], .bounds = child[1]};
    }
    for (uint32_t i = 0; i < task_count; i++) tasks[i].first = top_slots + tasks[i].begin;
    task_context context = {&b, tasks};
    rtt_parallel_run(task_count, threads, run_subtree_task, &context);

    /* the inner nodes reached from the root, laid out depth first */
    uint32_t node_count = next_top, leaves = 0, depth = 0;
    for (uint32_t i = 0; i < task_count; i++) {
        node_count += tasks[i].counted.next - tasks[i].first;
        leaves += tasks[i].counted.leaves;
        depth = tasks[i].counted.depth > depth ? tasks[i].counted.depth : depth;
    }
    /* the tree's arrays, one allocation: nodes (a cache line each), records, corners */
    size_t tree_bytes = 0;
    const size_t nodes_at = block_array(&tree_bytes, node_count, sizeof(bvh_node), 64);
    const size_t triangles_at = block_array(&tree_bytes, n, sizeof(kd_triangle), 64);
    const size_t corners_at = block_array(&tree_bytes, n, sizeof(bvh_corners), 64);
    char *arrays = rtt_alloc_pages(tree_bytes, 64);
    if (!arrays) goto out_of_memory;
    tree->arrays = arrays;
    tree->nodes = (bvh_node *)(arrays + nodes_at);
    tree->triangles = (kd_triangle *)(arrays + triangles_at);
    tree->corners = (bvh_corners *)(arrays + corners_at);
    tree->node_count = node_count;
    tree->triangle_count = n;
    double sah = 0.0;
    if (n > 0) {
        layout l = {.b = &b, .tasks = tasks, .task_count = task_count, .top_slots = top_slots, .nodes = tree->nodes};
        place(&l, &tree->root);
        box3 root_box;
        memcpy(root_box.lo, tree->root.lo, sizeof root_box.lo);
        memcpy(root_box.hi, tree->root.hi, sizeof root_box.hi);
        const double root_area = box_half_area(&root_box);
        sah = sah_term(&tree->root, root_area);
        widen(&tree->root);
        for (uint32_t i = 0; i < node_count; i++)
            for (int c = 0; c < 2; c++) {
                sah += sah_term(&tree->nodes[i].child[c], root_area);
                widen(&tree->nodes[i].child[c]);
            }
        const uint32_t blocks = 4u * threads, per_task = (n + blocks - 1) / blocks;
        record_copy copy = {scene, records, refs, tree, per_task};
        rtt_parallel_run((n + per_task - 1) / per_task, threads, copy_records, &copy);
    }
    free(scratch), free(tasks);

    rtt_tree_info *info = &tree->info;
    info->depth = depth;
    info->max_depth = b.max_depth;
    info->node_count = tree->node_count + leaves; /* inner nodes and leaves, as the kd-tree counts them */
    info->leaf_count = leaves;
    info->references = tree->triangle_count; /* with the parts of pre-split triangles */
    info->reference_cap = (uint64_t)triangles + (ref_capacity - n_tri);
    info->sah_cost = sah;
    info->memory_bytes = (uint64_t)tree->node_count * sizeof(bvh_node) +
                         (uint64_t)tree->triangle_count * (sizeof(kd_triangle) + sizeof(bvh_corners));
    info->build_seconds = rtt_clock_seconds() - start;
    return true;

out_of_memory:
    free(scratch), free(tasks);
    bvh_tree_free(tree);
    return rtt_error_set(err, "%s: out of memory building the BVH (%u triangles)", scene->path, n_tri);
}

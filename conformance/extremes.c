/* The numerical-extremes suite (docs/ARCHITECTURE.md "Conformance", Extremes): scenes
 * built in code, run through the reference and every engine named, each
 * result one check on one engine.  The reference is compared with brute
 * force over every triangle; every other engine with the reference.
 * conformance/README.md states what is asserted per engine and why. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "engine/clock.h"
#include "extremes_internal.h"
#include "rtt/reference.h"

#define DEFAULT_MAX_RAYS 8192u
#define DEFAULT_EMBREE_ESCAPE_LIMIT 0.02
#define DEEP_TREE_TRIANGLES 200u
#define DEEP_TREE_MAX_DEPTH 64u   /* the deepest tree the builders allow */
#define SEED 0xE7E7E5EEDull
/* Scales beyond 10^this are outside Embree's precision range (measured:
 * it loses most hits at 1e+-18 and 1e+-20, none at 1e+-10). */
#define EMBREE_RANGE_LOG10 15.0

void rtt_extremes_config_default(rtt_extremes_config *config)
{
    memset(config, 0, sizeof *config);
    config->max_rays = DEFAULT_MAX_RAYS;
    config->embree_escape_limit = DEFAULT_EMBREE_ESCAPE_LIMIT;
}

typedef struct run_context {
    const rtt_extremes_config *config;
    rtt_conform_engine_spec specs[64];
    int spec_count;
    size_t max_rays;
    rtt_extremes_report *report;
    rtt_error *err;
} run_context;

/* One hit-by-hit check: rays through one scene. */
typedef struct check_spec {
    const char *name;
    const rtt_scene *scene;
    const rtt_ray *rays;
    size_t n;
    bool grazing_by_design;        /* rays aimed at edges, vertices or along planes */
    bool beyond_embree;            /* outside Embree's precision range: reported for it */
    const uint8_t *must_miss;      /* per ray, NULL when none: invalid rays */
    const uint32_t *degenerate;    /* zero-area prims no engine may hit */
    uint32_t degenerate_count;
    uint32_t max_tree_depth;       /* 0 → the builders' default */
    const rtt_ray *timing_rays;    /* valid rays timed beside the check's own, or NULL */
    size_t timing_n;
} check_spec;

static bool is_embree(const char *name) { return strcmp(name, "embree") == 0; }
static bool is_reference(const char *name) { return strcmp(name, "reference") == 0; }

/* Whether the engine traces with a watertight test (the reference does). */
static bool is_watertight(rtt_engine *engine) { return strcmp(rtt_engine_isect_name(engine), "watertight") == 0; }

/* Share of grazing hit/miss a row may have.  Where the rays graze by
 * design, neither Embree nor the projected barycentric test is watertight,
 * so their share is measured and reported (1.0: unbounded); Embree's bound
 * applies to the watertight checks instead.  The reference and the
 * optimized engine's watertight test allow none: they run the brute force's
 * triangle test, in the same arithmetic. */
static double grazing_limit(const char *engine_name, bool watertight, bool by_design)
{
    if (is_reference(engine_name) || (watertight && !is_embree(engine_name))) return 0.0;
    if (by_design) return 1.0;
    return is_embree(engine_name) ? RTT_CONFORM_GRAZING_SHARE_EMBREE : RTT_CONFORM_GRAZING_SHARE_OPTIMIZED;
}

static void describe_limit(char *note, size_t size, double limit)
{
    size_t len = strlen(note);
    if (limit >= 1.0)
        snprintf(note + len, size - len, "%sgrazing reported, not bounded", len ? "; " : "");
    else
        snprintf(note + len, size - len, "%sgrazing <= %g%%", len ? "; " : "", 100.0 * limit);
}

/* Closest hit over every triangle; ties keep the smaller prim. */
static void brute_force(const rtt_scene *s, const rtt_ray *rays, size_t n, rtt_hit *hits)
{
    for (size_t i = 0; i < n; i++) {
        hits[i] = (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS};
        for (uint32_t p = 0; p < s->triangle_count; p++) {
            rtt_vec3 tri[3];
            float t, u, v;
            rtt_scene_triangle(s, p, tri);
            if (rtt_reference_intersect_triangle(&rays[i], tri, &t, &u, &v) && t < hits[i].t)
                hits[i] = (rtt_hit){t, u, v, p};
        }
    }
}

/* Hits no engine may report: on invalid rays and on zero-area prims. */
static uint64_t forbidden_hits(const check_spec *c, const rtt_hit *hits, const uint8_t *occluded)
{
    uint64_t bad = 0;
    for (size_t i = 0; i < c->n; i++) {
        if (c->must_miss && c->must_miss[i] && (hits[i].prim != RTT_MISS || occluded[i])) {
            bad++;
            continue;
        }
        for (uint32_t d = 0; d < c->degenerate_count; d++)
            if (hits[i].prim == c->degenerate[d]) {
                bad++;
                break;
            }
    }
    return bad;
}

static void finish_hit_result(rtt_extreme_result *r, const check_spec *c, double limit)
{
    r->has_counts = true;
    r->rays = c->n;
    r->row.grazing_limit = limit;
    r->row.set = RTT_CONFORM_EXTREME;
    rtt_conform_row_judge(&r->row);
    r->pass = r->row.pass && r->failures == 0;
    if (c->must_miss || c->degenerate_count) {
        size_t len = strlen(r->note);
        snprintf(r->note + len, sizeof r->note - len, "%sforbidden hits (%s) must be 0", len ? "; " : "",
                 c->must_miss ? "invalid rays" : "zero-area prims");
    }
    describe_limit(r->note, sizeof r->note, limit);
}

static void note_depth(rtt_extreme_result *r, rtt_engine *engine)
{
    rtt_tree_info info;
    if (!rtt_engine_tree_info(engine, &info)) return;
    size_t len = strlen(r->note);
    snprintf(r->note + len, sizeof r->note - len, "%stree depth %u of max %u%s", len ? "; " : "", info.depth,
             info.max_depth, info.depth >= info.max_depth ? " (reached)" : "");
}

static void note_timing(rtt_extreme_result *r, rtt_engine *engine, const check_spec *c, double seconds)
{
    if (!c->timing_rays || !c->timing_n || !c->n) return;
    rtt_hit *hits = malloc(c->timing_n * sizeof *hits);
    if (!hits) return;
    double start = rtt_clock_seconds();
    rtt_engine_intersect(engine, c->timing_rays, hits, c->timing_n);
    double valid = rtt_clock_seconds() - start;
    free(hits);
    size_t len = strlen(r->note);
    snprintf(r->note + len, sizeof r->note - len, "%s%.0f ns/invalid ray vs %.0f ns/valid ray", len ? "; " : "",
             1e9 * seconds / (double)c->n, 1e9 * valid / (double)c->timing_n);
}

/* Traces the check's rays through engine: hits, occlusion, seconds. */
static double trace(rtt_engine *engine, const check_spec *c, rtt_hit *hits, uint8_t *occluded)
{
    double start = rtt_clock_seconds();
    rtt_engine_intersect(engine, c->rays, hits, c->n);
    double seconds = rtt_clock_seconds() - start;
    rtt_engine_occluded(engine, c->rays, occluded, c->n);
    return seconds;
}

static rtt_engine_options spec_options(const rtt_conform_engine_spec *spec, const check_spec *c)
{
    rtt_engine_options opt = spec->opt;
    if (c->max_tree_depth) opt.max_tree_depth = c->max_tree_depth;
    return opt;
}

static bool run_hit_check(run_context *ctx, const check_spec *c)
{
    size_t n = c->n ? c->n : 1;
    rtt_hit *oracle = malloc(n * sizeof *oracle), *hits = malloc(n * sizeof *hits), *brute = malloc(n * sizeof *brute);
    uint8_t *occluded = malloc(n);
    rtt_engine_options ref_opt;
    rtt_engine_options_default(&ref_opt);
    ref_opt.max_tree_depth = c->max_tree_depth;
    rtt_engine *reference = oracle && hits && brute && occluded
                                ? rtt_engine_create("reference", c->scene, &ref_opt, ctx->err) : NULL;
    bool ok = reference != NULL;
    rtt_extreme_result *r = ok ? rtt_ext_add_result(ctx->report, c->name, "reference") : NULL;
    if (ok && r) {
        double seconds = trace(reference, c, oracle, occluded);
        brute_force(c->scene, c->rays, c->n, brute);
        snprintf(r->row.oracle, sizeof r->row.oracle, "brute-force");
        snprintf(r->row.engine, sizeof r->row.engine, "reference");
        rtt_conform_compare(c->scene, c->rays, oracle, occluded, brute, c->n, &r->row);
        r->failures = forbidden_hits(c, oracle, occluded);
        if (c->max_tree_depth) note_depth(r, reference);
        note_timing(r, reference, c, seconds);
        finish_hit_result(r, c, 0.0);
    }
    for (int e = 0; ok && r && e < ctx->spec_count; e++) {
        const rtt_conform_engine_spec *spec = &ctx->specs[e];
        rtt_engine_options opt = spec_options(spec, c);
        rtt_error engine_err = {{0}};
        rtt_engine *engine = rtt_engine_create(spec->name, c->scene, &opt, &engine_err);
        if (!(r = rtt_ext_add_result(ctx->report, c->name, spec->label))) {
            rtt_engine_destroy(engine);
            break;
        }
        if (!engine) {
            snprintf(r->note, sizeof r->note, "cannot create: %.180s", engine_err.message);
            r->pass = false;
            continue;
        }
        double seconds = trace(engine, c, hits, occluded);
        snprintf(r->row.oracle, sizeof r->row.oracle, "reference");
        snprintf(r->row.engine, sizeof r->row.engine, "%s", spec->label);
        rtt_conform_compare(c->scene, c->rays, hits, occluded, oracle, c->n, &r->row);
        r->failures = forbidden_hits(c, hits, occluded);
        if (c->max_tree_depth) note_depth(r, engine);
        note_timing(r, engine, c, seconds);
        finish_hit_result(r, c, grazing_limit(spec->name, is_watertight(engine), c->grazing_by_design));
        if (c->beyond_embree && is_embree(spec->name)) {
            r->asserted = false;
            size_t len = strlen(r->note);
            snprintf(r->note + len, sizeof r->note - len, "; beyond Embree's precision range");
        }
        rtt_engine_destroy(engine);
    }
    if (ok && !r) ok = rtt_error_set(ctx->err, "extremes: out of memory for the report");
    if (!oracle || !hits || !brute || !occluded) ok = rtt_error_set(ctx->err, "extremes: out of memory for %zu rays", n);
    rtt_engine_destroy(reference);
    free(oracle);
    free(hits);
    free(brute);
    free(occluded);
    return ok;
}

/* ---- watertightness --------------------------------------------------- */

/* Escapes of rays from inside: a miss in intersect() or in occluded(). */
static uint64_t count_escapes(rtt_engine *engine, const rtt_ray *rays, size_t n, uint64_t *misses,
                              uint64_t *unoccluded)
{
    rtt_hit *hits = malloc((n ? n : 1) * sizeof *hits);
    uint8_t *occluded = malloc(n ? n : 1);
    uint64_t escapes = 0;
    *misses = *unoccluded = 0;
    if (!hits || !occluded) {
        free(hits);
        free(occluded);
        return n; /* reported as all escaping rather than silently passing */
    }
    rtt_engine_intersect(engine, rays, hits, n);
    rtt_engine_occluded(engine, rays, occluded, n);
    for (size_t i = 0; i < n; i++) {
        *misses += hits[i].prim == RTT_MISS;
        *unoccluded += !occluded[i];
        escapes += hits[i].prim == RTT_MISS || !occluded[i];
    }
    free(hits);
    free(occluded);
    return escapes;
}

static void judge_watertight(const run_context *ctx, rtt_extreme_result *r, const char *engine_name, bool watertight,
                             bool beyond_embree, uint64_t misses, uint64_t unoccluded)
{
    double share = r->rays ? (double)r->failures / (double)r->rays : 0.0;
    int len = snprintf(r->note, sizeof r->note, "%.4f%% escape (%llu misses, %llu unoccluded); ", 100.0 * share,
                       (unsigned long long)misses, (unsigned long long)unoccluded);
    char *rest = r->note + len;
    size_t room = sizeof r->note - (size_t)len;
    if (is_reference(engine_name) || (watertight && !is_embree(engine_name))) {
        r->pass = r->failures == 0;
        snprintf(rest, room, "must be watertight");
    } else if (is_embree(engine_name)) {
        r->pass = share <= ctx->config->embree_escape_limit;
        r->asserted = !beyond_embree;
        snprintf(rest, room, beyond_embree ? "beyond Embree's precision range" : "bound %g%% (robust mode)",
                 100.0 * ctx->config->embree_escape_limit);
    } else {
        r->asserted = false;
        r->pass = r->failures == 0;
        snprintf(rest, room, "leak rate of the projected barycentric test");
    }
}

static bool run_watertight(run_context *ctx, const char *name, const rtt_scene *scene, const rtt_ray *rays, size_t n,
                           bool beyond_embree)
{
    rtt_error ref_err = {{0}};
    rtt_engine *reference = rtt_engine_create("reference", scene, NULL, &ref_err);
    if (!reference) return rtt_error_set(ctx->err, "%s", ref_err.message);
    uint64_t misses, unoccluded;
    rtt_extreme_result *r = rtt_ext_add_result(ctx->report, name, "reference");
    if (!r) {
        rtt_engine_destroy(reference);
        return rtt_error_set(ctx->err, "extremes: out of memory for the report");
    }
    r->rays = n;
    r->failures = count_escapes(reference, rays, n, &misses, &unoccluded);
    judge_watertight(ctx, r, "reference", true, false, misses, unoccluded);
    rtt_engine_destroy(reference);
    for (int e = 0; e < ctx->spec_count; e++) {
        const rtt_conform_engine_spec *spec = &ctx->specs[e];
        rtt_error engine_err = {{0}};
        rtt_engine *engine = rtt_engine_create(spec->name, scene, &spec->opt, &engine_err);
        if (!(r = rtt_ext_add_result(ctx->report, name, spec->label))) {
            rtt_engine_destroy(engine);
            return rtt_error_set(ctx->err, "extremes: out of memory for the report");
        }
        if (!engine) {
            snprintf(r->note, sizeof r->note, "cannot create: %.180s", engine_err.message);
            continue;
        }
        r->rays = n;
        r->failures = count_escapes(engine, rays, n, &misses, &unoccluded);
        judge_watertight(ctx, r, spec->name, is_watertight(engine), beyond_embree, misses, unoccluded);
        rtt_engine_destroy(engine);
    }
    return true;
}

/* Rays from two points inside (half each): the given one and `second`. */
static bool watertight_scene(run_context *ctx, const char *name, const rtt_scene *scene, const float inside[3],
                             const float second[3], bool beyond_embree)
{
    size_t half = ctx->max_rays / 2, n1 = 0, n2 = 0;
    rtt_ray *first = rtt_extremes_watertight_rays(scene, inside, half, &n1);
    rtt_ray *other = rtt_extremes_watertight_rays(scene, second, ctx->max_rays - half, &n2);
    rtt_ray *all = first && other ? malloc((n1 + n2 + 1) * sizeof *all) : NULL;
    bool ok = all != NULL;
    if (ok) {
        memcpy(all, first, n1 * sizeof *all);
        memcpy(all + n1, other, n2 * sizeof *all);
        ok = run_watertight(ctx, name, scene, all, n1 + n2, beyond_embree);
    } else {
        rtt_error_set(ctx->err, "extremes: out of memory for the rays of %s", name);
    }
    free(first);
    free(other);
    free(all);
    return ok;
}

/* ---- scenes ----------------------------------------------------------- */

/* Builds the scene from a soup (freed here) and names it after the check. */
static rtt_scene *soup_scene(run_context *ctx, const char *name, float *soup, uint32_t count)
{
    if (!soup) return rtt_error_set(ctx->err, "extremes: %s: out of memory", name), NULL;
    rtt_error scene_err = {{0}};
    rtt_scene *scene = rtt_scene_from_triangles(soup, count, &scene_err);
    free(soup);
    if (!scene) return rtt_error_set(ctx->err, "extremes: %s: %s", name, scene_err.message), NULL;
    snprintf(scene->path, sizeof scene->path, "extremes: %s", name);
    return scene;
}

static float *copy_soup(const float *soup, uint32_t count)
{
    float *copy = malloc((size_t)count * 9 * sizeof *copy);
    if (copy) memcpy(copy, soup, (size_t)count * 9 * sizeof *copy);
    return copy;
}

/* The conformance suite's random set for one scene, max rays. */
static rtt_ray *random_set(run_context *ctx, const rtt_scene *scene, uint64_t seed, size_t *n)
{
    rtt_ray *rays = NULL;
    if (!rtt_conform_make_rays(scene, RTT_CONFORM_RANDOM, NULL, ctx->max_rays, seed, &rays, n, ctx->err)) return NULL;
    return rays;
}

static bool random_check(run_context *ctx, const char *name, float *soup, uint32_t count, bool beyond_embree)
{
    rtt_scene *scene = soup_scene(ctx, name, soup, count);
    if (!scene) return false;
    size_t n = 0;
    rtt_ray *rays = random_set(ctx, scene, SEED, &n);
    bool ok = rays != NULL;
    if (ok) {
        check_spec c = {.name = name, .scene = scene, .rays = rays, .n = n, .beyond_embree = beyond_embree};
        ok = run_hit_check(ctx, &c);
    }
    free(rays);
    rtt_scene_free(scene);
    return ok;
}

static bool scale_and_move_checks(run_context *ctx, const float *base, uint32_t count)
{
    static const double scales[] = {1e-20, 1e-10, 1e-5, 1.0, 1e5, 1e10, 1e20};
    static const double offsets[] = {1e3, 1e6};
    const double zero[3] = {0, 0, 0};
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        char name[48];
        snprintf(name, sizeof name, "scale %.0e", scales[i]);
        float *soup = copy_soup(base, count);
        if (soup) rtt_ext_transform(soup, count, scales[i], zero);
        if (!random_check(ctx, name, soup, count, fabs(log10(scales[i])) > EMBREE_RANGE_LOG10)) return false;
    }
    for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; i++) {
        char name[48];
        snprintf(name, sizeof name, "moved %.0e from the origin", offsets[i]);
        const double offset[3] = {offsets[i], -0.75 * offsets[i], 0.5 * offsets[i]};
        float *soup = copy_soup(base, count);
        if (soup) rtt_ext_transform(soup, count, 1.0, offset);
        if (!random_check(ctx, name, soup, count, false)) return false;
    }
    return true;
}

typedef size_t (*pattern_fn)(const rtt_scene *, uint64_t, size_t, rtt_ray *);

static bool pattern_checks(run_context *ctx, const rtt_scene *scene)
{
    static const struct {
        const char *name;
        pattern_fn make;
        bool grazing_by_design;
    } patterns[] = {
        {"axis-parallel, +-0.0", rtt_ext_rays_axis_parallel, true},
        {"origins on split planes", rtt_ext_rays_split_planes, true}, /* half run inside axis planes */
        {"origins on surfaces", rtt_ext_rays_on_surface, false},
        {"aimed at vertices, edges", rtt_ext_rays_vertex_aimed, true},
    };
    rtt_ray *rays = malloc(ctx->max_rays * sizeof *rays);
    if (!rays) return rtt_error_set(ctx->err, "extremes: out of memory for rays");
    bool ok = true;
    for (size_t p = 0; p < sizeof patterns / sizeof patterns[0] && ok; p++) {
        size_t n = patterns[p].make(scene, SEED + p, ctx->max_rays, rays);
        check_spec c = {.name = patterns[p].name, .scene = scene, .rays = rays, .n = n,
                        .grazing_by_design = patterns[p].grazing_by_design};
        ok = run_hit_check(ctx, &c);
    }
    free(rays);
    return ok;
}

/* Invalid rays alone, then one in every four of a valid stream (so each
 * 2x2 packet and each frustum tile holds one). */
static bool invalid_ray_checks(run_context *ctx, const rtt_scene *scene)
{
    size_t n_valid = 0, n_invalid = 64 * rtt_ext_invalid_pattern_count();
    rtt_ray *valid = random_set(ctx, scene, SEED + 11, &n_valid);
    rtt_ray *invalid = malloc(n_invalid * sizeof *invalid);
    uint8_t *must_miss = malloc((n_valid > n_invalid ? n_valid : n_invalid) + 1);
    bool ok = valid && invalid && must_miss;
    if (!ok) {
        free(valid);
        free(invalid);
        free(must_miss);
        return rtt_error_set(ctx->err, "extremes: out of memory for rays");
    }
    rtt_vec3 centre = rtt_v3_add(rtt_v3_scale(scene->bounds.lo, 0.5f), rtt_v3_scale(scene->bounds.hi, 0.5f)); /* no overflow near FLT_MAX */
    rtt_ext_rays_invalid(centre, n_invalid, invalid);
    memset(must_miss, 1, n_invalid);
    check_spec alone = {.name = "NaN/Inf rays", .scene = scene, .rays = invalid, .n = n_invalid,
                        .must_miss = must_miss, .timing_rays = valid, .timing_n = n_valid};
    ok = run_hit_check(ctx, &alone);
    if (ok) {
        for (size_t i = 0; i < n_valid; i++) {
            must_miss[i] = i % 4 == 3;
            if (must_miss[i]) valid[i] = invalid[(i / 4) % n_invalid];
        }
        check_spec mixed = {.name = "NaN/Inf among valid rays", .scene = scene, .rays = valid, .n = n_valid,
                            .must_miss = must_miss};
        ok = run_hit_check(ctx, &mixed);
    }
    free(valid);
    free(invalid);
    free(must_miss);
    return ok;
}

/* rtt_scene_from_triangles must refuse NaN and infinite coordinates with a
 * message (a scene-level check: no engine involved). */
static bool invalid_input_check(run_context *ctx)
{
    static const struct {
        const char *what;
        float value;
        int place;
    } cases[] = {{"NaN", NAN, 4}, {"+Inf", INFINITY, 0}, {"-Inf", -INFINITY, 17}};
    rtt_extreme_result *r = rtt_ext_add_result(ctx->report, "NaN/Inf input rejected", "scene");
    if (!r) return rtt_error_set(ctx->err, "extremes: out of memory for the report");
    const float centre[3] = {0, 0, 0};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint32_t count = 0;
        float *soup = rtt_extremes_sphere(6, 3, 1.0f, centre, &count);
        if (!soup) return rtt_error_set(ctx->err, "extremes: out of memory");
        soup[9 + cases[i].place] = cases[i].value; /* in the second triangle */
        rtt_error err = {{0}};
        rtt_scene *scene = rtt_scene_from_triangles(soup, count, &err);
        free(soup);
        r->rays++;
        if (scene || err.message[0] == '\0') r->failures++;
        if (i == 0 || scene) {
            size_t len = strlen(r->note);
            snprintf(r->note + len, sizeof r->note - len, "%s%s: %.120s", len ? "; " : "", cases[i].what,
                     scene ? "ACCEPTED" : err.message[0] ? err.message : "refused without a message");
        }
        if (scene) rtt_scene_free(scene);
    }
    r->pass = r->failures == 0;
    return true;
}

static bool degenerate_check(run_context *ctx)
{
    uint32_t count = 0, degenerate[16], degenerate_count = 0;
    float *soup = rtt_ext_degenerate_soup(&count, degenerate, 16, &degenerate_count);
    rtt_scene *scene = soup_scene(ctx, "degenerate, needle, coplanar", soup, count);
    if (!scene) return false;
    size_t n_random = 0;
    rtt_ray *random = random_set(ctx, scene, SEED + 21, &n_random);
    rtt_ray *rays = random ? malloc(ctx->max_rays * sizeof *rays) : NULL;
    bool ok = rays != NULL;
    if (ok) {
        size_t half = n_random / 2;
        memcpy(rays, random, half * sizeof *rays);
        size_t n = half + rtt_ext_rays_vertex_aimed(scene, SEED + 22, ctx->max_rays - half, rays + half);
        check_spec c = {.name = "degenerate, needle, coplanar", .scene = scene, .rays = rays, .n = n,
                        .grazing_by_design = true, .degenerate = degenerate, .degenerate_count = degenerate_count};
        ok = run_hit_check(ctx, &c);
    } else if (random) {
        rtt_error_set(ctx->err, "extremes: out of memory for rays");
    }
    free(random);
    free(rays);
    rtt_scene_free(scene);
    return ok;
}

static bool sphere_checks(run_context *ctx)
{
    static const struct {
        const char *name;
        float radius, centre[3];
        bool beyond_embree;
    } spheres[] = {
        {"watertight sphere r=1", 1.0f, {0, 0, 0}, false},
        {"watertight sphere r=1e-18", 1e-18f, {3e-19f, -2e-19f, 1e-19f}, true},
        {"watertight sphere r=1e+18", 1e18f, {0, 0, 0}, true},
        {"watertight sphere 3e4 away", 7.0f, {1e4f, -3e4f, 3e3f}, false},
    };
    for (size_t i = 0; i < sizeof spheres / sizeof spheres[0]; i++) {
        uint32_t count = 0;
        float *soup = rtt_extremes_sphere(48, 24, spheres[i].radius, spheres[i].centre, &count);
        rtt_scene *scene = soup_scene(ctx, spheres[i].name, soup, count);
        if (!scene) return false;
        const float *c = spheres[i].centre;
        const double r = spheres[i].radius;
        const double first_file[3] = {c[0], c[1], c[2]}, second_file[3] = {c[0] + 0.31 * r, c[1] - 0.22 * r, c[2] + 0.17 * r};
        const rtt_vec3 a = rtt_scene_point_to_stored(scene, first_file), b = rtt_scene_point_to_stored(scene, second_file);
        const float first[3] = {a.x, a.y, a.z}, second[3] = {b.x, b.y, b.z};
        bool ok = watertight_scene(ctx, spheres[i].name, scene, first, second, spheres[i].beyond_embree);
        rtt_scene_free(scene);
        if (!ok) return false;
    }
    return true;
}

/* ---- benchmark meshes ------------------------------------------------- */

static int name_order(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static bool is_mesh_file(const char *name)
{
    const char *dot = strrchr(name, '.');
    return dot && (strcmp(dot, ".off") == 0 || strcmp(dot, ".ply") == 0 || strcmp(dot, ".obj") == 0);
}

static bool mesh_check(run_context *ctx, const char *dir, const char *file)
{
    char path[1024], name[48];
    if (snprintf(path, sizeof path, "%.500s/%.500s", dir, file) >= (int)sizeof path) return true;
    snprintf(name, sizeof name, "watertight %.36s", file);
    rtt_error err = {{0}};
    rtt_scene *scene = rtt_scene_load(path, NULL, &err);
    float inside[3], second[3];
    const char *skip = !scene                          ? err.message
                       : !rtt_ext_mesh_closed(scene)   ? "skipped: not a closed mesh (an edge not shared by two triangles)"
                       : !rtt_ext_inside_point(scene, 0, inside) ? "skipped: no point found inside"
                                                                 : NULL;
    if (skip) {
        rtt_extreme_result *r = rtt_ext_add_result(ctx->report, name, "-");
        if (r) {
            r->asserted = false;
            snprintf(r->note, sizeof r->note, "%.199s", skip);
        }
        if (scene) rtt_scene_free(scene);
        return r != NULL ? true : rtt_error_set(ctx->err, "extremes: out of memory for the report");
    }
    /* half the rays from a second point inside, when there is one */
    if (!rtt_ext_inside_point(scene, 1, second)) memcpy(second, inside, sizeof second);
    bool ok = watertight_scene(ctx, name, scene, inside, second, false);
    rtt_scene_free(scene);
    return ok;
}

static bool mesh_checks(run_context *ctx)
{
    char fallback[1024];
    const char *dir = ctx->config->mesh_dir;
    if (!dir) {
        const char *data = getenv("RTT_DATA_DIR"), *home = getenv("HOME");
        if (data && data[0])
            snprintf(fallback, sizeof fallback, "%s/meshes", data);
        else
            snprintf(fallback, sizeof fallback, "%s/.cache/rtt-data/meshes", home ? home : ".");
        dir = fallback;
    }
    if (!dir[0]) return true; /* "" disables the benchmark meshes */
    DIR *d = opendir(dir);
    if (!d) {
        rtt_extreme_result *r = rtt_ext_add_result(ctx->report, "watertight benchmark meshes", "-");
        if (!r) return rtt_error_set(ctx->err, "extremes: out of memory for the report");
        r->asserted = false;
        snprintf(r->note, sizeof r->note, "skipped: no %.150s (bench/fetch-scenes.sh)", dir);
        return true;
    }
    char *names[64];
    size_t count = 0;
    for (struct dirent *entry; (entry = readdir(d)) && count < 64;)
        if (is_mesh_file(entry->d_name) && (names[count] = strdup(entry->d_name))) count++;
    closedir(d);
    qsort(names, count, sizeof names[0], name_order);
    bool ok = true;
    for (size_t i = 0; i < count; i++) {
        if (ok) ok = mesh_check(ctx, dir, names[i]);
        free(names[i]);
    }
    return ok;
}

/* ---- the suite -------------------------------------------------------- */

/* Rays near each triangle at its own scale: traversal to the deepest
 * leaves, not the precision of tiny triangles seen from afar. */
static bool deep_tree_check(run_context *ctx)
{
    const char *name = "deep tree (max depth 64)";
    rtt_scene *scene = soup_scene(ctx, name, rtt_ext_deep_soup(DEEP_TREE_TRIANGLES), DEEP_TREE_TRIANGLES);
    if (!scene) return false;
    rtt_ray *rays = malloc(ctx->max_rays * sizeof *rays);
    bool ok = rays != NULL;
    if (ok) {
        size_t n = rtt_ext_rays_near_triangles(scene, SEED + 31, ctx->max_rays, rays);
        check_spec c = {.name = name, .scene = scene, .rays = rays, .n = n, .max_tree_depth = DEEP_TREE_MAX_DEPTH};
        ok = run_hit_check(ctx, &c);
    } else {
        rtt_error_set(ctx->err, "extremes: out of memory for rays");
    }
    free(rays);
    rtt_scene_free(scene);
    return ok;
}

bool rtt_extremes_run(const rtt_extremes_config *config, rtt_extremes_report *report, rtt_error *err)
{
    memset(report, 0, sizeof *report);
    run_context ctx = {.config = config, .report = report, .err = err};
    ctx.max_rays = config->max_rays ? config->max_rays : DEFAULT_MAX_RAYS;
    if (ctx.max_rays < 64) ctx.max_rays = 64;
    ctx.spec_count = rtt_conform_expand_engines(config->engines ? config->engines : rtt_conform_default_engines(),
                                                ctx.specs, 64, err);
    if (ctx.spec_count < 0) return false;
    rtt_conform_specs_set_isa(ctx.specs, ctx.spec_count, config->isa, config->isect);

    uint32_t base_count = 0;
    float *base = rtt_ext_base_soup(&base_count);
    bool ok = base != NULL;
    if (!ok) rtt_error_set(err, "extremes: out of memory");
    if (ok) ok = scale_and_move_checks(&ctx, base, base_count);
    rtt_scene *scene = ok ? soup_scene(&ctx, "base scene", copy_soup(base, base_count), base_count) : NULL;
    free(base);
    if (ok) ok = scene != NULL;
    if (ok) ok = pattern_checks(&ctx, scene);
    if (ok) ok = invalid_ray_checks(&ctx, scene);
    if (scene) rtt_scene_free(scene);
    if (ok) ok = invalid_input_check(&ctx);
    if (ok) ok = degenerate_check(&ctx);
    if (ok) ok = deep_tree_check(&ctx);
    if (ok) ok = sphere_checks(&ctx);
    if (ok) ok = mesh_checks(&ctx);
    if (!ok) {
        rtt_extremes_report_free(report);
        return false;
    }
    report->pass = true;
    for (size_t i = 0; i < report->count; i++)
        if (report->items[i].asserted && !report->items[i].pass) report->pass = false;
    return true;
}

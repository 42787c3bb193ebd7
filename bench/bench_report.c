/* The benchmark report as text: a plain table, the thesis' tables in
 * Markdown with the Embree ratios beside them, JSON, and TSV for plots
 * (bench.h).  Every ratio printed is between rows of the same run. */
#include <cjson/cJSON.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "bench_internal.h"

/* ---- a growing string ---- */

typedef struct text {
    char *data;
    size_t length, cap;
    bool failed;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
    if (t->failed) return;
    for (;;) {
        va_list args;
        va_start(args, fmt);
        int n = vsnprintf(t->data ? t->data + t->length : NULL, t->data ? t->cap - t->length : 0, fmt, args);
        va_end(args);
        if (n < 0) {
            t->failed = true;
            return;
        }
        if (t->data && t->length + (size_t)n < t->cap) {
            t->length += (size_t)n;
            return;
        }
        size_t cap = t->cap ? 2 * t->cap : 4096;
        while (cap < t->length + (size_t)n + 1) cap *= 2;
        char *grown = realloc(t->data, cap);
        if (!grown) {
            t->failed = true;
            return;
        }
        t->data = grown;
        t->cap = cap;
    }
}

static char *finish(text *t)
{
    if (t->failed) {
        free(t->data);
        return NULL;
    }
    if (!t->data) put(t, "%s", "");
    return t->data;
}

static const char *kind_name(rtt_bench_kind k)
{
    static const char *const names[] = {"primary", "shadow", "render", "build", "soft"};
    return k < RTT_BENCH_KIND_COUNT ? names[k] : "?";
}

/* ---- finding rows ---- */

typedef struct row_query {
    rtt_bench_kind kind;
    const char *engine, *family, *shadows, *variant;
    uint32_t tile, threads, lanes;
    int leaf_culling;  /* -2: any */
    bool any_tile, coherent_only;
} row_query;

static bool matches(const rtt_bench_row *r, const row_query *q)
{
    if (r->error[0] || r->kind != q->kind || strcmp(r->engine, q->engine)) return false;
    if (q->family && strcmp(r->family, q->family)) return false;
    if (q->shadows && strcmp(r->shadows, q->shadows)) return false;
    if (q->variant && strcmp(r->variant, q->variant)) return false;
    if (!q->any_tile && r->tile != q->tile) return false;
    if (q->threads && r->threads != q->threads) return false;
    if (q->lanes && r->lanes != q->lanes) return false;
    if (q->coherent_only && r->lanes < 4) return false;
    if (q->leaf_culling != -2 && r->leaf_culling != q->leaf_culling) return false;
    return true;
}

static const rtt_bench_row *find(const rtt_bench_report *rep, const row_query *q)
{
    for (size_t i = 0; i < rep->row_count; i++)
        if (matches(&rep->rows[i], q)) return &rep->rows[i];
    return NULL;
}

static const rtt_bench_row *best(const rtt_bench_report *rep, const row_query *q)
{
    const rtt_bench_row *b = NULL;
    for (size_t i = 0; i < rep->row_count; i++)
        if (matches(&rep->rows[i], q) && (!b || rep->rows[i].fps > b->fps)) b = &rep->rows[i];
    return b;
}

static const rtt_bench_row *primary_rtt(const rtt_bench_report *rep, const char *family, uint32_t tile,
                                        uint32_t threads, int culling)
{
    row_query q = {.kind = RTT_BENCH_PRIMARY, .engine = "rtt", .family = family, .tile = tile, .threads = threads,
                   .leaf_culling = culling};
    return find(rep, &q);
}

static const rtt_bench_row *best_primary_rtt(const rtt_bench_report *rep, const char *family, uint32_t threads)
{
    row_query q = {.kind = RTT_BENCH_PRIMARY, .engine = "rtt", .family = family, .threads = threads,
                   .leaf_culling = 1, .any_tile = true};
    return best(rep, &q);
}

static const rtt_bench_row *best_embree(const rtt_bench_report *rep, rtt_bench_kind kind, uint32_t threads,
                                        bool coherent)
{
    row_query q = {.kind = kind, .engine = "embree", .threads = threads, .leaf_culling = -2, .any_tile = true,
                   .coherent_only = coherent};
    return best(rep, &q);
}

static void thread_counts(const rtt_bench_report *rep, uint32_t out[4], uint32_t *count)
{
    *count = 0;
    for (size_t i = 0; i < rep->row_count && *count < 4; i++) {
        bool seen = false;
        for (uint32_t k = 0; k < *count; k++) seen |= out[k] == rep->rows[i].threads;
        if (!seen && rep->rows[i].kind != RTT_BENCH_BUILD) out[(*count)++] = rep->rows[i].threads;
    }
}

static double ratio(const rtt_bench_row *a, const rtt_bench_row *b)
{
    return a && b && b->fps > 0 ? a->fps / b->fps : 0.0;
}

static double pct(double a, double b) { return b != 0 ? 100.0 * (a - b) / b : 0.0; }

/* ---- headline ratios: the speed targets the kernels are held to ---- */

typedef struct headline {
    char name[80];
    double value, target;
    char detail[160];
} headline;

static size_t headlines(const rtt_bench_report *rep, headline *out, size_t cap)
{
    size_t n = 0;
    uint32_t threads[4], tc;
    thread_counts(rep, threads, &tc);
    for (uint32_t k = 0; k < tc && n < cap; k++) {
        const rtt_bench_row *m = best_primary_rtt(rep, "mft", threads[k]);
        const rtt_bench_row *e = best_embree(rep, RTT_BENCH_PRIMARY, threads[k], true);
        if (!m || !e) continue;
        headline *h = &out[n++];
        snprintf(h->name, sizeof h->name, "mft_vs_embree_t%u", threads[k]);
        h->value = ratio(m, e);
        h->target = 1.0;
        snprintf(h->detail, sizeof h->detail, "mft %ux%u %.1f fps vs Embree %s %s %.1f fps, %u thread%s", m->tile,
                 m->tile, m->fps, e->method, e->variant, e->fps, threads[k], threads[k] == 1 ? "" : "s");
    }
    if (tc > 0 && n + 3 <= cap) {
        uint32_t t1 = threads[0];
        const rtt_bench_row *f8 = primary_rtt(rep, "frustum", 8, t1, 1);
        const rtt_bench_row *p = primary_rtt(rep, "packet", 0, t1, 1);
        if (f8 && p) {
            headline *h = &out[n++];
            snprintf(h->name, sizeof h->name, "frustum8_vs_packet");
            h->value = ratio(f8, p);
            h->target = 1.5;
            snprintf(h->detail, sizeof h->detail, "frustum 8x8 %.1f fps vs 2x2 packets %.1f fps, %u thread", f8->fps,
                     p->fps, t1);
        }
        const rtt_bench_row *m = best_primary_rtt(rep, "mft", t1), *f = best_primary_rtt(rep, "frustum", t1);
        if (m && f) {
            headline *h = &out[n++];
            snprintf(h->name, sizeof h->name, "mft_best_vs_frustum_best");
            h->value = ratio(m, f);
            h->target = 1.1;
            snprintf(h->detail, sizeof h->detail, "mft %ux%u %.1f fps vs frustum %ux%u %.1f fps, %u thread", m->tile,
                     m->tile, m->fps, f->tile, f->tile, f->fps, t1);
        }
    }
    if (tc > 1 && n + 2 <= cap) {
        const rtt_bench_row *a = best_primary_rtt(rep, "mft", threads[0]);
        const rtt_bench_row *b = a ? primary_rtt(rep, "mft", a->tile, threads[tc - 1], 1) : NULL;
        if (a && b) {
            headline *h = &out[n++];
            snprintf(h->name, sizeof h->name, "threads%u_vs_%u_primary", threads[tc - 1], threads[0]);
            h->value = ratio(b, a);
            h->target = 1.9;
            snprintf(h->detail, sizeof h->detail, "mft %ux%u primary kernels: %.1f vs %.1f fps", a->tile, a->tile,
                     b->fps, a->fps);
        }
        row_query q = {.kind = RTT_BENCH_RENDER, .engine = "rtt", .family = "mft", .shadows = "hard", .tile = 16,
                       .threads = threads[0], .leaf_culling = 1};
        const rtt_bench_row *r1 = find(rep, &q);
        q.threads = threads[tc - 1];
        const rtt_bench_row *r2 = find(rep, &q);
        if (r1 && r2) {
            headline *h = &out[n++];
            snprintf(h->name, sizeof h->name, "threads%u_vs_%u_render", threads[tc - 1], threads[0]);
            h->value = ratio(r2, r1);
            h->target = 1.9;
            snprintf(h->detail, sizeof h->detail, "full render, mft 16x16, hard shadows: %.1f vs %.1f fps", r2->fps,
                     r1->fps);
        }
    }
    return n;
}

/* ---- plain table ---- */

char *rtt_bench_report_table(const rtt_bench_report *rep)
{
    text t = {0};
    put(&t, "scene %s%s%s%s: %u triangles, %ux%u, median of %u frames after %u warm-up\n", rep->scene,
        rep->view[0] ? " (view " : "", rep->view, rep->view[0] ? ")" : "", rep->triangles, rep->width, rep->height,
        rep->frames, rep->warmup);
    if (rep->embree_note[0]) put(&t, "%s\n", rep->embree_note);
    put(&t, "%-7s %-6s %-16s %-15s %-10s %3s %8s %9s %8s %8s %8s %7s %6s\n", "kind", "engine", "method", "variant",
        "shadows", "thr", "fps", "Mrays/s", "N", "I", "xEmbree", "agree", "build");
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        put(&t, "%-7s %-6s %-16s %-15s %-10s %3u ", kind_name(r->kind), r->engine, r->method, r->variant,
            r->shadows[0] ? r->shadows : "-", r->threads);
        if (r->error[0]) {
            put(&t, "%s\n", r->error);
            continue;
        }
        if (r->kind == RTT_BENCH_BUILD) {
            put(&t, "build %.3f s, %.1f MB\n", r->seconds, (double)r->memory_bytes / 1048576.0);
            continue;
        }
        put(&t, "%8.2f %9.2f ", r->fps, r->rays_per_second / 1e6);
        if (r->n >= 0) put(&t, "%8.2f %8.2f ", r->n, r->i);
        else put(&t, "%8s %8s ", "-", "-");
        if (r->vs_embree > 0) put(&t, "%8.2f ", r->vs_embree);
        else put(&t, "%8s ", "-");
        if (r->agree >= 0) put(&t, "%6.2f%%\n", 100.0 * r->agree);
        else put(&t, "%7s\n", "-");
    }
    headline h[8];
    size_t n = headlines(rep, h, 8);
    for (size_t k = 0; k < n; k++)
        put(&t, "headline %-28s %6.2fx (target %.2fx)  %s\n", h[k].name, h[k].value, h[k].target, h[k].detail);
    return finish(&t);
}

/* ---- Markdown: the thesis' tables ---- */

static void md_cell_fps(text *t, const rtt_bench_row *r)
{
    if (!r) put(t, " – |");
    else put(t, " %.2f |", r->fps);
}

static void md_primary_row(text *t, const rtt_bench_report *rep, const rtt_bench_row *r, const uint32_t *threads,
                           uint32_t tc)
{
    put(t, "| %s | %s |", r->method, r->leaf_culling ? "on" : "off");
    for (uint32_t k = 0; k < tc; k++) {
        const rtt_bench_row *o = primary_rtt(rep, r->family, r->tile, threads[k], r->leaf_culling);
        if (!o) put(t, " – | – | – |");
        else put(t, " %.2f | %.1f | %.2f |", o->fps, o->rays_per_second / 1e6, o->vs_embree);
    }
    if (r->n >= 0) put(t, " %.2f | %.2f |", r->n, r->i);
    else put(t, " – | – |");
    const rtt_bench_row *f = primary_rtt(rep, "frustum", r->tile, threads[0], 1);
    bool relative = f && f != r && r->tile && (!strcmp(r->family, "mft") || strstr(r->family, "cone"));
    if (relative) put(t, " %+.1f%% | %+.1f%% | %+.1f%% |", pct(r->fps, f->fps), pct(r->n, f->n), pct(r->i, f->i));
    else put(t, " | | |");
    if (r->agree >= 0) put(t, " %.3f%% |\n", 100.0 * r->agree);
    else put(t, " – |\n");
}

static void md_primary(text *t, const rtt_bench_report *rep, const uint32_t *threads, uint32_t tc)
{
    put(t, "\n### Tables 4.1, 4.3, 4.5 – primary rays, traversal kernels alone (same rays as Embree)\n\n");
    put(t, "fps and Mrays/s per thread count; ×E = fps over Embree's best coherent variant at the same thread count; "
           "N, I per 2×2 packet; %% columns against the single frustum at the same tile (Tables 4.3, 4.5); agree = "
           "share of pixels whose hit prim equals Embree's.\n\n| method | cull |");
    for (uint32_t k = 0; k < tc; k++) put(t, " fps (%u) | Mrays/s (%u) | ×E (%u) |", threads[k], threads[k], threads[k]);
    put(t, " N | I | %% FPS | %% N | %% I | agree |\n|---|---|");
    for (uint32_t k = 0; k < tc; k++) put(t, "---:|---:|---:|");
    put(t, "---:|---:|---:|---:|---:|---:|\n");
    /* Rows in the thesis' order: packets, then each frustum family by tile. */
    static const struct { const char *family; int culling; } order[] = {
        {"mono", 1}, {"packet", 1}, {"omni", 1}, {"frustum", 1}, {"frustum", 0}, {"mft", 1}, {"cone", 1}, {"mft-cone", 1}};
    static const uint32_t tiles[] = {0, 4, 8, 16, 32};
    for (size_t o = 0; o < sizeof order / sizeof order[0]; o++)
        for (size_t k = 0; k < sizeof tiles / sizeof tiles[0]; k++) {
            const rtt_bench_row *r = primary_rtt(rep, order[o].family, tiles[k], threads[0], order[o].culling);
            if (r) md_primary_row(t, rep, r, threads, tc);
        }
    put(t, "\nEmbree on the same rays (coherent context flag for 4/8/16-wide calls):\n\n| call | variant |");
    for (uint32_t k = 0; k < tc; k++) put(t, " fps (%u) | Mrays/s (%u) |", threads[k], threads[k]);
    put(t, " agree |\n|---|---|");
    for (uint32_t k = 0; k < tc; k++) put(t, "---:|---:|");
    put(t, "---:|\n");
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        if (r->kind != RTT_BENCH_PRIMARY || strcmp(r->engine, "embree") || r->threads != threads[0]) continue;
        put(t, "| %s | %s |", r->method, r->variant);
        for (uint32_t k = 0; k < tc; k++) {
            row_query q = {.kind = RTT_BENCH_PRIMARY, .engine = "embree", .variant = r->variant, .lanes = r->lanes,
                           .threads = threads[k], .leaf_culling = -2, .any_tile = true};
            const rtt_bench_row *o = find(rep, &q);
            if (!o) put(t, " – | – |");
            else put(t, " %.2f | %.1f |", o->fps, o->rays_per_second / 1e6);
        }
        if (r->agree >= 0) put(t, " %.3f%% |\n", 100.0 * r->agree);
        else put(t, " %s |\n", r->error[0] ? r->error : "–");
    }
}

static void md_culling_and_peaks(text *t, const rtt_bench_report *rep, const uint32_t *threads, uint32_t tc)
{
    put(t, "\n### Table 4.2 – packet/leaf culling (frustum, %u thread)\n\n", threads[0]);
    put(t, "| tile | fps on | fps off | framerate increase | culled intersections |\n|---|---:|---:|---:|---:|\n");
    static const uint32_t tiles[] = {4, 8, 16, 32};
    for (int k = 0; k < 4; k++) {
        const rtt_bench_row *on = primary_rtt(rep, "frustum", tiles[k], threads[0], 1);
        const rtt_bench_row *off = primary_rtt(rep, "frustum", tiles[k], threads[0], 0);
        if (!on || !off) continue;
        put(t, "| %u×%u | %.2f | %.2f | %+.1f%% | %.1f%% |\n", tiles[k], tiles[k], on->fps, off->fps,
            pct(on->fps, off->fps), off->i > 0 ? 100.0 * (off->i - on->i) / off->i : 0.0);
    }
    put(t, "\n### Table 4.4 – peak MFT against peak single frustum and 2×2 packets\n\n");
    put(t, "| threads | MFT fps | MFT tile | frustum fps | frustum tile | MFT / frustum | packet 2×2 fps | "
           "frustum 8×8 / packet |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (uint32_t k = 0; k < tc; k++) {
        const rtt_bench_row *m = best_primary_rtt(rep, "mft", threads[k]);
        const rtt_bench_row *f = best_primary_rtt(rep, "frustum", threads[k]);
        const rtt_bench_row *p = primary_rtt(rep, "packet", 0, threads[k], 1);
        const rtt_bench_row *f8 = primary_rtt(rep, "frustum", 8, threads[k], 1);
        if (!m || !f) continue;
        put(t, "| %u | %.2f | %u×%u | %.2f | %u×%u | %.3f |", threads[k], m->fps, m->tile, m->tile, f->fps, f->tile,
            f->tile, ratio(m, f));
        if (p && f8) put(t, " %.2f | %.3f |\n", p->fps, ratio(f8, p));
        else put(t, " – | – |\n");
    }
}

static void md_shadow_rays(text *t, const rtt_bench_report *rep, const uint32_t *threads, uint32_t tc)
{
    put(t, "\n### Hard-shadow rays (primary hit to the light centre), occlusion kernels against rtcOccluded\n\n");
    put(t, "| engine | method | variant |");
    for (uint32_t k = 0; k < tc; k++) put(t, " fps (%u) | Mrays/s (%u) | ×E (%u) |", threads[k], threads[k], threads[k]);
    put(t, " agree |\n|---|---|---|");
    for (uint32_t k = 0; k < tc; k++) put(t, "---:|---:|---:|");
    put(t, "---:|\n");
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        if (r->kind != RTT_BENCH_SHADOW || r->threads != threads[0]) continue;
        put(t, "| %s | %s | %s |", r->engine, r->method, r->variant);
        for (uint32_t k = 0; k < tc; k++) {
            row_query q = {.kind = RTT_BENCH_SHADOW, .engine = r->engine, .family = r->family, .variant = r->variant,
                           .tile = r->tile, .lanes = r->lanes, .threads = threads[k], .leaf_culling = -2};
            const rtt_bench_row *o = find(rep, &q);
            if (!o) put(t, " – | – | – |");
            else put(t, " %.2f | %.1f | %.2f |", o->fps, o->rays_per_second / 1e6, o->vs_embree);
        }
        if (r->agree >= 0) put(t, " %.3f%% |\n", 100.0 * r->agree);
        else put(t, " %s |\n", r->error[0] ? r->error : "–");
    }
}

static void md_renders(text *t, const rtt_bench_report *rep, const uint32_t *threads, uint32_t tc)
{
    put(t, "\n### Full renders (rtt_optimized_render: shading, shadows, secondary rays)\n\n");
    put(t, "| method | shadows | threads | fps | Mrays/s (all rays) | N | I | vs hard |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|\n");
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        if (r->kind != RTT_BENCH_RENDER) continue;
        put(t, "| %s | %s | %u |", r->method, r->shadows, r->threads);
        if (r->error[0]) {
            put(t, " %s | | | | |\n", r->error);
            continue;
        }
        row_query q = {.kind = RTT_BENCH_RENDER, .engine = "rtt", .family = r->family, .shadows = "hard",
                       .tile = r->tile, .threads = r->threads, .leaf_culling = r->leaf_culling};
        const rtt_bench_row *hard = find(rep, &q);
        put(t, " %.2f | %.2f | %.2f | %.2f |", r->fps, r->rays_per_second / 1e6, r->n, r->i);
        if (hard && hard != r) put(t, " %.2f× |\n", ratio(r, hard));
        else put(t, " |\n");
    }
    put(t, "\n### Table 6.2 – threads (full render, MFT 16×16)\n\n| shadows |");
    for (uint32_t k = 0; k < tc; k++) put(t, " %u thread%s |", threads[k], threads[k] == 1 ? "" : "s");
    put(t, " speed-up |\n|---|");
    for (uint32_t k = 0; k < tc; k++) put(t, "---:|");
    put(t, "---:|\n");
    static const char *const methods[] = {"hard", "edgewidth"};
    for (int m = 0; m < 2; m++) {
        const rtt_bench_row *first = NULL, *last = NULL;
        put(t, "| %s |", methods[m]);
        for (uint32_t k = 0; k < tc; k++) {
            row_query q = {.kind = RTT_BENCH_RENDER, .engine = "rtt", .family = "mft", .shadows = methods[m],
                           .tile = 16, .threads = threads[k], .leaf_culling = 1};
            const rtt_bench_row *r = find(rep, &q);
            md_cell_fps(t, r);
            if (k == 0) first = r;
            last = r;
        }
        if (first && last && first != last) put(t, " %.2f× |\n", ratio(last, first));
        else put(t, " – |\n");
    }
}

char *rtt_bench_report_markdown(const rtt_bench_report *rep)
{
    text t = {0};
    uint32_t threads[4], tc;
    thread_counts(rep, threads, &tc);
    put(&t, "## %s%s%s%s\n\n", rep->scene, rep->view[0] ? " – view " : "", rep->view, "");
    put(&t, "%u triangles, %u×%u, median of %u frames after %u warm-up. %s.\n\n", rep->triangles, rep->width,
        rep->height, rep->frames, rep->warmup, rep->embree_note[0] ? rep->embree_note : "");
    put(&t, "| build | variant | seconds | memory MB |\n|---|---|---:|---:|\n");
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        if (r->kind != RTT_BENCH_BUILD) continue;
        if (r->error[0]) put(&t, "| %s %s | | %s | |\n", r->engine, r->method, r->error);
        else
            put(&t, "| %s %s | %s | %.3f | %.1f |\n", r->engine, r->method, r->variant[0] ? r->variant : "1 thread",
                r->seconds, (double)r->memory_bytes / 1048576.0);
    }
    if (rep->have_tree)
        put(&t, "\nkd-tree: depth %u (bound %u), %u nodes, %u leaves (%u empty), %.2f references per triangle, "
                "SAH cost %.1f.\n",
            rep->tree.depth, rep->tree.max_depth, rep->tree.node_count, rep->tree.leaf_count,
            rep->tree.empty_leaf_count, rep->triangles ? (double)rep->tree.references / rep->triangles : 0.0,
            rep->tree.sah_cost);
    if (tc > 0) {
        md_primary(&t, rep, threads, tc);
        md_culling_and_peaks(&t, rep, threads, tc);
        md_shadow_rays(&t, rep, threads, tc);
        md_renders(&t, rep, threads, tc);
    }
    headline h[8];
    size_t n = headlines(rep, h, 8);
    if (n) put(&t, "\n### Headline ratios (targets: MFT at least Embree's best coherent packets, frustum faster than 2x2 packets)\n\n| ratio | measured | target | rows |\n|---|---:|---:|---|\n");
    for (size_t k = 0; k < n; k++)
        put(&t, "| %s | %.2f× | %s%.2f× | %s |\n", h[k].name, h[k].value, h[k].value >= h[k].target ? "met, " : "missed, ",
            h[k].target, h[k].detail);
    put(&t, "\n");
    return finish(&t);
}

/* ---- TSV for plots and the cross-scene summary ---- */


char *rtt_bench_report_tsv(const rtt_bench_report *rep)
{
    text t = {0};
    char scene[64];
    if (rep->view[0]) snprintf(scene, sizeof scene, "%s", rep->view);
    else bench_base_name(rep->scene, scene);
    for (size_t i = 0; i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        if (r->error[0]) continue;
        if (r->kind == RTT_BENCH_BUILD) {
            put(&t, "build\t%s\t%ux%u\t%s\t%s\t%.4f\t%llu\t%u\n", scene, r->width, r->height, r->engine,
                r->variant[0] ? r->variant : "-", r->seconds, (unsigned long long)r->memory_bytes, rep->triangles);
            continue;
        }
        char method[64];
        snprintf(method, sizeof method, "%s%s%s", r->method, r->leaf_culling == 0 ? " nocull" : "",
                 r->shadows[0] && strcmp(r->shadows, "hard") ? "" : "");
        for (char *c = method; *c; c++)
            if (*c == ' ') *c = '_';
        char variant[40];
        snprintf(variant, sizeof variant, "%s", r->variant[0] ? r->variant : "-");
        for (char *c = variant; *c; c++)
            if (*c == ' ') *c = '_';
        put(&t, "row\t%s\t%ux%u\t%s\t%s\t%s\t%s\t%u\t%u\t%.4f\t%.1f\t%.4f\t%s\n", scene, r->width, r->height,
            kind_name(r->kind), r->engine, method, variant, r->tile, r->threads, r->fps, r->rays_per_second,
            r->vs_embree, r->shadows[0] ? r->shadows : "-");
    }
    headline h[8];
    size_t n = headlines(rep, h, 8);
    for (size_t k = 0; k < n; k++)
        put(&t, "headline\t%s\t%ux%u\t%s\t%.4f\t%.2f\t%s\n", scene, rep->width, rep->height, h[k].name, h[k].value,
            h[k].target, h[k].detail);
    return finish(&t);
}

/* ---- JSON ---- */

char *rtt_bench_report_json(const rtt_bench_report *rep)
{
    cJSON *root = cJSON_CreateObject();
    if (!root) return NULL;
    cJSON_AddStringToObject(root, "scene", rep->scene);
    cJSON_AddStringToObject(root, "view", rep->view);
    cJSON_AddNumberToObject(root, "triangles", rep->triangles);
    cJSON_AddNumberToObject(root, "width", rep->width);
    cJSON_AddNumberToObject(root, "height", rep->height);
    cJSON_AddNumberToObject(root, "frames", rep->frames);
    cJSON_AddNumberToObject(root, "warmup", rep->warmup);
    cJSON_AddStringToObject(root, "embree", rep->embree_note);
    if (rep->have_tree) {
        cJSON *tree = cJSON_AddObjectToObject(root, "kd_tree");
        cJSON_AddNumberToObject(tree, "depth", rep->tree.depth);
        cJSON_AddNumberToObject(tree, "max_depth", rep->tree.max_depth);
        cJSON_AddNumberToObject(tree, "nodes", rep->tree.node_count);
        cJSON_AddNumberToObject(tree, "leaves", rep->tree.leaf_count);
        cJSON_AddNumberToObject(tree, "empty_leaves", rep->tree.empty_leaf_count);
        cJSON_AddNumberToObject(tree, "references", (double)rep->tree.references);
        cJSON_AddNumberToObject(tree, "sah_cost", rep->tree.sah_cost);
        cJSON_AddNumberToObject(tree, "build_seconds", rep->tree.build_seconds);
        cJSON_AddNumberToObject(tree, "memory_bytes", (double)rep->tree.memory_bytes);
    }
    cJSON *rows = cJSON_AddArrayToObject(root, "rows");
    for (size_t i = 0; rows && i < rep->row_count; i++) {
        const rtt_bench_row *r = &rep->rows[i];
        cJSON *o = cJSON_CreateObject();
        if (!o) break;
        cJSON_AddItemToArray(rows, o);
        cJSON_AddStringToObject(o, "kind", kind_name(r->kind));
        cJSON_AddStringToObject(o, "engine", r->engine);
        cJSON_AddStringToObject(o, "method", r->method);
        cJSON_AddStringToObject(o, "family", r->family);
        cJSON_AddStringToObject(o, "variant", r->variant);
        cJSON_AddStringToObject(o, "shadows", r->shadows);
        cJSON_AddStringToObject(o, "isect", r->isect);
        cJSON_AddNumberToObject(o, "tile", r->tile);
        cJSON_AddNumberToObject(o, "leaf_culling", r->leaf_culling);
        cJSON_AddNumberToObject(o, "lanes", r->lanes);
        cJSON_AddNumberToObject(o, "threads", r->threads);
        cJSON_AddNumberToObject(o, "width", r->width);
        cJSON_AddNumberToObject(o, "height", r->height);
        if (r->error[0]) {
            cJSON_AddStringToObject(o, "error", r->error);
            continue;
        }
        cJSON_AddNumberToObject(o, "frames", r->frames);
        cJSON_AddNumberToObject(o, "seconds", r->seconds);
        cJSON_AddNumberToObject(o, "seconds_min", r->seconds_min);
        cJSON_AddNumberToObject(o, "fps", r->fps);
        cJSON_AddNumberToObject(o, "rays", (double)r->rays);
        cJSON_AddNumberToObject(o, "rays_per_second", r->rays_per_second);
        if (r->n >= 0) {
            cJSON_AddNumberToObject(o, "N", r->n);
            cJSON_AddNumberToObject(o, "I", r->i);
        }
        if (r->kind == RTT_BENCH_BUILD) cJSON_AddNumberToObject(o, "memory_bytes", (double)r->memory_bytes);
        if (r->vs_embree > 0) cJSON_AddNumberToObject(o, "vs_embree", r->vs_embree);
        if (r->agree >= 0) cJSON_AddNumberToObject(o, "agree", r->agree);
        if (r->image[0]) cJSON_AddStringToObject(o, "image", r->image);
    }
    cJSON *heads = cJSON_AddObjectToObject(root, "headlines");
    headline h[8];
    size_t n = headlines(rep, h, 8);
    for (size_t k = 0; heads && k < n; k++) {
        cJSON *o = cJSON_AddObjectToObject(heads, h[k].name);
        cJSON_AddNumberToObject(o, "value", h[k].value);
        cJSON_AddNumberToObject(o, "target", h[k].target);
        cJSON_AddStringToObject(o, "rows", h[k].detail);
    }
    char *out = cJSON_Print(root);
    cJSON_Delete(root);
    return out;
}

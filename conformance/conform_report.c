/* The conformance report as text (a table per engine pair and ray set, then
 * the rays each failing row fails on) and as JSON (cJSON) for machines.
 * Both are returned as strings: only cli/ prints. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "conform.h"

static unsigned long long own_errors(const rtt_conform_row *r)
{
    unsigned long long sum = r->occluded_errors;
    for (int c = RTT_CONFORM_T_MISMATCH; c <= RTT_CONFORM_HITMISS_OTHER; c++) sum += r->errors[c];
    return sum;
}

static void print_hit(FILE *out, const char *who, uint32_t prim, double t)
{
    if (prim == RTT_MISS)
        fprintf(out, "%s miss", who);
    else
        fprintf(out, "%s prim %u t %.9g", who, prim, t);
}

static void print_note(FILE *out, const rtt_conform_row *row, const rtt_conform_ray_note *n)
{
    fprintf(out, "    %s ray %u", rtt_conform_ray_set_name(row->set), n->index);
    if (n->file_index >= 0) fprintf(out, " (record %lld of the failing-rays file)", (long long)n->file_index);
    fprintf(out, ": org (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) tnear %.9g tfar %.9g\n      ", n->ray.org[0],
            n->ray.org[1], n->ray.org[2], n->ray.dir[0], n->ray.dir[1], n->ray.dir[2], n->ray.tnear, n->ray.tfar);
    print_hit(out, row->engine, n->engine.prim, n->engine.t);
    if (n->occluded) fprintf(out, " (occluded() %s)", n->engine_occluded ? "yes" : "no");
    fputs(", ", out);
    print_hit(out, row->oracle, n->oracle.prim, n->oracle.t);
    fputs(", ", out);
    if (n->verdict == RTT_VERDICT_NONE || n->verdict == RTT_VERDICT_UNDECIDABLE)
        fputs("referee -", out);
    else
        print_hit(out, "referee", n->referee.prim, n->referee.t);
    fprintf(out, ": %s, %s", n->occluded ? "occluded mismatch" : rtt_conform_category_name(n->category),
            rtt_conform_verdict_name(n->verdict));
    if (n->judged < RTT_CONFORM_CATEGORY_COUNT) fprintf(out, " (%s against the referee)", rtt_conform_category_name(n->judged));
    fputc('\n', out);
}

static void print_notes(FILE *out, const rtt_conform_report *report)
{
    for (size_t i = 0; i < report->row_count; i++) {
        const rtt_conform_row *r = &report->rows[i];
        if (!r->pass && r->failing_count)
            fprintf(out, "%s on %s fails on %llu rays; the first %zu:\n", r->engine, rtt_conform_ray_set_name(r->set),
                    own_errors(r), r->failing_count);
        for (size_t k = 0; !r->pass && k < r->failing_count; k++) print_note(out, r, &r->failing[k]);
        if (r->wrong_oracle_count)
            fprintf(out, "%s on %s: the referee finds Embree wrong on %llu rays and the reference wrong on %llu%s; "
                         "the first %zu:\n",
                    r->engine, rtt_conform_ray_set_name(r->set), (unsigned long long)r->embree_wrong,
                    (unsigned long long)r->reference_wrong,
                    r->engine_is_embree_row ? " (the reference's errors, counted in errors)" : " (not this row's errors)",
                    r->wrong_oracle_count);
        for (size_t k = 0; k < r->wrong_oracle_count; k++) print_note(out, r, &r->wrong_oracle[k]);
    }
}

char *rtt_conform_report_table(const rtt_conform_report *report)
{
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    if (!out) return NULL;
    fprintf(out, "%s: %u triangles, coordinate magnitude %g\n", report->scene, report->triangles, report->magnitude);
    fprintf(out, "%-22s %-9s %-8s %9s %9s %6s %8s %10s %8s %8s %6s %6s %9s %9s %7s  %s\n", "engine", "vs", "rays",
            "count", "agree", "tie", "boundary", "t-mismatch", "hm-graze", "hm-other", "occl", "unspec", "emb-wrong",
            "ref-wrong", "errors", "result");
    for (size_t i = 0; i < report->row_count; i++) {
        const rtt_conform_row *r = &report->rows[i];
        fprintf(out, "%-22s %-9s %-8s %9llu %9llu %6llu %8llu %10llu %8llu %8llu %6llu %6llu %9llu %9llu %7llu  %s",
                r->engine, r->oracle, rtt_conform_ray_set_name(r->set), (unsigned long long)r->rays,
                (unsigned long long)r->count[RTT_CONFORM_AGREE], (unsigned long long)r->count[RTT_CONFORM_TIE],
                (unsigned long long)r->count[RTT_CONFORM_BOUNDARY], (unsigned long long)r->count[RTT_CONFORM_T_MISMATCH],
                (unsigned long long)r->count[RTT_CONFORM_GRAZING], (unsigned long long)r->count[RTT_CONFORM_HITMISS_OTHER],
                (unsigned long long)r->occluded_mismatch, (unsigned long long)r->count[RTT_CONFORM_UNSPECIFIED],
                (unsigned long long)r->embree_wrong, (unsigned long long)r->reference_wrong, own_errors(r),
                r->pass ? "ok" : "FAIL");
        if (r->error[0]) fprintf(out, " (%s)", r->error);
        if (r->unrefereed) fprintf(out, " (%llu beyond the referee's budget)", (unsigned long long)r->unrefereed);
        fputc('\n', out);
    }
    fprintf(out, "columns up to occl: the engine against the reference; every disagreement is decided by a double-"
                 "precision brute force (the referee); errors: the row's own (on embree rows the reference's), "
                 "what the thresholds bound\n");
    fprintf(out, "thresholds: t-mismatch 0, hit/miss other 0, occluded mismatch 0; hit/miss grazing <= %.2f%% "
                 "(optimized), <= %.0f%% (embree) of the rays, reported only on the extreme set\n",
            100.0 * RTT_CONFORM_GRAZING_SHARE_OPTIMIZED, 100.0 * RTT_CONFORM_GRAZING_SHARE_EMBREE);
    print_notes(out, report);
    if (report->failing_ray_count)
        fprintf(out, "failing rays: %zu (each once)%s\n", report->failing_ray_count,
                report->failing_rays_inexact ? "; some do not round-trip exactly through the scene's coordinates" : "");
    fprintf(out, "conformance: %s\n", report->pass ? "PASS" : "FAIL");
    if (fclose(out) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

/* JSON has no infinity: non-finite values are the strings "inf", "-inf", "nan". */
static void add_number(cJSON *obj, const char *name, double x)
{
    if (isfinite(x))
        cJSON_AddNumberToObject(obj, name, x);
    else
        cJSON_AddStringToObject(obj, name, isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
}

static void add_vector(cJSON *obj, const char *name, const float v[3])
{
    cJSON *a = cJSON_AddArrayToObject(obj, name);
    for (int k = 0; k < 3; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
}

/* {"prim": P, "t": T}, both null on a miss. */
static void add_hit(cJSON *obj, const char *name, uint32_t prim, double t)
{
    cJSON *h = cJSON_AddObjectToObject(obj, name);
    if (prim == RTT_MISS) {
        cJSON_AddNullToObject(h, "prim");
        cJSON_AddNullToObject(h, "t");
    } else {
        cJSON_AddNumberToObject(h, "prim", prim);
        cJSON_AddNumberToObject(h, "t", t);
    }
}

static cJSON *note_json(const rtt_conform_ray_note *n)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "index", n->index);
    if (n->file_index >= 0)
        cJSON_AddNumberToObject(o, "file_index", (double)n->file_index);
    else
        cJSON_AddNullToObject(o, "file_index");
    add_vector(o, "org", n->ray.org);
    add_vector(o, "dir", n->ray.dir);
    add_number(o, "tnear", n->ray.tnear);
    add_number(o, "tfar", n->ray.tfar);
    add_hit(o, "engine", n->engine.prim, n->engine.t);
    add_hit(o, "oracle", n->oracle.prim, n->oracle.t);
    if (n->occluded) cJSON_AddBoolToObject(o, "engine_occluded", n->engine_occluded != 0);
    if (n->verdict == RTT_VERDICT_NONE || n->verdict == RTT_VERDICT_UNDECIDABLE)
        cJSON_AddNullToObject(o, "referee");
    else
        add_hit(o, "referee", n->referee.prim, n->referee.t);
    cJSON_AddStringToObject(o, "category", n->occluded ? "occluded mismatch" : rtt_conform_category_name(n->category));
    cJSON_AddStringToObject(o, "verdict", rtt_conform_verdict_name(n->verdict));
    if (n->judged < RTT_CONFORM_CATEGORY_COUNT)
        cJSON_AddStringToObject(o, "against_referee", rtt_conform_category_name(n->judged));
    else
        cJSON_AddNullToObject(o, "against_referee");
    return o;
}

char *rtt_conform_report_json(const rtt_conform_report *report)
{
    cJSON *root = cJSON_CreateObject();
    if (!root) return NULL;
    cJSON_AddStringToObject(root, "scene", report->scene);
    cJSON_AddNumberToObject(root, "triangles", report->triangles);
    cJSON_AddNumberToObject(root, "magnitude", report->magnitude);
    cJSON_AddBoolToObject(root, "pass", report->pass);
    cJSON *thresholds = cJSON_AddObjectToObject(root, "thresholds");
    cJSON_AddNumberToObject(thresholds, "grazing_share_optimized", RTT_CONFORM_GRAZING_SHARE_OPTIMIZED);
    cJSON_AddNumberToObject(thresholds, "grazing_share_embree", RTT_CONFORM_GRAZING_SHARE_EMBREE);
    cJSON_AddNumberToObject(root, "referee_budget", (double)RTT_CONFORM_REFEREE_BUDGET);
    cJSON_AddNumberToObject(root, "failing_ray_count", (double)report->failing_ray_count);
    cJSON_AddNumberToObject(root, "failing_rays_inexact", (double)report->failing_rays_inexact);
    cJSON *rows = cJSON_AddArrayToObject(root, "rows");
    for (size_t i = 0; i < report->row_count; i++) {
        const rtt_conform_row *r = &report->rows[i];
        cJSON *row = cJSON_CreateObject();
        cJSON_AddStringToObject(row, "engine", r->engine);
        cJSON_AddStringToObject(row, "oracle", r->oracle);
        cJSON_AddStringToObject(row, "rays", rtt_conform_ray_set_name(r->set));
        cJSON_AddNumberToObject(row, "count", (double)r->rays);
        cJSON_AddNumberToObject(row, "agree", (double)r->count[RTT_CONFORM_AGREE]);
        cJSON_AddNumberToObject(row, "tie", (double)r->count[RTT_CONFORM_TIE]);
        cJSON_AddNumberToObject(row, "boundary", (double)r->count[RTT_CONFORM_BOUNDARY]);
        cJSON_AddNumberToObject(row, "t_mismatch", (double)r->count[RTT_CONFORM_T_MISMATCH]);
        cJSON_AddNumberToObject(row, "hitmiss_grazing", (double)r->count[RTT_CONFORM_GRAZING]);
        cJSON_AddNumberToObject(row, "hitmiss_other", (double)r->count[RTT_CONFORM_HITMISS_OTHER]);
        cJSON_AddNumberToObject(row, "unspecified", (double)r->count[RTT_CONFORM_UNSPECIFIED]);
        cJSON_AddNumberToObject(row, "occluded_mismatch", (double)r->occluded_mismatch);
        cJSON *errors = cJSON_AddObjectToObject(row, "errors");
        cJSON_AddNumberToObject(errors, "t_mismatch", (double)r->errors[RTT_CONFORM_T_MISMATCH]);
        cJSON_AddNumberToObject(errors, "hitmiss_grazing", (double)r->errors[RTT_CONFORM_GRAZING]);
        cJSON_AddNumberToObject(errors, "hitmiss_other", (double)r->errors[RTT_CONFORM_HITMISS_OTHER]);
        cJSON_AddNumberToObject(errors, "occluded", (double)r->occluded_errors);
        cJSON_AddNumberToObject(row, "refereed", (double)r->refereed);
        cJSON_AddNumberToObject(row, "unrefereed", (double)r->unrefereed);
        cJSON_AddNumberToObject(row, "embree_wrong", (double)r->embree_wrong);
        cJSON_AddNumberToObject(row, "reference_wrong", (double)r->reference_wrong);
        cJSON_AddNumberToObject(row, "both_right", (double)r->both_right);
        cJSON_AddNumberToObject(row, "grazing_limit", r->grazing_limit);
        cJSON_AddBoolToObject(row, "pass", r->pass);
        if (r->error[0]) cJSON_AddStringToObject(row, "error", r->error);
        cJSON *failing = cJSON_AddArrayToObject(row, "failing_rays");
        for (size_t k = 0; !r->pass && k < r->failing_count; k++) cJSON_AddItemToArray(failing, note_json(&r->failing[k]));
        cJSON *wrong = cJSON_AddArrayToObject(row, "oracle_wrong_rays");
        for (size_t k = 0; k < r->wrong_oracle_count; k++) cJSON_AddItemToArray(wrong, note_json(&r->wrong_oracle[k]));
        cJSON_AddItemToArray(rows, row);
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    return text;
}

/* The extremes report: its storage, the text table and the JSON.  Only
 * cli/ prints; these return strings. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "extremes_internal.h"

rtt_extreme_result *rtt_ext_add_result(rtt_extremes_report *report, const char *check, const char *engine)
{
    if (report->count == report->cap) {
        size_t cap = report->cap ? 2 * report->cap : 64;
        rtt_extreme_result *items = realloc(report->items, cap * sizeof *items);
        if (!items) return NULL;
        report->items = items;
        report->cap = cap;
    }
    rtt_extreme_result *r = &report->items[report->count++];
    memset(r, 0, sizeof *r);
    snprintf(r->check, sizeof r->check, "%.47s", check);
    snprintf(r->engine, sizeof r->engine, "%.39s", engine);
    r->asserted = true;
    return r;
}

void rtt_extremes_report_free(rtt_extremes_report *report)
{
    free(report->items);
    memset(report, 0, sizeof *report);
}

static unsigned long long count_of(const rtt_extreme_result *r, rtt_conform_category c)
{
    return r->has_counts ? (unsigned long long)r->row.count[c] : 0ull;
}

char *rtt_extremes_report_table(const rtt_extremes_report *report)
{
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    if (!out) return NULL;
    fprintf(out, "%-30s %-18s %7s %7s %5s %5s %6s %6s %6s %5s %8s  %-8s %s\n", "check", "engine", "rays", "agree", "tie",
            "bound", "t-mis", "graze", "other", "occl", "failures", "result", "note");
    for (size_t i = 0; i < report->count; i++) {
        const rtt_extreme_result *r = &report->items[i];
        const char *result = !r->asserted ? "reported" : r->pass ? "ok" : "FAIL";
        fprintf(out, "%-30s %-18s %7llu ", r->check, r->engine, (unsigned long long)r->rays);
        if (r->has_counts)
            fprintf(out, "%7llu %5llu %5llu %6llu %6llu %6llu %5llu", count_of(r, RTT_CONFORM_AGREE),
                    count_of(r, RTT_CONFORM_TIE), count_of(r, RTT_CONFORM_BOUNDARY),
                    count_of(r, RTT_CONFORM_T_MISMATCH), count_of(r, RTT_CONFORM_GRAZING),
                    count_of(r, RTT_CONFORM_HITMISS_OTHER), (unsigned long long)r->row.occluded_mismatch);
        else
            fprintf(out, "%7s %5s %5s %6s %6s %6s %5s", "-", "-", "-", "-", "-", "-", "-");
        fprintf(out, " %8llu  %-8s %s\n", (unsigned long long)r->failures, result, r->note);
    }
    fprintf(out, "hit-by-hit rows: against the reference (the reference against brute force); t-mismatch, other\n"
                 "hit/miss and occluded disagreements must be 0, grazing hit/miss within the limit in the note.\n"
                 "\"reported\" rows are measured, not asserted (conformance/README.md).\n");
    fprintf(out, "extremes: %s\n", report->pass ? "PASS" : "FAIL");
    if (fclose(out) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

char *rtt_extremes_report_json(const rtt_extremes_report *report)
{
    cJSON *root = cJSON_CreateObject();
    if (!root) return NULL;
    cJSON_AddBoolToObject(root, "pass", report->pass);
    cJSON *items = cJSON_AddArrayToObject(root, "results");
    for (size_t i = 0; i < report->count; i++) {
        const rtt_extreme_result *r = &report->items[i];
        cJSON *item = cJSON_CreateObject();
        cJSON_AddStringToObject(item, "check", r->check);
        cJSON_AddStringToObject(item, "engine", r->engine);
        cJSON_AddNumberToObject(item, "rays", (double)r->rays);
        cJSON_AddNumberToObject(item, "failures", (double)r->failures);
        if (r->has_counts) {
            cJSON *counts = cJSON_AddObjectToObject(item, "counts");
            cJSON_AddStringToObject(counts, "oracle", r->row.oracle);
            for (int c = 0; c < RTT_CONFORM_CATEGORY_COUNT; c++)
                cJSON_AddNumberToObject(counts, rtt_conform_category_name((rtt_conform_category)c),
                                        (double)r->row.count[c]);
            cJSON_AddNumberToObject(counts, "occluded mismatch", (double)r->row.occluded_mismatch);
            cJSON_AddNumberToObject(counts, "grazing limit", r->row.grazing_limit);
        }
        cJSON_AddBoolToObject(item, "asserted", r->asserted);
        cJSON_AddBoolToObject(item, "pass", r->pass);
        cJSON_AddStringToObject(item, "note", r->note);
        cJSON_AddItemToArray(items, item);
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    return text;
}

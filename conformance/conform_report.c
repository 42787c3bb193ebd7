/* The conformance report as text (a table per engine pair and ray set) and
 * as JSON (cJSON) for machines.  Both are returned as strings: only cli/
 * prints. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>

#include "conform.h"

char *rtt_conform_report_table(const rtt_conform_report *report)
{
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    if (!out) return NULL;
    fprintf(out, "%s: %u triangles, coordinate magnitude %g\n", report->scene, report->triangles, report->magnitude);
    fprintf(out, "%-22s %-9s %-8s %9s %9s %6s %8s %10s %8s %8s %6s  %s\n", "engine", "vs", "rays", "count", "agree",
            "tie", "boundary", "t-mismatch", "hm-graze", "hm-other", "occl", "result");
    for (size_t i = 0; i < report->row_count; i++) {
        const rtt_conform_row *r = &report->rows[i];
        fprintf(out, "%-22s %-9s %-8s %9llu %9llu %6llu %8llu %10llu %8llu %8llu %6llu  %s", r->engine, r->oracle,
                rtt_conform_ray_set_name(r->set), (unsigned long long)r->rays,
                (unsigned long long)r->count[RTT_CONFORM_AGREE], (unsigned long long)r->count[RTT_CONFORM_TIE],
                (unsigned long long)r->count[RTT_CONFORM_BOUNDARY], (unsigned long long)r->count[RTT_CONFORM_T_MISMATCH],
                (unsigned long long)r->count[RTT_CONFORM_GRAZING], (unsigned long long)r->count[RTT_CONFORM_HITMISS_OTHER],
                (unsigned long long)r->occluded_mismatch, r->pass ? "ok" : "FAIL");
        if (r->error[0]) fprintf(out, " (%s)", r->error);
        fputc('\n', out);
    }
    fprintf(out, "thresholds: t-mismatch 0, hit/miss other 0, occluded mismatch 0; hit/miss grazing <= %.2f%% "
                 "(optimized), <= %.0f%% (embree) of the rays, reported only on the extreme set\n",
            100.0 * RTT_CONFORM_GRAZING_SHARE_OPTIMIZED, 100.0 * RTT_CONFORM_GRAZING_SHARE_EMBREE);
    fprintf(out, "conformance: %s\n", report->pass ? "PASS" : "FAIL");
    if (fclose(out) != 0) {
        free(text);
        return NULL;
    }
    return text;
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
        cJSON_AddNumberToObject(row, "occluded_mismatch", (double)r->occluded_mismatch);
        cJSON_AddNumberToObject(row, "grazing_limit", r->grazing_limit);
        cJSON_AddBoolToObject(row, "pass", r->pass);
        if (r->error[0]) cJSON_AddStringToObject(row, "error", r->error);
        cJSON_AddItemToArray(rows, row);
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    return text;
}

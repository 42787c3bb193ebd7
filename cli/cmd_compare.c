/* rtt compare: image metrics between two EXR files, optionally checked
 * against thresholds (the golden-image tests use that). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "rtt/image.h"

static const char compare_help[] =
    "usage: rtt compare A.exr B.exr [--json] [--max-rmse X] [--max-error X] [--max-share X]\n"
    "\n"
    "Prints RMSE over all RGB samples, the largest channel error, and the share of\n"
    "pixels with any channel off by more than 1/255 (colours clamped to [0,1]).\n"
    "With thresholds, exits 1 when a metric exceeds its bound.\n"
    "\n"
    "Exit status: 0 success, 1 bad input or a threshold exceeded, 2 bad usage.\n";

int cmd_compare(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL};
    int path_count = 0;
    bool json = false;
    float limits[3] = {-1.0f, -1.0f, -1.0f}; /* rmse, max error, share; negative = unchecked */
    static const char *const limit_flags[3] = {"--max-rmse", "--max-error", "--max-share"};
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(compare_help, stdout);
            return RTT_EXIT_OK;
        }
        if (strcmp(argv[i], "--json") == 0) {
            json = true;
            continue;
        }
        int limit = -1;
        for (int k = 0; k < 3; k++)
            if (strcmp(argv[i], limit_flags[k]) == 0) limit = k;
        if (limit >= 0) {
            if (i + 1 >= argc || !cli_parse_float(argv[i + 1], &limits[limit]) || limits[limit] < 0.0f)
                return cli_usage_error("compare", "%s needs a non-negative number", argv[i]);
            i++;
            continue;
        }
        if (argv[i][0] == '-') return cli_usage_error("compare", "unknown option \"%s\"", argv[i]);
        if (path_count == 2) return cli_usage_error("compare", "expected exactly two images");
        paths[path_count++] = argv[i];
    }
    if (path_count != 2) return cli_usage_error("compare", "expected two images");

    rtt_error err = {0};
    rtt_image *a = rtt_image_read_exr(paths[0], &err);
    rtt_image *b = a ? rtt_image_read_exr(paths[1], &err) : NULL;
    rtt_image_metrics m;
    bool ok = a && b && rtt_image_compare(a, b, &m, &err);
    rtt_image_free(a);
    rtt_image_free(b);
    if (!ok) {
        if (a && b) {
            rtt_error named;
            rtt_error_set(&named, "%s vs %s: %s", paths[0], paths[1], err.message);
            return cli_fail(&named);
        }
        return cli_fail(&err);
    }
    if (json)
        printf("{\"rmse\": %.9g, \"max_error\": %.9g, \"share_over_1_255\": %.9g, \"pixels_over_1_255\": %llu}\n",
               m.rmse, m.max_error, m.share_over_1_255, (unsigned long long)m.pixels_over_1_255);
    else
        printf("rmse %.6g  max error %.6g  pixels off by more than 1/255: %llu (%.4f%%)\n", m.rmse, m.max_error,
               (unsigned long long)m.pixels_over_1_255, 100.0 * m.share_over_1_255);
    const double values[3] = {m.rmse, m.max_error, m.share_over_1_255};
    for (int k = 0; k < 3; k++) {
        if (limits[k] >= 0.0f && values[k] > limits[k]) {
            fprintf(stderr, "rtt: %s vs %s: %s %.6g exceeds %.6g\n", paths[0], paths[1], limit_flags[k] + 6,
                    values[k], limits[k]);
            return RTT_EXIT_BAD_INPUT;
        }
    }
    return RTT_EXIT_OK;
}

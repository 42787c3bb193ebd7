/* rtt compare: image metrics between two EXR files, optionally checked
 * against thresholds (the golden-image tests use that). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "options.h"
#include "rtt/image.h"

typedef struct compare_args {
    const char *paths[2];
    bool json;
    float limits[3]; /* rmse, max error, share; negative = unchecked */
} compare_args;

static const cli_option compare_options[] = {
    {.name = "--json", .help = "the metrics as one JSON object", .kind = CLI_FLAG, CLI_FIELD(compare_args, json)},
    {.name = "--max-rmse", .value_name = "X", .help = "exit 1 when the RMSE exceeds X",
     .kind = CLI_FLOAT, CLI_FIELD(compare_args, limits[0]), .min = 0.0f},
    {.name = "--max-error", .value_name = "X", .help = "exit 1 when the largest channel error exceeds X",
     .kind = CLI_FLOAT, CLI_FIELD(compare_args, limits[1]), .min = 0.0f},
    {.name = "--max-share", .value_name = "X",
     .help = "exit 1 when the share of pixels off by more than 1/255 exceeds X",
     .kind = CLI_FLOAT, CLI_FIELD(compare_args, limits[2]), .min = 0.0f},
};

static void compare_defaults(void *opaque)
{
    compare_args *args = opaque;
    for (int k = 0; k < 3; k++) args->limits[k] = -1.0f;
}

static int compare(void *opaque, const cli_parsed *parsed)
{
    (void)parsed;
    const compare_args *args = opaque;
    const char *const *paths = args->paths;
    const float *limits = args->limits;
    static const char *const metric_names[3] = {"rmse", "error", "share"};

    rtt_error err = {0};
    rtt_image *a = rtt_image_read(paths[0], &err);
    rtt_image *b = a ? rtt_image_read(paths[1], &err) : NULL;
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
    if (args->json)
        printf("{\"rmse\": %.9g, \"max_error\": %.9g, \"share_over_1_255\": %.9g, \"pixels_over_1_255\": %llu}\n",
               m.rmse, m.max_error, m.share_over_1_255, (unsigned long long)m.pixels_over_1_255);
    else
        printf("rmse %.6g  max error %.6g  pixels off by more than 1/255: %llu (%.4f%%)\n", m.rmse, m.max_error,
               (unsigned long long)m.pixels_over_1_255, 100.0 * m.share_over_1_255);
    const double values[3] = {m.rmse, m.max_error, m.share_over_1_255};
    for (int k = 0; k < 3; k++) {
        if (limits[k] >= 0.0f && values[k] > limits[k]) {
            fprintf(stderr, "rtt: %s vs %s: %s %.6g exceeds %.6g\n", paths[0], paths[1], metric_names[k],
                    values[k], limits[k]);
            return RTT_EXIT_BAD_INPUT;
        }
    }
    return RTT_EXIT_OK;
}

const cli_command compare_command = {
    .name = "compare", .summary = "image metrics: RMSE, max error, share of pixels over 1/255", .run = compare,
    CLI_ARGS(compare_args, compare_defaults), CLI_ROWS(compare_options),
    .synopsis = "A.exr|A.png B.exr|B.png [options]",
    .description = "Prints RMSE over all RGB samples, the largest channel error, and the share of\n"
                   "pixels with any channel off by more than 1/255 (colours clamped to [0,1]).\n"
                   "Either image may be EXR (linear float) or PNG (8-bit sRGB, decoded to linear),\n"
                   "so a PNG compares with an EXR: a render's PNG is within its 8-bit rounding\n"
                   "of its EXR.\n",
    .operand = "IMAGE", .operand_min = 2, .operand_max = 2, .operand_offset = offsetof(compare_args, paths),
    .operands_wrong = "expected two images, A and B (.exr or .png)",
    .exit_status = "0 success, 1 bad input or a threshold exceeded, 2 bad usage.",
};

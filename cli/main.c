/* rtt: the command-line driver.  A thin dispatcher over the subcommands;
 * each lives in its own cmd_*.c file. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "conform.h"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"render", cmd_render, "render a scene to EXR or PNG"},
    {"bake", cmd_bake, "build the kd-tree offline and save it as .kdt"},
    {"info", cmd_info, "triangles, bounds, tree depth, leaves, SAH cost, duplication"},
    {"triangles", cmd_triangles, "write the triangles in global order, 9 float32 each"},
    {"trace", cmd_trace, "trace rays.bin through an engine, write hits.bin"},
    {"conform", cmd_conform, "hit-by-hit agreement of the engines"},
    {"compare", cmd_compare, "image metrics: RMSE, max error, share of pixels over 1/255"},
    {"bench", cmd_bench, "the papers' tables on a scene, raced against Embree"},
};

static void print_usage(FILE *out)
{
    fprintf(out, "usage: rtt COMMAND [options]   (rtt COMMAND --help for each)\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\nexit codes: 0 success, 1 bad input, 2 bad usage\n");
}

int main(int argc, char **argv)
{
    rtt_error err = {0};
    if (!rtt_conform_register_engines(&err)) return cli_fail(&err);
    if (argc < 2) {
        print_usage(stderr);
        return RTT_EXIT_USAGE;
    }
    if (cli_is_help(argv[1])) {
        print_usage(stdout);
        return RTT_EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "rtt: unknown command \"%s\" (see rtt --help)\n", argv[1]);
    return RTT_EXIT_USAGE;
}

/* rtt: the command-line driver.  A thin dispatcher over the subcommands;
 * each lives in its own cmd_*.c file and is run by the option parser
 * (options.h: cli_run). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "conform.h"
#include "options.h"

static const cli_command *const commands[] = {
    &render_command, &bake_command,    &info_command,    &triangles_command,
    &trace_command,  &conform_command, &compare_command, &bench_command,   &view_command,
};

static void print_usage(FILE *out)
{
    fprintf(out, "usage: rtt COMMAND [options]   (rtt COMMAND --help for each)\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-10s %s\n", commands[i]->name, commands[i]->summary);
    fprintf(out, "\nexit codes: 0 success, 1 bad input, 2 bad usage, 130 and 143 interrupted (SIGINT, SIGTERM:\n"
                 "no output is left half-written, no temporary is left behind)\n");
}

int main(int argc, char **argv)
{
    rtt_error err = {0};
    cli_handle_signals();
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
        if (strcmp(argv[1], commands[i]->name) == 0) return cli_run(commands[i], argc - 1, argv + 1);
    fprintf(stderr, "rtt: unknown command \"%s\" (see rtt --help)\n", argv[1]);
    return RTT_EXIT_USAGE;
}

/* The option parser every subcommand uses.  A command declares its options
 * once, in one table of cli_option rows; from that table the parser reads
 * `--opt value`, `--opt=value`, `-o value` and `-o=value`, refuses unknown
 * options, missing values, junk and out-of-range numbers and single-use
 * options given twice, and prints --help.  Each refusal is one line,
 * "rtt CMD: --opt VALUE: what is wrong (see rtt CMD --help)", exit 2.
 *
 * After parsing, the command refuses what does not apply (an option the
 * engine does not read, a setting a file kind cannot honour) with
 * cli_refuse and cli_check_engine_options, which name the option the user
 * typed; library messages never name command-line flags. */
#ifndef RTT_CLI_OPTIONS_H
#define RTT_CLI_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/error.h"

/* cli_parse and the checks return this when the command should go on;
 * anything else is the exit code to return. */
#define CLI_CONTINUE (-1)
#define CLI_OPTIONS_MAX 32

typedef enum cli_option_kind {
    CLI_FLAG,   /* no value; sets a bool */
    CLI_U32,    /* a whole number from lo to hi into a uint32_t */
    CLI_FLOAT,  /* a finite number of at least `min` into a float */
    CLI_STRING, /* any text into a const char * (paths, names checked later) */
    CLI_CHOICE, /* one of `choices` (NULL-terminated); its index into an int */
    CLI_CHOICE_LIST, /* a comma list of `choices`; bit (1 << index) of each into a uint32_t */
    CLI_CUSTOM, /* `parse` converts and checks the value into the field */
} cli_option_kind;

/* Converts `value` into `field`; on failure puts what is wrong (without the
 * option's name) in `why`. */
typedef bool (*cli_value_parser)(const char *value, void *field, rtt_error *why);
/* Appends run-time text (names from the engine registry, say) to a help line. */
typedef void (*cli_help_writer)(char *out, size_t size);

typedef struct cli_option {
    const char *name;            /* "--tile" */
    char short_name;             /* 'o' for -o; 0 for none */
    const char *value_name;      /* "N", "FILE"; NULL for a flag */
    const char *help;            /* one line, wrapped when printed */
    cli_option_kind kind;
    size_t offset, size;         /* the field in the command's argument struct (CLI_FIELD) */
    uint32_t lo, hi;             /* CLI_U32: the range */
    float min;                   /* CLI_FLOAT: the least value */
    const char *const *choices;  /* CLI_CHOICE, CLI_CHOICE_LIST */
    cli_value_parser parse;      /* CLI_CUSTOM */
    cli_help_writer help_more;   /* optional */
    uint32_t given;              /* an RTT_OPTION_* bit set in the command's engine options */
    uint32_t repeat_max;         /* > 1: repeatable; the field is an array of repeat_max values */
    size_t count_offset;         /* repeatable: a uint32_t counting the values given */
} cli_option;

#define CLI_FIELD(type, member) .offset = offsetof(type, member), .size = sizeof(((type *)0)->member)

typedef struct cli_parsed cli_parsed;

/* A subcommand: what `rtt --help` and its own --help say, its options and
 * operands, and what it does once they are parsed. */
typedef struct cli_command {
    const char *name;                /* "render" */
    const char *summary;             /* its line in `rtt --help` */
    size_t args_size;                /* the command's argument struct, which the table's fields are in */
    void (*defaults)(void *args);    /* fills the defaults into zeroed args; NULL: zero is the default */
    /* the checks after parsing, then the work; returns the exit code */
    int (*run)(void *args, const cli_parsed *parsed);
    const char *synopsis;            /* what follows "usage: rtt NAME "; one line per form */
    const char *description;         /* paragraphs between usage and options, wrapped by hand */
    const cli_option *options;
    size_t option_count;
    const char *operand;             /* "SCENE"; NULL when the command takes none */
    uint32_t operand_min, operand_max;
    size_t operand_offset;           /* an array of operand_max const char * */
    const char *operands_wrong;      /* message for a wrong operand count; NULL: "no SCENE given" */
    size_t engine_offset;            /* the rtt_engine_options the rows' `given` bits go to */
    const char *environment;         /* optional: the variables the command reads */
    const char *exit_status;         /* NULL: "0 success, 1 bad input, 2 bad usage." */
} cli_command;

#define CLI_ROWS(table) .options = table, .option_count = sizeof table / sizeof table[0]
/* The argument struct of a command, and its defaults function. */
#define CLI_ARGS(type, defaults_function) .args_size = sizeof(type), .defaults = defaults_function
/* The one SCENE operand most commands take, into `type`'s scene_path. */
#define CLI_SCENE_OPERAND(type)                                                                                 \
    .operand = "SCENE", .operand_min = 1, .operand_max = 1, .operand_offset = offsetof(type, scene_path)

/* What was given, for the checks after parsing. */
struct cli_parsed {
    const cli_command *command;
    const char *value[CLI_OPTIONS_MAX];    /* per row: the last value ("" for a flag); NULL: not given */
    const char *spelling[CLI_OPTIONS_MAX]; /* per row: as typed, "-o" or "--output" */
    char short_spelling[CLI_OPTIONS_MAX][3];
};

/* Runs `command` on argv[1..argc-1] (argv[0] is its name): its defaults,
 * the options parsed into them, then its run.  Prints --help (exit 0), and,
 * for the help test, --list-options: one line per row, "NAME SHORT VALUE"
 * ("-" for none).  Returns the exit code. */
int cli_run(const cli_command *command, int argc, char **argv);

bool cli_given(const cli_parsed *parsed, const char *name);
/* Prints "rtt CMD: NAME VALUE: <message> (see rtt CMD --help)" (NAME as the
 * user typed it; no NAME when name is NULL) and returns RTT_EXIT_USAGE. */
int cli_refuse(const cli_parsed *parsed, const char *name, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* rtt_engine_options_check for engine `engine`; on failure names the option
 * that made it fail (the first given one, in table order, whose addition
 * to the defaults the check refuses). */
int cli_check_engine_options(const cli_parsed *parsed, const char *engine, const rtt_engine_options *opt);

/* Rows every command that creates an engine shares; `type` is the command's
 * argument struct, `engine` the path of its rtt_engine_options member. */
bool cli_parse_engine_name(const char *value, void *field, rtt_error *why);
bool cli_parse_accel(const char *value, void *field, rtt_error *why);
bool cli_parse_traversal(const char *value, void *field, rtt_error *why);
bool cli_parse_tile(const char *value, void *field, rtt_error *why);
bool cli_parse_isa(const char *value, void *field, rtt_error *why);
void cli_help_engines(char *out, size_t size);
void cli_help_accels(char *out, size_t size);
void cli_help_kernels(char *out, size_t size);
void cli_help_isas(char *out, size_t size);
extern const char *const cli_on_off[];

#define CLI_OPTION_ENGINE(type, member)                                                                         \
    {.name = "--engine", .value_name = "NAME", .help = "the engine (default optimized):", .kind = CLI_CUSTOM,   \
     CLI_FIELD(type, member), .parse = cli_parse_engine_name, .help_more = cli_help_engines}
#define CLI_OPTION_ACCEL(type, engine)                                                                          \
    {.name = "--accel", .value_name = "NAME", .help = "acceleration structure (default: the engine's):",        \
     .kind = CLI_CUSTOM, CLI_FIELD(type, engine.accel), .parse = cli_parse_accel,                               \
     .help_more = cli_help_accels, .given = RTT_OPTION_ACCEL}
#define CLI_OPTION_TRAVERSAL(type, engine)                                                                      \
    {.name = "--traversal", .value_name = "NAME",                                                               \
     .help = "the traversal kernel, one of the engine's (default: the engine's own):",                          \
     .kind = CLI_CUSTOM, CLI_FIELD(type, engine.traversal), .parse = cli_parse_traversal,                       \
     .help_more = cli_help_kernels, .given = RTT_OPTION_TRAVERSAL}
#define CLI_OPTION_TILE(type, engine)                                                                           \
    {.name = "--tile", .value_name = "N", .help = "tile side in pixels (rays): 4, 8 (default), 16, 32",         \
     .kind = CLI_CUSTOM, CLI_FIELD(type, engine.tile), .parse = cli_parse_tile, .given = RTT_OPTION_TILE}
#define CLI_OPTION_LEAF_CULLING(type, engine)                                                                   \
    {.name = "--leaf-culling", .value_name = "on|off",                                                          \
     .help = "packet/leaf culling of the frustum kernels (default on)",                                         \
     .kind = CLI_CHOICE, CLI_FIELD(type, engine.leaf_culling), .choices = cli_on_off,                           \
     .given = RTT_OPTION_LEAF_CULLING}
#define CLI_OPTION_ISA(type, engine)                                                                            \
    {.name = "--isa", .value_name = "NAME",                                                                     \
     .help = "instruction set of the kernels: auto (default: $RTT_ISA when set, else the widest this "          \
             "CPU has) or one of",                                                                              \
     .kind = CLI_CUSTOM, CLI_FIELD(type, engine.isa), .parse = cli_parse_isa, .help_more = cli_help_isas,       \
     .given = RTT_OPTION_ISA}
#define CLI_OPTION_MAX_DEPTH(type, engine)                                                                      \
    {.name = "--max-depth", .value_name = "N",                                                                  \
     .help = "kd-tree depth bound, 1 to 64 (default round(2 + log2 N), at least 8, N the triangles)",           \
     .kind = CLI_U32, CLI_FIELD(type, engine.max_tree_depth), .lo = 1, .hi = RTT_KD_DEPTH_LIMIT,                \
     .given = RTT_OPTION_MAX_DEPTH}
/* The options of an engine that traces with kernels of a kd-tree: every
 * engine option but --engine itself (render, trace). */
#define CLI_OPTIONS_KD_ENGINE(type, engine)                                                                     \
    CLI_OPTION_ACCEL(type, engine), CLI_OPTION_TRAVERSAL(type, engine), CLI_OPTION_TILE(type, engine),          \
        CLI_OPTION_LEAF_CULLING(type, engine), CLI_OPTION_ISA(type, engine), CLI_OPTION_MAX_DEPTH(type, engine)
/* The options of building a kd-tree (bake, info). */
#define CLI_OPTIONS_KD_TREE(type, engine) CLI_OPTION_ACCEL(type, engine), CLI_OPTION_MAX_DEPTH(type, engine)
/* --threads N for the commands that build a tree but do not render. */
#define CLI_OPTION_BUILD_THREADS(type, engine)                                                                  \
    {.name = "--threads", .value_name = "N",                                                                    \
     .help = "threads for the kd-tree build and the check of a baked tree, 1 to 1024 (default: one per core)",   \
     .kind = CLI_U32, CLI_FIELD(type, engine.threads), .lo = 1, .hi = 1024}

/* --max-memory SIZE into a uint64_t of bytes (rtt_memory_size_parse). */
bool cli_parse_memory_size(const char *value, void *field, rtt_error *why);
#define CLI_OPTION_MAX_MEMORY(type, member)                                                                     \
    {.name = "--max-memory", .value_name = "SIZE",                                                              \
     .help = "refuse a scene that would need more memory than SIZE (512M, 4G, ...; default: the machine's "      \
             "memory or the process's limit, whichever is lower)",                                              \
     .kind = CLI_CUSTOM, CLI_FIELD(type, member), .parse = cli_parse_memory_size}
#define CLI_OPTION_BEZIER_LEVEL(type, member)                                                                   \
    {.name = "--bezier-level", .value_name = "N", .help = "Quake III patch tessellation, 1 to 64 (default 4)",  \
     .kind = CLI_U32, CLI_FIELD(type, member), .lo = 1, .hi = 64}

/* Rows of the render settings every command that renders shares (render,
 * view); `render` is the path of its rtt_render_options member. */
#define CLI_OPTION_RENDER_THREADS(type, render)                                                                 \
    {.name = "--threads", .value_name = "N",                                                                    \
     .help = "threads for the tree build and the render, 1 to 1024 (default: one per core)", .kind = CLI_U32,   \
     CLI_FIELD(type, render.threads), .lo = 1, .hi = 1024}
#define CLI_OPTION_RENDER_SIZE(type, render)                                                                    \
    {.name = "--width", .value_name = "W", .help = "image width, 1 to 16384 (default: the scene's)",            \
     .kind = CLI_U32, CLI_FIELD(type, render.width), .lo = 1, .hi = 16384},                                     \
    {.name = "--height", .value_name = "H", .help = "image height, 1 to 16384 (default: the scene's)",          \
     .kind = CLI_U32, CLI_FIELD(type, render.height), .lo = 1, .hi = 16384}
#define CLI_OPTION_MAX_BOUNCES(type, render)                                                                    \
    {.name = "--max-bounces", .value_name = "N",                                                                \
     .help = "reflection/refraction depth, 0 (none) to 64 (default: the scene's)", .kind = CLI_U32,             \
     CLI_FIELD(type, render.max_bounces), .lo = 0, .hi = RTT_MAX_BOUNCES}

/* Refuses the options the kind of scene file at `scene_path`
 * (rtt_file_kind_of, as the loader picks its reader) makes meaningless:
 * --bezier-level for a .kdt (its patches were tessellated when it was
 * baked) and for a mesh file (it has none), and --max-depth when `engine`
 * (NULL: none) adopts the .kdt's tree as is. */
int cli_check_scene_options(const cli_parsed *parsed, const char *scene_path, const char *engine);

#endif

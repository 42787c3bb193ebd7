/* The table-driven option parser (options.h): argument scanning, value
 * conversion by kind, --help generated from the table, and the checks that
 * name the option behind a refusal. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "options.h"
#include "rtt/memory_budget.h"

#define HELP_WIDTH 80
#define HELP_COLUMN 26 /* where an option's text starts */

const char *const cli_on_off[] = {"off", "on", NULL};

/* ---- the table itself ---- */

static size_t kind_size(cli_option_kind kind)
{
    switch (kind) {
    case CLI_FLAG: return sizeof(bool);
    case CLI_U32: return sizeof(uint32_t);
    case CLI_FLOAT: return sizeof(float);
    case CLI_STRING: return sizeof(const char *);
    case CLI_CHOICE: return sizeof(int);
    case CLI_CHOICE_LIST: return sizeof(uint32_t);
    default: return 0; /* CLI_CUSTOM: any field */
    }
}

/* A row's one value (the element of a repeatable row's array). */
static size_t element_size(const cli_option *o)
{
    return o->repeat_max > 1 ? o->size / o->repeat_max : o->size;
}

/* The table's rows as the parser needs them: the mistakes a row can make
 * are programming errors, reported once with the row's name. */
static bool table_valid(const cli_command *c)
{
    const char *problem = NULL;
    size_t i = 0;
    if (c->option_count > CLI_OPTIONS_MAX) problem = "too many rows";
    for (; !problem && i < c->option_count; i++) {
        const cli_option *o = &c->options[i];
        if (!o->name || strncmp(o->name, "--", 2) != 0 || !o->help || !o->help[0]) problem = "a name and help";
        else if ((o->kind == CLI_FLAG) != (o->value_name == NULL)) problem = "a value name exactly when not a flag";
        else if (kind_size(o->kind) && element_size(o) != kind_size(o->kind)) problem = "a field of its kind's size";
        else if (o->kind == CLI_CUSTOM && !o->parse) problem = "a parser";
        else if ((o->kind == CLI_CHOICE || o->kind == CLI_CHOICE_LIST) && !o->choices) problem = "choices";
        else if (o->repeat_max > 1 && o->size % o->repeat_max) problem = "an array of repeat_max values";
        for (size_t j = 0; !problem && j < i; j++)
            if (strcmp(c->options[j].name, o->name) == 0 ||
                (o->short_name && c->options[j].short_name == o->short_name))
                problem = "a name of its own";
    }
    if (!problem) return true;
    fprintf(stderr, "rtt %s: internal error: option row %s needs %s\n", c->name,
            i && i <= c->option_count ? c->options[i - 1].name : "-", problem);
    return false;
}

/* ---- help ---- */

/* Prints `text` from column `column` (the cursor stands there), wrapping at
 * HELP_WIDTH with continuation lines indented to HELP_COLUMN. */
static void print_wrapped(FILE *out, const char *text, int column)
{
    while (*text) {
        const char *word = text;
        while (*text && *text != ' ') text++;
        int length = (int)(text - word);
        if (column > HELP_COLUMN && column + 1 + length > HELP_WIDTH) {
            fprintf(out, "\n%*s", HELP_COLUMN, "");
            column = HELP_COLUMN;
        } else if (column > HELP_COLUMN) {
            fputc(' ', out);
            column++;
        }
        fprintf(out, "%.*s", length, word);
        column += length;
        while (*text == ' ') text++;
    }
    fputc('\n', out);
}

static void print_option_help(FILE *out, const char *spelling, const char *text)
{
    int column = fprintf(out, "  %s", spelling);
    if (column >= HELP_COLUMN - 1) {
        fputc('\n', out);
        column = 0;
    }
    fprintf(out, "%*s", HELP_COLUMN - column, "");
    print_wrapped(out, text, HELP_COLUMN);
}

static void print_help(const cli_command *c)
{
    const char *form = c->synopsis;
    for (int i = 0; *form; i++) {
        size_t length = strcspn(form, "\n");
        printf("%s rtt %s %.*s\n", i == 0 ? "usage:" : "      ", c->name, (int)length, form);
        form += length + (form[length] == '\n');
    }
    printf("\n%s\noptions:\n", c->description);
    for (size_t i = 0; i < c->option_count; i++) {
        const cli_option *o = &c->options[i];
        char short_form[8] = "    ", spelling[64], text[1024];
        if (o->short_name) snprintf(short_form, sizeof short_form, "-%c, ", o->short_name);
        snprintf(spelling, sizeof spelling, "%s%s%s%s", short_form, o->name, o->value_name ? " " : "",
                 o->value_name ? o->value_name : "");
        snprintf(text, sizeof text, "%s", o->help);
        if (o->help_more) o->help_more(text + strlen(text), sizeof text - strlen(text));
        print_option_help(stdout, spelling, text);
    }
    print_option_help(stdout, "-h, --help", "this text");
    if (c->environment) printf("\nEnvironment: %s", c->environment);
    printf("\nExit status: %s\n", c->exit_status ? c->exit_status : "0 success, 1 bad input, 2 bad usage.");
}

/* The table for tests/cli_help.sh: name, short form and value name per row. */
static void print_option_list(const cli_command *c)
{
    for (size_t i = 0; i < c->option_count; i++) {
        const cli_option *o = &c->options[i];
        printf("%s %s%c %s\n", o->name, o->short_name ? "-" : "", o->short_name ? o->short_name : '-',
               o->value_name ? o->value_name : "-");
    }
}

/* ---- messages ---- */

static int vrefuse(const cli_command *c, const char *spelling, const char *value, const char *fmt, va_list args)
{
    fprintf(stderr, "rtt %s: ", c->name);
    if (spelling) fprintf(stderr, "%s%s%s: ", spelling, value && value[0] ? " " : "", value ? value : "");
    vfprintf(stderr, fmt, args);
    fprintf(stderr, " (see rtt %s --help)\n", c->name);
    return RTT_EXIT_USAGE;
}

static int refuse_row(const cli_command *c, const char *spelling, const char *value, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int refuse_row(const cli_command *c, const char *spelling, const char *value, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    int rc = vrefuse(c, spelling, value, fmt, args);
    va_end(args);
    return rc;
}

static int row_index(const cli_command *c, const char *name)
{
    for (size_t i = 0; i < c->option_count; i++)
        if (strcmp(c->options[i].name, name) == 0) return (int)i;
    return -1;
}

bool cli_given(const cli_parsed *p, const char *name)
{
    int i = row_index(p->command, name);
    return i >= 0 && p->value[i] != NULL;
}

int cli_refuse(const cli_parsed *p, const char *name, const char *fmt, ...)
{
    int i = name ? row_index(p->command, name) : -1;
    const char *spelling = i >= 0 && p->spelling[i] ? p->spelling[i] : name;
    va_list args;
    va_start(args, fmt);
    int rc = vrefuse(p->command, spelling, i >= 0 ? p->value[i] : NULL, fmt, args);
    va_end(args);
    return rc;
}

/* ---- parsing ---- */

static const char *kind_expectation(const cli_option *o, char *buffer, size_t size)
{
    switch (o->kind) {
    case CLI_U32: snprintf(buffer, size, "expected a whole number from %u to %u", o->lo, o->hi); break;
    case CLI_FLOAT: snprintf(buffer, size, "expected a number of at least %g", (double)o->min); break;
    case CLI_CHOICE:
    case CLI_CHOICE_LIST: {
        const bool list = o->kind == CLI_CHOICE_LIST;
        size_t used = (size_t)snprintf(buffer, size, "expected %s", list ? "a comma list of " : "");
        for (size_t k = 0; o->choices[k] && used < size; k++)
            used += (size_t)snprintf(buffer + used, size - used, "%s%s",
                                     k == 0 ? "" : list || o->choices[k + 1] ? ", " : " or ", o->choices[k]);
        break;
    }
    default: snprintf(buffer, size, "bad value"); break;
    }
    return buffer;
}

static int choice_index(const char *const *choices, const char *name, size_t length)
{
    for (int k = 0; choices[k]; k++)
        if (strlen(choices[k]) == length && strncmp(name, choices[k], length) == 0) return k;
    return -1;
}

/* A comma list of choices, each at least once: their bits. */
static bool choose_list(const char *const *choices, const char *list, uint32_t *mask)
{
    *mask = 0;
    for (const char *item = list;; item++) {
        size_t length = strcspn(item, ",");
        int k = choice_index(choices, item, length);
        if (k < 0) return false;
        *mask |= 1u << k;
        item += length;
        if (!*item) return true;
    }
}

/* Converts `value` into the row's field (the next element of a repeatable
 * row); false with `why` on junk. */
static bool store_value(const cli_option *o, const char *value, void *args, rtt_error *why)
{
    char *field = (char *)args + o->offset;
    if (o->repeat_max > 1) {
        uint32_t *count = (uint32_t *)((char *)args + o->count_offset);
        if (*count >= o->repeat_max) return rtt_error_set(why, "given more than %u times", o->repeat_max);
        field += element_size(o) * (*count)++;
    }
    char expected[160];
    switch (o->kind) {
    case CLI_FLAG: *(bool *)field = true; return true;
    case CLI_STRING:
        if (!value[0]) return rtt_error_set(why, "expected a non-empty value");
        *(const char **)field = value;
        return true;
    case CLI_U32:
        if (cli_parse_u32(value, o->lo, o->hi, (uint32_t *)field)) return true;
        break;
    case CLI_FLOAT:
        if (cli_parse_float(value, (float *)field) && *(float *)field >= o->min) return true;
        break;
    case CLI_CHOICE: {
        int k = choice_index(o->choices, value, strlen(value));
        if (k < 0) break;
        *(int *)field = k;
        return true;
    }
    case CLI_CHOICE_LIST:
        if (choose_list(o->choices, value, (uint32_t *)field)) return true;
        break;
    case CLI_CUSTOM: return o->parse(value, field, why);
    }
    return rtt_error_set(why, "%s", kind_expectation(o, expected, sizeof expected));
}

/* The row an argument names: "--name", "--name=value", "-x", "-x=value".
 * *inline_value is the text after '=', or NULL. */
static int find_row(const cli_command *c, const char *arg, const char **inline_value)
{
    const char *equals = strchr(arg, '=');
    size_t length = equals ? (size_t)(equals - arg) : strlen(arg);
    *inline_value = equals ? equals + 1 : NULL;
    for (size_t i = 0; i < c->option_count; i++) {
        const cli_option *o = &c->options[i];
        if (strlen(o->name) == length && strncmp(arg, o->name, length) == 0) return (int)i;
        if (o->short_name && length == 2 && arg[0] == '-' && arg[1] == o->short_name) return (int)i;
    }
    return -1;
}

static bool is_operand(const char *arg)
{
    return arg[0] != '-' || arg[1] == '\0';
}

/* Fills `args` (holding the defaults) from the arguments. */
static int parse(const cli_command *c, int argc, char **argv, void *args, cli_parsed *p)
{
    memset(p, 0, sizeof *p);
    p->command = c;
    if (!table_valid(c)) return RTT_EXIT_BAD_INPUT;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            print_help(c);
            return RTT_EXIT_OK;
        }
        if (strcmp(argv[i], "--list-options") == 0) {
            print_option_list(c);
            return RTT_EXIT_OK;
        }
    }
    uint32_t operands = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (is_operand(arg)) {
            if (!c->operand || operands == c->operand_max) {
                if (c->operands_wrong) return refuse_row(c, NULL, NULL, "%s", c->operands_wrong);
                if (!c->operand) return refuse_row(c, NULL, NULL, "unexpected argument \"%s\"", arg);
                return refuse_row(c, NULL, NULL, "more than one %s given (\"%s\")", c->operand, arg);
            }
            ((const char **)((char *)args + c->operand_offset))[operands++] = arg;
            continue;
        }
        const char *value;
        int r = find_row(c, arg, &value);
        if (r < 0) return refuse_row(c, arg, NULL, "unknown option");
        const cli_option *o = &c->options[r];
        char spelling[48]; /* the option without "=value" */
        snprintf(spelling, sizeof spelling, "%.*s", value ? (int)(value - 1 - arg) : (int)strlen(arg), arg);
        if (o->kind == CLI_FLAG && value) return refuse_row(c, spelling, NULL, "takes no value (\"%s\")", arg);
        if (o->kind != CLI_FLAG && !value) {
            if (i + 1 >= argc) return refuse_row(c, spelling, NULL, "needs a value (%s)", o->value_name);
            value = argv[++i];
        }
        if (p->value[r] && o->repeat_max <= 1)
            return refuse_row(c, spelling, value, "given more than once (first as %s%s%s)", p->spelling[r],
                              p->value[r][0] ? " " : "", p->value[r]);
        rtt_error why = {{0}};
        if (!store_value(o, value ? value : "", args, &why)) return refuse_row(c, spelling, value, "%s", why.message);
        p->value[r] = value ? value : "";
        if (arg[1] == '-') {
            p->spelling[r] = o->name;
        } else {
            snprintf(p->short_spelling[r], sizeof p->short_spelling[r], "-%c", o->short_name);
            p->spelling[r] = p->short_spelling[r];
        }
        if (o->given) {
            rtt_engine_options *engine = (rtt_engine_options *)((char *)args + c->engine_offset);
            engine->given |= o->given;
        }
    }
    if (c->operand && operands < c->operand_min) {
        if (c->operands_wrong) return refuse_row(c, NULL, NULL, "%s", c->operands_wrong);
        return refuse_row(c, NULL, NULL, "no %s given", c->operand);
    }
    return CLI_CONTINUE;
}

int cli_run(const cli_command *c, int argc, char **argv)
{
    void *args = calloc(1, c->args_size);
    if (!args) {
        fprintf(stderr, "rtt %s: out of memory\n", c->name);
        return RTT_EXIT_BAD_INPUT;
    }
    if (c->defaults) c->defaults(args);
    cli_parsed parsed;
    int rc = parse(c, argc, argv, args, &parsed);
    if (rc == CLI_CONTINUE) rc = c->run(args, &parsed);
    free(args);
    return rc;
}

/* ---- checks after parsing ---- */

int cli_check_engine_options(const cli_parsed *p, const char *engine, const rtt_engine_options *opt)
{
    rtt_error err = {{0}}, trial_err = {{0}};
    if (rtt_engine_options_check(engine, opt, &err)) return CLI_CONTINUE;
    const cli_command *c = p->command;
    rtt_engine_options trial;
    rtt_engine_options_default(&trial);
    trial.threads = opt->threads;
    /* the defaults themselves may fail ($RTT_ISA): then no option is to blame */
    if (rtt_engine_options_check(engine, &trial, &trial_err)) {
        for (size_t i = 0; i < c->option_count; i++) {
            const cli_option *o = &c->options[i];
            if (!o->given || !p->value[i]) continue;
            size_t within = o->offset - c->engine_offset;
            memcpy((char *)&trial + within, (const char *)opt + within, o->size);
            trial.given |= o->given;
            if (!rtt_engine_options_check(engine, &trial, &trial_err))
                return cli_refuse(p, o->name, "%s", trial_err.message);
        }
    }
    return cli_refuse(p, NULL, "%s", err.message);
}

/* Whether the engine uses a .kdt's tree as is (its class says; the
 * reference builds its own from the file's triangles). */
static bool adopts_baked_tree(const char *engine)
{
    const rtt_engine_class *cls = rtt_engine_find(engine);
    return cls && cls->adopts_baked_tree;
}

int cli_check_scene_options(const cli_parsed *p, const char *scene_path, const char *engine)
{
    const rtt_file_kind kind = rtt_file_kind_of(scene_path);
    if (kind == RTT_FILE_MESH && cli_given(p, "--bezier-level"))
        return cli_refuse(p, "--bezier-level", "%s is a mesh file: it has no Quake III patches to tessellate",
                          scene_path);
    if (kind != RTT_FILE_KDT) return CLI_CONTINUE;
    if (cli_given(p, "--bezier-level"))
        return cli_refuse(p, "--bezier-level", "%s holds triangles, its patches tessellated when it was baked; "
                          "rebake the source scene with rtt bake --bezier-level", scene_path);
    if (cli_given(p, "--max-depth") && adopts_baked_tree(engine))
        return cli_refuse(p, "--max-depth", "engine \"%s\" adopts the tree baked into %s as is; rebake to change "
                          "its depth (rtt bake SCENE -o new.kdt --max-depth N)", engine, scene_path);
    return CLI_CONTINUE;
}

/* ---- rows every engine-creating command shares ---- */

bool cli_parse_engine_name(const char *value, void *field, rtt_error *why)
{
    if (!rtt_engine_find(value)) {
        rtt_engine_options defaults;
        rtt_engine_options_default(&defaults);
        return rtt_engine_options_check(value, &defaults, why); /* says which engines there are */
    }
    *(const char **)field = value;
    return true;
}

/* "expected <lead><the names `names` lists>" */
static bool expected_names(rtt_error *why, const char *lead, cli_help_writer names)
{
    char list[256] = "";
    names(list, sizeof list);
    return rtt_error_set(why, "expected %s%s", lead, list);
}

bool cli_parse_accel(const char *value, void *field, rtt_error *why)
{
    return rtt_accel_parse(value, (rtt_accel *)field) || expected_names(why, "one of", cli_help_accels);
}

bool cli_parse_traversal(const char *value, void *field, rtt_error *why)
{
    /* which kernels exist is the engine's to say (rtt_engine_options_check) */
    if (!value[0]) return rtt_error_set(why, "expected a kernel name");
    if (strlen(value) >= RTT_TRAVERSAL_NAME_MAX) return rtt_error_set(why, "no kernel has so long a name");
    strcpy((char *)field, value);
    return true;
}

bool cli_parse_tile(const char *value, void *field, rtt_error *why)
{
    uint32_t tile;
    if (!cli_parse_u32(value, 4, 32, &tile) || (tile & (tile - 1)) != 0)
        return rtt_error_set(why, "expected 4, 8, 16 or 32");
    *(uint32_t *)field = tile;
    return true;
}

bool cli_parse_isa(const char *value, void *field, rtt_error *why)
{
    return rtt_isa_parse(value, (rtt_isa *)field) || expected_names(why, "auto or one of", cli_help_isas);
}

bool cli_parse_isect(const char *value, void *field, rtt_error *why)
{
    return rtt_isect_parse(value, (rtt_isect *)field) || rtt_error_set(why, "expected watertight or projected");
}

static void append(char *out, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void append(char *out, size_t size, const char *fmt, ...)
{
    size_t used = strlen(out);
    if (used + 1 >= size) return;
    va_list args;
    va_start(args, fmt);
    vsnprintf(out + used, size - used, fmt, args);
    va_end(args);
}

void cli_help_engines(char *out, size_t size)
{
    const rtt_engine_class *cls;
    for (uint32_t i = 0; (cls = rtt_engine_class_at(i)); i++)
        append(out, size, "%s %s (%s)", i ? ";" : "", cls->name, cls->summary ? cls->summary : "");
}

void cli_help_accels(char *out, size_t size)
{
    for (int a = RTT_ACCEL_DEFAULT + 1; a < RTT_ACCEL_COUNT; a++)
        append(out, size, "%s %s", a > RTT_ACCEL_DEFAULT + 1 ? "," : "", rtt_accel_name((rtt_accel)a));
}

void cli_help_kernels(char *out, size_t size)
{
    const rtt_engine_class *cls;
    bool any = false;
    for (uint32_t i = 0; (cls = rtt_engine_class_at(i)); i++) {
        const char *name;
        if (!cls->kernel || !cls->kernel(RTT_ACCEL_DEFAULT, 0)) continue;
        append(out, size, "%s %s:", any ? ";" : "", cls->name);
        for (uint32_t k = 0; (name = cls->kernel(RTT_ACCEL_DEFAULT, k)); k++)
            append(out, size, "%s %s", k ? "," : "", name);
        /* the accels whose kernels are not the default's (e.g. pgrid) */
        for (int a = RTT_ACCEL_DEFAULT + 1; a < RTT_ACCEL_COUNT; a++) {
            const char *first = cls->kernel((rtt_accel)a, 0);
            if (!first || strcmp(first, cls->kernel(RTT_ACCEL_DEFAULT, 0)) == 0) continue;
            append(out, size, " (--accel %s:", rtt_accel_name((rtt_accel)a));
            for (uint32_t k = 0; (name = cls->kernel((rtt_accel)a, k)); k++)
                append(out, size, "%s %s", k ? "," : "", name);
            append(out, size, ")");
        }
        any = true;
    }
    if (!any) append(out, size, " no engine of this build has a choice of kernels");
}

void cli_help_isas(char *out, size_t size)
{
    for (int isa = RTT_ISA_AUTO + 1; isa < RTT_ISA_COUNT; isa++)
        append(out, size, "%s %s", isa > RTT_ISA_AUTO + 1 ? "," : "", rtt_isa_name((rtt_isa)isa));
}

bool cli_parse_memory_size(const char *value, void *field, rtt_error *why)
{
    if (!rtt_memory_size_parse(value, field))
        return rtt_error_set(why, "not a size (bytes, or a number with K, M, G or T: 512M, 4G, 1.5GiB)");
    return true;
}

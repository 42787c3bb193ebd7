/* Linked into every cmocka test (tests/CMakeLists.txt wraps cmocka's group
 * runner with -Wl,--wrap=_cmocka_run_group_tests): RTT_TEST_SKIP, a comma-
 * separated list of case names, makes those cases report Skipped, each with
 * a note naming it, instead of running.  ci/sanitize.sh sets it for the TSan
 * run, which looks for races: the single-threaded oracle sweeps it leaves
 * out run whole in the Release suites and under ASan.  Unset or empty, every
 * case runs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

int __real__cmocka_run_group_tests(const char *group_name, const struct CMUnitTest *const tests, size_t num_tests,
                                   CMFixtureFunction group_setup, CMFixtureFunction group_teardown);
int __wrap__cmocka_run_group_tests(const char *group_name, const struct CMUnitTest *const tests, size_t num_tests,
                                   CMFixtureFunction group_setup, CMFixtureFunction group_teardown);

static void skipped_case(void **state)
{
    (void)state;
    skip();
}

/* 1 when `name` is one of the comma-separated names in `list`. */
static int listed(const char *list, const char *name)
{
    const size_t len = strlen(name);
    for (const char *p = list; *p;) {
        const char *end = strchr(p, ',');
        const size_t n = end ? (size_t)(end - p) : strlen(p);
        if (n == len && memcmp(p, name, n) == 0) return 1;
        if (!end) break;
        p = end + 1;
    }
    return 0;
}

int __wrap__cmocka_run_group_tests(const char *group_name, const struct CMUnitTest *const tests, size_t num_tests,
                                   CMFixtureFunction group_setup, CMFixtureFunction group_teardown)
{
    const char *list = getenv("RTT_TEST_SKIP");
    if (!list || !*list) return __real__cmocka_run_group_tests(group_name, tests, num_tests, group_setup, group_teardown);
    struct CMUnitTest *copy = malloc((num_tests ? num_tests : 1) * sizeof *copy);
    if (!copy) {
        print_error("RTT_TEST_SKIP: out of memory copying %zu cases\n", num_tests);
        return 1;
    }
    for (size_t i = 0; i < num_tests; i++) {
        copy[i] = tests[i];
        if (tests[i].name && listed(list, tests[i].name)) {
            print_message("note: %s skipped: it is in RTT_TEST_SKIP\n", tests[i].name);
            copy[i].test_func = skipped_case;
            copy[i].setup_func = NULL;
            copy[i].teardown_func = NULL;
        }
    }
    const int failed = __real__cmocka_run_group_tests(group_name, copy, num_tests, group_setup, group_teardown);
    free(copy);
    return failed;
}

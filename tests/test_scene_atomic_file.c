/* Atomic outputs (scene/atomic_file.c): a commit renames, an abort leaves
 * the target untouched, held outputs are all or nothing, and the signal-time
 * removal finds every live temporary. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "rtt/atomic_file.h"
#include "test_tempdir.h"

static int make_scratch(void **state) { return scratch_create(state, "atomic_file"); }

static const char *in_scratch(void **state, const char *name, char *out, size_t size)
{
    scratch *s = *state;
    snprintf(out, size, "%s/%s", s->dir, name);
    return out;
}

static bool exists(const char *path)
{
    struct stat info;
    return stat(path, &info) == 0;
}

/* Files in the scratch directory, temporaries included. */
static int entries(void **state)
{
    scratch *s = *state;
    char command[160];
    snprintf(command, sizeof command, "exit $(ls -A '%s' | wc -l)", s->dir);
    int rc = system(command);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static void test_write_replaces_the_target(void **state)
{
    char a[160];
    rtt_error err = {{0}};
    assert_true(rtt_atomic_file_write(in_scratch(state, "a.bin", a, sizeof a), "old", 3, &err));
    assert_true(rtt_atomic_file_write(a, "new!", 4, &err));
    struct stat info;
    assert_int_equal(stat(a, &info), 0);
    assert_int_equal(info.st_size, 4);
    assert_int_equal(entries(state), 1);
}

static void test_held_outputs_are_all_or_nothing(void **state)
{
    char a[160], b[160];
    rtt_error err = {{0}};
    in_scratch(state, "a.bin", a, sizeof a);
    in_scratch(state, "b.bin", b, sizeof b);
    rtt_atomic_files_hold();
    assert_true(rtt_atomic_file_write(a, "a", 1, &err));
    assert_false(exists(a)); /* held: not renamed yet */
    assert_int_equal(entries(state), 1);
    assert_true(rtt_atomic_files_release(false, &err)); /* the second output failed: none is kept */
    assert_int_equal(entries(state), 0);

    rtt_atomic_files_hold();
    assert_true(rtt_atomic_file_write(a, "a", 1, &err));
    assert_true(rtt_atomic_file_write(b, "b", 1, &err));
    assert_true(rtt_atomic_files_release(true, &err));
    assert_true(exists(a) && exists(b));
    assert_int_equal(entries(state), 2);
}

static void test_remove_all_finds_every_live_temporary(void **state)
{
    char a[160], b[160];
    rtt_error err = {{0}};
    rtt_atomic_file open_one;
    rtt_atomic_files_hold();
    assert_true(rtt_atomic_file_write(in_scratch(state, "held.bin", b, sizeof b), "b", 1, &err));
    assert_true(rtt_atomic_file_open(&open_one, in_scratch(state, "open.bin", a, sizeof a), &err));
    fputs("partial", open_one.stream);
    fflush(open_one.stream);
    assert_int_equal(entries(state), 2);
    rtt_atomic_files_remove_all(); /* what the signal handler does */
    assert_int_equal(entries(state), 0);
    rtt_atomic_file_abort(&open_one);
    assert_true(rtt_atomic_files_release(false, &err));
    assert_int_equal(entries(state), 0);
}

static void test_a_failed_open_leaves_nothing(void **state)
{
    (void)state;
    rtt_atomic_file file;
    rtt_error err = {{0}};
    assert_false(rtt_atomic_file_open(&file, "/nonexistent-dir/x.bin", &err));
    assert_string_equal(err.message, "/nonexistent-dir/x.bin: cannot create: No such file or directory");
    rtt_atomic_file_abort(&file); /* safe after a failed open */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_write_replaces_the_target, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_held_outputs_are_all_or_nothing, make_scratch, remove_scratch),
        cmocka_unit_test_setup_teardown(test_remove_all_finds_every_live_temporary, make_scratch, remove_scratch),
        cmocka_unit_test(test_a_failed_open_leaves_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* A fresh scratch directory per test, removed with everything in it after
 * the test: the tests that write files (test_image_exr.c, test_image_png.c)
 * set it up in their cmocka setup and teardown. */
#ifndef RTT_TEST_TEMPDIR_H
#define RTT_TEST_TEMPDIR_H

#include <stdio.h>
#include <stdlib.h>

typedef struct scratch {
    char dir[64];
    char path[128];
} scratch;

/* Creates /tmp/rtt_test_<name>_XXXXXX as the test's state; -1 when it cannot. */
static inline int scratch_create(void **state, const char *name)
{
    scratch *s = calloc(1, sizeof *s);
    if (!s)
        return -1;
    snprintf(s->dir, sizeof s->dir, "/tmp/rtt_test_%s_XXXXXX", name);
    if (!mkdtemp(s->dir)) {
        free(s);
        return -1;
    }
    *state = s;
    return 0;
}

/* cmocka teardown: removes the directory and all that the test left in it. */
static inline int remove_scratch(void **state)
{
    scratch *s = *state;
    char command[128];
    snprintf(command, sizeof command, "rm -rf '%s'", s->dir);
    int rc = system(command);
    free(s);
    return rc == 0 ? 0 : -1;
}

/* `name` inside the scratch directory; valid until the next call. */
static inline const char *scratch_path(void **state, const char *name)
{
    scratch *s = *state;
    snprintf(s->path, sizeof s->path, "%s/%s", s->dir, name);
    return s->path;
}

#endif

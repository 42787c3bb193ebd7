/* rtt_file_read: a whole file into one buffer, and the regular-file test
 * every input goes through (include/rtt/files.h).
 *
 * The file is opened with O_NONBLOCK, so that opening a FIFO without a
 * writer returns at once, then fstat'ed: only a regular file is kept (and
 * its descriptor made blocking again).  A stat() before open() would leave
 * a window in which the name could be swapped for a FIFO.
 *
 * A regular file's size is known before reading, so its buffer is allocated
 * once at the right size and an oversized file is refused without reading
 * it; anything else (a pipe, a file that grows while read) is read in
 * doubling steps. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_read.h"

/* "larger than 1 GiB": the limit in the largest unit that divides it. */
static bool too_large(const char *path, size_t max_bytes, rtt_error *err)
{
    static const struct { size_t bytes; const char *unit; } units[] = {
        {(size_t)1 << 30, "GiB"}, {(size_t)1 << 20, "MiB"}, {(size_t)1 << 10, "KiB"}, {1, "bytes"}};
    size_t u = 0;
    while (max_bytes % units[u].bytes != 0) u++;
    return rtt_error_set(err, "%s: larger than %zu %s", path, max_bytes / units[u].bytes, units[u].unit);
}

static const char *kind_of(mode_t mode)
{
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a file";
}

FILE *rtt_file_open_regular(const char *path, rtt_error *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        int code = errno;
        rtt_error_set(err, "%s: cannot open: %s", path, strerror(code));
        errno = code; /* callers may tell a missing file from the rest */
        return NULL;
    }
    struct stat info;
    if (fstat(fd, &info) != 0) {
        int code = errno;
        close(fd);
        return rtt_error_set(err, "%s: cannot open: %s", path, strerror(code)), NULL;
    }
    if (!S_ISREG(info.st_mode)) {
        close(fd);
        if (S_ISDIR(info.st_mode)) return rtt_error_set(err, "%s: is a directory", path), NULL;
        return rtt_error_set(err, "%s: not a regular file (%s)", path, kind_of(info.st_mode)), NULL;
    }
    int flags = fcntl(fd, F_GETFL);
    FILE *f = flags >= 0 && fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        int code = errno;
        close(fd);
        return rtt_error_set(err, "%s: cannot open: %s", path, strerror(code)), NULL;
    }
    return f;
}

bool rtt_file_check_regular(const char *path, rtt_error *err)
{
    FILE *f = rtt_file_open_regular(path, err);
    if (f) fclose(f);
    return f != NULL;
}

char *rtt_file_read(const char *path, size_t max_bytes, size_t *length, rtt_error *err)
{
    FILE *f = rtt_file_open_regular(path, err);
    if (!f) return NULL;
    struct stat info;
    size_t capacity = 4096; /* bytes allocated, the final NUL included */
    if (fstat(fileno(f), &info) == 0 && S_ISREG(info.st_mode)) {
        if ((uintmax_t)info.st_size > max_bytes) {
            fclose(f);
            return too_large(path, max_bytes, err), NULL;
        }
        capacity = (size_t)info.st_size + 1u;
    }
    /* Room for one byte past the limit, so that a longer file shows itself. */
    size_t cap = max_bytes <= SIZE_MAX - 2u ? max_bytes + 2u : SIZE_MAX;
    size_t used = 0;
    char *bytes = malloc(capacity);
    while (bytes) {
        used += fread(bytes + used, 1, capacity - used - 1u, f);
        if (used < capacity - 1u || used > max_bytes) break; /* the end, an error, or too long */
        int next = fgetc(f); /* the buffer is full: the end, or more to come */
        if (next == EOF) break;
        size_t grown_capacity = capacity <= cap / 2 ? capacity * 2 : cap;
        char *grown = realloc(bytes, grown_capacity);
        if (!grown) free(bytes);
        bytes = grown;
        capacity = grown_capacity;
        if (bytes) bytes[used++] = (char)next;
    }
    int read_errno = ferror(f) ? errno : 0;
    fclose(f);
    if (!bytes) return rtt_error_set(err, "%s: out of memory", path), NULL;
    if (read_errno || used > max_bytes) {
        free(bytes);
        if (read_errno) return rtt_error_set(err, "%s: cannot read: %s", path, strerror(read_errno)), NULL;
        return too_large(path, max_bytes, err), NULL;
    }
    bytes[used] = '\0';
    *length = used;
    return bytes;
}

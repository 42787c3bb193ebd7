/* Atomic file replacement: write to "<path>.tmp.<pid>", then rename.
 *
 * rename() within one directory is atomic on POSIX file systems, so a reader
 * sees either the old file or the complete new one, never a half-written
 * image; a crash leaves at worst a stray temporary. */
#include "atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

bool rtt_atomic_file_open(rtt_atomic_file *file, const char *path, rtt_error *err)
{
    *file = (rtt_atomic_file){ .path = path };
    size_t size = strlen(path) + 32;
    file->tmp_path = malloc(size);
    if (!file->tmp_path)
        return rtt_error_set(err, "%s: out of memory", path);
    snprintf(file->tmp_path, size, "%s.tmp.%ld", path, (long)getpid());
    file->stream = fopen(file->tmp_path, "wb");
    if (!file->stream) {
        int code = errno;
        rtt_atomic_file_abort(file);
        return rtt_error_set(err, "%s: cannot create: %s", path, strerror(code));
    }
    return true;
}

bool rtt_atomic_file_commit(rtt_atomic_file *file, rtt_error *err)
{
    bool written = fflush(file->stream) == 0 && !ferror(file->stream);
    int code = errno;
    if (fclose(file->stream) != 0 && written) {
        written = false;
        code = errno;
    }
    file->stream = NULL;
    if (!written) {
        rtt_atomic_file_abort(file);
        return rtt_error_set(err, "%s: write failed: %s", file->path, strerror(code));
    }
    if (rename(file->tmp_path, file->path) != 0) {
        code = errno;
        rtt_atomic_file_abort(file);
        return rtt_error_set(err, "%s: cannot replace: %s", file->path, strerror(code));
    }
    free(file->tmp_path);
    file->tmp_path = NULL;
    return true;
}

void rtt_atomic_file_abort(rtt_atomic_file *file)
{
    if (file->stream)
        fclose(file->stream);
    file->stream = NULL;
    if (file->tmp_path)
        unlink(file->tmp_path);
    free(file->tmp_path);
    file->tmp_path = NULL;
}

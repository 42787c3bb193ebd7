/* Atomic file replacement (include/rtt/atomic_file.h): write to
 * "<path>.tmp.<pid>", then rename.
 *
 * rename() within one directory is atomic on POSIX file systems, so a reader
 * sees either the old file or the complete new one, never a half-written
 * file.  The registry below holds every live temporary: a signal handler
 * walks it with unlink() alone, and a slot is filled only once its path is
 * complete and emptied only after the file is renamed or removed, so the
 * handler never sees a half-made entry or misses a live one. */
#include "rtt/atomic_file.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SLOTS 64

typedef struct temporary {
    char *volatile tmp_path; /* NULL: a free slot */
    char *final_path;        /* while held: the target it will be renamed to */
    unsigned long order;     /* while held: commit order */
} temporary;

static temporary slots[SLOTS];
static bool holding;
static unsigned long commits;

static bool register_temporary(char *tmp_path)
{
    for (int i = 0; i < SLOTS; i++)
        if (!slots[i].tmp_path) {
            slots[i].final_path = NULL;
            slots[i].tmp_path = tmp_path;
            return true;
        }
    return false;
}

static temporary *slot_of(const char *tmp_path)
{
    for (int i = 0; i < SLOTS; i++)
        if (slots[i].tmp_path == tmp_path) return &slots[i];
    return NULL;
}

/* Removes the file if `remove_file`, then frees the slot and the path. */
static void release_slot(temporary *slot, bool remove_file)
{
    char *tmp = slot->tmp_path;
    if (remove_file) unlink(tmp);
    slot->tmp_path = NULL;
    free(slot->final_path);
    slot->final_path = NULL;
    free(tmp);
}

bool rtt_atomic_file_open(rtt_atomic_file *file, const char *path, rtt_error *err)
{
    *file = (rtt_atomic_file){ .path = path };
    size_t size = strlen(path) + 32;
    char *tmp = malloc(size);
    if (!tmp)
        return rtt_error_set(err, "%s: out of memory", path);
    snprintf(tmp, size, "%s.tmp.%ld", path, (long)getpid());
    if (!register_temporary(tmp)) {
        free(tmp);
        return rtt_error_set(err, "%s: more than %d files open for writing", path, SLOTS);
    }
    file->tmp_path = tmp; /* registered before it exists: a signal now finds nothing to remove */
    file->stream = fopen(tmp, "wb");
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
    temporary *slot = slot_of(file->tmp_path);
    if (holding && slot) {
        slot->final_path = strdup(file->path);
        slot->order = ++commits;
        if (!slot->final_path) {
            rtt_atomic_file_abort(file);
            return rtt_error_set(err, "%s: out of memory", file->path);
        }
        file->tmp_path = NULL; /* the release owns it now */
        return true;
    }
    if (rename(file->tmp_path, file->path) != 0) {
        code = errno;
        rtt_atomic_file_abort(file);
        return rtt_error_set(err, "%s: cannot replace: %s", file->path, strerror(code));
    }
    if (slot) release_slot(slot, false);
    else free(file->tmp_path);
    file->tmp_path = NULL;
    return true;
}

void rtt_atomic_file_abort(rtt_atomic_file *file)
{
    if (file->stream)
        fclose(file->stream);
    file->stream = NULL;
    if (file->tmp_path) {
        temporary *slot = slot_of(file->tmp_path);
        if (slot) {
            release_slot(slot, true);
        } else {
            unlink(file->tmp_path);
            free(file->tmp_path);
        }
    }
    file->tmp_path = NULL;
}

bool rtt_atomic_file_write(const char *path, const void *data, size_t size, rtt_error *err)
{
    rtt_atomic_file file;
    if (!rtt_atomic_file_open(&file, path, err)) return false;
    if (size && fwrite(data, 1, size, file.stream) != size) {
        int code = errno;
        rtt_atomic_file_abort(&file);
        return rtt_error_set(err, "%s: write failed: %s", path, strerror(code));
    }
    return rtt_atomic_file_commit(&file, err);
}

void rtt_atomic_files_hold(void)
{
    holding = true;
}

bool rtt_atomic_files_release(bool keep, rtt_error *err)
{
    holding = false;
    bool ok = true;
    for (;;) { /* the held temporaries, oldest commit first */
        temporary *next = NULL;
        for (int i = 0; i < SLOTS; i++)
            if (slots[i].tmp_path && slots[i].final_path && (!next || slots[i].order < next->order)) next = &slots[i];
        if (!next) break;
        if (keep && ok && rename(next->tmp_path, next->final_path) != 0) {
            ok = rtt_error_set(err, "%s: cannot replace: %s", next->final_path, strerror(errno));
        }
        release_slot(next, !(keep && ok));
    }
    return ok;
}

void rtt_atomic_files_remove_all(void)
{
    for (int i = 0; i < SLOTS; i++) {
        char *tmp = slots[i].tmp_path;
        if (tmp) unlink(tmp);
    }
}

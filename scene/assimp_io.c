/* aiFileIO over stdio, with inputs opened by rtt_file_open_regular (see
 * assimp_io.h).  Assimp only reads through it. */
#include "assimp_io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "rtt/files.h"

static FILE *stream_of(struct aiFile *file) { return (FILE *)(void *)file->UserData; }

static size_t io_read(struct aiFile *file, char *buffer, size_t size, size_t count)
{
    return size && count ? fread(buffer, size, count, stream_of(file)) : 0;
}

static size_t io_write(struct aiFile *file, const char *buffer, size_t size, size_t count)
{
    (void)file, (void)buffer, (void)size, (void)count;
    return 0; /* inputs only */
}

static size_t io_tell(struct aiFile *file)
{
    long at = ftell(stream_of(file));
    return at < 0 ? 0 : (size_t)at;
}

static size_t io_size(struct aiFile *file)
{
    struct stat info;
    return fstat(fileno(stream_of(file)), &info) == 0 ? (size_t)info.st_size : 0;
}

static enum aiReturn io_seek(struct aiFile *file, size_t offset, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    return fseeko(stream_of(file), (off_t)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void io_flush(struct aiFile *file) { (void)file; }

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode)
{
    rtt_assimp_io *self = (rtt_assimp_io *)(void *)io;
    if (!mode || mode[0] != 'r') return NULL;
    rtt_error err;
    FILE *stream = rtt_file_open_regular(path, &err);
    if (!stream) {
        struct stat info;
        if (!self->refused && stat(path, &info) == 0) { /* it exists: a FIFO, a device, a directory */
            self->refused = true;
            self->error = err;
        }
        return NULL;
    }
    struct aiFile *file = malloc(sizeof *file);
    if (!file) {
        fclose(stream);
        return NULL;
    }
    *file = (struct aiFile){.ReadProc = io_read, .WriteProc = io_write, .TellProc = io_tell,
                            .FileSizeProc = io_size, .SeekProc = io_seek, .FlushProc = io_flush,
                            .UserData = (aiUserData)(void *)stream};
    return file;
}

static void io_close(struct aiFileIO *io, struct aiFile *file)
{
    (void)io;
    if (!file) return;
    fclose(stream_of(file));
    free(file);
}

void rtt_assimp_io_init(rtt_assimp_io *io)
{
    *io = (rtt_assimp_io){.io = {.OpenProc = io_open, .CloseProc = io_close}};
}

/* OpenEXR glue: file-descriptor I/O and an error handler that records the
 * message instead of printing it (see exr_stream.h). */
#include "exr_stream.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void keep_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    rtt_exr_stream *stream = user;
    if (stream->message[0])
        return;
    const char *text = msg && msg[0] ? msg : exr_get_default_error_message(code);
    /* one line: cut at the first newline */
    size_t n = strcspn(text, "\r\n");
    if (n >= sizeof stream->message)
        n = sizeof stream->message - 1;
    memcpy(stream->message, text, n);
    stream->message[n] = '\0';
}

static int64_t read_at(exr_const_context_t ctxt, void *user, void *buffer, uint64_t size, uint64_t offset,
                       exr_stream_error_func_ptr_t error_cb)
{
    rtt_exr_stream *stream = user;
    uint8_t *out = buffer;
    uint64_t total = 0;
    while (total < size) {
        ssize_t n = pread(stream->fd, out + total, size - total, (off_t)(offset + total));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s", strerror(errno));
            return -1;
        }
        if (n == 0)
            break;   /* end of file: a short read, the library reports it */
        total += (uint64_t)n;
    }
    return (int64_t)total;
}

static int64_t write_at(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t size,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    rtt_exr_stream *stream = user;
    const uint8_t *in = buffer;
    uint64_t total = 0;
    while (total < size) {
        ssize_t n = pwrite(stream->fd, in + total, size - total, (off_t)(offset + total));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed: %s", n < 0 ? strerror(errno) : "no space");
            return -1;
        }
        total += (uint64_t)n;
    }
    return (int64_t)total;
}

static int64_t file_size(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    rtt_exr_stream *stream = user;
    struct stat st;
    if (fstat(stream->fd, &st) != 0)
        return -1;
    return (int64_t)st.st_size;
}

exr_context_initializer_t rtt_exr_stream_initializer(rtt_exr_stream *stream)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keep_error;
    init.user_data = stream;
    init.read_fn = read_at;
    init.size_fn = file_size;
    init.write_fn = write_at;
    return init;
}

const char *rtt_exr_stream_message(const rtt_exr_stream *stream, exr_result_t code)
{
    return stream->message[0] ? stream->message : exr_get_default_error_message(code);
}

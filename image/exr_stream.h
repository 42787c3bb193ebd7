/* OpenEXR glue shared by the EXR reader and writer (image/ only).
 *
 * OpenEXR's core library prints errors to stderr unless given a handler, and
 * library code here must never print: every context gets our file I/O on a
 * file descriptor and an error handler that keeps the first message, which
 * the caller turns into one rtt_error line. */
#ifndef RTT_IMAGE_EXR_STREAM_H
#define RTT_IMAGE_EXR_STREAM_H

#include <openexr.h>

typedef struct rtt_exr_stream {
    int fd;
    char message[256];   /* first error OpenEXR reported, "" if none */
} rtt_exr_stream;

/* An initializer whose I/O and error reports go through stream. */
exr_context_initializer_t rtt_exr_stream_initializer(rtt_exr_stream *stream);
/* The library's message if it gave one, else the text for code. */
const char *rtt_exr_stream_message(const rtt_exr_stream *stream, exr_result_t code);

#endif

#include "rtt/error.h"

#include <stdarg.h>
#include <stdio.h>

bool rtt_error_set(rtt_error *err, const char *fmt, ...)
{
    if (err) {
        va_list args;
        va_start(args, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, args);
        va_end(args);
        /* Errors are one line (the error contract), even when they quote what a file
         * holds: a key or name with a newline or a terminal escape in it
         * (found by fuzz_scene_json) is shown with '?' for each control byte. */
        for (char *c = err->message; *c; c++)
            if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = *c == '\t' ? ' ' : '?';
    }
    return false;
}

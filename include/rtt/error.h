/* rtt_error: how every library function reports failure.
 *
 * Library code never prints or exits; it fills an rtt_error with one line of
 * the form "file:place: what is wrong" and returns failure (NULL, false or -1).
 * Only cli/ prints the message and picks the exit code.  */
#ifndef RTT_ERROR_H
#define RTT_ERROR_H

#include <stdbool.h>

typedef struct rtt_error {
    char message[512];
} rtt_error;

/* Formats one line into err (which may be NULL); always returns false so that
 * callers can write `return rtt_error_set(err, ...);` in bool functions. */
bool rtt_error_set(rtt_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif

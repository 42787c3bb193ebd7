/* Output paths checked before any work, and the signal handlers that
 * remove temporaries (cli.h). */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "rtt/atomic_file.h"

static const char *kind_of(mode_t mode)
{
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

/* The directory a path's file goes in: "." for a bare name. */
static void directory_of(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(out, size, ".");
    else if (slash == path) snprintf(out, size, "/");
    else snprintf(out, size, "%.*s", (int)(slash - path), path);
}

bool cli_check_directory(const char *dir, const char *what, rtt_error *err)
{
    struct stat info;
    if (stat(dir, &info) != 0) return rtt_error_set(err, "%s: cannot write in %s: %s", what, dir, strerror(errno));
    if (!S_ISDIR(info.st_mode)) return rtt_error_set(err, "%s: cannot write in %s: not a directory", what, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return rtt_error_set(err, "%s: cannot write in %s: %s", what, dir, strerror(errno));
    return true;
}

bool cli_check_outputs(const char *const *outputs, size_t output_count, const char *const *inputs,
                       size_t input_count, rtt_error *err)
{
    for (size_t i = 0; i < output_count; i++) {
        const char *path = outputs[i];
        if (!path) continue;
        char dir[4096];
        directory_of(path, dir, sizeof dir);
        if (!path[0] || path[strlen(path) - 1] == '/') return rtt_error_set(err, "%s: not a file name", path);
        if (!cli_check_directory(dir, path, err)) return false;
        for (size_t j = 0; j < i; j++)
            if (outputs[j] && strcmp(outputs[j], path) == 0) return rtt_error_set(err, "%s: given twice as an output", path);
        struct stat out;
        if (stat(path, &out) != 0) continue; /* a new file: it cannot be an input */
        if (!S_ISREG(out.st_mode)) return rtt_error_set(err, "%s: cannot write: it is %s", path, kind_of(out.st_mode));
        for (size_t j = 0; j < i; j++) {
            struct stat other;
            if (outputs[j] && stat(outputs[j], &other) == 0 && other.st_dev == out.st_dev && other.st_ino == out.st_ino)
                return rtt_error_set(err, "%s: the same file as the output %s", path, outputs[j]);
        }
        for (size_t j = 0; j < input_count; j++) {
            struct stat in;
            if (inputs[j] && stat(inputs[j], &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino) {
                if (strcmp(inputs[j], path) == 0)
                    return rtt_error_set(err, "%s: is an input of this command; an input is never written", path);
                return rtt_error_set(err, "%s: is the input %s; an input is never written", path, inputs[j]);
            }
        }
    }
    return true;
}

static void remove_temporaries_and_exit(int signal_number)
{
    rtt_atomic_files_remove_all();
    _exit(128 + signal_number); /* 130 for SIGINT, 143 for SIGTERM, as a shell reports a signal */
}

void cli_handle_signals(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = remove_temporaries_and_exit;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGINT);
    sigaddset(&action.sa_mask, SIGTERM);
    sigaddset(&action.sa_mask, SIGHUP);
    sigaction(SIGINT, &action, NULL);
    sigaction(SIGTERM, &action, NULL);
    sigaction(SIGHUP, &action, NULL);
}

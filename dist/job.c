/* The MPI job: joining it, polite waiting, and the reports and verdict that
 * keep every rank in step (rtt_dist_agree). */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dist_internal.h"
#include "dist_launcher.h"

/* How long a waiting rank sleeps between tests: short beside a tile's
 * render time, long enough that a waiter costs its core nothing. */
#define WAIT_NAP_NS 20000L

void dist_nap(void)
{
    struct timespec pause = {0, WAIT_NAP_NS};
    nanosleep(&pause, NULL);
}

bool rtt_dist_open(rtt_dist **out, rtt_error *err)
{
    *out = NULL;
    uint32_t processes = 0;
    if (!dist_launched(&processes)) return true;
    int provided = 0;
    /* workers of one rank talk to rank 0 one at a time, under a lock, and
     * rank 0 talks from one thread: SERIALIZED is all it takes */
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        return rtt_error_set(err, "mpi: MPI_Init_thread failed");
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        return rtt_error_set(err, "mpi: this MPI library cannot be called from several threads in turn "
                                  "(MPI_THREAD_SERIALIZED)");
    }
    rtt_dist *dist = calloc(1, sizeof *dist);
    if (!dist) {
        MPI_Finalize();
        return rtt_error_set(err, "mpi: out of memory");
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &dist->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &dist->size);
    dist->tiles_of_rank = malloc((size_t)dist->size * sizeof *dist->tiles_of_rank);
    dist->frames_of_rank = malloc((size_t)dist->size * sizeof *dist->frames_of_rank);
    if (!dist->tiles_of_rank || !dist->frames_of_rank) {
        free(dist->tiles_of_rank);
        free(dist->frames_of_rank);
        free(dist);
        MPI_Finalize();
        return rtt_error_set(err, "mpi: out of memory");
    }
    for (int r = 0; r < dist->size; r++) {
        atomic_init(&dist->tiles_of_rank[r], 0);
        atomic_init(&dist->frames_of_rank[r], 0);
    }
    *out = dist;
    return true;
}

void rtt_dist_close(rtt_dist *dist)
{
    if (!dist) return;
    MPI_Finalize();
    free(dist->tiles_of_rank);
    free(dist->frames_of_rank);
    free(dist);
}

uint32_t rtt_dist_rank(const rtt_dist *dist)
{
    return dist ? (uint32_t)dist->rank : 0;
}

uint32_t rtt_dist_size(const rtt_dist *dist)
{
    return dist ? (uint32_t)dist->size : 1;
}

static void wait_status(MPI_Request *request, MPI_Status *status)
{
    int done = 0;
    for (MPI_Test(request, &done, status); !done; MPI_Test(request, &done, status)) dist_nap();
}

uint32_t rtt_dist_tiles_of_rank(const rtt_dist *dist, uint32_t rank)
{
    return dist && rank < (uint32_t)dist->size ? atomic_load(&dist->tiles_of_rank[rank]) : 0;
}

uint32_t rtt_dist_frames_of_rank(const rtt_dist *dist, uint32_t rank)
{
    return dist && rank < (uint32_t)dist->size ? atomic_load(&dist->frames_of_rank[rank]) : 0;
}

void dist_wait(MPI_Request *request)
{
    wait_status(request, MPI_STATUS_IGNORE);
}

void dist_send(const void *data, size_t bytes, int to, int tag)
{
    MPI_Request request;
    MPI_Isend(data, (int)bytes, MPI_BYTE, to, tag, MPI_COMM_WORLD, &request);
    dist_wait(&request);
}

void dist_recv(void *data, size_t bytes, int from, int tag)
{
    MPI_Request request;
    MPI_Irecv(data, (int)bytes, MPI_BYTE, from, tag, MPI_COMM_WORLD, &request);
    dist_wait(&request);
}

int dist_recv_any(void *data, size_t bytes, int tag)
{
    MPI_Request request;
    MPI_Status status;
    MPI_Irecv(data, (int)bytes, MPI_BYTE, MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &request);
    wait_status(&request, &status);
    return status.MPI_SOURCE;
}

static void probe(int source, int tag, MPI_Status *status)
{
    int found = 0;
    for (MPI_Iprobe(source, tag, MPI_COMM_WORLD, &found, status); !found;
         MPI_Iprobe(source, tag, MPI_COMM_WORLD, &found, status))
        dist_nap();
}

static size_t byte_count(MPI_Status *status)
{
    int count = 0;
    MPI_Get_count(status, MPI_BYTE, &count);
    return (size_t)count;
}

void dist_probe_from(int source, int tag, size_t *bytes)
{
    MPI_Status status;
    probe(source, tag, &status);
    *bytes = byte_count(&status);
}

void dist_probe(int *source, int *tag, size_t *bytes)
{
    MPI_Status status;
    probe(MPI_ANY_SOURCE, MPI_ANY_TAG, &status);
    *source = status.MPI_SOURCE;
    *tag = status.MPI_TAG;
    *bytes = byte_count(&status);
}

void dist_discard(int rank, int tag, size_t bytes)
{
    unsigned char *scrap = malloc(bytes ? bytes : 1);
    if (!scrap) MPI_Abort(MPI_COMM_WORLD, 1);
    dist_recv(scrap, bytes, rank, tag);
    free(scrap);
}

unsigned char *dist_buffer_fit(unsigned char **buffer, size_t *size, size_t bytes)
{
    if (bytes > *size || !*buffer) {
        free(*buffer);
        *buffer = malloc(bytes ? bytes : 1);
        *size = *buffer ? bytes : 0;
        if (!*buffer) MPI_Abort(MPI_COMM_WORLD, 1);
    }
    return *buffer;
}

void dist_reports_init(dist_reports *reports)
{
    memset(reports, 0, sizeof *reports);
    reports->failed_rank = -1;
}

void dist_reports_note(dist_reports *reports, int rank, const dist_report *report)
{
    if (report->ok) {
        dist_stats_add(&reports->stats, &report->stats);
        return;
    }
    if (reports->failed_rank >= 0 && reports->failed_rank < rank) return;
    reports->failed_rank = rank;
    if (rank == 0) {
        reports->error = report->error;
        return;
    }
    char message[sizeof report->error.message];
    memcpy(message, report->error.message, sizeof message);
    message[sizeof message - 1] = '\0';
    rtt_error_set(&reports->error, "rank %d: %s", rank, message);
}

void dist_reports_fail(dist_reports *reports, int rank, const char *what)
{
    dist_report report = {.ok = 0};
    rtt_error_set(&report.error, "%s", what);
    dist_reports_note(reports, rank, &report);
}

void dist_serve(rtt_dist *dist, const dist_service *service)
{
    for (int left = dist->size - 1; left > 0;) {
        int rank, tag;
        size_t bytes;
        dist_probe(&rank, &tag, &bytes);
        if (tag == DIST_TAG_TAKE) {
            service->take(service->server, rank, bytes);
        } else if (tag == DIST_TAG_PIXELS) {
            service->pixels(service->server, rank, bytes);
        } else if (tag == DIST_TAG_REPORT && bytes == sizeof(dist_report)) {
            dist_report report;
            dist_recv(&report, sizeof report, rank, DIST_TAG_REPORT);
            dist_reports_note(service->reports, rank, &report);
            if (!report.ok) atomic_store(service->stop, true);
            left--;
        } else {
            /* nothing else travels while rank 0 serves: a rank out of step */
            dist_discard(rank, tag, bytes);
            dist_reports_fail(service->reports, rank, "mpi: a message out of step with rank 0");
            atomic_store(service->stop, true);
        }
    }
}

bool dist_verdict_send(rtt_dist *dist, const dist_reports *reports, rtt_error *err)
{
    int32_t verdict = reports->failed_rank < 0;
    for (int rank = 1; rank < dist->size; rank++) dist_send(&verdict, sizeof verdict, rank, DIST_TAG_VERDICT);
    if (!verdict && err) *err = reports->error;
    return verdict;
}

bool dist_verdict_await(rtt_dist *dist, bool ok, const rtt_error *mine, const rtt_render_stats *stats,
                        rtt_error *err)
{
    (void)dist;
    dist_report report;
    memset(&report, 0, sizeof report);
    report.ok = ok;
    if (!ok && mine) report.error = *mine;
    if (stats) report.stats = *stats;
    dist_send(&report, sizeof report, 0, DIST_TAG_REPORT);
    int32_t verdict = 0;
    dist_recv(&verdict, sizeof verdict, 0, DIST_TAG_VERDICT);
    if (!verdict && ok) rtt_error_set(err, "mpi: another rank failed (rank 0 names it)");
    return verdict;
}

bool rtt_dist_agree(rtt_dist *dist, bool ok, rtt_error *err)
{
    if (!dist) return ok;
    if (dist->rank != 0) return dist_verdict_await(dist, ok, err, NULL, err);
    dist_reports reports;
    dist_reports_init(&reports);
    dist_report own = {.ok = ok};
    if (!ok) own.error = *err;
    dist_reports_note(&reports, 0, &own);
    for (int left = dist->size - 1; left > 0; left--) {
        dist_report report;
        int source = dist_recv_any(&report, sizeof report, DIST_TAG_REPORT);
        dist_reports_note(&reports, source, &report);
    }
    return dist_verdict_send(dist, &reports, err);
}

/* What the MPI files of dist/ share: the job, the message tags and layouts,
 * polite waiting, the per-step reports and rank 0's verdict. */
#ifndef RTT_DIST_INTERNAL_H
#define RTT_DIST_INTERNAL_H

#include <mpi.h>
#include <stdatomic.h>
#include <stddef.h>

#include "dist/dist.h"
#include "dist_frames.h"

struct rtt_dist {
    int rank, size;
    atomic_uint *tiles_of_rank;   /* rank 0: the tiles handed to each rank since the job began */
    atomic_uint *frames_of_rank;  /* rank 0: the whole frames */
};

/* Tags of the point-to-point messages (all on MPI_COMM_WORLD). */
enum {
    DIST_TAG_TAKE = 1,   /* rank K → 0: a worker wants tiles; a dist_run_header with count 0 */
    DIST_TAG_RUN,        /* 0 → K: the run it gets (count 0: none left) */
    DIST_TAG_PIXELS,     /* K → 0: a dist_run_header, then the run's pixels (dist_run_copy) */
    DIST_TAG_REPORT,     /* K → 0: a dist_report, the outcome of K's step */
    DIST_TAG_VERDICT     /* 0 → K: an int32, 1 when every rank succeeded */
};

/* A run of tiles of one frame and the grid it is cut from: both sides check
 * the grid is the same before they trust first and count. */
typedef struct dist_run_header {
    uint32_t frame, first, count;
    uint32_t width, height, tile, planes;
} dist_run_header;

/* One rank's outcome of a step (plain bytes: every rank runs the same build). */
typedef struct dist_report {
    int32_t ok;
    rtt_error error;
    rtt_render_stats stats;
} dist_report;

/* A short sleep between tests of something not yet done. */
void dist_nap(void);
/* MPI_Test until done, sleeping between tests: a rank that waits leaves
 * the core to the ranks and threads that render (an oversubscribed node
 * would otherwise spin its waiters against its workers). */
void dist_wait(MPI_Request *request);
/* Sends or receives bytes and waits politely. */
void dist_send(const void *data, size_t bytes, int to, int tag);
void dist_recv(void *data, size_t bytes, int from, int tag);
/* Receives one message with `tag` from any rank; returns the rank. */
int dist_recv_any(void *data, size_t bytes, int tag);
/* Waits politely for any message; its source, tag and size in bytes. */
void dist_probe(int *source, int *tag, size_t *bytes);
/* Waits politely for a message from `source` with `tag`; its size. */
void dist_probe_from(int source, int tag, size_t *bytes);

/* Receives and drops a message rank 0 cannot use (its sender waits until
 * it is received). */
void dist_discard(int rank, int tag, size_t bytes);
/* *buffer grown to hold `bytes`.  Rank 0 cannot stay in step with a rank
 * whose message it cannot receive: without the memory, MPI_Abort ends
 * every rank, non-zero. */
unsigned char *dist_buffer_fit(unsigned char **buffer, size_t *size, size_t bytes);

/* Rank 0 gathers reports: the lowest failing rank's error wins, rank 0's
 * own first. */
typedef struct dist_reports {
    int failed_rank;          /* -1: none */
    rtt_error error;
    rtt_render_stats stats;   /* the other ranks' counters summed */
} dist_reports;
void dist_reports_init(dist_reports *reports);
void dist_reports_note(dist_reports *reports, int rank, const dist_report *report);
/* Notes that `rank` failed with message `what`. */
void dist_reports_fail(dist_reports *reports, int rank, const char *what);
/* Rank 0's serving loop, until every other rank has sent its report: run
 * requests and pixels go to the server's own handlers, a failed report
 * sets *stop, anything else is a rank out of step. */
typedef struct dist_service {
    void (*take)(void *server, int rank, size_t bytes);
    void (*pixels)(void *server, int rank, size_t bytes);
    void *server;
    dist_reports *reports;
    atomic_bool *stop;
} dist_service;
void dist_serve(rtt_dist *dist, const dist_service *service);
/* Rank 0: tells every rank the outcome; returns it and fills err. */
bool dist_verdict_send(rtt_dist *dist, const dist_reports *reports, rtt_error *err);
/* Rank K: sends its report and waits for rank 0's verdict. */
bool dist_verdict_await(rtt_dist *dist, bool ok, const rtt_error *mine, const rtt_render_stats *stats,
                        rtt_error *err);

/* Pixel planes of an image as bits (rgb 1, depth 2, prim 4, normal 8). */
uint32_t dist_image_planes(const rtt_image *image);
/* Bytes of a run's pixels; 0 when the run is not inside the grid. */
size_t dist_run_bytes(const rtt_tile_grid *grid, uint32_t planes, uint32_t first, uint32_t count);
/* Copies a run's pixels between the image and bytes (to_image: unpack). */
void dist_run_copy(rtt_image *image, const rtt_tile_grid *grid, uint32_t first, uint32_t count,
                   unsigned char *bytes, bool to_image);

/* The two sides of rtt_dist_render on a job of several ranks. */
bool dist_render_rank0(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                       rtt_render_stats *stats, rtt_error *err);
bool dist_render_other_rank(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                            rtt_render_stats *stats, rtt_error *err);

#endif

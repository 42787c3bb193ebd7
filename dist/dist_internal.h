/* What the MPI files of dist/ share: the job, the message tags and layouts,
 * polite waiting, the per-step reports and rank 0's verdict. */
#ifndef RTT_DIST_INTERNAL_H
#define RTT_DIST_INTERNAL_H

#include <mpi.h>
#include <stdatomic.h>
#include <stddef.h>

#include "dist/dist.h"

struct rtt_dist {
    int rank, size;
    atomic_uint *tiles_of_rank;   /* rank 0: the tiles handed to each rank in the last frame */
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

/* Rank 0 gathers reports: the lowest failing rank's error wins, rank 0's
 * own first. */
typedef struct dist_reports {
    int failed_rank;          /* -1: none */
    rtt_error error;
    rtt_render_stats stats;   /* the other ranks' counters summed */
} dist_reports;
void dist_reports_init(dist_reports *reports);
void dist_reports_note(dist_reports *reports, int rank, const dist_report *report);
/* Rank 0: tells every rank the outcome; returns it and fills err. */
bool dist_verdict_send(rtt_dist *dist, const dist_reports *reports, rtt_error *err);
/* Rank K: sends its report and waits for rank 0's verdict. */
bool dist_verdict_await(rtt_dist *dist, bool ok, const rtt_error *mine, const rtt_render_stats *stats,
                        rtt_error *err);
void dist_stats_add(rtt_render_stats *sum, const rtt_render_stats *more);

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

/* Rendering over MPI (dist/): one frame's tiles, or a sequence's frames,
 * shared by the ranks of an MPI job; the pixels gathered on rank 0.
 *
 * A process started by no MPI launcher never touches MPI: rtt_dist_open
 * gives NULL, and every function below then acts for the one process
 * (rtt_dist_render is rtt_render), so a run without mpirun is exactly the
 * run of a build without MPI.  Library code: nothing here prints or exits;
 * failures come back as rtt_error, rank 0's naming the failing rank. */
#ifndef RTT_DIST_H
#define RTT_DIST_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/engine.h"
#include "rtt/error.h"
#include "rtt/image.h"
#include "rtt/render.h"

typedef struct rtt_dist rtt_dist;

/* Joins the MPI job when a launcher started this process (*out = the job),
 * else *out = NULL.  False + err when the job cannot be joined (MPI fails to
 * start, or this build has no MPI and the launcher started several copies). */
bool rtt_dist_open(rtt_dist **out, rtt_error *err);
/* Leaves the job (MPI_Finalize); NULL is fine. */
void rtt_dist_close(rtt_dist *dist);
/* 0 and 1 for NULL. */
uint32_t rtt_dist_rank(const rtt_dist *dist);
uint32_t rtt_dist_size(const rtt_dist *dist);

/* Every rank's outcome of one step, in step: true on every rank when all
 * succeeded.  On a failure every rank returns false; rank 0's err is its
 * own when it failed, else "rank K: <K's message>" for the lowest failing
 * rank K. */
bool rtt_dist_agree(rtt_dist *dist, bool ok, rtt_error *err);

/* One frame, every rank's engine built from the same scene and options:
 * rank 0 hands runs of tiles to its own workers and, on demand, to the
 * other ranks, which send their pixels (and AOVs) back.  `out` is complete
 * on rank 0 only; byte for byte the image rtt_render makes in one process.
 * Ends with rtt_dist_agree; stats on rank 0 sum every rank's counters (the
 * total time is rank 0's). */
bool rtt_dist_render(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                     rtt_render_stats *stats, rtt_error *err);

/* Rank 0, after rtt_dist_render: how many tiles rank r rendered (0 elsewhere). */
uint32_t rtt_dist_tiles_of_rank(const rtt_dist *dist, uint32_t rank);

#endif

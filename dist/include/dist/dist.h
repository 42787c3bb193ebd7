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

/* A sequence of frames (rtt render --camera-path). */
typedef struct rtt_dist_frames {
    uint32_t count;
    /* On every rank before it renders frame f: put f's camera into the scene
     * the engine was built from (NULL: the frames differ in nothing). */
    void (*prepare)(void *context, uint32_t frame);
    /* On rank 0 with frame f complete in `image`: write it.  Called from
     * one thread at a time, frames in any order. */
    bool (*write)(void *context, uint32_t frame, const rtt_image *image, rtt_error *err);
    void *context;
} rtt_dist_frames;

/* Renders and writes every frame.  Up to one frame per rank (and always in
 * one process): frame after frame, each frame's tiles shared by the ranks
 * (rtt_dist_render).  More frames than ranks: whole frames go to the ranks
 * on demand, each rendered by one rank's threads into its own image and
 * sent to rank 0 (rank 0 renders frames too).  Either way each frame is
 * byte for byte its one-process render.  A failure stops the job: frames
 * already written stay, complete; no frame is half-written.  stats: summed
 * over frames and ranks; seconds_total the frames' render times (one frame
 * in one process: exactly rtt_render's), or with whole frames to the ranks
 * the sequence's wall time on rank 0, writes included. */
bool rtt_dist_render_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                            const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err);

/* Rank 0: how many tiles of frames shared by tiles, and how many whole
 * frames, rank r has rendered since the job began (0 on the other ranks). */
uint32_t rtt_dist_tiles_of_rank(const rtt_dist *dist, uint32_t rank);
uint32_t rtt_dist_frames_of_rank(const rtt_dist *dist, uint32_t rank);

#endif

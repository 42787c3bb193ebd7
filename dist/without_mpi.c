/* dist/ in a build without MPI (RTT_MPI off): always the one process.
 * Started by a launcher as one of several copies, it refuses rather than
 * render the whole frame once per copy. */
#include "dist/dist.h"
#include "dist_launcher.h"

bool rtt_dist_open(rtt_dist **out, rtt_error *err)
{
    *out = NULL;
    uint32_t processes = 0;
    if (dist_launched(&processes) && processes != 1)
        return rtt_error_set(err, "mpi: this rtt was built without MPI (RTT_MPI off) and cannot share a frame "
                                  "with the other processes of the launcher's job");
    return true;
}

void rtt_dist_close(rtt_dist *dist)
{
    (void)dist;
}

uint32_t rtt_dist_rank(const rtt_dist *dist)
{
    (void)dist;
    return 0;
}

uint32_t rtt_dist_size(const rtt_dist *dist)
{
    (void)dist;
    return 1;
}

uint32_t rtt_dist_tiles_of_rank(const rtt_dist *dist, uint32_t rank)
{
    (void)dist;
    (void)rank;
    return 0;
}

uint32_t rtt_dist_frames_of_rank(const rtt_dist *dist, uint32_t rank)
{
    (void)dist;
    (void)rank;
    return 0;
}

bool rtt_dist_agree(rtt_dist *dist, bool ok, rtt_error *err)
{
    (void)dist;
    (void)err;
    return ok;
}

bool rtt_dist_render(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                     rtt_render_stats *stats, rtt_error *err)
{
    (void)dist;
    return rtt_render(engine, opt, out, stats, err);
}

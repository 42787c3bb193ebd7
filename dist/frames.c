/* rtt_dist_render_frames: a sequence frame by frame, each frame's tiles
 * over the ranks; with more frames than ranks, whole frames to the ranks
 * (frame_server.c).  Built with and without MPI. */
#include <string.h>

#include "dist/dist.h"
#include "dist_frames.h"
#include "engine/clock.h"

void dist_stats_add(rtt_render_stats *sum, const rtt_render_stats *more)
{
    sum->primary_rays += more->primary_rays;
    sum->shadow_rays += more->shadow_rays;
    sum->secondary_rays += more->secondary_rays;
    sum->packets += more->packets;
    sum->traversal_steps += more->traversal_steps;
    sum->intersection_tests += more->intersection_tests;
    sum->seconds_primary_traversal += more->seconds_primary_traversal;
    sum->seconds_primary_intersection += more->seconds_primary_intersection;
    sum->seconds_shading += more->seconds_shading;
    sum->seconds_secondary += more->seconds_secondary;
}

static bool frame_by_frame(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                           const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err)
{
    const bool writer = rtt_dist_rank(dist) == 0;
    rtt_render_stats frame_stats;
    for (uint32_t f = 0; f < frames->count; f++) {
        if (frames->prepare) frames->prepare(frames->context, f);
        memset(&frame_stats, 0, sizeof frame_stats);
        if (!rtt_dist_render(dist, engine, opt, image, stats ? &frame_stats : NULL, err)) return false;
        if (stats) {
            dist_stats_add(stats, &frame_stats);
            stats->seconds_total += frame_stats.seconds_total; /* the renders', not the writes' */
        }
        bool written = !writer || frames->write(frames->context, f, image, err);
        if (!rtt_dist_agree(dist, written, err)) return false;
    }
    return true;
}

bool rtt_dist_render_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                            const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err)
{
    if (stats) memset(stats, 0, sizeof *stats);
#if RTT_HAVE_MPI
    if (rtt_dist_size(dist) > 1 && frames->count > rtt_dist_size(dist)) {
        const uint64_t start = rtt_clock_ns();
        bool ok = dist_render_whole_frames(dist, engine, opt, image, frames, stats, err);
        if (stats) stats->seconds_total = 1e-9 * (double)(rtt_clock_ns() - start);
        return ok;
    }
#endif
    return frame_by_frame(dist, engine, opt, image, frames, stats, err);
}

/* What frames.c (built with and without MPI) shares with the MPI files. */
#ifndef RTT_DIST_FRAMES_H
#define RTT_DIST_FRAMES_H

#include "dist/dist.h"

/* Adds the counters and stage times (not seconds_total). */
void dist_stats_add(rtt_render_stats *sum, const rtt_render_stats *more);
/* More frames than ranks: whole frames to the ranks (frame_server.c). */
bool dist_render_whole_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                              const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err);

#endif

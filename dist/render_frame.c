/* rtt_dist_render: one frame over the job, rank 0 serving (tile_server.c),
 * the others fetching (tile_client.c). */
#include "dist_internal.h"

bool rtt_dist_render(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                     rtt_render_stats *stats, rtt_error *err)
{
    if (!dist || dist->size == 1) return rtt_dist_agree(dist, rtt_render(engine, opt, out, stats, err), err);
    if (dist->rank == 0) return dist_render_rank0(dist, engine, opt, out, stats, err);
    return dist_render_other_rank(dist, engine, opt, out, stats, err);
}

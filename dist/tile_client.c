/* The side of a distributed frame on every rank but 0: its workers ask
 * rank 0 for runs of tiles, render them into the rank's own image, and
 * send each run's pixels back.  The workers talk to rank 0 one at a time
 * (MPI_THREAD_SERIALIZED), under the client's lock. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "dist_internal.h"

typedef struct tile_client {
    rtt_image *image;
    uint32_t planes;
    pthread_mutex_t lock;
    bool failed;            /* under lock */
    rtt_error failure;
} tile_client;

static dist_run_header header_of(const tile_client *client, const rtt_tile_grid *grid)
{
    return (dist_run_header){.width = grid->width, .height = grid->height, .tile = grid->tile,
                             .planes = client->planes};
}

static bool take_remote(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t *first, uint32_t *count)
{
    (void)thread;
    tile_client *client = context;
    dist_run_header ask = header_of(client, grid), run = {0};
    pthread_mutex_lock(&client->lock);
    bool go = !client->failed;
    if (go) {
        dist_send(&ask, sizeof ask, 0, DIST_TAG_TAKE);
        dist_recv(&run, sizeof run, 0, DIST_TAG_RUN);
    }
    pthread_mutex_unlock(&client->lock);
    *first = run.first;
    *count = run.count;
    return go && run.count > 0 && dist_run_bytes(grid, client->planes, run.first, run.count) > 0;
}

static void send_pixels(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t first, uint32_t count)
{
    (void)thread;
    tile_client *client = context;
    dist_run_header header = header_of(client, grid);
    header.first = first;
    header.count = count;
    size_t bytes = sizeof header + dist_run_bytes(grid, client->planes, first, count);
    unsigned char *message = malloc(bytes);
    if (message) {
        memcpy(message, &header, sizeof header);
        dist_run_copy(client->image, grid, first, count, message + sizeof header, false);
    }
    pthread_mutex_lock(&client->lock);
    if (message && !client->failed) dist_send(message, bytes, 0, DIST_TAG_PIXELS);
    if (!message && !client->failed) {
        client->failed = true;
        rtt_error_set(&client->failure, "mpi: out of memory packing %u tiles' pixels", count);
    }
    pthread_mutex_unlock(&client->lock);
    free(message);
}

bool dist_render_other_rank(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                            rtt_render_stats *stats, rtt_error *err)
{
    tile_client client = {.image = out, .planes = dist_image_planes(out)};
    pthread_mutex_init(&client.lock, NULL);
    rtt_tile_source source = {.take = take_remote, .rendered = send_pixels, .context = &client};
    rtt_render_options remote = *opt;
    remote.tile_source = &source;
    remote.progress = NULL;
    rtt_error own = {{0}};
    bool ok = rtt_render(engine, &remote, out, stats, &own);
    if (ok && client.failed) {
        ok = false;
        own = client.failure;
    }
    pthread_mutex_destroy(&client.lock);
    bool agreed = dist_verdict_await(dist, ok, &own, stats, err);
    if (!ok) *err = own;
    return agreed;
}

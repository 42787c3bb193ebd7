/* The side of a distributed frame on every rank but 0: its workers ask
 * rank 0 for runs of tiles, render them into the rank's own image, and
 * send each run's pixels back.
 *
 * The rank asks one run ahead: the worker that takes a run sends the
 * request for the next before it starts rendering, so the answer is there
 * when a worker next needs one and rank 0's round trip hides behind the
 * render (on a cluster, and on a busy node whose rank 0 answers late).
 * Pixels go out with MPI_Isend and the worker goes back to rendering; the
 * sends are completed as later calls pass.  Every MPI call is made under
 * the client's lock (MPI_THREAD_SERIALIZED); a worker waiting for an answer
 * lets go of the lock between tests. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "dist_internal.h"

typedef struct pixel_send {
    MPI_Request request;
    unsigned char *message;
} pixel_send;

typedef struct tile_client {
    rtt_image *image;
    uint32_t planes;
    pthread_mutex_t lock;        /* everything below, and every MPI call */
    bool failed;
    rtt_error failure;
    bool asking;                 /* a request is in flight */
    bool answered;               /* `answer` holds a run not yet taken */
    bool no_more;                /* rank 0 has none left */
    MPI_Request ask_send, ask_recv;
    dist_run_header ask, answer;
    pixel_send *sends;           /* pixels in flight */
    size_t send_count, send_capacity;
} tile_client;

static dist_run_header header_of(const tile_client *client, const rtt_tile_grid *grid)
{
    return (dist_run_header){.width = grid->width, .height = grid->height, .tile = grid->tile,
                             .planes = client->planes};
}

static void ask_for_run(tile_client *client, const rtt_tile_grid *grid)
{
    client->ask = header_of(client, grid);
    MPI_Irecv(&client->answer, sizeof client->answer, MPI_BYTE, 0, DIST_TAG_RUN, MPI_COMM_WORLD, &client->ask_recv);
    MPI_Isend(&client->ask, sizeof client->ask, MPI_BYTE, 0, DIST_TAG_TAKE, MPI_COMM_WORLD, &client->ask_send);
    client->asking = true;
}

/* Under the lock: whether the request in flight has its answer. */
static bool answer_arrived(tile_client *client)
{
    int done = 0;
    MPI_Test(&client->ask_recv, &done, MPI_STATUS_IGNORE);
    if (!done) return false;
    MPI_Wait(&client->ask_send, MPI_STATUS_IGNORE); /* answered: rank 0 has the request */
    client->asking = false;
    client->answered = true;
    return true;
}

/* Under the lock: frees the sends that have completed. */
static void reap_sends(tile_client *client)
{
    size_t kept = 0;
    for (size_t i = 0; i < client->send_count; i++) {
        int done = 0;
        MPI_Test(&client->sends[i].request, &done, MPI_STATUS_IGNORE);
        if (done)
            free(client->sends[i].message);
        else
            client->sends[kept++] = client->sends[i];
    }
    client->send_count = kept;
}

static bool take_remote(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t *first, uint32_t *count)
{
    (void)thread;
    tile_client *client = context;
    pthread_mutex_lock(&client->lock);
    for (;;) {
        if (client->failed) break;
        if (client->answered) {
            dist_run_header run = client->answer;
            client->answered = false;
            if (run.count == 0 || dist_run_bytes(grid, client->planes, run.first, run.count) == 0) {
                client->no_more = true;
                break;
            }
            ask_for_run(client, grid); /* the next, while this one renders */
            pthread_mutex_unlock(&client->lock);
            *first = run.first;
            *count = run.count;
            return true;
        }
        if (client->no_more) break;
        if (!client->asking) ask_for_run(client, grid);
        if (answer_arrived(client)) continue;
        pthread_mutex_unlock(&client->lock);
        dist_nap();
        pthread_mutex_lock(&client->lock);
    }
    pthread_mutex_unlock(&client->lock);
    return false;
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
    reap_sends(client);
    if (!message && !client->failed) {
        client->failed = true;
        rtt_error_set(&client->failure, "mpi: out of memory packing %u tiles' pixels", count);
    }
    if (message && !client->failed && client->send_count == client->send_capacity) {
        size_t capacity = client->send_capacity ? 2 * client->send_capacity : 16;
        pixel_send *grown = realloc(client->sends, capacity * sizeof *grown);
        if (grown) {
            client->sends = grown;
            client->send_capacity = capacity;
        }
    }
    if (message && !client->failed && client->send_count < client->send_capacity) {
        pixel_send *send = &client->sends[client->send_count++];
        send->message = message;
        MPI_Isend(message, (int)bytes, MPI_BYTE, 0, DIST_TAG_PIXELS, MPI_COMM_WORLD, &send->request);
        message = NULL;
    } else if (message && !client->failed) {
        dist_send(message, bytes, 0, DIST_TAG_PIXELS); /* no room to keep it in flight */
    }
    pthread_mutex_unlock(&client->lock);
    free(message);
}

/* After the render, alone: the answer still in flight and every send
 * complete, so the report follows the pixels. */
static void finish(tile_client *client)
{
    if (client->asking) {
        dist_wait(&client->ask_recv);
        dist_wait(&client->ask_send);
    }
    for (size_t i = 0; i < client->send_count; i++) {
        dist_wait(&client->sends[i].request);
        free(client->sends[i].message);
    }
    free(client->sends);
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
    finish(&client);
    if (ok && client.failed) {
        ok = false;
        own = client.failure;
    }
    pthread_mutex_destroy(&client.lock);
    bool agreed = dist_verdict_await(dist, ok, &own, stats, err);
    if (!ok) *err = own;
    return agreed;
}

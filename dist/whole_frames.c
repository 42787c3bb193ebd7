/* More frames than ranks: whole frames to the ranks on demand.  Each rank
 * renders its frame with all its threads, as one process would, and sends
 * it to rank 0 one row of transfer tiles at a time; rank 0 renders frames
 * too, and one serving thread answers the ranks, receives their frames
 * into one image and writes them.  A rank's frame is received in one go,
 * so rank 0 holds two images however many ranks there are. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "dist_internal.h"

/* The transfer grid: a frame goes to rank 0 in rows of 64-pixel tiles (a
 * message stays far below MPI's 2 GiB count at 16384 pixels across). */
#define TRANSFER_TILE 64u

typedef struct frame_server {
    rtt_dist *dist;
    const rtt_dist_frames *frames;
    rtt_image *received;         /* a rank's frame, as it arrives */
    rtt_tile_grid grid;          /* the transfer grid */
    uint32_t planes;
    atomic_uint next;            /* the first frame not handed out */
    atomic_bool stop;            /* a rank failed: hand out nothing more */
    pthread_mutex_t write_lock;  /* frames->write: one thread at a time */
    dist_reports reports;        /* the serving thread's */
    rtt_error write_error;       /* rank 0's own, from the serving thread */
    bool write_failed;
    unsigned char *buffer;
    size_t buffer_size;
} frame_server;

static rtt_tile_grid transfer_grid(const rtt_image *image)
{
    uint32_t tiles_x = (image->width + TRANSFER_TILE - 1) / TRANSFER_TILE;
    uint32_t tiles_y = (image->height + TRANSFER_TILE - 1) / TRANSFER_TILE;
    return (rtt_tile_grid){.width = image->width, .height = image->height, .tile = TRANSFER_TILE,
                           .tiles_x = tiles_x, .total = tiles_x * tiles_y};
}

static bool take_frame(frame_server *server, int rank, uint32_t *frame)
{
    uint32_t f = atomic_fetch_add(&server->next, 1);
    if (atomic_load(&server->stop) || f >= server->frames->count) return false;
    atomic_fetch_add(&server->dist->frames_of_rank[rank], 1);
    *frame = f;
    return true;
}

static bool write_frame(frame_server *server, uint32_t frame, const rtt_image *image, rtt_error *err)
{
    pthread_mutex_lock(&server->write_lock);
    bool ok = server->frames->write(server->frames->context, frame, image, err);
    pthread_mutex_unlock(&server->write_lock);
    if (!ok) atomic_store(&server->stop, true);
    return ok;
}

static void fail_rank(frame_server *server, int rank, const char *what)
{
    dist_reports_fail(&server->reports, rank, what);
    atomic_store(&server->stop, true);
}

/* One row of a rank's frame (probed at `bytes`) into the received image;
 * false when it is not a row of the transfer grid. */
static bool receive_row(frame_server *server, int rank, size_t bytes, dist_run_header *header)
{
    dist_buffer_fit(&server->buffer, &server->buffer_size, bytes);
    dist_recv(server->buffer, bytes, rank, DIST_TAG_PIXELS);
    if (bytes < sizeof *header) return false;
    memcpy(header, server->buffer, sizeof *header);
    const rtt_tile_grid *grid = &server->grid;
    bool fits = header->frame < server->frames->count && header->count == grid->tiles_x &&
                header->first % grid->tiles_x == 0 && header->width == grid->width &&
                header->height == grid->height && header->tile == grid->tile && header->planes == server->planes &&
                bytes == sizeof *header + dist_run_bytes(grid, server->planes, header->first, header->count);
    if (fits)
        dist_run_copy(server->received, grid, header->first, header->count, server->buffer + sizeof *header, true);
    return fits;
}

/* The first row of `rank`'s frame has arrived: the rest follow back to back. */
static void receive_frame(void *context, int rank, size_t bytes)
{
    frame_server *server = context;
    const uint32_t rows = server->grid.total / server->grid.tiles_x;
    dist_run_header header = {0};
    uint32_t frame = 0;
    for (uint32_t row = 0; row < rows; row++) {
        if (row > 0) dist_probe_from(rank, DIST_TAG_PIXELS, &bytes);
        bool fits = receive_row(server, rank, bytes, &header);
        if (row == 0) frame = header.frame;
        if (!fits || header.frame != frame || header.first != row * server->grid.tiles_x) {
            fail_rank(server, rank, "mpi: sent a frame that does not fit rank 0's image");
            return;
        }
    }
    rtt_error err = {{0}};
    if (!write_frame(server, frame, server->received, &err) && !server->write_failed) {
        server->write_failed = true;
        server->write_error = err;
    }
}

static void answer_take(void *context, int rank, size_t bytes)
{
    frame_server *server = context;
    dist_run_header ask, run = {0};
    if (bytes == sizeof ask) {
        dist_recv(&ask, sizeof ask, rank, DIST_TAG_TAKE);
    } else {
        dist_discard(rank, DIST_TAG_TAKE, bytes);
        fail_rank(server, rank, "mpi: a request for a frame of the wrong size");
    }
    if (take_frame(server, rank, &run.first)) run.count = 1;
    dist_send(&run, sizeof run, rank, DIST_TAG_RUN);
}

/* Serves until every other rank has sent its report. */
static void *serve(void *context)
{
    frame_server *server = context;
    dist_service service = {.take = answer_take, .pixels = receive_frame, .server = server,
                            .reports = &server->reports, .stop = &server->stop};
    dist_serve(server->dist, &service);
    return NULL;
}

static bool rank0_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                         const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err)
{
    frame_server server = {.dist = dist, .frames = frames, .grid = transfer_grid(image),
                           .planes = dist_image_planes(image)};
    atomic_init(&server.next, 0);
    atomic_init(&server.stop, false);
    pthread_mutex_init(&server.write_lock, NULL);
    dist_reports_init(&server.reports);
    dist_report own = {.ok = 1};
    server.received = rtt_image_create(image->width, image->height,
                                       (image->depth ? RTT_AOV_DEPTH : 0u) | (image->prim ? RTT_AOV_PRIM : 0u) |
                                           (image->normal ? RTT_AOV_NORMAL : 0u),
                                       &own.error);
    if (!server.received) own.ok = 0;
    if (!own.ok) atomic_store(&server.stop, true);
    pthread_t thread;
    bool serving = pthread_create(&thread, NULL, serve, &server) == 0;
    rtt_render_stats frame_stats;
    uint32_t frame;
    while (own.ok && take_frame(&server, 0, &frame)) {
        if (frames->prepare) frames->prepare(frames->context, frame);
        memset(&frame_stats, 0, sizeof frame_stats);
        own.ok = rtt_render(engine, opt, image, stats ? &frame_stats : NULL, &own.error) &&
                 write_frame(&server, frame, image, &own.error);
        if (own.ok && stats) dist_stats_add(stats, &frame_stats);
    }
    if (!own.ok) atomic_store(&server.stop, true);
    if (serving)
        pthread_join(thread, NULL);
    else
        serve(&server);
    if (own.ok && server.write_failed) {
        own.ok = 0;
        own.error = server.write_error;
    }
    dist_reports_note(&server.reports, 0, &own);
    if (stats) dist_stats_add(stats, &server.reports.stats);
    rtt_image_free(server.received);
    free(server.buffer);
    pthread_mutex_destroy(&server.write_lock);
    return dist_verdict_send(dist, &server.reports, err);
}

/* A rank's frame to rank 0, row after row of the transfer grid. */
static bool send_frame(const rtt_image *image, uint32_t frame, rtt_error *err)
{
    const rtt_tile_grid grid = transfer_grid(image);
    const uint32_t planes = dist_image_planes(image);
    size_t bytes = sizeof(dist_run_header) + dist_run_bytes(&grid, planes, 0, grid.tiles_x);
    unsigned char *message = malloc(bytes);
    if (!message) return rtt_error_set(err, "mpi: out of memory sending frame %u", frame);
    for (uint32_t first = 0; first < grid.total; first += grid.tiles_x) {
        dist_run_header header = {.frame = frame, .first = first, .count = grid.tiles_x, .width = grid.width,
                                  .height = grid.height, .tile = grid.tile, .planes = planes};
        size_t size = sizeof header + dist_run_bytes(&grid, planes, first, grid.tiles_x);
        memcpy(message, &header, sizeof header);
        dist_run_copy((rtt_image *)image, &grid, first, grid.tiles_x, message + sizeof header, false);
        dist_send(message, size, 0, DIST_TAG_PIXELS);
    }
    free(message);
    return true;
}

static bool other_rank_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                              const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err)
{
    bool ok = true;
    rtt_error own = {{0}};
    rtt_render_stats frame_stats;
    for (;;) {
        dist_run_header ask = {0}, run = {0};
        dist_send(&ask, sizeof ask, 0, DIST_TAG_TAKE);
        dist_recv(&run, sizeof run, 0, DIST_TAG_RUN);
        if (run.count == 0 || run.first >= frames->count) break;
        if (frames->prepare) frames->prepare(frames->context, run.first);
        memset(&frame_stats, 0, sizeof frame_stats);
        ok = rtt_render(engine, opt, image, stats ? &frame_stats : NULL, &own) && send_frame(image, run.first, &own);
        if (!ok) break;
        if (stats) dist_stats_add(stats, &frame_stats);
    }
    bool agreed = dist_verdict_await(dist, ok, &own, stats, err);
    if (!ok) *err = own;
    return agreed;
}

bool dist_render_whole_frames(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *image,
                              const rtt_dist_frames *frames, rtt_render_stats *stats, rtt_error *err)
{
    if (dist->rank == 0) return rank0_frames(dist, engine, opt, image, frames, stats, err);
    return other_rank_frames(dist, engine, opt, image, frames, stats, err);
}

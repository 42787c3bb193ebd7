/* Rank 0's side of a distributed frame: it hands out runs of tiles, on
 * demand, to its own workers and to the other ranks' (one thread serves
 * the ranks while the workers render), and copies the pixels the ranks
 * send into the image.  The first run a rank asks for fixes nothing: every
 * run request carries the rank's tile grid and must match rank 0's. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "dist_internal.h"
#include "engine/clock.h"

/* Runs shrink as the frame empties (guided scheduling), so the ranks finish
 * close together: a rank takes 1/RUN_SHARE of what is left over the ranks,
 * at least one tile and at most MAX_RUN (64 tiles of 8x8: 112 KiB of pixels
 * with every AOV, one message). */
#define RUN_SHARE 8u
#define MAX_RUN 64u

typedef struct tile_server {
    rtt_dist *dist;
    rtt_image *out;
    uint32_t planes;
    pthread_mutex_t grid_lock;
    bool grid_known;
    rtt_tile_grid grid;
    atomic_uint next;            /* the first tile not handed out */
    atomic_bool stop;            /* a rank failed: hand out nothing more */
    atomic_bool grid_differs;    /* rank 0's workers met a grid a rank fixed first */
    atomic_uint *tiles_of_rank;  /* tiles handed to each rank */
    dist_reports reports;        /* the serving thread's */
    unsigned char *buffer;       /* a received message */
    size_t buffer_size;
} tile_server;

static bool same_grid(const rtt_tile_grid *a, const rtt_tile_grid *b)
{
    return a->width == b->width && a->height == b->height && a->tile == b->tile;
}

/* The grid every run is cut from: the first one seen, which later ones must equal. */
static bool accept_grid(tile_server *server, const rtt_tile_grid *grid)
{
    pthread_mutex_lock(&server->grid_lock);
    if (!server->grid_known) {
        server->grid = *grid;
        server->grid_known = true;
    }
    bool same = same_grid(&server->grid, grid);
    pthread_mutex_unlock(&server->grid_lock);
    return same;
}

static bool hand_out(tile_server *server, int rank, uint32_t *first, uint32_t *count)
{
    const uint32_t total = server->grid.total;
    const uint32_t share = RUN_SHARE * (uint32_t)server->dist->size;
    uint32_t next = atomic_load(&server->next);
    for (;;) {
        if (atomic_load(&server->stop) || next >= total) return false;
        uint32_t run = (total - next) / share;
        run = run < 1 ? 1 : run > MAX_RUN ? MAX_RUN : run;
        if (atomic_compare_exchange_weak(&server->next, &next, next + run)) {
            *first = next;
            *count = run;
            atomic_fetch_add(&server->tiles_of_rank[rank], run);
            return true;
        }
    }
}

/* rtt_tile_source.take for rank 0's own workers */
static bool take_local(void *context, const rtt_tile_grid *grid, uint32_t thread, uint32_t *first, uint32_t *count)
{
    (void)thread;
    tile_server *server = context;
    if (!accept_grid(server, grid)) {
        atomic_store(&server->grid_differs, true);
        atomic_store(&server->stop, true);
        return false;
    }
    return hand_out(server, 0, first, count);
}

static void fail_rank(tile_server *server, int rank, const char *what)
{
    dist_reports_fail(&server->reports, rank, what);
    atomic_store(&server->stop, true);
}

static void grid_from(const dist_run_header *header, rtt_tile_grid *grid)
{
    uint32_t tile = header->tile ? header->tile : 1;
    uint32_t tiles_x = (uint32_t)(((uint64_t)header->width + tile - 1) / tile);
    uint32_t tiles_y = (uint32_t)(((uint64_t)header->height + tile - 1) / tile);
    *grid = (rtt_tile_grid){.width = header->width, .height = header->height, .tile = tile, .tiles_x = tiles_x,
                            .total = tiles_x * tiles_y};
}

static void answer_take(void *context, int rank, size_t bytes)
{
    tile_server *server = context;
    dist_run_header header = {0};
    if (bytes != sizeof header) {
        dist_discard(rank, DIST_TAG_TAKE, bytes);
        fail_rank(server, rank, "mpi: a request for tiles of the wrong size");
    } else {
        dist_recv(&header, sizeof header, rank, DIST_TAG_TAKE);
        rtt_tile_grid grid;
        grid_from(&header, &grid);
        if (!accept_grid(server, &grid))
            fail_rank(server, rank, "mpi: renders a different image size or tile size than rank 0");
    }
    dist_run_header run = header;
    run.first = run.count = 0;
    if (atomic_load(&server->stop) || !hand_out(server, rank, &run.first, &run.count)) run.count = 0;
    dist_send(&run, sizeof run, rank, DIST_TAG_RUN);
}

static void take_pixels(void *context, int rank, size_t bytes)
{
    tile_server *server = context;
    dist_buffer_fit(&server->buffer, &server->buffer_size, bytes);
    dist_recv(server->buffer, bytes, rank, DIST_TAG_PIXELS);
    dist_run_header header = {0};
    memcpy(&header, server->buffer, sizeof header < bytes ? sizeof header : bytes);
    rtt_tile_grid grid;
    grid_from(&header, &grid);
    size_t run_bytes = bytes >= sizeof header && server->grid_known && same_grid(&grid, &server->grid) &&
                               header.planes == server->planes && header.frame == 0
                           ? dist_run_bytes(&server->grid, server->planes, header.first, header.count)
                           : 0;
    if (run_bytes == 0 || bytes != sizeof header + run_bytes) {
        fail_rank(server, rank, "mpi: sent pixels that do not fit rank 0's image");
        return;
    }
    dist_run_copy(server->out, &server->grid, header.first, header.count, server->buffer + sizeof header, true);
}

/* Serves until every other rank has sent its report. */
static void *serve(void *context)
{
    tile_server *server = context;
    dist_service service = {.take = answer_take, .pixels = take_pixels, .server = server,
                            .reports = &server->reports, .stop = &server->stop};
    dist_serve(server->dist, &service);
    return NULL;
}

bool dist_render_rank0(rtt_dist *dist, rtt_engine *engine, const rtt_render_options *opt, rtt_image *out,
                       rtt_render_stats *stats, rtt_error *err)
{
    const uint64_t start = rtt_clock_ns();
    tile_server server = {.dist = dist, .out = out, .planes = dist_image_planes(out)};
    pthread_mutex_init(&server.grid_lock, NULL);
    atomic_init(&server.next, 0);
    atomic_init(&server.stop, false);
    atomic_init(&server.grid_differs, false);
    dist_reports_init(&server.reports);
    server.tiles_of_rank = dist->tiles_of_rank;
    rtt_tile_source source = {.take = take_local, .context = &server};
    rtt_render_options local = *opt;
    local.tile_source = &source;
    local.progress = NULL; /* rank 0's own tiles are not the frame's */

    pthread_t server_thread;
    bool serving = pthread_create(&server_thread, NULL, serve, &server) == 0;
    dist_report own = {.ok = 1};
    own.ok = rtt_render(engine, &local, out, stats, &own.error);
    if (own.ok && atomic_load(&server.grid_differs)) {
        own.ok = 0;
        rtt_error_set(&own.error, "mpi: the ranks cut the image into different tiles");
    }
    if (!own.ok) atomic_store(&server.stop, true);
    if (serving)
        pthread_join(server_thread, NULL);
    else
        serve(&server); /* no thread to spare: rank 0's workers took every tile, the ranks get none */
    dist_reports_note(&server.reports, 0, &own);
    if (stats && own.ok) {
        dist_stats_add(stats, &server.reports.stats);
        stats->seconds_total = 1e-9 * (double)(rtt_clock_ns() - start);
    }
    free(server.buffer);
    pthread_mutex_destroy(&server.grid_lock);
    return dist_verdict_send(dist, &server.reports, err);
}

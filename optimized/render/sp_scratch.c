/* The shader proxy's per-thread scratch (sp_scratch.h) and the steps of a
 * tile that only move rays and hits: the primary packets, tracing packets
 * through the descriptor table's kernels, and storing their hits.  Every
 * array grows through rtt_buffer; the first failed growth marks the scratch
 * failed and every later step does nothing. */
#include <stdlib.h>
#include <string.h>

#include "engine/clock.h"
#include "sp_scratch.h"

sp_scratch *sp_scratch_create(uint32_t level_count, bool timing)
{
    sp_scratch *s = calloc(1, sizeof *s);
    sp_level *levels = calloc(level_count, sizeof *levels);
    if (s && levels) {
        *s = (sp_scratch){.levels = levels, .level_count = level_count, .timing = timing};
        return s;
    }
    free(levels);
    free(s);
    return NULL;
}

/* Every buffer of a scratch but the levels' nodes, in one list for
 * destroy and match. */
#define SP_SCRATCH_BUFFERS 22u
static void scratch_buffers(sp_scratch *s, rtt_buffer *out[SP_SCRATCH_BUFFERS])
{
    rtt_buffer *buffers[SP_SCRATCH_BUFFERS] = {
        &s->packets,      &s->hits,     &s->occluded, &s->primary_lanes, &s->shadow_rays,
        &s->shadow_clear, &s->surfaces, &s->requests, &s->group_first,   &s->edge_rays,
        &s->edge_order,   &s->edge_light, &s->edge_occlusion, &s->shadow_transmission, &s->shadow_pending,
        &s->frusta_points, &s->frusta_light, &s->frusta_pixel, &s->frusta_mask, &s->frusta_order,
        &s->frusta_sorted, &s->frusta_answer};
    memcpy(out, buffers, sizeof buffers);
}

void sp_scratch_destroy(sp_scratch *s)
{
    if (!s) return;
    for (uint32_t i = 0; i < s->level_count; i++) rtt_buffer_free(&s->levels[i].nodes);
    free(s->levels);
    rtt_buffer *buffers[SP_SCRATCH_BUFFERS];
    scratch_buffers(s, buffers);
    for (size_t i = 0; i < SP_SCRATCH_BUFFERS; i++) rtt_buffer_free(buffers[i]);
    free(s);
}

bool sp_scratch_match(sp_scratch *s, sp_scratch *other)
{
    bool ok = s->level_count == other->level_count;
    for (uint32_t i = 0; ok && i < s->level_count; i++) ok = rtt_buffer_match(&s->levels[i].nodes, &other->levels[i].nodes);
    rtt_buffer *mine[SP_SCRATCH_BUFFERS], *theirs[SP_SCRATCH_BUFFERS];
    scratch_buffers(s, mine);
    scratch_buffers(other, theirs);
    for (size_t i = 0; ok && i < SP_SCRATCH_BUFFERS; i++) ok = rtt_buffer_match(mine[i], theirs[i]);
    return ok;
}

bool sp_scratch_failed(const sp_scratch *s) { return s->failed; }

void sp_scratch_begin_frame(sp_scratch *s)
{
    memset(&s->stats, 0, sizeof s->stats);
}

const sp_stats *sp_scratch_stats(const sp_scratch *s) { return &s->stats; }

int32_t sp_level_push(sp_scratch *s, uint32_t level, const rtt_ray *ray, uint32_t pixel)
{
    sp_level *l = &s->levels[level];
    if (!SP_RESERVE(s, levels[level].nodes, (size_t)l->count + 1, sp_node)) return -1;
    sp_node *n = &sp_level_nodes(s, level)[l->count];
    n->ray = *ray;
    n->pixel = pixel;
    n->reflected = n->refracted = -1;
    n->wr = n->wt = 0.0f;
    return (int32_t)l->count++;
}

bool sp_ensure_packets(sp_scratch *s, uint32_t packets)
{
    return SP_RESERVE(s, packets, packets, ray_packet4) && SP_RESERVE(s, hits, packets, hit_packet4) &&
           SP_RESERVE(s, occluded, packets, uint8_t);
}

/* With --accel bvh: the packets' rays, 64 at a time, through the BVH kernel
 * (it takes any rays, so one row serves primary, shadow and secondary
 * rays); answers back into the packets' hit and mask layout. */
#define SP_BVH_CHUNK_PACKETS 16u
static void trace_bvh(const sp_tracer *tr, const kd_query *q)
{
    rtt_ray rays[4 * SP_BVH_CHUNK_PACKETS];
    rtt_hit hits[4 * SP_BVH_CHUNK_PACKETS];
    uint8_t occluded[4 * SP_BVH_CHUNK_PACKETS];
    for (uint32_t first = 0; first < q->packet_count; first += SP_BVH_CHUNK_PACKETS) {
        const uint32_t packets = q->packet_count - first < SP_BVH_CHUNK_PACKETS ? q->packet_count - first
                                                                                 : SP_BVH_CHUNK_PACKETS;
        for (uint32_t p = 0; p < packets; p++) {
            const ray_packet4 *r = &q->packets[first + p];
            _Alignas(16) float org[3][4], dir[3][4], tnear[4], tfar[4];
            for (int a = 0; a < 3; a++) _mm_store_ps(org[a], r->org[a]), _mm_store_ps(dir[a], r->dir[a]);
            _mm_store_ps(tnear, r->tnear), _mm_store_ps(tfar, r->tfar);
            for (uint32_t l = 0; l < 4; l++)
                rays[4 * p + l] = (rtt_ray){{org[0][l], org[1][l], org[2][l]}, {dir[0][l], dir[1][l], dir[2][l]},
                                            tnear[l], tfar[l]};
        }
        bvh_counters counters = {0};
        tr->bvh_kernel->trace(tr->bvh, &(bvh_query){.rays = rays, .count = 4u * packets,
                                                    .hits = q->hits ? hits : NULL,
                                                    .occluded = q->hits ? NULL : occluded,
                                                    .counters = q->counters ? &counters : NULL});
        if (q->counters) {
            q->counters->packets += packets;
            q->counters->steps += counters.aabb_tests;
            q->counters->isects += counters.isect_tests;
        }
        for (uint32_t p = 0; p < packets; p++) {
            if (q->hits) {
                const rtt_hit *h = &hits[4 * p];
                hit_packet4 *out = &q->hits[first + p];
                out->t = _mm_setr_ps(h[0].t, h[1].t, h[2].t, h[3].t);
                out->u = _mm_setr_ps(h[0].u, h[1].u, h[2].u, h[3].u);
                out->v = _mm_setr_ps(h[0].v, h[1].v, h[2].v, h[3].v);
                out->prim = _mm_setr_epi32((int)h[0].prim, (int)h[1].prim, (int)h[2].prim, (int)h[3].prim);
            } else {
                const uint8_t *o = &occluded[4 * p];
                q->occluded[first + p] = (uint8_t)(o[0] | o[1] << 1 | o[2] << 2 | o[3] << 3);
            }
        }
    }
}

/* A kernel over packet_count packets, cut into the blocks it reads. */
static void trace_blocks(const sp_tracer *tr, const kd_kernel *kernel, kd_query q)
{
    if (tr->bvh) {
        trace_bvh(tr, &q);
        return;
    }
    const uint32_t total = q.packet_count, block = kernel->block == KD_BLOCK_TILE ? tr->block_packets : total;
    const ray_packet4 *packets = q.packets;
    hit_packet4 *hits = q.hits;
    uint8_t *occluded = q.occluded;
    for (uint32_t first = 0; first < total; first += block) {
        q.packets = packets + first;
        q.packet_count = total - first < block ? total - first : block;
        q.hits = hits ? hits + first : NULL;
        q.occluded = occluded ? occluded + first : NULL;
        kernel->trace(tr->tree, &q);
    }
}

void sp_trace_packets(const sp_tracer *tr, const kd_kernel *kernel, const ray_packet4 *packets, hit_packet4 *hits,
                      uint32_t packet_count, kd_counters *counters, uint64_t *isect_ns)
{
    for (uint32_t p = 0; p < packet_count; p++) hit_packet4_clear(&hits[p]);
    trace_blocks(tr, kernel,
                 (kd_query){.packets = packets, .packet_count = packet_count, .hits = hits,
                            .leaf_culling = tr->leaf_culling, .counters = counters, .isect_ns = isect_ns});
}

void sp_trace_packets_occluded(const sp_tracer *tr, const kd_kernel *kernel, const ray_packet4 *packets,
                               uint8_t *occluded, uint32_t packet_count)
{
    trace_blocks(tr, kernel,
                 (kd_query){.packets = packets, .packet_count = packet_count, .occluded = occluded,
                            .leaf_culling = tr->leaf_culling});
}

void sp_store_hits(sp_scratch *s, uint32_t level, const uint8_t *lanes, uint32_t packet_count)
{
    const hit_packet4 *hits = SP_ARRAY(s->hits, hit_packet4);
    sp_node *nodes = sp_level_nodes(s, level);
    const uint32_t count = s->levels[level].count;
    for (uint32_t p = 0, node = 0; p < packet_count; p++) {
        uint32_t n = lanes ? lanes[p] : (count - node < 4 ? count - node : 4);
        rtt_hit out[4];
        hit_packet4_store(&hits[p], out, n);
        for (uint32_t l = 0; l < n; l++) nodes[node + l].hit = out[l];
        node += n;
    }
}

void sp_tile_begin(sp_scratch *s, uint32_t packets)
{
    s->levels[0].count = 0;
    s->primary_packets = 0;
    if (!s->failed && sp_ensure_packets(s, packets)) SP_RESERVE(s, primary_lanes, packets, uint8_t);
}

void sp_primary_push(sp_scratch *s, const rtt_ray *rays, const uint32_t *pixels, uint32_t count)
{
    if (s->failed) return;
    const uint32_t p = s->primary_packets;
    if (!sp_ensure_packets(s, p + 1) || !SP_RESERVE(s, primary_lanes, (size_t)p + 1, uint8_t)) return;
    for (uint32_t l = 0; l < count; l++)
        if (sp_level_push(s, 0, &rays[l], pixels[l]) < 0) return;
    ray_packet4_load(&SP_ARRAY(s->packets, ray_packet4)[p], rays, count);
    SP_ARRAY(s->primary_lanes, uint8_t)[p] = (uint8_t)count;
    s->primary_packets = p + 1;
}

void sp_primary_trace(const sp_tracer *tr, sp_scratch *s)
{
    if (s->failed) return;
    uint64_t t0 = s->timing ? rtt_clock_ns() : 0, isect_ns = 0;
    sp_trace_packets(tr, tr->kernel, SP_ARRAY(s->packets, ray_packet4), SP_ARRAY(s->hits, hit_packet4),
                     s->primary_packets, s->timing ? &s->stats.primary : NULL, s->timing ? &isect_ns : NULL);
    if (s->timing) {
        uint64_t total = rtt_clock_ns() - t0;
        s->stats.ns_primary_intersection += isect_ns;
        s->stats.ns_primary_traversal += total > isect_ns ? total - isect_ns : 0;
    }
    sp_store_hits(s, 0, SP_ARRAY(s->primary_lanes, uint8_t), s->primary_packets);
    s->stats.primary_rays += s->levels[0].count;
}

void sp_primary_push_hit(sp_scratch *s, const rtt_ray *ray, const rtt_hit *hit, uint32_t pixel)
{
    if (s->failed) return;
    int32_t i = sp_level_push(s, 0, ray, pixel);
    if (i >= 0) sp_level_nodes(s, 0)[i].hit = *hit;
}

void sp_primary_hits_done(sp_scratch *s, uint64_t ns)
{
    if (s->failed) return;
    s->stats.primary_rays += s->levels[0].count;
    if (s->timing) s->stats.ns_primary_traversal += ns;
}

bool sp_tile_counting(const sp_scratch *s) { return !s->failed && s->timing; }

void sp_primary_hits_counted(sp_scratch *s, uint64_t packets, uint64_t steps, uint64_t isects)
{
    if (!sp_tile_counting(s)) return;
    s->stats.primary.packets += packets;
    s->stats.primary.steps += steps;
    s->stats.primary.isects += isects;
}

uint32_t sp_tile_pixel_count(const sp_scratch *s) { return s->failed ? 0 : s->levels[0].count; }

const sp_node *sp_tile_pixel(const sp_scratch *s, uint32_t i) { return &sp_level_nodes(s, 0)[i]; }

/* A growable array: the one place scratch memory grows.  Capacity doubles
 * (at least `count` elements), so pushes are amortised O(1); contents are
 * kept on growth.  Growth past SIZE_MAX / element bytes fails cleanly. */
#ifndef RTT_ENGINE_BUFFER_H
#define RTT_ENGINE_BUFFER_H

#include <stdbool.h>
#include <stddef.h>

typedef struct rtt_buffer {
    void *data;
    size_t capacity;      /* elements */
    size_t element, align; /* of the last growth (rtt_buffer_match copies them) */
} rtt_buffer;

/* Room for `count` elements of `element` bytes, aligned to `align` (a power
 * of two, at most 64; 0 → malloc's).  False (buffer unchanged) when out of
 * memory. */
bool rtt_buffer_grow(rtt_buffer *b, size_t count, size_t element, size_t align);
/* Inline, so the common case (room already there) costs one compare where
 * renderers reserve per ray; growing goes out of line. */
static inline bool rtt_buffer_reserve(rtt_buffer *b, size_t count, size_t element, size_t align)
{
    return count <= b->capacity || rtt_buffer_grow(b, count, element, align);
}
void rtt_buffer_free(rtt_buffer *b);
/* Grows b to at least other's capacity (of other's element type): scratch
 * kept between frames is made as large as the largest of its kind, so the
 * next frame grows none.  False when out of memory. */
bool rtt_buffer_match(rtt_buffer *b, const rtt_buffer *other);

/* Typed use: RTT_BUFFER_RESERVE(&s->rays, n, rtt_ray) */
#define RTT_BUFFER_RESERVE(b, count, type) rtt_buffer_reserve((b), (count), sizeof(type), _Alignof(type))

#endif

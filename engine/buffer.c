/* Growable scratch arrays (buffer.h). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "engine/buffer.h"

bool rtt_buffer_grow(rtt_buffer *b, size_t count, size_t element, size_t align)
{
    if (count <= b->capacity) return true;
    size_t capacity = b->capacity ? b->capacity : 16;
    while (capacity < count) capacity = capacity > SIZE_MAX / 2 ? count : 2 * capacity;
    if (element == 0 || capacity > SIZE_MAX / element) return false;
    size_t bytes = capacity * element;
    void *data;
    if (align > _Alignof(max_align_t)) {
        bytes = (bytes + align - 1) & ~(align - 1);
        data = aligned_alloc(align, bytes);
        if (data && b->data) memcpy(data, b->data, b->capacity * element);
        if (data) free(b->data);
    } else {
        data = realloc(b->data, bytes);
    }
    if (!data) return false;
    b->data = data;
    b->capacity = capacity;
    b->element = element;
    b->align = align;
    return true;
}

bool rtt_buffer_match(rtt_buffer *b, const rtt_buffer *other)
{
    if (other->capacity <= b->capacity) return true;
    return rtt_buffer_grow(b, other->capacity, other->element, other->align);
}

void rtt_buffer_free(rtt_buffer *b)
{
    free(b->data);
    b->data = NULL;
    b->capacity = 0;
}

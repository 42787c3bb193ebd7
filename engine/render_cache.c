/* rtt_render_cache (render.h, engine/render_cache.h): one renderer's data at a
 * time, released when the cache goes or another renderer takes it. */
#include <stdlib.h>

#include "engine/render_cache.h"

struct rtt_render_cache {
    const void *owner;
    void *data;
    void (*release)(void *data);
};

rtt_render_cache *rtt_render_cache_create(void)
{
    return calloc(1, sizeof(rtt_render_cache));
}

static void release(rtt_render_cache *cache)
{
    if (cache->data && cache->release) cache->release(cache->data);
    cache->owner = cache->data = NULL;
    cache->release = NULL;
}

void rtt_render_cache_destroy(rtt_render_cache *cache)
{
    if (!cache) return;
    release(cache);
    free(cache);
}

void *rtt_render_cache_take(rtt_render_cache *cache, const void *owner)
{
    if (!cache) return NULL;
    if (cache->owner != owner) release(cache);
    void *data = cache->data;
    cache->owner = cache->data = NULL;
    cache->release = NULL;
    return data;
}

void rtt_render_cache_keep(rtt_render_cache *cache, const void *owner, void *data, void (*release_fn)(void *data))
{
    if (!cache) {
        if (data && release_fn) release_fn(data);
        return;
    }
    release(cache);
    cache->owner = owner;
    cache->data = data;
    cache->release = release_fn;
}

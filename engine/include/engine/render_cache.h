/* The renderer's side of rtt_render_cache (include/rtt/render.h): a renderer
 * keeps its per-thread working memory in the cache a caller passes, keyed by
 * the renderer, and finds it again on the next frame. */
#ifndef RTT_ENGINE_RENDER_CACHE_H
#define RTT_ENGINE_RENDER_CACHE_H

#include "rtt/render.h"

/* The data `owner` stored, or NULL when the cache is empty or holds another
 * renderer's (which it then releases). */
void *rtt_render_cache_take(rtt_render_cache *cache, const void *owner);
/* Stores `data` for `owner`, releasing what the cache held; `release` frees
 * it when the cache is destroyed or handed to another renderer. */
void rtt_render_cache_keep(rtt_render_cache *cache, const void *owner, void *data, void (*release)(void *data));

#endif

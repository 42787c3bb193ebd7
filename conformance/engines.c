/* Every engine this build has, by name: the built-in ones and, in builds
 * with Embree, the Embree engine, registered by this layer because it is the
 * one that links Embree. */
#include "conform.h"
#include "embree_engine.h"
#include "rtt/rtt.h"

bool rtt_conform_register_engines(rtt_error *err)
{
    if (!rtt_builtin_engines_register(err)) return false;
#ifdef RTT_HAVE_EMBREE
    if (!rtt_engine_register(&rtt_embree_engine_class, err)) return false;
#endif
    return true;
}

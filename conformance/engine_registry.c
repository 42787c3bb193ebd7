/* rtt_engine_create: the one place that maps an engine's name to its
 * constructor, because only this layer may see all three engines. */
#include <string.h>

#include "rtt/engine.h"
#include "rtt/optimized.h"
#include "rtt/reference.h"
#include "embree_engine.h"

rtt_engine *rtt_engine_create(const char *name, const rtt_scene *scene, const rtt_engine_options *opt,
                              rtt_error *err)
{
    rtt_engine_options defaults;
    if (!opt) {
        rtt_engine_options_default(&defaults);
        opt = &defaults;
    }
    if (strcmp(name, "reference") == 0) return rtt_reference_engine_create(scene, opt, err);
    if (strcmp(name, "optimized") == 0) return rtt_optimized_engine_create(scene, opt, err);
    if (strcmp(name, "embree") == 0) {
#ifdef RTT_HAVE_EMBREE
        return rtt_embree_engine_create(scene, opt, err);
#else
        rtt_error_set(err, "engine \"embree\": this build has no Embree (configure with -DRTT_EMBREE=ON)");
        return NULL;
#endif
    }
    rtt_error_set(err, "unknown engine \"%s\": expected reference, optimized or embree", name);
    return NULL;
}

/* The built-in engines by name: the one place that knows both engine
 * libraries, so neither engine/ (below them) nor cli/ (a driver) must. */
#include "rtt/rtt.h"

bool rtt_builtin_engines_register(rtt_error *err)
{
    return rtt_engine_register(&rtt_reference_engine_class, err) &&
           rtt_engine_register(&rtt_optimized_engine_class, err);
}

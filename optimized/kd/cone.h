/* Cone proxies (Thesis 4.1.7, Listing 4.4): built in cone.c, declared with
 * the other proxies in frustum.h (kd_cone, kd_cone4, kd_cone_build). */
#ifndef RTT_OPTIMIZED_CONE_H
#define RTT_OPTIMIZED_CONE_H

#include "frustum.h"

#endif

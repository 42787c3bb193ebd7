/* dist_launched (launcher.c): in both builds, with MPI and without. */
#ifndef RTT_DIST_LAUNCHER_H
#define RTT_DIST_LAUNCHER_H

#include <stdbool.h>
#include <stdint.h>

/* True when an MPI launcher started this process; *processes is the job's
 * size when the launcher says (0 when it does not). */
bool dist_launched(uint32_t *processes);

#endif

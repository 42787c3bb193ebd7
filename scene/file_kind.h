/* The extension of a path, for the places in scene/ that look at more than
 * rtt_file_kind_of tells (which mesh format a file claims to be).  The kind
 * itself, rtt_file_kind_of, is public: include/rtt/scene.h. */
#ifndef RTT_SCENE_FILE_KIND_H
#define RTT_SCENE_FILE_KIND_H

#include "rtt/scene.h"

/* What follows the last dot of the path's last component ("obj" for
 * "meshes/bunny.obj"), or "" when that component has no dot: a dot in a
 * folder name ("a.b/scene") is not an extension.  Points into path. */
const char *rtt_file_extension(const char *path);

#endif

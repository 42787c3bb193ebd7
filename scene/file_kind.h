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

/* `name` as seen from the file at `path`: itself when absolute or when path
 * has no directory, else "DIR/name" with path's directory (how a scene file
 * names its meshes and a glTF its buffers).  Truncated to `size`. */
void rtt_path_beside(const char *path, const char *name, char *out, size_t size);

#endif

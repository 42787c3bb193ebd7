/* What a file is, decided by its extension alone (case-insensitive): the one
 * place in scene/ that maps extensions to readers, so that rtt_scene_load,
 * the JSON scene file's "file" references and the command line (which
 * refuses options a kind of file does not use) always agree. */
#include <assimp/cimport.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "file_kind.h"

const char *rtt_file_extension(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    return dot && (!slash || dot > slash) ? dot + 1 : "";
}

rtt_file_kind rtt_file_kind_of(const char *path)
{
    static const struct { const char *extension; rtt_file_kind kind; } kinds[] = {
        {"json", RTT_FILE_SCENE_JSON}, {"kdt", RTT_FILE_KDT}, {"bsp", RTT_FILE_Q3BSP}};
    const char *ext = rtt_file_extension(path);
    if (!ext[0]) return RTT_FILE_UNKNOWN;
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        if (strcasecmp(ext, kinds[i].extension) == 0) return kinds[i].kind;
    return aiIsExtensionSupported(ext - 1) ? RTT_FILE_MESH : RTT_FILE_UNKNOWN; /* Assimp wants the dot */
}

void rtt_path_beside(const char *path, const char *name, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (name[0] == '/' || !slash)
        snprintf(out, size, "%s", name);
    else
        snprintf(out, size, "%.*s/%s", (int)(slash - path), path, name);
}

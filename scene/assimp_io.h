/* The file system Assimp sees (assimp_io.c): every file Assimp opens — the
 * mesh itself, an OBJ's MTL libraries, a glTF's buffers — goes through
 * rtt_file_open_regular, so a FIFO or a device is never opened blocking.
 * Assimp treats a file it cannot open as missing (an MTL library it only
 * warns about), so the first refusal is kept here and the importer turns it
 * into its error after the import. */
#ifndef RTT_SCENE_ASSIMP_IO_H
#define RTT_SCENE_ASSIMP_IO_H

#include <assimp/cfileio.h>
#include <stdbool.h>

#include "rtt/error.h"

typedef struct rtt_assimp_io {
    struct aiFileIO io;  /* hand &io to aiImportFileEx */
    bool refused;        /* a file existed but was not a regular file */
    rtt_error error;     /* the first such refusal, one line */
} rtt_assimp_io;

void rtt_assimp_io_init(rtt_assimp_io *io);

#endif

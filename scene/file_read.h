/* Reading a whole file into memory, for every reader in scene/ that wants
 * all of a file at once (the JSON scene file, the glTF signature check, the
 * baked tree).  One reader means one set of failure messages, all one line:
 * "file: cannot open: reason", "file: cannot read: reason",
 * "file: larger than 1 GiB", "file: out of memory". */
#ifndef RTT_SCENE_FILE_READ_H
#define RTT_SCENE_FILE_READ_H

#include <stddef.h>

#include "rtt/files.h"

/* Text files (scene files, glTF) are refused past this: they are edited by
 * hand or exported, and a larger one is a mistake that would only exhaust
 * memory. */
#define RTT_FILE_TEXT_MAX ((size_t)1 << 30)

#endif

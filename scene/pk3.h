/* Quake III's .pk3 archives (zip files) read with zlib (pk3.c): internal
 * to scene/.  Only what pk3 archives use: stored and deflated members, no
 * encryption, no zip64, one disk. */
#ifndef RTT_SCENE_PK3_H
#define RTT_SCENE_PK3_H

#include <stdint.h>
#include <stdio.h>

#include "rtt/error.h"

#define RTT_PK3_MAX_ENTRIES (1u << 20)
#define RTT_PK3_MEMBER_MAX (64u << 20) /* a member larger than this is refused */

typedef struct rtt_pk3_entry {
    uint32_t name;                     /* offset in rtt_pk3.names */
    uint16_t method;                   /* 0 stored, 8 deflated */
    uint32_t crc, compressed, size, local_offset;
} rtt_pk3_entry;

typedef struct rtt_pk3 {
    char path[512];                    /* for messages */
    FILE *file;
    long file_size;
    rtt_pk3_entry *entries;
    uint32_t count;
    char *names;                       /* NUL-terminated member names */
} rtt_pk3;

/* Reads the central directory of the archive in `file` (kept open and
 * owned by the archive from then on: rtt_pk3_close closes it, also on
 * failure).  Every count, offset and length is checked against the file. */
bool rtt_pk3_open_stream(rtt_pk3 *archive, FILE *file, const char *path, rtt_error *err);
bool rtt_pk3_open(rtt_pk3 *archive, const char *path, rtt_error *err);
void rtt_pk3_close(rtt_pk3 *archive);

/* The member named `name` (case-insensitive, '/' separators, as Quake
 * looks names up), or -1. */
int64_t rtt_pk3_find(const rtt_pk3 *archive, const char *name);
static inline const char *rtt_pk3_name(const rtt_pk3 *archive, uint32_t i)
{
    return archive->names + archive->entries[i].name;
}

/* Member i uncompressed into a new buffer (NUL appended, not counted in
 * *size), its CRC checked; NULL with err set on failure. */
uint8_t *rtt_pk3_read(const rtt_pk3 *archive, uint32_t i, size_t *size, rtt_error *err);

#endif

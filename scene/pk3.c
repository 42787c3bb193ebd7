/* Quake III's .pk3 archives: zip files (PKWARE APPNOTE 6.3, sections 4.3.7
 * local file header, 4.3.12 central directory header, 4.3.16 end of
 * central directory), inflated with zlib.
 *
 * The end-of-central-directory record is looked for in the last 64 KiB +
 * 22 bytes (its comment is at most 65535 bytes); the central directory it
 * points to must lie before it, each header inside the directory, each
 * member's data inside the file.  A member is read in one piece: stored
 * (method 0) or raw deflate (method 8), at most RTT_PK3_MEMBER_MAX bytes
 * uncompressed, its CRC-32 checked.  Encrypted members, zip64 and split
 * archives are refused; members with other methods can be listed but not
 * read. */
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

#include "pk3.h"
#include "rtt/files.h"

#define EOCD_SIZE 22u
#define EOCD_SIGNATURE 0x06054b50u
#define CENTRAL_SIZE 46u
#define CENTRAL_SIGNATURE 0x02014b50u
#define LOCAL_SIZE 30u
#define LOCAL_SIGNATURE 0x04034b50u

static uint16_t le16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static bool read_at(const rtt_pk3 *a, long offset, void *out, size_t size, rtt_error *err)
{
    if (offset < 0 || fseek(a->file, offset, SEEK_SET) != 0 || fread(out, 1, size, a->file) != size)
        return rtt_error_set(err, "%s: read error at byte %ld", a->path, offset);
    return true;
}

/* The end-of-central-directory record: the last signature in the tail
 * whose comment length reaches exactly to the end of the file. */
static bool find_eocd(const rtt_pk3 *a, uint8_t eocd[EOCD_SIZE], long *at, rtt_error *err)
{
    if (a->file_size < (long)EOCD_SIZE)
        return rtt_error_set(err, "%s: not a pk3 (zip) archive: %ld bytes is too small", a->path, a->file_size);
    long tail = a->file_size < 65535L + EOCD_SIZE ? a->file_size : 65535L + EOCD_SIZE;
    uint8_t *buffer = malloc((size_t)tail);
    if (!buffer) return rtt_error_set(err, "%s: out of memory", a->path);
    if (!read_at(a, a->file_size - tail, buffer, (size_t)tail, err)) {
        free(buffer);
        return false;
    }
    for (long i = tail - (long)EOCD_SIZE; i >= 0; i--) {
        if (le32(buffer + i) != EOCD_SIGNATURE) continue;
        if (i + (long)EOCD_SIZE + le16(buffer + i + 20) != tail) continue;
        memcpy(eocd, buffer + i, EOCD_SIZE);
        *at = a->file_size - tail + i;
        free(buffer);
        return true;
    }
    free(buffer);
    return rtt_error_set(err, "%s: not a pk3 (zip) archive: no end of central directory record", a->path);
}

static bool parse_directory(rtt_pk3 *a, const uint8_t *dir, uint32_t size, uint32_t count, long directory_at,
                            rtt_error *err)
{
    a->entries = malloc((size_t)count * sizeof *a->entries + 1);
    a->names = malloc((size_t)size + count + 1); /* names are inside the directory: its size bounds them */
    if (!a->entries || !a->names) return rtt_error_set(err, "%s: out of memory for %u members", a->path, count);
    uint32_t at = 0, names = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (size - at < CENTRAL_SIZE || le32(dir + at) != CENTRAL_SIGNATURE)
            return rtt_error_set(err, "%s: central directory entry %u at byte %ld is damaged", a->path, i,
                                 directory_at + (long)at);
        const uint8_t *h = dir + at;
        uint32_t name_length = le16(h + 28), extra = le16(h + 30), comment = le16(h + 32);
        uint64_t end = (uint64_t)at + CENTRAL_SIZE + name_length + extra + comment;
        if (end > size)
            return rtt_error_set(err, "%s: central directory entry %u runs past the directory", a->path, i);
        rtt_pk3_entry *e = &a->entries[i];
        e->method = le16(h + 10);
        e->crc = le32(h + 16);
        e->compressed = le32(h + 20);
        e->size = le32(h + 24);
        e->local_offset = le32(h + 42);
        if (le16(h + 8) & 1u) e->method = 0xffff; /* encrypted: listed, never read */
        if (e->compressed == UINT32_MAX || e->size == UINT32_MAX || e->local_offset == UINT32_MAX)
            return rtt_error_set(err, "%s: member %u is a zip64 entry (not supported)", a->path, i);
        e->name = names;
        memcpy(a->names + names, h + CENTRAL_SIZE, name_length);
        for (uint32_t k = 0; k < name_length; k++) {
            char *c = &a->names[names + k];
            if (*c == '\\') *c = '/';
            if (*c == '\0') *c = '?'; /* a NUL inside a name would cut it */
        }
        names += name_length;
        a->names[names++] = '\0';
        at = (uint32_t)end;
    }
    a->count = count;
    return true;
}

bool rtt_pk3_open_stream(rtt_pk3 *a, FILE *file, const char *path, rtt_error *err)
{
    memset(a, 0, sizeof *a);
    snprintf(a->path, sizeof a->path, "%s", path);
    a->file = file;
    if (!file) return rtt_error_set(err, "%s: cannot open the archive", path);
    if (fseek(file, 0, SEEK_END) != 0 || (a->file_size = ftell(file)) < 0) {
        rtt_pk3_close(a);
        return rtt_error_set(err, "%s: cannot determine the file size", path);
    }
    uint8_t eocd[EOCD_SIZE] = {0};
    long eocd_at = 0;
    bool ok = find_eocd(a, eocd, &eocd_at, err);
    uint32_t count = 0, size = 0, offset = 0;
    if (ok) {
        count = le16(eocd + 10);
        size = le32(eocd + 12);
        offset = le32(eocd + 16);
        if (le16(eocd + 4) != 0 || le16(eocd + 6) != 0 || le16(eocd + 8) != count)
            ok = rtt_error_set(err, "%s: a split (multi-disk) archive is not supported", path);
        else if (count == 0xffff || size == UINT32_MAX || offset == UINT32_MAX)
            ok = rtt_error_set(err, "%s: a zip64 archive is not supported", path);
        else if ((uint64_t)offset + size > (uint64_t)eocd_at)
            ok = rtt_error_set(err, "%s: the central directory (%u bytes at %u) overlaps its end record at %ld", path,
                               size, offset, eocd_at);
        else if ((uint64_t)count * CENTRAL_SIZE > size)
            ok = rtt_error_set(err, "%s: %u members do not fit a %u-byte central directory", path, count, size);
    }
    uint8_t *dir = NULL;
    if (ok) {
        dir = malloc((size_t)size + 1);
        ok = dir ? read_at(a, (long)offset, dir, size, err) : rtt_error_set(err, "%s: out of memory", path);
    }
    ok = ok && parse_directory(a, dir, size, count, (long)offset, err);
    free(dir);
    if (!ok) rtt_pk3_close(a);
    return ok;
}

bool rtt_pk3_open(rtt_pk3 *a, const char *path, rtt_error *err)
{
    FILE *file = rtt_file_open_regular(path, err);
    if (!file) {
        memset(a, 0, sizeof *a);
        return false;
    }
    return rtt_pk3_open_stream(a, file, path, err);
}

void rtt_pk3_close(rtt_pk3 *a)
{
    if (a->file) fclose(a->file);
    free(a->entries);
    free(a->names);
    a->file = NULL;
    a->entries = NULL;
    a->names = NULL;
    a->count = 0;
}

int64_t rtt_pk3_find(const rtt_pk3 *a, const char *name)
{
    for (uint32_t i = 0; i < a->count; i++)
        if (strcasecmp(rtt_pk3_name(a, i), name) == 0) return i;
    return -1;
}

static bool inflate_member(const rtt_pk3 *a, const char *name, const uint8_t *in, uint32_t in_size, uint8_t *out,
                           uint32_t out_size, rtt_error *err)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, -MAX_WBITS) != Z_OK) return rtt_error_set(err, "%s: %s: zlib failed to start", a->path, name);
    z.next_in = (Bytef *)(uintptr_t)in;
    z.avail_in = in_size;
    z.next_out = out;
    z.avail_out = out_size;
    int status = inflate(&z, Z_FINISH);
    uLong produced = z.total_out;
    inflateEnd(&z);
    if (status != Z_STREAM_END || produced != out_size)
        return rtt_error_set(err, "%s: %s: the deflated data is damaged (%s)", a->path, name,
                             status == Z_STREAM_END ? "wrong size" : z.msg ? z.msg : "truncated");
    return true;
}

uint8_t *rtt_pk3_read(const rtt_pk3 *a, uint32_t i, size_t *size, rtt_error *err)
{
    if (i >= a->count) {
        rtt_error_set(err, "%s: member %u does not exist", a->path, i);
        return NULL;
    }
    const rtt_pk3_entry *e = &a->entries[i];
    const char *name = rtt_pk3_name(a, i);
    if (e->method != 0 && e->method != 8) {
        rtt_error_set(err, "%s: %s: compression method %u is not supported (stored or deflated only)", a->path, name,
                      e->method);
        return NULL;
    }
    if (e->size > RTT_PK3_MEMBER_MAX || (e->method == 0 && e->compressed != e->size)) {
        rtt_error_set(err, "%s: %s: %u bytes (%u compressed) is too large or inconsistent", a->path, name, e->size,
                      e->compressed);
        return NULL;
    }
    uint8_t local[LOCAL_SIZE];
    if (!read_at(a, (long)e->local_offset, local, LOCAL_SIZE, err)) return NULL;
    uint64_t data = (uint64_t)e->local_offset + LOCAL_SIZE + le16(local + 26) + le16(local + 28);
    if (le32(local) != LOCAL_SIGNATURE || data + e->compressed > (uint64_t)a->file_size) {
        rtt_error_set(err, "%s: %s: the local header at byte %u is damaged or its data runs past the file", a->path,
                      name, e->local_offset);
        return NULL;
    }
    uint8_t *in = malloc((size_t)e->compressed + 1), *out = malloc((size_t)e->size + 1);
    bool ok = in && out ? read_at(a, (long)data, in, e->compressed, err)
                        : rtt_error_set(err, "%s: %s: out of memory", a->path, name);
    if (ok && e->method == 0) memcpy(out, in, e->size);
    if (ok && e->method == 8) ok = inflate_member(a, name, in, e->compressed, out, e->size, err);
    if (ok && (uint32_t)crc32(0L, out, e->size) != e->crc)
        ok = rtt_error_set(err, "%s: %s: CRC mismatch", a->path, name);
    free(in);
    if (!ok) {
        free(out);
        return NULL;
    }
    out[e->size] = 0;
    *size = e->size;
    return out;
}

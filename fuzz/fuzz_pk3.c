/* Fuzz target: the pk3 (zip) reader of scene/pk3.c.  The bytes are the
 * archive (through fmemopen, the same FILE path as a real file): every
 * count, offset and length of the end record, the central directory and
 * the local headers comes from them.  An accepted archive's members are
 * looked up by name and read (stored or inflated, CRC checked); a refusal
 * must be one line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_common.h"
#include "pk3.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0 || size > 1 << 20) return 0;
    FILE *file = fmemopen((void *)(uintptr_t)data, size, "rb");
    if (!file) return 0;
    rtt_pk3 archive;
    rtt_error err;
    if (!rtt_pk3_open_stream(&archive, file, "fuzz.pk3", &err)) {
        fuzz_check_error_line(&err);
        return 0;
    }
    for (uint32_t i = 0; i < archive.count && i < 64; i++) {
        if (rtt_pk3_find(&archive, rtt_pk3_name(&archive, i)) < 0) fuzz_fail("member %u is not found by its name", i);
        size_t n = 0;
        uint8_t *bytes = rtt_pk3_read(&archive, i, &n, &err);
        if (bytes) {
            if (n != archive.entries[i].size || bytes[n] != 0) fuzz_fail("member %u: %zu bytes read", i, n);
            free(bytes);
        } else {
            fuzz_check_error_line(&err);
        }
    }
    rtt_pk3_close(&archive);
    return 0;
}

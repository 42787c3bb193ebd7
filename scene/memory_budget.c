/* The memory budget of include/rtt/memory_budget.h. */
#include "rtt/memory_budget.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

uint64_t rtt_memory_budget_default(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    uint64_t budget = pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page : (uint64_t)1 << 32;
    static const int limits[] = {RLIMIT_AS, RLIMIT_DATA};
    for (size_t i = 0; i < sizeof limits / sizeof limits[0]; i++) {
        struct rlimit limit;
        if (getrlimit(limits[i], &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && (uint64_t)limit.rlim_cur < budget)
            budget = (uint64_t)limit.rlim_cur;
    }
    return budget;
}

/* What `triangles` more triangles and `bytes` more bytes bring `reserved`
 * to; false when that passes `budget` (0: the default). */
static bool fits(const char *source, uint64_t reserved, uint64_t reserved_triangles, uint64_t triangles,
                 uint64_t bytes, uint64_t budget, uint64_t *needed, rtt_error *err)
{
    const uint64_t limit = UINT64_C(1) << 62;
    if (triangles > limit / RTT_BYTES_PER_TRIANGLE) triangles = limit / RTT_BYTES_PER_TRIANGLE;
    if (bytes > limit) bytes = limit;
    *needed = reserved + triangles * RTT_BYTES_PER_TRIANGLE + bytes;
    if (!budget) budget = rtt_memory_budget_default();
    if (*needed <= budget) return true;
    char need[32], have[32];
    rtt_memory_size_format(*needed, need, sizeof need);
    rtt_memory_size_format(budget, have, sizeof have);
    return rtt_error_set(err, "%s: needs about %s for %llu triangles, over the memory budget of %s", source, need,
                         (unsigned long long)(reserved_triangles + triangles), have);
}

bool rtt_memory_budget_check(const char *source, uint64_t triangles, uint64_t bytes, uint64_t budget,
                             rtt_error *err)
{
    uint64_t needed;
    return fits(source, 0, 0, triangles, bytes, budget, &needed, err);
}

bool rtt_scene_budget_reserve(rtt_scene *scene, const char *source, uint64_t triangles, uint64_t bytes,
                              rtt_error *err)
{
    uint64_t needed;
    if (!fits(source, scene->memory_reserved, scene->memory_triangles, triangles, bytes, scene->memory_budget,
              &needed, err))
        return false;
    scene->memory_reserved = needed;
    scene->memory_triangles += triangles;
    return true;
}

static const struct { char letter; unsigned shift; const char *unit; } units[] = {
    {'T', 40, "TiB"}, {'G', 30, "GiB"}, {'M', 20, "MiB"}, {'K', 10, "KiB"}};

void rtt_memory_size_format(uint64_t bytes, char *out, size_t size)
{
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
        if (bytes >= UINT64_C(1) << units[i].shift) {
            snprintf(out, size, "%.1f %s", (double)bytes / (double)(UINT64_C(1) << units[i].shift), units[i].unit);
            return;
        }
    snprintf(out, size, "%llu bytes", (unsigned long long)bytes);
}

bool rtt_memory_size_parse(const char *text, uint64_t *out)
{
    if (!text || *text < '0' || *text > '9') return false;
    char *end = NULL;
    double value = strtod(text, &end);
    unsigned shift = 0;
    for (size_t i = 0; *end && i < sizeof units / sizeof units[0]; i++)
        if (*end == units[i].letter || *end == units[i].letter + ('a' - 'A')) {
            shift = units[i].shift;
            end++;
            if (strcmp(end, "iB") == 0 || strcmp(end, "B") == 0) end += strlen(end);
            break;
        }
    if (*end == 'B' && end[1] == '\0' && shift == 0) end++;
    if (*end != '\0' || !(value > 0)) return false;
    double bytes = value * (double)(UINT64_C(1) << shift);
    if (bytes < 1 || bytes > (double)(UINT64_C(1) << 60)) return false;
    *out = (uint64_t)bytes;
    return true;
}

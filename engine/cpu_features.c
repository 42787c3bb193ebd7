/* CPU feature detection and the instruction-set choice.  Every kernel is
 * compiled for SSE4.1, AVX2 and AVX-512 (per-file flags, optimized/); which
 * one runs is decided here, at run time.  __builtin_cpu_supports checks the
 * OS's XSAVE state too (libgcc reads XCR0), so a CPU whose OS does not save
 * the wide registers reports them unsupported. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rtt/engine.h"

static const char *const isa_names[RTT_ISA_COUNT] = {"auto", "sse4", "avx2", "avx512"};

const char *rtt_isa_name(rtt_isa isa)
{
    return (unsigned)isa < RTT_ISA_COUNT ? isa_names[isa] : "unknown";
}

bool rtt_isa_parse(const char *name, rtt_isa *out)
{
    for (int i = 0; i < RTT_ISA_COUNT; i++)
        if (name && strcmp(name, isa_names[i]) == 0) {
            *out = (rtt_isa)i;
            return true;
        }
    return false;
}

bool rtt_isa_supported(rtt_isa isa)
{
    __builtin_cpu_init();
    switch (isa) {
    case RTT_ISA_AUTO: return true;
    case RTT_ISA_SSE4: return __builtin_cpu_supports("sse4.1");
    case RTT_ISA_AVX2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case RTT_ISA_AVX512:
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
    default: return false;
    }
}

rtt_isa rtt_isa_resolve(rtt_isa requested)
{
    if (requested != RTT_ISA_AUTO) return requested;
    rtt_isa from_env;
    const char *env = getenv("RTT_ISA");
    if (env && rtt_isa_parse(env, &from_env) && from_env != RTT_ISA_AUTO && rtt_isa_supported(from_env))
        return from_env;
    for (int isa = RTT_ISA_COUNT - 1; isa > RTT_ISA_AUTO; isa--)
        if (rtt_isa_supported((rtt_isa)isa)) return (rtt_isa)isa;
    return RTT_ISA_SSE4;
}

size_t rtt_cpu_l2_bytes(void)
{
#ifdef _SC_LEVEL2_CACHE_SIZE
    const long bytes = sysconf(_SC_LEVEL2_CACHE_SIZE); /* glibc: from cpuid; 0 or -1 when unknown */
    return bytes > 0 ? (size_t)bytes : 0;
#else
    return 0;
#endif
}

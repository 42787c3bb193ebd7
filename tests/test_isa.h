/* The instruction sets the tests run every kernel copy at: SSE4 through
 * AVX-512 (rtt_isa), those this CPU does not run skipped with a note. */
#ifndef RTT_TEST_ISA_H
#define RTT_TEST_ISA_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "rtt/engine.h"

#define TEST_ISA_FIRST RTT_ISA_SSE4

/* 1 when the CPU runs `isa`; else prints why it is skipped. */
static inline int isa_runs(rtt_isa isa)
{
    if (rtt_isa_supported(isa)) return 1;
    print_message("note: %s not tested: this CPU does not run it\n", rtt_isa_name(isa));
    return 0;
}

static inline rtt_isa isa_next(rtt_isa isa) { return (rtt_isa)(isa + 1); }

#endif

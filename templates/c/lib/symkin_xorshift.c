/* symkin C library: xorshift64 (see symkin_xorshift.h). */
#ifndef SYMKIN_AMALGAMATION
#include "symkin_xorshift.h"
#endif

SYMKIN_API uint64_t symkin_xorshift64(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    *state = x;
    return x;
}

SYMKIN_API real_t symkin_uniform(uint64_t *state)
{
    return (real_t)(symkin_xorshift64(state) >> 11) * REAL(1.1102230246251565e-16);
}

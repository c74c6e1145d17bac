/* symkin C library: Marsaglia's xorshift64 generator (shifts 13, 7, 17; "Xorshift RNGs",
 * J. Stat. Software 8(14), 2003). The state must not be 0 (it would stay 0). */
#ifndef SYMKIN_XORSHIFT_H
#define SYMKIN_XORSHIFT_H

#include <stdint.h>

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#endif

/* Advances *state by one step and returns the new state. */
SYMKIN_API uint64_t symkin_xorshift64(uint64_t *state);

/* A uniform number in [0, 1]: the top 53 bits of the next state times 2^-53 (as the NumPy
 * solver symkin.solve.ik.batch draws it). */
SYMKIN_API real_t symkin_uniform(uint64_t *state);

#endif /* SYMKIN_XORSHIFT_H */

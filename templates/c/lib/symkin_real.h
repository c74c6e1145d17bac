/* symkin C library: the real type, chosen when compiling (SYMKIN_FLOAT: float, else double).
 *
 * The library sources (symkin_*.h, symkin_*.c) compile on their own with this header; a
 * generated file instead pastes symkin_real_float.h or symkin_real_double.h and the sources it
 * needs into itself, defines SYMKIN_AMALGAMATION (the sources then skip their #includes of
 * each other) and SYMKIN_API as static (each generated file keeps its own copy, so several
 * robots, in either precision, link into one program).
 */
#ifndef SYMKIN_REAL_H
#define SYMKIN_REAL_H

#ifdef SYMKIN_FLOAT
#include "symkin_real_float.h"
#else
#include "symkin_real_double.h"
#endif

/* Linkage of the library functions. */
#ifndef SYMKIN_API
#define SYMKIN_API
#endif

#endif /* SYMKIN_REAL_H */

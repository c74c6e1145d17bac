/* symkin C library: Cholesky factorisation and solve of a symmetric positive definite system. */
#ifndef SYMKIN_CHOLESKY_H
#define SYMKIN_CHOLESKY_H

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#endif

/* A = L L^T in place: a is n x n row-major, of which the lower triangle (diagonal included) is
 * read and overwritten by L; the upper triangle is neither read nor written. Returns 1, or 0
 * as soon as a pivot is not positive (A is not numerically positive definite, or holds NaN);
 * a is then partly overwritten. */
SYMKIN_API int symkin_cholesky_factor(real_t *a, int n);

/* x = (L L^T)^-1 x in place by forward (L y = x) and back (L^T x = y) substitution, with L the
 * lower triangle of the n x n row-major l from symkin_cholesky_factor. */
SYMKIN_API void symkin_cholesky_solve(const real_t *l, int n, real_t *x);

#endif /* SYMKIN_CHOLESKY_H */

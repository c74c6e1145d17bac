/* symkin C library: many right-hand sides solved with one Cholesky factor. */
#ifndef SYMKIN_CHOLESKY_COLUMNS_H
#define SYMKIN_CHOLESKY_COLUMNS_H

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#endif

/* B = (L L^T)^-1 B in place for an n x m row-major b (m right-hand sides), with L the lower
 * triangle of the n x n row-major l from symkin_cholesky_factor. Row operations on all m
 * columns at once: the columns are independent, so the arithmetic pipelines instead of
 * waiting on one column's chain of divisions, and each diagonal is divided by once. */
SYMKIN_API void symkin_cholesky_solve_columns(const real_t *l, int n, real_t *b, int m);

#endif /* SYMKIN_CHOLESKY_COLUMNS_H */

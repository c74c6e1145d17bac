/* symkin C library: Cholesky solve of many right-hand sides (see symkin_cholesky_columns.h). */
#ifndef SYMKIN_AMALGAMATION
#include "symkin_cholesky_columns.h"
#endif

SYMKIN_API void symkin_cholesky_solve_columns(const real_t *l, int n, real_t *b, int m)
{
    int i, j, k;
    /* Forward substitution, L Y = B, row by row. */
    for (i = 0; i < n; ++i) {
        const real_t inverse = REAL(1.0) / l[i * n + i];
        for (k = 0; k < i; ++k) {
            const real_t factor = l[i * n + k];
            for (j = 0; j < m; ++j) {
                b[i * m + j] -= factor * b[k * m + j];
            }
        }
        for (j = 0; j < m; ++j) {
            b[i * m + j] *= inverse;
        }
    }
    /* Back substitution, L^T X = Y. */
    for (i = n - 1; i >= 0; --i) {
        const real_t inverse = REAL(1.0) / l[i * n + i];
        for (k = i + 1; k < n; ++k) {
            const real_t factor = l[k * n + i];
            for (j = 0; j < m; ++j) {
                b[i * m + j] -= factor * b[k * m + j];
            }
        }
        for (j = 0; j < m; ++j) {
            b[i * m + j] *= inverse;
        }
    }
}

/* symkin C library: Cholesky (see symkin_cholesky.h). */
#ifndef SYMKIN_AMALGAMATION
#include "symkin_cholesky.h"
#endif

SYMKIN_API int symkin_cholesky_factor(real_t *a, int n)
{
    int i, j, k;
    for (j = 0; j < n; ++j) {
        real_t diagonal = a[j * n + j];
        for (k = 0; k < j; ++k) {
            diagonal -= a[j * n + k] * a[j * n + k];
        }
        if (!(diagonal > 0)) {
            return 0;
        }
        a[j * n + j] = SYMKIN_SQRT(diagonal);
        for (i = j + 1; i < n; ++i) {
            real_t entry = a[i * n + j];
            for (k = 0; k < j; ++k) {
                entry -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = entry / a[j * n + j];
        }
    }
    return 1;
}

SYMKIN_API void symkin_cholesky_solve(const real_t *l, int n, real_t *x)
{
    int i, k;
    for (i = 0; i < n; ++i) {
        for (k = 0; k < i; ++k) {
            x[i] -= l[i * n + k] * x[k];
        }
        x[i] /= l[i * n + i];
    }
    for (i = n - 1; i >= 0; --i) {
        for (k = i + 1; k < n; ++k) {
            x[i] -= l[k * n + i] * x[k];
        }
        x[i] /= l[i * n + i];
    }
}

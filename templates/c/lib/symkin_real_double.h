/* symkin C library, double precision: real_t, literals REAL(1.5) and the math functions. */
#ifndef SYMKIN_REAL_PRECISION_H
#define SYMKIN_REAL_PRECISION_H

#include <math.h>

typedef double real_t;
#define REAL(x) x
#define SYMKIN_SQRT sqrt
#define SYMKIN_ATAN2 atan2
#define SYMKIN_FLOOR floor
#define SYMKIN_FABS fabs

#endif /* SYMKIN_REAL_PRECISION_H */

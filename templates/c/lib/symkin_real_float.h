/* symkin C library, single precision: real_t, literals REAL(1.5) and the math functions
 * (the float ones: no promotion to the other type anywhere). */
#ifndef SYMKIN_REAL_PRECISION_H
#define SYMKIN_REAL_PRECISION_H

#include <math.h>

typedef float real_t;
#define REAL(x) x##F
#define SYMKIN_SQRT sqrtf
#define SYMKIN_ATAN2 atan2f
#define SYMKIN_FLOOR floorf
#define SYMKIN_FABS fabsf

#endif /* SYMKIN_REAL_PRECISION_H */

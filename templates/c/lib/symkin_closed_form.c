/* symkin C library: closed-form IK steps (see symkin_closed_form.h). */
#ifndef SYMKIN_AMALGAMATION
#include "symkin_closed_form.h"
#endif

#ifdef SYMKIN_CLOSED_FORM_TWO_LINK
SYMKIN_API int symkin_two_link(real_t x, real_t y, real_t l1, real_t l2, real_t tolerance, real_t beta[2], real_t delta[2])
{
    real_t cos_delta = (x * x + y * y - l1 * l1 - l2 * l2) / (REAL(2.0) * l1 * l2);
    real_t sin_delta, direction;
    int k;
    if (!(SYMKIN_FABS(cos_delta) <= REAL(1.0) + tolerance)) {
        return 0;
    }
    cos_delta = cos_delta > REAL(1.0) ? REAL(1.0) : (cos_delta < REAL(-1.0) ? REAL(-1.0) : cos_delta);
    sin_delta = SYMKIN_SQRT((REAL(1.0) - cos_delta) * (REAL(1.0) + cos_delta));
    direction = SYMKIN_ATAN2(y, x);
    for (k = 0; k < 2; ++k) {
        const real_t s = k == 0 ? sin_delta : -sin_delta;
        beta[k] = direction - SYMKIN_ATAN2(l2 * s, l1 + l2 * cos_delta);
        delta[k] = SYMKIN_ATAN2(s, cos_delta);
    }
    return 2;
}
#endif

#ifdef SYMKIN_CLOSED_FORM_CLAMPED_SQRT
SYMKIN_API int symkin_clamped_sqrt(real_t value, real_t scale2, real_t tolerance, real_t *root)
{
    if (value >= REAL(0.0)) {
        *root = SYMKIN_SQRT(value);
        return 1;
    }
    *root = REAL(0.0);
    return value >= -tolerance * scale2;
}
#endif

#ifdef SYMKIN_CLOSED_FORM_SHOULDER
SYMKIN_API int symkin_shoulder(real_t x, real_t y, real_t offset, real_t scale, real_t tolerance, real_t X[2], real_t theta1[2])
{
    real_t reach, direction;
    int k;
    if (!symkin_clamped_sqrt(x * x + y * y - offset * offset, scale * scale, tolerance, &reach)) {
        return 0;
    }
    direction = SYMKIN_ATAN2(y, x);
    X[0] = reach;
    X[1] = -reach;
    for (k = 0; k < 2; ++k) {
        theta1[k] = direction - SYMKIN_ATAN2(offset, X[k]);
    }
    return 2;
}
#endif

#ifdef SYMKIN_CLOSED_FORM_SHOULDER_RIGHT
SYMKIN_API int symkin_shoulder_right(real_t X, real_t offset)
{
    return offset != REAL(0.0) ? X * offset < REAL(0.0) : X >= REAL(0.0);
}
#endif

#ifdef SYMKIN_CLOSED_FORM_ELBOW_UP
SYMKIN_API int symkin_elbow_up(int k, real_t X, int twist)
{
    const int sign = k == 0 ? 1 : -1;
    const int forward = X >= REAL(0.0) ? 1 : -1;
    return -sign * forward * twist > 0;
}
#endif

#ifdef SYMKIN_CLOSED_FORM_UNROTATE
SYMKIN_API void symkin_unrotate_z(real_t c, real_t s, real_t v[3])
{
    const real_t x = c * v[0] + s * v[1];
    v[1] = c * v[1] - s * v[0];
    v[0] = x;
}

SYMKIN_API void symkin_unrotate_x(real_t c, real_t s, real_t v[3])
{
    const real_t y = c * v[1] + s * v[2];
    v[2] = c * v[2] - s * v[1];
    v[1] = y;
}
#endif

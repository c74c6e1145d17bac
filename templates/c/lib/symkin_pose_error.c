/* symkin C library: pose error (see symkin_pose_error.h). */
#ifndef SYMKIN_AMALGAMATION
#include "symkin_pose_error.h"
#endif

SYMKIN_API void symkin_pose_error(const real_t T_target[16], const real_t T[16], real_t e[6], real_t *position_error, real_t *rotation_error)
{
    real_t E[9], w[3], c, s, angle;
    int i, j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            E[3 * i + j] = T_target[4 * i] * T[4 * j] + T_target[4 * i + 1] * T[4 * j + 1]
                           + T_target[4 * i + 2] * T[4 * j + 2];
        }
        e[i] = T_target[4 * i + 3] - T[4 * i + 3];
    }
    w[0] = (E[7] - E[5]) / 2;
    w[1] = (E[2] - E[6]) / 2;
    w[2] = (E[3] - E[1]) / 2;
    c = (E[0] + E[4] + E[8] - 1) / 2;
    s = SYMKIN_SQRT(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    angle = SYMKIN_ATAN2(s, c);
    if (c < 0) {
        real_t k[3], norm, sign;
        const int m = (E[0] >= E[4] && E[0] >= E[8]) ? 0 : (E[4] >= E[8] ? 1 : 2);
        k[m] = SYMKIN_SQRT((E[4 * m] - c) / (1 - c));
        for (j = 0; j < 3; ++j) {
            if (j != m) {
                k[j] = (E[3 * m + j] + E[3 * j + m]) / (2 * (1 - c) * k[m]);
            }
        }
        norm = SYMKIN_SQRT(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
        sign = (k[0] * w[0] + k[1] * w[1] + k[2] * w[2] < 0) ? -1 : 1;
        for (j = 0; j < 3; ++j) {
            e[3 + j] = sign * angle * k[j] / norm;
        }
    } else {
        /* angle / sin(angle) -> 1 as the angle -> 0 */
        const real_t scale = s > 0 ? angle / s : 1;
        for (j = 0; j < 3; ++j) {
            e[3 + j] = scale * w[j];
        }
    }
    *position_error = SYMKIN_SQRT(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    *rotation_error = angle;
}

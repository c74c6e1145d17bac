/* symkin C library: the pose error of a 4x4 transform from a target, in the base frame. */
#ifndef SYMKIN_POSE_ERROR_H
#define SYMKIN_POSE_ERROR_H

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#endif

/* e = [p_target - p; w] for the 4x4 row-major transforms T_target and T, with w the rotation
 * vector (axis times angle) of E = R_target R^T: what the geometric Jacobian [Jv; Jw] maps joint
 * steps to. position_error = |p_target - p| (m), rotation_error = the angle of E in [0, pi]
 * (rad). The angle is atan2(|vee(E - E^T)| / 2, (tr E - 1) / 2); near pi (tr E < 1) the axis
 * comes from the symmetric part (E + E^T) / 2 = c I + (1 - c) k k^T, as in symkin.spatial. */
SYMKIN_API void symkin_pose_error(const real_t T_target[16], const real_t T[16], real_t e[6], real_t *position_error, real_t *rotation_error);

#endif /* SYMKIN_POSE_ERROR_H */

/* symkin C library: inverse kinematics by damped least squares with random restarts.
 *
 * Pose error e = [p_target - p; w] (symkin_pose_error.h), E = e^T e / 2 over the matched rows
 * (x y z when position_only, all six otherwise). Each step solves (J^T J + lambda I) dq = J^T e
 * with lambda = error_damping * E + damping (Sugihara's lambda = E + lambda_bar, IEEE Trans.
 * Robotics 27(5), 2011, with E weighted) by Cholesky, and takes it. Then the joints are
 * limited: a revolute joint outside its limits first moves by the multiple of 2 pi that brings
 * it nearest the middle of its range, then every joint is clamped. An attempt ends after
 * max_iterations steps, when it stalls (E above stall_factor times its value stall_window steps
 * earlier) or when the system is not numerically positive definite; the next one starts from
 * q drawn uniformly within the limits (symkin_xorshift.h), up to max_restarts times. The same
 * algorithm runs in NumPy as symkin.solve.ik.batch.solve_ik_batch.
 */
#ifndef SYMKIN_DLS_H
#define SYMKIN_DLS_H

#include <stdint.h>

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#endif

#define SYMKIN_DLS_SUCCESS 0       /* both errors below their tolerances */
#define SYMKIN_DLS_NOT_CONVERGED 1 /* iteration cap reached; q is the best pose found */
#define SYMKIN_DLS_INVALID_INPUT 2 /* non-finite input, a target rotation that is not
                                      orthonormal or bad options; q is left untouched */

/* Tool pose T[16] (4x4 row-major) and geometric Jacobian J[6 * dof] (row-major, rows
 * vx vy vz wx wy wz, base frame) at joint positions q[dof] with parameters p. */
typedef void (*symkin_fk_jacobian)(const real_t *q, const real_t *p, real_t *T, real_t *J);

/* The robot and the solver's fixed constants. */
typedef struct {
    int dof;                      /* joints, >= 1 */
    int num_parameters;           /* p holds this many values (p may be NULL when 0) */
    symkin_fk_jacobian fk_jacobian;
    const int *revolute;          /* dof flags: nonzero for a revolute joint */
    const real_t *span;           /* dof restart widths where a limit is missing (rad or m):
                                     centred on 0 without limits, ending at the one limit */
    int stall_window;             /* steps, >= 1 */
    real_t stall_factor;
    real_t orthonormal_tolerance; /* |R^T R - I| entry by entry above this: not a rotation */
    uint64_t fallback_seed;       /* the generator's state when options.seed is 0; nonzero */
} symkin_dls_problem;

typedef struct {
    int max_iterations;        /* steps per attempt (the first and each restart), >= 0 */
    int max_restarts;          /* random restarts after the first attempt, >= 0 */
    real_t position_tolerance; /* m, > 0 */
    real_t rotation_tolerance; /* rad, > 0; ignored when position_only */
    real_t damping;            /* lambda_bar, >= 0 */
    real_t error_damping;      /* weight of E in lambda, >= 0 */
    int position_only;         /* nonzero: match the tool position only (rows x y z) */
    const real_t *lower;       /* dof joint limits (rad or m); -INFINITY / INFINITY for none */
    const real_t *upper;
    uint64_t seed;             /* state of the restart generator; 0: fallback_seed */
} symkin_dls_options;

typedef struct {
    int status;            /* SYMKIN_DLS_SUCCESS, _NOT_CONVERGED or _INVALID_INPUT */
    int iterations;        /* steps taken over all attempts */
    int restarts;          /* random restarts used */
    real_t position_error; /* |p_target - p| at the returned q (m); INFINITY if invalid */
    real_t rotation_error; /* angle of R_target R^T at the returned q (rad) */
} symkin_dls_result;

/* Elements of the work array symkin_dls_solve needs. */
#define SYMKIN_DLS_WORKSPACE(dof, stall_window) (22 + (dof) * ((dof) + 8) + (stall_window))

/* Joint positions q[dof] whose tool pose is T_target[16] (4x4 row-major, base frame), from
 * q_seed[dof]; q may be q_seed. work holds SYMKIN_DLS_WORKSPACE(dof, stall_window) elements.
 * Fills *result and returns its status. */
SYMKIN_API int symkin_dls_solve(const symkin_dls_problem *problem, const real_t T_target[16], const real_t *q_seed, const real_t *p, const symkin_dls_options *options, real_t *work, real_t *q, symkin_dls_result *result);

#endif /* SYMKIN_DLS_H */

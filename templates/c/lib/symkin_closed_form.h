/* symkin C library: the steps the closed-form IK families share (the Python twin is
 * symkin.kernels.ik.closed_form_steps): the two-link elbow, the waist angle with a shoulder
 * offset, square roots clamped at the edge of the workspace, the branch-flag tests and the
 * inverse elementary rotations.
 *
 * A generated file pastes this part with only the functions its family calls: it defines
 * SYMKIN_CLOSED_FORM_<NAME> for each (static functions nobody calls would be warned about).
 * Compiled on its own, every function is compiled. */
#ifndef SYMKIN_CLOSED_FORM_H
#define SYMKIN_CLOSED_FORM_H

#ifndef SYMKIN_AMALGAMATION
#include "symkin_real.h"
#define SYMKIN_CLOSED_FORM_TWO_LINK
#define SYMKIN_CLOSED_FORM_CLAMPED_SQRT
#define SYMKIN_CLOSED_FORM_SHOULDER
#define SYMKIN_CLOSED_FORM_SHOULDER_RIGHT
#define SYMKIN_CLOSED_FORM_ELBOW_UP
#define SYMKIN_CLOSED_FORM_UNROTATE
#endif

#ifdef SYMKIN_CLOSED_FORM_TWO_LINK
/* Both (beta_1, delta) with l1 (cos beta_1, sin beta_1) + l2 (cos(beta_1 + delta),
 * sin(beta_1 + delta)) = (x, y), the one with sin delta >= 0 first, without acos:
 * cos delta = (x^2 + y^2 - l1^2 - l2^2) / (2 l1 l2), clamped to [-1, 1] when it is off by up to
 * tolerance (rounding at full stretch). Returns 2, or 0 when out of reach. l1, l2 != 0. */
SYMKIN_API int symkin_two_link(real_t x, real_t y, real_t l1, real_t l2, real_t tolerance, real_t beta[2], real_t delta[2]);
#endif

#ifdef SYMKIN_CLOSED_FORM_CLAMPED_SQRT
/* *root = sqrt(value); a value below 0 by at most tolerance * scale2 gives 0 (rounding at the
 * edge of the workspace). Returns 1, or 0 (no real root, *root = 0) for a value clearly below 0. */
SYMKIN_API int symkin_clamped_sqrt(real_t value, real_t scale2, real_t tolerance, real_t *root);
#endif

#ifdef SYMKIN_CLOSED_FORM_SHOULDER
/* Both (X, theta_1) with Rz(theta_1) (X, offset) = (x, y), X >= 0 first: the waist angle that
 * puts a point at the horizontal offset `offset` from the arm's plane. Returns 2, or 0 when the
 * point is closer to the waist axis than |offset| (square root clamped as symkin_clamped_sqrt,
 * relative to scale^2). */
SYMKIN_API int symkin_shoulder(real_t x, real_t y, real_t offset, real_t scale, real_t tolerance, real_t X[2], real_t theta1[2]);
#endif

#ifdef SYMKIN_CLOSED_FORM_SHOULDER_RIGHT
/* 1 when the shoulder offset lies right of the reach direction seen from above
 * (X offset < 0); without an offset, when reaching forward (X >= 0). */
SYMKIN_API int symkin_shoulder_right(real_t X, real_t offset);
#endif

#ifdef SYMKIN_CLOSED_FORM_ELBOW_UP
/* 1 when the elbow of two-link solution k (0: sin delta >= 0) lies above the line from the
 * shoulder to the wrist: -sign(sin delta) sign(X) twist > 0, twist = sin(alpha_1) = +-1. */
SYMKIN_API int symkin_elbow_up(int k, real_t X, int twist);
#endif

#ifdef SYMKIN_CLOSED_FORM_UNROTATE
/* v = Rz(angle)^T v for the angle with cosine c and sine s. */
SYMKIN_API void symkin_unrotate_z(real_t c, real_t s, real_t v[3]);

/* v = Rx(alpha)^T v for the twist with cosine c and sine s. */
SYMKIN_API void symkin_unrotate_x(real_t c, real_t s, real_t v[3]);
#endif

#endif /* SYMKIN_CLOSED_FORM_H */

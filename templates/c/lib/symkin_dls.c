/* symkin C library: damped least squares (see symkin_dls.h). */
#include <stddef.h>

#ifndef SYMKIN_AMALGAMATION
#include "symkin_cholesky.h"
#include "symkin_dls.h"
#include "symkin_pose_error.h"
#include "symkin_xorshift.h"
#endif

/* Revolute joints outside their limits go to the equivalent angle nearest the middle of the
 * range (they may then be inside); then every joint is clamped to its limits. */
static void symkin_dls_limit(const symkin_dls_problem *problem, const real_t *lower, const real_t *upper, real_t *q)
{
    const real_t two_pi = REAL(6.283185307179586);
    int i;
    for (i = 0; i < problem->dof; ++i) {
        if (problem->revolute[i] && (q[i] < lower[i] || q[i] > upper[i]) && isfinite(lower[i])
            && isfinite(upper[i])) {
            const real_t middle = (lower[i] + upper[i]) / 2;
            q[i] -= two_pi * SYMKIN_FLOOR((q[i] - middle) / two_pi + REAL(0.5));
        }
        q[i] = q[i] < lower[i] ? lower[i] : (q[i] > upper[i] ? upper[i] : q[i]);
    }
}

/* A random configuration within the limits, joint by joint; where a limit is missing, the
 * range has the joint's span. */
static void symkin_dls_random(const symkin_dls_problem *problem, const real_t *lower, const real_t *upper, uint64_t *state, real_t *q)
{
    int i;
    for (i = 0; i < problem->dof; ++i) {
        real_t low = lower[i], high = upper[i];
        if (!isfinite(low) && !isfinite(high)) {
            low = -problem->span[i] / 2;
            high = problem->span[i] / 2;
        } else if (!isfinite(low)) {
            low = high - problem->span[i];
        } else if (!isfinite(high)) {
            high = low + problem->span[i];
        }
        q[i] = low + symkin_uniform(state) * (high - low);
    }
}

/* dq[n] from (J^T J + lambda I) dq = J^T e over the first `rows` rows of J (6 x n) and e, with
 * H[n * n] as scratch. Returns 0 if the system is not numerically positive definite. */
static int symkin_dls_step(const real_t *J, const real_t *e, int n, int rows, real_t lambda, real_t *H, real_t *dq)
{
    int i, j, k;
    for (i = 0; i < n; ++i) {
        real_t gradient = 0;
        for (j = 0; j <= i; ++j) {
            real_t entry = 0;
            for (k = 0; k < rows; ++k) {
                entry += J[k * n + i] * J[k * n + j];
            }
            H[i * n + j] = entry;
        }
        H[i * n + i] += lambda;
        for (k = 0; k < rows; ++k) {
            gradient += J[k * n + i] * e[k];
        }
        dq[i] = gradient;
    }
    if (!symkin_cholesky_factor(H, n)) {
        return 0;
    }
    symkin_cholesky_solve(H, n, dq);
    return 1;
}

static int symkin_dls_all_finite(const real_t *values, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        if (!isfinite(values[i])) {
            return 0;
        }
    }
    return 1;
}

static int symkin_dls_valid(const symkin_dls_problem *problem, const real_t T_target[16], const real_t *q_seed, const real_t *p, const symkin_dls_options *o)
{
    int i, j;
    if (!symkin_dls_all_finite(T_target, 16) || !symkin_dls_all_finite(q_seed, problem->dof)
        || (problem->num_parameters > 0
            && (p == NULL || !symkin_dls_all_finite(p, problem->num_parameters)))) {
        return 0;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            const real_t product = T_target[i] * T_target[j] + T_target[4 + i] * T_target[4 + j]
                                   + T_target[8 + i] * T_target[8 + j];
            if (SYMKIN_FABS(product - (real_t)(i == j)) > problem->orthonormal_tolerance) {
                return 0;
            }
        }
    }
    for (i = 0; i < problem->dof; ++i) {
        if (!(o->lower[i] <= o->upper[i])) {
            return 0;
        }
    }
    return o->max_iterations >= 0 && o->max_restarts >= 0 && o->position_tolerance > 0
           && o->rotation_tolerance > 0 && o->damping >= 0 && o->error_damping >= 0
           && isfinite(o->damping) && isfinite(o->error_damping);
}

SYMKIN_API int symkin_dls_solve(const symkin_dls_problem *problem, const real_t T_target[16], const real_t *q_seed, const real_t *p, const symkin_dls_options *options, real_t *work, real_t *q, symkin_dls_result *result)
{
    const int n = problem->dof;
    real_t *T = work, *e = T + 16, *J = e + 6, *H = J + 6 * n, *dq = H + n * n, *best = dq + n;
    real_t *history = best + n;
    real_t best_error = INFINITY;
    uint64_t state;
    int i, rows, step = 0;

    result->status = SYMKIN_DLS_NOT_CONVERGED;
    result->iterations = 0;
    result->restarts = 0;
    result->position_error = INFINITY;
    result->rotation_error = INFINITY;
    if (!symkin_dls_valid(problem, T_target, q_seed, p, options)) {
        result->status = SYMKIN_DLS_INVALID_INPUT;
        return result->status;
    }
    rows = options->position_only ? 3 : 6;
    state = options->seed != 0 ? options->seed : problem->fallback_seed;
    for (i = 0; i < n; ++i) {
        q[i] = q_seed[i];
    }
    symkin_dls_limit(problem, options->lower, options->upper, q);
    for (i = 0; i < n; ++i) {
        best[i] = q[i];
    }
    for (;;) {
        real_t error = 0, position_error, rotation_error;
        int stalled;
        problem->fk_jacobian(q, p, T, J);
        symkin_pose_error(T_target, T, e, &position_error, &rotation_error);
        for (i = 0; i < rows; ++i) {
            error += e[i] * e[i] / 2;
        }
        if (error < best_error) {
            best_error = error;
            result->position_error = position_error;
            result->rotation_error = rotation_error;
            for (i = 0; i < n; ++i) {
                best[i] = q[i];
            }
        }
        if (position_error < options->position_tolerance
            && (options->position_only || rotation_error < options->rotation_tolerance)) {
            result->status = SYMKIN_DLS_SUCCESS;
            result->position_error = position_error;
            result->rotation_error = rotation_error;
            return result->status;
        }
        stalled = step >= problem->stall_window
                  && error > problem->stall_factor * history[step % problem->stall_window];
        history[step % problem->stall_window] = error;
        if (!stalled && step < options->max_iterations
            && symkin_dls_step(J, e, n, rows, options->error_damping * error + options->damping, H, dq)) {
            for (i = 0; i < n; ++i) {
                q[i] += dq[i];
            }
            symkin_dls_limit(problem, options->lower, options->upper, q);
            ++step;
            ++result->iterations;
            continue;
        }
        if (result->restarts == options->max_restarts) {
            for (i = 0; i < n; ++i) {
                q[i] = best[i];
            }
            return result->status;
        }
        ++result->restarts;
        step = 0;
        symkin_dls_random(problem, options->lower, options->upper, &state, q);
    }
}

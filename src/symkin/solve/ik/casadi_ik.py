"""Inverse kinematics as a nonlinear program on the generated CasADi forward kinematics.

``min_q  |p_t - p(q)|^2 / 2 + |R(q) - R_t|_F^2 / 4``  subject to  ``lower <= q <= upper``,

solved by IPOPT through ``casadi.nlpsol``; ``p(q)``, ``R(q)`` come from the CasADi backend's
``fk_function()``, with CasADi's exact derivatives.  The rotation term equals
``1 - cos(angle)`` of ``R_t^T R`` (``|R - R_t|_F^2 = 6 - 2 tr(R_t^T R) = 4 (1 - cos angle)``),
smooth everywhere and ``angle^2 / 2`` near the solution, so the objective matches the
``E = e^T e / 2`` of the damped-least-squares solvers there.  Joint limits are bounds on
``q`` (IPOPT's bound relaxation is switched off, so the returned ``q`` never leaves them).
The result is judged like :func:`symkin.solve.ik.numeric.solve_ik`'s: by the forward kinematics of
the returned ``q`` (position error in m, rotation angle in rad, both at most ``tolerance``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from functools import lru_cache

import casadi
import numpy as np

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.runtime.modules import generated_casadi_module, generated_numpy_module
from symkin.solve.ik.batch import pose_errors, sample_ranges
from symkin.solve.ik.joints import joint_bounds, middle_configuration, parameter_vector
from symkin.solve.ik.numeric import DEFAULT_TOLERANCE, IKResult

ALL_ROWS = ("x", "y", "z", "wx", "wy", "wz")
IPOPT_OPTIONS = {
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "print_time": False,
    # Stop on the objective's own scale: a 1e-10 residual is an objective of 1e-20.  The
    # adaptive barrier with a tiny floor lets the barrier's pull away from the limits vanish
    # (with the monotone default, Panda solves stalled at residuals of 1e-7 to 1e-9).
    "ipopt.tol": 1e-20,
    "ipopt.acceptable_iter": 0,
    "ipopt.mu_strategy": "adaptive",
    "ipopt.mu_min": 1e-22,
    "ipopt.bound_relax_factor": 0.0,
}


@lru_cache(maxsize=32)
def ik_nlp_solver(model: Model, position_only: bool, max_iterations: int) -> casadi.Function:
    """The IPOPT solver of the IK program; its parameters are the target pose (12 values:
    the rotation row by row, then the position) and the robot parameters."""
    n = model.robot.dof
    q = casadi.SX.sym("q", n)
    target = casadi.SX.sym("target", 12)
    p = casadi.SX.sym("p", len(model.robot.parameters))
    T = generated_casadi_module(model, "kinematics").fk_function()(q, p)
    rotation_target = casadi.reshape(target[:9], 3, 3).T  # reshape fills column by column
    position_error = target[9:] - T[:3, 3]
    objective = casadi.sumsqr(position_error) / 2
    if not position_only:
        objective += casadi.sumsqr(T[:3, :3] - rotation_target) / 4
    problem = {"x": q, "p": casadi.vertcat(target, p), "f": objective}
    return casadi.nlpsol(
        f"{model.robot.name}_ik",
        "ipopt",
        problem,
        {**IPOPT_OPTIONS, "ipopt.max_iter": max_iterations},
    )


def _check_settings(tolerance: float, max_iterations: int, restarts: int) -> None:
    if not tolerance > 0 or max_iterations < 1 or restarts < 0:
        raise SymkinError(
            "need tolerance > 0, max_iterations >= 1 and restarts >= 0, got "
            f"{tolerance}, {max_iterations} and {restarts}"
        )


def _checked_target(target: np.ndarray) -> np.ndarray:
    target = np.asarray(target, dtype=float)
    if target.shape != (4, 4) or not np.all(np.isfinite(target)):
        raise SymkinError("the IK target must be a finite 4x4 homogeneous transform")
    return target


def _bounds_and_start(
    model: Model,
    q0: Sequence[float] | None,
    limits: tuple[Sequence[float], Sequence[float]] | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lower and upper joint bounds (the robot file's unless ``limits``) and the first guess."""
    n = model.robot.dof
    lower, upper = joint_bounds(model) if limits is None else limits
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    if lower.shape != (n,) or upper.shape != (n,) or not np.all(lower <= upper):
        raise SymkinError(f"limits: expected lower <= upper, {n} values each")
    start = middle_configuration(model) if q0 is None else np.asarray(q0, dtype=float)
    if start.shape != (n,) or not np.all(np.isfinite(start)):
        raise SymkinError(f"q0: expected {n} finite values")
    return lower, upper, start


def solve_ik_casadi(
    model: Model,
    target: np.ndarray,
    q0: Sequence[float] | None = None,
    *,
    position_only: bool = False,
    tolerance: float = DEFAULT_TOLERANCE,
    max_iterations: int = 100,
    restarts: int = 0,
    seed: int | None = 0,
    limits: tuple[Sequence[float], Sequence[float]] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> IKResult:
    """Joint values that put the tool at ``target`` (4x4, base frame), within the limits.

    ``q0`` is the initial guess (default: the middle of the joint ranges); ``limits`` replaces
    the robot file's ``(lower, upper)``.  After a failed solve, up to ``restarts`` more start
    from configurations drawn uniformly within the limits (``seed``); the best is returned.
    """
    _check_settings(tolerance, max_iterations, restarts)
    target = _checked_target(target)
    lower, upper, start = _bounds_and_start(model, q0, limits)

    solver = ik_nlp_solver(model, position_only, max_iterations)
    p = parameter_vector(model, overrides)
    parameters = np.concatenate([target[:3, :3].ravel(), target[:3, 3], p])
    fk = generated_numpy_module(model, "kinematics").fk
    low, high = sample_ranges(model, lower, upper)
    rng = np.random.default_rng(seed)
    best: IKResult | None = None
    iterations = 0
    for attempt in range(restarts + 1):
        guess = np.clip(start, lower, upper) if attempt == 0 else rng.uniform(low, high)
        solution = solver(x0=guess, p=parameters, lbx=lower, ubx=upper)
        iterations += int(solver.stats()["iter_count"])
        q = np.clip(np.asarray(solution["x"], dtype=float).ravel(), lower, upper)
        pose = fk(q, p)
        _, position_error, rotation_error = pose_errors(target[None], pose[None])
        # Position only: the rotation rows do not count (as in solve_ik's metric).
        errors = float(position_error[0]), 0.0 if position_only else float(rotation_error[0])
        candidate = IKResult(
            q=q,
            success=max(errors) <= tolerance,
            position_error=errors[0],
            rotation_error=errors[1],
            iterations=iterations,
            restarts=attempt,
            pose=pose,
            rows=ALL_ROWS[:3] if position_only else ALL_ROWS,
            method="ipopt",
            backend="casadi",
        )
        if best is None or candidate.residual < best.residual:
            best = candidate
        if best.success:
            break
    assert best is not None
    return replace(best, iterations=iterations, restarts=attempt)

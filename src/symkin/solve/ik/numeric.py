"""Numeric inverse kinematics on the generated forward kinematics and geometric Jacobian.

Error (docs/ik.md).  At a configuration ``q`` with tool pose ``(R, p)`` and target
``(R_t, p_t)`` the 6-vector error is ``e = [p_t - p; r]`` (base frame), where ``r`` is the
rotation vector (axis times angle) of ``R_t R^T``: the rotation that carries the tool
orientation onto the target, expressed in the base frame like the angular rows of the
geometric Jacobian, so that ``e ~ J dq`` to first order.  The task rows (names
``x y z wx wy wz``) select which components count.  The residuals reported are the Euclidean
norm of the selected linear components (metres) and of the selected angular components
(radians; with all three angular rows this is the rotation angle between tool and target).
A solution succeeds only when the forward kinematics of the returned ``q`` has both residuals
at or below the tolerance.

Methods.

* ``"lm"``: Levenberg–Marquardt, ``dq = (J^T W J + lambda I)^-1 J^T W e`` with Sugihara's
  damping ``lambda = E + mu``, ``E = e^T W e / 2`` (T. Sugihara, "Solvability-unconcerned
  inverse kinematics by the Levenberg–Marquardt method", IEEE Trans. Robotics 27(5), 2011),
  here with ``E`` weighted by ``E_FACTOR`` (``lambda = 0.1 E + mu``).
  ``mu`` adapts as in Marquardt's method: a step is taken only if it lowers ``E`` (then ``mu``
  shrinks tenfold), otherwise it is rejected and ``mu`` grows tenfold.  ``lambda > 0`` keeps
  the system positive definite, so singular configurations give finite steps, never NaN.
* ``"newton"``: Newton–Raphson, ``dq = J^-1 e`` for a square task Jacobian (least squares,
  ``J^+ e``, otherwise and at a singular ``J``), full steps, as in the lecture.

Joint limits.  An attempt first iterates without limits (clamping every iterate stalls at a
limit when the solution lies on another branch).  A converged ``q`` is shifted into the limits
by multiples of 2 pi on revolute joints (the pose is unchanged); if that is impossible, or the
attempt did not converge, a bounded run follows from the clamped ``q``, in which a joint that
a step would carry past a limit is held there (an active set, :func:`_bounded_lm_step`).
Every returned ``q`` is within the limits; revolute joints without limits are wrapped to
``(-pi, pi]``.

Restarts.  When an attempt fails, the solver restarts from a random configuration drawn
uniformly within the limits (revolute joints without limits in ``(-pi, pi]``, prismatic ones
in ``[-1, 1]`` m).  If none succeeds, the best attempt is continued without the early stop for
stalled runs, and its pose is returned as the closest reached.

Redundancy.  With fewer task rows than joints, a converged solution is moved along its
self-motion toward a rest posture (:func:`_toward_rest`; default: the middle of each joint's
range, 0 for joints without limits).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.errors import ParameterError, SymkinError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.joints import (
    joint_bounds,
    middle_configuration,
    parameter_vector,
    random_configuration,
)
from symkin.spatial import axis_angle_from_rotation

METHODS = ("lm", "newton")
DEFAULT_TOLERANCE = 1e-10
DEFAULT_MAX_ITERATIONS = 100
DEFAULT_RESTARTS = 30
# Damping lambda = E_FACTOR * E + mu.  Sugihara's law has E_FACTOR = 1; 0.1 took a third fewer
# iterations on random PUMA 560 and Panda poses (median 9 instead of 13) with the same success.
E_FACTOR = 0.1
# Marquardt's adaptive part mu: start, the factor of each change, floor, and the ceiling at
# which an attempt has stalled (steps no longer move q).
MU_START = 1e-3
MU_FACTOR = 10.0
MU_MIN = 1e-12
MU_MAX = 1e8
# The rest posture: at most this many null-space rounds, each corrected by at most this many
# Newton steps; reached when the null-space step is this small (rad or m); each round tries
# these fractions of the null-space step in turn.
POSTURE_ROUNDS = 20
POSTURE_CORRECTION = 5
POSTURE_TOLERANCE = 1e-4
POSTURE_SCALES = (1.0, 0.5, 0.25, 0.125, 0.0625)
# E above STALL_RATIO times its value STALL_WINDOW iterations ago: a local minimum.
STALL_WINDOW = 10
STALL_RATIO = 0.99
# Newton: a square Jacobian with a larger condition number counts as singular.
SINGULAR_CONDITION = 1e12
# Limits are met when exceeded by no more than this (rounding of the 2 pi shifts).
LIMIT_SLACK = 1e-12


@dataclass(frozen=True)
class IKResult:
    """The outcome of :func:`solve_ik`.

    ``q`` is the best configuration found (the solution when ``success``, otherwise the closest
    pose reached), ``pose`` its forward kinematics.  ``position_error`` (m) and
    ``rotation_error`` (rad) are the norms of the selected linear and angular error components
    at ``q``; ``residual`` is the larger of the two.  ``iterations`` counts every iteration of
    every attempt, ``restarts`` the attempts after the first.
    """

    q: np.ndarray
    success: bool
    position_error: float
    rotation_error: float
    iterations: int
    restarts: int
    pose: np.ndarray
    rows: tuple[str, ...]
    method: str

    @property
    def residual(self) -> float:
        return max(self.position_error, self.rotation_error)


def rotation_vector(R: np.ndarray) -> np.ndarray:
    """Axis times angle of the rotation ``R`` (angle in ``[0, pi]``), never NaN.

    Below 90 degrees directly from the skew part: ``w = vee(R - R^T) = 2 sin(a) k`` and
    ``a = atan2(|w| / 2, (tr R - 1) / 2)``, so ``r = w a / (2 sin a)`` (``a / sin a -> 1`` at 0).
    Beyond, where ``sin a`` gets small again, :func:`symkin.spatial.axis_angle_from_rotation`.
    """
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    if c <= 0.0:
        axis, angle, _ = axis_angle_from_rotation(R)
        return np.asarray(axis, dtype=float) * angle
    half_norm = 0.5 * math.sqrt(w @ w)
    if half_norm == 0.0:
        return 0.5 * w
    return w * (0.5 * math.atan2(half_norm, c) / half_norm)


@dataclass(frozen=True)
class _Problem:
    """Everything an iteration needs, fixed for one call of :func:`solve_ik`."""

    fk_jacobian: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
    parameters: np.ndarray
    rows: np.ndarray | None  # indices into x y z wx wy wz, ascending; None: all six
    linear: np.ndarray  # positions within ``rows`` of the linear rows
    angular: np.ndarray  # ... and of the angular rows
    weights: np.ndarray | None
    lower: np.ndarray
    upper: np.ndarray
    revolute: np.ndarray
    target: np.ndarray
    tolerance: float

    @property
    def unlimited(self) -> np.ndarray:
        """Revolute joints without limits (their angles count modulo 2 pi)."""
        return self.revolute & ~np.isfinite(self.lower) & ~np.isfinite(self.upper)

    @property
    def has_limits(self) -> bool:
        return bool(np.isfinite(self.lower).any() or np.isfinite(self.upper).any())

    def evaluate(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pose, task Jacobian rows and task error at ``q``."""
        T, J = self.fk_jacobian(q, self.parameters)
        e = np.zeros(6)
        e[:3] = self.target[:3, 3] - T[:3, 3]
        if self.angular.size:
            e[3:] = rotation_vector(self.target[:3, :3] @ T[:3, :3].T)
        if self.rows is None:
            return T, J, e
        return T, J[self.rows], e[self.rows]

    def energy(self, e: np.ndarray) -> float:
        """``E = e^T W e / 2``."""
        return 0.5 * float(e @ e if self.weights is None else e @ (self.weights * e))

    def errors(self, e: np.ndarray) -> tuple[float, float]:
        """Position error (m) and rotation error (rad) of the selected components."""
        linear, angular = e[self.linear], e[self.angular]
        return math.sqrt(linear @ linear), math.sqrt(angular @ angular)

    def converged(self, e: np.ndarray) -> bool:
        position, rotation = self.errors(e)
        return position <= self.tolerance and rotation <= self.tolerance

    def clamp(self, q: np.ndarray) -> np.ndarray:
        return np.minimum(np.maximum(q, self.lower), self.upper)

    def into_limits(self, q: np.ndarray) -> np.ndarray | None:
        """``q`` with revolute joints shifted by multiples of 2 pi into their limits (the pose
        is the same); ``None`` when some joint cannot be brought inside."""
        shifted = q.copy()
        for i, (value, low, high) in enumerate(zip(q, self.lower, self.upper, strict=True)):
            if low - LIMIT_SLACK <= value <= high + LIMIT_SLACK:
                continue
            if not self.revolute[i]:
                return None
            # The smallest value >= low in the class of q mod 2 pi.
            value = value + 2 * np.pi * math.ceil((low - value) / (2 * np.pi))
            if value > high + LIMIT_SLACK:
                return None
            shifted[i] = value
        return self.clamp(shifted)  # only removes the rounding slack


@dataclass(frozen=True)
class _Attempt:
    q: np.ndarray
    energy: float
    converged: bool
    iterations: int


def _lm_step(problem: _Problem, J: np.ndarray, e: np.ndarray, damping: float) -> np.ndarray:
    """``(J^T W J + damping I)^-1 J^T W e``."""
    WJ = J if problem.weights is None else problem.weights[:, None] * J
    A = J.T @ WJ
    A.flat[:: A.shape[0] + 1] += damping  # the diagonal, in place
    return np.linalg.solve(A, WJ.T @ e)


def _bounded_lm_step(
    problem: _Problem, q: np.ndarray, J: np.ndarray, e: np.ndarray, damping: float
) -> np.ndarray:
    """The LM step with joints that would cross a limit held at that limit.

    Clamping the free step alone stalls at a limit (the step keeps pushing into it), so each
    joint the step would carry past a limit is set to the limit and the step is solved again
    for the remaining joints, with the error that the held joints leave (an active set).
    """
    step = _lm_step(problem, J, e, damping)
    free = np.ones(q.size, dtype=bool)
    while True:
        beyond = free & ((q + step > problem.upper) | (q + step < problem.lower))
        if not beyond.any():
            return step
        step[beyond] = problem.clamp(q + step)[beyond] - q[beyond]
        free &= ~beyond
        if not free.any():
            return step
        held = ~free
        step[free] = _lm_step(problem, J[:, free], e - J[:, held] @ step[held], damping)


def newton_step(J: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``J^-1 e`` for a square, regular ``J``; otherwise ``J^+ e``, the least-squares step of
    least norm (by the normal equations while ``J`` has full rank, else by an SVD)."""
    rows, columns = J.shape
    try:
        if rows == columns:
            if np.linalg.cond(J) < SINGULAR_CONDITION:
                return np.linalg.solve(J, e)
        elif rows < columns:
            return J.T @ np.linalg.solve(J @ J.T, e)  # J^+ = J^T (J J^T)^-1
        else:
            return np.linalg.solve(J.T @ J, J.T @ e)  # J^+ = (J^T J)^-1 J^T
    except np.linalg.LinAlgError:
        pass  # rank-deficient: the SVD below
    return np.linalg.lstsq(J, e, rcond=None)[0]


def _null_space_step(J: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``(I - J^+ J) z``: the part of ``z`` that does not move the task to first order."""
    return z - newton_step(J, J @ z)


def _lm_attempt(
    problem: _Problem, q: np.ndarray, max_iterations: int, bounded: bool, stall: bool = True
) -> _Attempt:
    """One LM run from ``q``: free (limits checked afterwards) or ``bounded`` (active set).

    With ``stall``, a run that makes little progress ends early (the next attempt is likely to
    do better); without it, the run goes on to the closest pose it can reach.
    """
    _, J, e = problem.evaluate(q)
    energy = problem.energy(e)
    history = [energy]
    mu = MU_START
    while len(history) <= max_iterations and not problem.converged(e):
        damping = E_FACTOR * energy + mu
        if bounded:
            trial = problem.clamp(q + _bounded_lm_step(problem, q, J, e, damping))
        else:
            trial = q + _lm_step(problem, J, e, damping)
        _, J_trial, e_trial = problem.evaluate(trial)
        energy_trial = problem.energy(e_trial)
        if energy_trial < energy:
            q, J, e, energy = trial, J_trial, e_trial, energy_trial
            mu = max(mu / MU_FACTOR, MU_MIN)
        else:
            mu *= MU_FACTOR
        history.append(energy)
        # history[-1] is this iteration's E, history[-1 - STALL_WINDOW] the one to compare.
        stalled = (
            stall
            and len(history) > STALL_WINDOW
            and energy > STALL_RATIO * history[-1 - STALL_WINDOW]
        )
        if mu > MU_MAX or stalled:
            break  # a local minimum: the target is out of reach from here
    return _Attempt(q, energy, problem.converged(e), len(history) - 1)


def _toward_rest(problem: _Problem, solution: _Attempt, rest: np.ndarray) -> _Attempt:
    """Move a solution along its self-motion manifold toward the rest posture.

    Each round steps ``(I - J^+ J)(q_rest - q)`` (halved up to four times), which leaves the
    task unchanged to first order, then corrects the task with a few bounded Newton steps; the
    round counts only if the task converges again closer to ``q_rest``.  So the posture never
    costs the solution: success is kept, and the joints stay within their limits.
    """

    def distance(q: np.ndarray) -> float:
        difference = q - rest
        difference[problem.unlimited] = _wrap(difference[problem.unlimited])
        return float(np.linalg.norm(difference))

    q, iterations = solution.q, solution.iterations
    for _ in range(POSTURE_ROUNDS):
        _, J, _ = problem.evaluate(q)
        toward = rest - q
        toward[problem.unlimited] = _wrap(toward[problem.unlimited])  # the short way round
        null_step = _null_space_step(J, toward)
        if np.linalg.norm(null_step) <= POSTURE_TOLERANCE:
            break
        for scale in POSTURE_SCALES:
            corrected = _newton_attempt(
                problem, problem.clamp(q + scale * null_step), POSTURE_CORRECTION, bounded=True
            )
            iterations += corrected.iterations
            if corrected.converged and distance(corrected.q) < distance(q):
                q = corrected.q
                break
        else:
            break
    return replace(solution, q=q, iterations=iterations)


def _newton_attempt(
    problem: _Problem, q: np.ndarray, max_iterations: int, bounded: bool
) -> _Attempt:
    """Full Newton steps from ``q``; ``bounded`` clamps every iterate to the limits."""
    _, J, e = problem.evaluate(q)
    iterations = 0
    while iterations < max_iterations and not problem.converged(e):
        trial = q + newton_step(J, e)
        iterations += 1
        if not np.all(np.isfinite(trial)):
            break
        q = problem.clamp(trial) if bounded else trial
        _, J, e = problem.evaluate(q)
    return _Attempt(q, problem.energy(e), problem.converged(e), iterations)


def _attempt(problem: _Problem, start: np.ndarray, method: str, max_iterations: int) -> _Attempt:
    """A free run, then the limits: a converged ``q`` is shifted into them by multiples of
    2 pi; if that fails, or the run did not converge, a bounded run from the clamped ``q``
    (so that every attempt ends within the limits)."""

    def run(q: np.ndarray, bounded: bool) -> _Attempt:
        if method == "lm":
            return _lm_attempt(problem, q, max_iterations, bounded)
        return _newton_attempt(problem, q, max_iterations, bounded)

    free = run(problem.clamp(start), bounded=False)
    if not problem.has_limits:
        return free
    inside = problem.into_limits(free.q) if free.converged else None
    if inside is not None:
        return replace(free, q=inside)
    bounded = run(problem.clamp(free.q), bounded=True)
    return replace(bounded, iterations=free.iterations + bounded.iterations)


def _vector(values: Sequence[float] | np.ndarray, n: int, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float).reshape(-1)
    if array.size != n:
        raise SymkinError(f"{what}: expected {n} values, got {array.size}")
    if not np.all(np.isfinite(array)):
        raise SymkinError(f"{what}: expected finite numbers, got {array.tolist()}")
    return array


def task_rows_for(
    model: Model, task: Sequence[str] | None = None, position_only: bool = False
) -> tuple[str, ...]:
    """The rows an IK problem matches: ``task``, else ``x y z`` for a position-only target,
    else the robot's default task rows (``model.task_rows``: planar 2R ``x y``, 6 DOF all)."""
    if task is not None:
        rows = tuple(task)
    elif position_only:
        rows = ("x", "y", "z")
    else:
        rows = model.task_rows
    rows_from_names(rows)
    if not rows:
        raise SymkinError("the task needs at least one row of x, y, z, wx, wy, wz")
    return rows


def _wrap(angles: np.ndarray) -> np.ndarray:
    """Angles mapped to ``(-pi, pi]``."""
    return np.pi - np.mod(np.pi - angles, 2 * np.pi)


def _problem(
    model: Model,
    target: np.ndarray,
    rows: tuple[str, ...],
    weights: Sequence[float] | None,
    tolerance: float,
    overrides: Mapping[str, float] | None,
) -> _Problem:
    target = np.asarray(target, dtype=float)
    if target.shape != (4, 4) or not np.all(np.isfinite(target)):
        raise SymkinError("the IK target must be a finite 4x4 homogeneous transform")
    if not tolerance > 0:
        raise ParameterError(f"the {{tolerance}} must be positive, got {tolerance}")
    # Rows in ascending order (the solution does not depend on it; all six need no indexing).
    order = np.argsort(rows_from_names(rows))
    indices = np.array(rows_from_names(rows))[order]
    weight_array = None
    if weights is not None:
        weight_array = _vector(weights, len(rows), f"weights (one per task row {','.join(rows)})")
        if np.any(weight_array <= 0):
            raise SymkinError(f"weights must be positive, got {weight_array.tolist()}")
        weight_array = weight_array[order]
    lower, upper = joint_bounds(model)
    revolute = np.array([j.type == "revolute" for j in model.robot.joints])
    return _Problem(
        fk_jacobian=generated_numpy_module(model, "kinematics").fk_jacobian,
        parameters=parameter_vector(model, overrides),
        rows=None if indices.size == 6 else indices,
        linear=np.flatnonzero(indices < 3),
        angular=np.flatnonzero(indices >= 3),
        weights=weight_array,
        lower=lower,
        upper=upper,
        revolute=revolute,
        target=target,
        tolerance=float(tolerance),
    )


def task_errors(
    model: Model,
    q: Sequence[float],
    target: np.ndarray,
    rows: Sequence[str] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> tuple[float, float]:
    """Position error (m) and rotation error (rad) of ``q`` for ``target`` on the task
    ``rows`` (default: the robot's task rows), the metric :func:`solve_ik` reports."""
    rows = task_rows_for(model, rows)
    problem = _problem(model, target, rows, None, DEFAULT_TOLERANCE, overrides)
    _, _, e = problem.evaluate(_vector(q, model.robot.dof, "q"))
    return problem.errors(e)


def _rest_configuration(
    model: Model, rest_posture: Sequence[float] | str | None
) -> np.ndarray | None:
    """The null-space preference: given joint values, the middle of the ranges, or none."""
    if rest_posture is None:
        return None
    if isinstance(rest_posture, str):
        if rest_posture != "middle":
            raise SymkinError(
                f"rest posture: expected {model.robot.dof} joint values or 'middle', "
                f"got {rest_posture!r}"
            )
        return middle_configuration(model)
    return _vector(rest_posture, model.robot.dof, "rest posture")


def _first_converged(
    problem: _Problem, starts: Iterable[np.ndarray], method: str, max_iterations: int
) -> tuple[_Attempt, int, int]:
    """Attempts from each start until one converges: the best attempt (the converged one, or
    the lowest error), the iterations of all attempts, and the number of restarts made."""
    best: _Attempt | None = None
    iterations = 0
    attempts = 0
    for start in starts:
        attempt = _attempt(problem, start, method, max_iterations)
        attempts += 1
        iterations += attempt.iterations
        if best is None or attempt.converged or attempt.energy < best.energy:
            best = attempt
        if best.converged:
            break
    assert best is not None  # starts always holds the first seed
    return best, iterations, attempts - 1


def _result(
    problem: _Problem,
    q: np.ndarray,
    tolerance: float,
    effort: tuple[int, int],
    rows: tuple[str, ...],
    method: str,
) -> IKResult:
    """The result at ``q`` with unlimited revolute joints wrapped to ``(-pi, pi]``, judged at
    the returned values themselves (wrapping changes them by multiples of 2 pi).  ``effort``:
    the iterations and restarts it took."""
    q = q.copy()
    q[problem.unlimited] = _wrap(q[problem.unlimited])
    pose, _, e = problem.evaluate(q)
    position_error, rotation_error = problem.errors(e)
    return IKResult(
        q=q,
        success=position_error <= tolerance and rotation_error <= tolerance,
        position_error=position_error,
        rotation_error=rotation_error,
        iterations=effort[0],
        restarts=effort[1],
        pose=pose,
        rows=rows,
        method=method,
    )


def solve_ik(
    model: Model,
    target: np.ndarray,
    q0: Sequence[float] | None = None,
    *,
    method: str = "lm",
    position_only: bool = False,
    task: Sequence[str] | None = None,
    weights: Sequence[float] | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    restarts: int = DEFAULT_RESTARTS,
    seed: int | None = 0,
    rest_posture: Sequence[float] | str | None = "middle",
    overrides: Mapping[str, float] | None = None,
) -> IKResult:
    """Joint values that put the tool at ``target`` (4x4 pose in the base frame).

    ``q0`` is the first seed (default: the middle of the joint ranges).  ``task`` names the rows
    to match (default :func:`task_rows_for`), ``weights`` weigh them (one per row, LM only).
    ``tolerance`` applies to the position error in metres and the rotation error in radians.
    Each attempt runs at most ``max_iterations`` iterations; up to ``restarts`` further attempts
    start from random configurations (``seed`` makes them reproducible).  ``rest_posture`` is
    the posture preferred in the null space when the task has fewer rows than the robot has
    joints (LM only): joint values, ``"middle"`` (the middle of the joint ranges) or ``None``
    (no preference: the solution the iteration reaches).  Returns the best attempt; see the
    module docstring for the metric.
    """
    if method not in METHODS:
        raise SymkinError(f"unknown IK method {method!r}; expected one of {', '.join(METHODS)}")
    if max_iterations < 1 or restarts < 0:
        raise ParameterError(
            f"need {{max_iterations}} >= 1 and {{restarts}} >= 0, got {max_iterations} and "
            f"{restarts}"
        )
    n = model.robot.dof
    rows = task_rows_for(model, task, position_only)
    problem = _problem(model, target, rows, weights, tolerance, overrides)
    seed_q = middle_configuration(model) if q0 is None else _vector(q0, n, "q0")
    rest = _rest_configuration(model, rest_posture)
    if method != "lm" or len(rows) >= n:
        rest = None  # no null space to move in (Newton: the lecture's plain iteration)
    rng = np.random.default_rng(seed)
    starts = (seed_q if k == 0 else random_configuration(model, rng) for k in range(restarts + 1))
    best, iterations, attempt_count = _first_converged(problem, starts, method, max_iterations)
    if not best.converged and method == "lm":
        # The closest pose: go on from the best attempt without the early stop.
        polished = _lm_attempt(problem, best.q, max_iterations, problem.has_limits, stall=False)
        iterations += polished.iterations
        best = polished if polished.energy < best.energy else best
    if rest is not None and best.converged:
        moved = _toward_rest(problem, best, rest)
        iterations += moved.iterations - best.iterations
        best = moved
    return _result(problem, best.q, tolerance, (iterations, attempt_count), rows, method)


__all__ = [
    "DEFAULT_RESTARTS",
    "DEFAULT_TOLERANCE",
    "METHODS",
    "IKResult",
    "newton_step",
    "rotation_vector",
    "solve_ik",
    "task_errors",
    "task_rows_for",
]

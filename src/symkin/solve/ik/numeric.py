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
from types import ModuleType

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.errors import ParameterError, SymkinError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.backends import (
    choose_backend,
    dls_extension,
    dls_settings,
    fits_dls,
    run_dls,
    solve_dls,
)
from symkin.solve.ik.joints import (
    joint_data,
    joint_vector,
    parameter_vector,
    random_configuration,
    rest_configuration,
    wrap_angles,
)
from symkin.solve.ik.result import IKResult
from symkin.solve.ik.steps import newton_step, null_space_step, rotation_vector
from symkin.solve.ik.target import task_rows_for

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
# Limits are met when exceeded by no more than this (rounding of the 2 pi shifts).
LIMIT_SLACK = 1e-12


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
    unlimited: np.ndarray  # revolute joints without limits (angles count modulo 2 pi)
    has_limits: bool
    target: np.ndarray
    tolerance: float

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
        difference[problem.unlimited] = wrap_angles(difference[problem.unlimited])
        return float(np.linalg.norm(difference))

    q, iterations = solution.q, solution.iterations
    for _ in range(POSTURE_ROUNDS):
        _, J, _ = problem.evaluate(q)
        toward = rest - q
        toward[problem.unlimited] = wrap_angles(toward[problem.unlimited])  # the short way round
        null_step = null_space_step(J, toward)
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


def _target(target: np.ndarray) -> np.ndarray:
    target = np.asarray(target, dtype=float)
    if target.shape != (4, 4) or not np.isfinite(target).all():
        raise SymkinError("the IK target must be a finite 4x4 homogeneous transform")
    return target


def _problem(
    model: Model,
    target: np.ndarray,
    rows: tuple[str, ...],
    weights: Sequence[float] | None,
    tolerance: float,
    overrides: Mapping[str, float] | None,
    fk_jacobian: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None,
) -> _Problem:
    """The problem; ``fk_jacobian`` defaults to the generated NumPy kernel."""
    target = _target(target)
    if not tolerance > 0:
        raise ParameterError(f"the {{tolerance}} must be positive, got {tolerance}")
    # Rows in ascending order (the solution does not depend on it; all six need no indexing).
    names = np.array(rows_from_names(rows))
    order = np.argsort(names)
    indices = names[order]
    weight_array = None
    if weights is not None:
        weight_array = joint_vector(
            weights, len(rows), f"weights (one per task row {','.join(rows)})"
        )
        if np.any(weight_array <= 0):
            raise SymkinError(f"weights must be positive, got {weight_array.tolist()}")
        weight_array = weight_array[order]
    joints = joint_data(model)
    parameters = joints.parameters
    if overrides is not None or parameters is None:
        parameters = parameter_vector(model, overrides)  # names a missing value
    if fk_jacobian is None:
        fk_jacobian = generated_numpy_module(model, "kinematics").fk_jacobian
    return _Problem(
        fk_jacobian=fk_jacobian,
        parameters=parameters,
        rows=None if indices.size == 6 else indices,
        linear=np.flatnonzero(indices < 3),
        angular=np.flatnonzero(indices >= 3),
        weights=weight_array,
        lower=joints.lower,
        upper=joints.upper,
        revolute=joints.revolute,
        unlimited=joints.unlimited,
        has_limits=joints.has_limits,
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
    _, _, e = problem.evaluate(joint_vector(q, model.robot.dof, "q"))
    return problem.errors(e)


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
    backend: str,
) -> IKResult:
    """The result at ``q`` with unlimited revolute joints wrapped to ``(-pi, pi]``, judged at
    the returned values themselves (wrapping changes them by multiples of 2 pi).  ``effort``:
    the iterations and restarts it took."""
    q = np.array(q, dtype=float)
    if problem.unlimited.any():
        q[problem.unlimited] = wrap_angles(q[problem.unlimited])
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
        backend=backend,
    )


def _solve_python(
    model: Model,
    problem: _Problem,
    seed_q: np.ndarray,
    method: str,
    limits: tuple[int, int, int | None],
) -> tuple[_Attempt, int, int]:
    """The general solver: attempts from ``seed_q`` and random starts, then (LM) the closest
    pose when none converged.  ``limits``: max iterations, restarts, seed."""
    max_iterations, restarts, seed = limits
    rng = np.random.default_rng(seed)
    starts = (seed_q if k == 0 else random_configuration(model, rng) for k in range(restarts + 1))
    best, iterations, attempt_count = _first_converged(problem, starts, method, max_iterations)
    if not best.converged and method == "lm":
        # The closest pose: go on from the best attempt without the early stop.
        polished = _lm_attempt(problem, best.q, max_iterations, problem.has_limits, stall=False)
        iterations += polished.iterations
        best = polished if polished.energy < best.energy else best
    return best, iterations, attempt_count


def _solve_dls(
    model: Model,
    problem: _Problem,
    seed_q: np.ndarray,
    extension: ModuleType | None,
    options: tuple[int, int, int | None, Mapping[str, float] | None],
) -> tuple[_Attempt, int]:
    """The damped least squares, compiled (``extension``) or in NumPy
    (:mod:`symkin.solve.ik.backends`): the answer and the restarts it took."""
    max_iterations, restarts, seed, overrides = options
    run = run_dls(
        model,
        extension,
        problem.target,
        seed_q,
        (problem.lower, problem.upper),
        problem.parameters,
        dls_settings(max_iterations, restarts, problem.tolerance, seed),
        problem.linear.size + problem.angular.size == 3,
        overrides,
    )
    return _Attempt(run.q, 0.0, run.converged, run.iterations), run.restarts


def _attempts(
    model: Model,
    problem: _Problem,
    seed_q: np.ndarray,
    method: str,
    extension: ModuleType | str | None,
    options: tuple[int, int, int | None, Mapping[str, float] | None],
) -> tuple[_Attempt, int, int, str]:
    """The best attempt, all iterations, the restarts and the backend that ran: the general
    solver when ``extension`` is ``"python"``, else the damped least squares (compiled with
    an extension module, NumPy with ``None``)."""
    if extension == "python":
        best, iterations, restarts = _solve_python(model, problem, seed_q, method, options[:3])
        return best, iterations, restarts, "python"
    assert not isinstance(extension, str)
    best, restarts = _solve_dls(model, problem, seed_q, extension, options)
    return best, best.iterations, restarts, "numpy" if extension is None else "c"


def _check_arguments(method: str, max_iterations: int, restarts: int, tolerance: float) -> None:
    if not tolerance > 0:
        raise ParameterError(f"the {{tolerance}} must be positive, got {tolerance}")
    if method not in METHODS:
        raise SymkinError(f"unknown IK method {method!r}; expected one of {', '.join(METHODS)}")
    if max_iterations < 1 or restarts < 0:
        raise ParameterError(
            f"need {{max_iterations}} >= 1 and {{restarts}} >= 0, got {max_iterations} and "
            f"{restarts}"
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
    backend: str = "auto",
) -> IKResult:
    """Joint values that put the tool at ``target`` (4x4 pose in the base frame).

    ``q0`` is the first seed (default: the middle of the joint ranges).  ``task`` names the rows
    to match (default :func:`task_rows_for`), ``weights`` weigh them (one per row, LM only).
    ``tolerance`` applies to the position error in metres and the rotation error in radians.
    Each attempt runs at most ``max_iterations`` iterations; up to ``restarts`` further attempts
    start from random configurations (``seed`` makes them reproducible).  ``rest_posture`` is
    the posture preferred in the null space when the task has fewer rows than the robot has
    joints (LM only): joint values, ``"middle"`` (the middle of the joint ranges) or ``None``
    (no preference: the solution the iteration reaches).  ``backend`` picks the
    implementation (:mod:`symkin.solve.ik.backends`: ``"auto"``, ``"c"``, ``"numpy"``,
    ``"python"``); the result names the one that ran.  Returns the best attempt; see the
    module docstring for the metric.
    """
    _check_arguments(method, max_iterations, restarts, tolerance)
    n = model.robot.dof
    rows = task_rows_for(model, task, position_only)
    target = _target(target)
    backend = choose_backend(backend, fits_dls(method, rows, weights, target))
    extension = dls_extension(model, backend)
    seed_q = joint_data(model).middle if q0 is None else joint_vector(q0, n, "q0")
    rest = rest_configuration(model, rest_posture)
    if method != "lm" or len(rows) >= n:
        rest = None  # no null space to move in (Newton: the lecture's plain iteration)
    if backend != "python" and rest is None:  # the short way: no Python-side iteration
        settings = dls_settings(max_iterations, restarts, tolerance, seed)
        return solve_dls(model, extension, target, seed_q, rows, settings, overrides)
    fk_jacobian = None if extension is None else extension.fk_jacobian
    problem = _problem(model, target, rows, weights, tolerance, overrides, fk_jacobian)
    best, iterations, attempt_count, backend = _attempts(
        model, problem, seed_q, method, extension if backend != "python" else "python",
        (max_iterations, restarts, seed, overrides),
    )  # fmt: skip
    if rest is not None and best.converged:
        moved = _toward_rest(problem, best, rest)
        iterations += moved.iterations - best.iterations
        best = moved
    effort = (iterations, attempt_count)
    return _result(problem, best.q, tolerance, effort, rows, method, backend)


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

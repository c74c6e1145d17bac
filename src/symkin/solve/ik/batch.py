"""Damped-least-squares IK over a batch of targets, the NumPy twin of the generated C solver.

The algorithm is the C library's ``symkin_dls_solve`` (``templates/c/lib/symkin_dls.c``, pasted
into the generated ``<robot>_ik.c``; docs/ik-generated.md), step for step, vectorised over
poses with the generated NumPy ``fk_jacobian`` kernel (which broadcasts over a leading batch
axis).  Every pose runs its own iteration on its own random stream, so a
batch gives the same answer as solving each pose alone.

* Error (base frame): ``e = [p_t - p; r]`` with ``r`` the rotation vector of ``R_t R^T``
  (:func:`symkin.solve.ik.numeric.rotation_vector`), ``E = e^T e / 2`` over the matched rows
  (``x y z`` when ``position_only``, all six otherwise).
* Step: ``(J^T J + lambda I) dq = J^T e`` with ``lambda = error_damping * E + damping``:
  Sugihara's ``lambda = E + lambda_bar`` (IEEE Trans. Robotics 27(5), 2011) with ``E``
  weighted.  Every step is taken.  A weight of 0.1 instead of Sugihara's 1 halves the
  iterations on random PUMA 560 and Panda targets; rejecting steps that raise ``E``
  (Marquardt's rule, :mod:`symkin.solve.ik.numeric`) costs two to four times as many iterations.
* Limits: a revolute joint outside its limits first moves by the multiple of ``2 pi`` that
  brings it nearest the middle of its range, then every joint is clamped.
* Restarts: an attempt ends after ``max_iterations`` steps, or when it stalls (``E`` above
  ``STALL_FACTOR`` times its value ``STALL_WINDOW`` steps earlier), or when the system is not
  numerically positive definite; the next attempt starts from a configuration drawn uniformly
  within the limits by Marsaglia's xorshift64 (shifts 13, 7, 17), seeded by ``seed``.  A joint
  without a limit is drawn from a range of width ``2 pi`` (revolute) or 2 m (prismatic)
  centred on 0 or ending at its one limit.  A pose that does not converge returns the
  configuration with the lowest ``E`` seen.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.kernels.ik.settings import (
    FALLBACK_SEED,
    PRISMATIC_SPAN,
    REVOLUTE_SPAN,
    STALL_FACTOR,
    STALL_WINDOW,
    DampedLeastSquares,
)
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.joints import joint_bounds, parameter_vector


@dataclass(frozen=True)
class BatchIKResult:
    """One row per target: ``q`` (best configuration found), ``success``, the errors at
    ``q`` (position in m, rotation angle in rad), steps over all attempts and restarts."""

    q: np.ndarray
    success: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    iterations: np.ndarray
    restarts: np.ndarray


def pose_errors(targets: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, ...]:
    """``e = [p_t - p; r]`` per pose (``r``: rotation vector of ``R_t R^T``), ``|p_t - p|`` and
    the rotation angle, for stacks of 4x4 transforms (the C ``symkin_pose_error``, vectorised)."""
    E = targets[:, :3, :3] @ np.swapaxes(poses[:, :3, :3], 1, 2)
    w = np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], 1)
    w = w / 2
    c = (E[:, 0, 0] + E[:, 1, 1] + E[:, 2, 2] - 1) / 2
    s = np.sqrt(np.sum(w * w, axis=1))
    angle = np.arctan2(s, c)
    scale = np.divide(angle, s, out=np.ones_like(s), where=s > 0)
    r = scale[:, None] * w
    for b in np.flatnonzero(c < 0):  # near pi: the axis from the symmetric part
        m = int(np.argmax(np.diag(E[b])))
        k_m = math.sqrt((E[b, m, m] - c[b]) / (1 - c[b]))
        k = (E[b, m, :] + E[b, :, m]) / (2 * (1 - c[b]) * k_m)
        k[m] = k_m
        sign = -1.0 if k @ w[b] < 0 else 1.0
        r[b] = sign * angle[b] * k / math.sqrt(k @ k)
    e = np.concatenate([targets[:, :3, 3] - poses[:, :3, 3], r], axis=1)
    return e, np.sqrt(np.sum(e[:, :3] ** 2, axis=1)), angle


def limit_joints(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> np.ndarray:
    """Revolute joints outside their limits moved by ``2 pi k`` toward the middle of the
    range, then every joint clamped (the C ``symkin_dls_limit``)."""
    outside = revolute & ((q < lower) | (q > upper)) & np.isfinite(lower) & np.isfinite(upper)
    with np.errstate(invalid="ignore"):  # inf - inf where a limit is missing; masked out
        middle = (lower + upper) / 2
        shifted = q - 2 * math.pi * np.floor((q - middle) / (2 * math.pi) + 0.5)
    return np.clip(np.where(outside, shifted, q), lower, upper)


def _uniform(states: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """One xorshift64 (13, 7, 17) step of the chosen rows' states (updated in place), as
    uniform numbers in [0, 1] from the top 53 bits."""
    x = states[rows]
    x ^= x << np.uint64(13)
    x ^= x >> np.uint64(7)
    x ^= x << np.uint64(17)
    states[rows] = x
    return (x >> np.uint64(11)).astype(float) * 2.0**-53


def sample_ranges(
    model: Model, lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Where restarts draw each joint: the limits, or a span where one or both are missing."""
    span = np.array(
        [REVOLUTE_SPAN if j.type == "revolute" else PRISMATIC_SPAN for j in model.robot.joints]
    )
    low = np.where(np.isfinite(lower), lower, np.where(np.isfinite(upper), upper - span, -span / 2))
    high = np.where(np.isfinite(upper), upper, np.where(np.isfinite(lower), lower + span, span / 2))
    return low, high


def _as_stack(values, shape: tuple[int, ...], what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape == shape:
        array = array[None]
    if array.ndim != len(shape) + 1 or array.shape[1:] != shape:
        raise SymkinError(
            f"{what}: expected shape {shape} or (count, {', '.join(map(str, shape))})"
            f", got {array.shape}"
        )
    if not np.all(np.isfinite(array)):
        raise SymkinError(f"{what}: expected finite numbers")
    return array


# long: one loop over the batch that mirrors templates/c/lib/symkin_dls.c step for step
# (error, convergence, stall, damped step, restart); split, the correspondence is lost.
def solve_ik_batch(
    model: Model,
    targets: np.ndarray,
    seeds: np.ndarray,
    *,
    position_only: bool = False,
    settings: DampedLeastSquares = DampedLeastSquares(),
    limits: tuple[Sequence[float], Sequence[float]] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> BatchIKResult:
    """Joint values for each 4x4 target (``(count, 4, 4)``) from each seed (``(count, n)``).

    ``limits`` replaces the robot file's joint limits (``(lower, upper)``, ``-inf``/``inf`` for
    none).  Every pose draws its restarts from its own xorshift64 stream started at
    ``settings.seed``, as the C solver does.  See the module docstring for the method.
    """
    n = model.robot.dof
    targets = _as_stack(targets, (4, 4), "targets")
    seeds = _as_stack(seeds, (n,), "seeds")
    if len(targets) != len(seeds):
        raise SymkinError(f"{len(targets)} targets but {len(seeds)} seeds; give one per target")
    lower, upper = joint_bounds(model) if limits is None else map(np.asarray, limits)
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    if lower.shape != (n,) or upper.shape != (n,) or not np.all(lower <= upper):
        raise SymkinError(f"limits: expected lower <= upper, {n} values each")
    revolute = np.array([j.type == "revolute" for j in model.robot.joints])
    low, high = sample_ranges(model, lower, upper)
    fk_jacobian = generated_numpy_module(model, "kinematics").fk_jacobian
    p = parameter_vector(model, overrides)
    rows = 3 if position_only else 6
    count = len(targets)

    q = limit_joints(seeds, lower, upper, revolute)
    best = q.copy()
    best_error = np.full(count, np.inf)
    position_error = np.full(count, np.inf)
    rotation_error = np.full(count, np.inf)
    success = np.zeros(count, dtype=bool)
    running = np.ones(count, dtype=bool)
    step = np.zeros(count, dtype=int)
    iterations = np.zeros(count, dtype=int)
    restarts = np.zeros(count, dtype=int)
    history = np.zeros((count, STALL_WINDOW))
    states = np.full(count, settings.seed or FALLBACK_SEED, dtype=np.uint64)

    while running.any():
        active = np.flatnonzero(running)
        T, J = fk_jacobian(q[active], p)
        e, pe, re = pose_errors(targets[active], T)
        error = np.sum(e[:, :rows] * e[:, :rows] / 2, axis=1)
        better = error < best_error[active]
        improved = active[better]
        best_error[improved] = error[better]
        best[improved] = q[improved]
        position_error[improved], rotation_error[improved] = pe[better], re[better]

        converged = (pe < settings.position_tolerance) & (
            position_only | (re < settings.rotation_tolerance)
        )
        done = active[converged]
        success[done] = True
        running[done] = False
        position_error[done], rotation_error[done] = pe[converged], re[converged]

        slot = step[active] % STALL_WINDOW
        stalled = (step[active] >= STALL_WINDOW) & (error > STALL_FACTOR * history[active, slot])
        history[active, slot] = error
        stepping = ~converged & ~stalled & (step[active] < settings.max_iterations)
        dq, solved = _damped_steps(
            J[stepping, :rows],
            e[stepping, :rows],
            settings.error_damping * error[stepping] + settings.damping,
        )
        moving = active[stepping][solved]
        q[moving] = limit_joints(q[moving] + dq[solved], lower, upper, revolute)
        step[moving] += 1
        iterations[moving] += 1

        stuck = active[~converged & ~np.isin(active, moving)]
        exhausted = stuck[restarts[stuck] == settings.max_restarts]
        running[exhausted] = False
        q[exhausted] = best[exhausted]
        again = stuck[restarts[stuck] < settings.max_restarts]
        restarts[again] += 1
        step[again] = 0
        for i in range(n):  # joint by joint, as C draws them
            draw = _uniform(states, again)
            q[again, i] = low[i] + draw * (high[i] - low[i])

    return BatchIKResult(q, success, position_error, rotation_error, iterations, restarts)


def _damped_steps(
    J: np.ndarray, e: np.ndarray, damping: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(J^T J + damping I)^-1 J^T e`` per pose, and which systems were positive definite
    (the C code's Cholesky test; the others restart)."""
    n = J.shape[-1]
    H = np.swapaxes(J, 1, 2) @ J + damping[:, None, None] * np.eye(n)
    g = np.einsum("bji,bj->bi", J, e)
    solved = np.ones(len(J), dtype=bool)
    try:
        factor = np.linalg.cholesky(H)
    except np.linalg.LinAlgError:
        factor = np.zeros_like(H)
        for b in range(len(H)):
            try:
                factor[b] = np.linalg.cholesky(H[b])
            except np.linalg.LinAlgError:
                solved[b] = False
                factor[b] = np.eye(n)
    y = np.linalg.solve(factor, g[..., None])
    dq = np.linalg.solve(np.swapaxes(factor, 1, 2), y)[..., 0]
    return dq, solved

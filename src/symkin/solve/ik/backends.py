"""Which implementation runs :func:`symkin.solve.ik.numeric.solve_ik` (docs/ik.md, "Backends").

* ``"c"``: the generated C solver (``c/<robot>_ik.c``: damped least squares with Sugihara's
  damping, ``templates/c/lib/symkin_dls.c``) through a CPython extension built once per robot
  and process (:mod:`symkin.runtime.compiled_ik`);
* ``"numpy"``: the same algorithm step for step in NumPy
  (:func:`symkin.solve.ik.batch.solve_ik_batch`), when the extension cannot be built (no C
  compiler, a failed build);
* ``"python"``: the general solver of :mod:`symkin.solve.ik.numeric` (Marquardt's
  Levenberg–Marquardt with step rejection, or Newton), for what the damped least squares does
  not offer: ``method="newton"``, ``weights``, task rows other than all six or ``x y z``, or a
  target whose rotation is not orthonormal (to 1e-6).

``"auto"`` (the default) takes ``"c"``, else ``"numpy"``, when the request fits the damped
least squares, and ``"python"`` otherwise.  ``"c"`` and ``"numpy"`` share the settings of
:mod:`symkin.kernels.ik.settings` and are given the same tolerance, iteration cap, restarts,
joint limits and seed, so they return the same answers up to rounding.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from types import ModuleType

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError, SymkinError
from symkin.kernels.ik.settings import ORTHONORMAL_TOLERANCE, DampedLeastSquares
from symkin.runtime.compiled_ik import ik_extension
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.batch import pose_errors, solve_ik_batch
from symkin.solve.ik.joints import joint_data, parameter_vector, wrap_angles
from symkin.solve.ik.result import IKResult

BACKENDS = ("auto", "c", "numpy", "python")
ALL_ROWS = frozenset(("x", "y", "z", "wx", "wy", "wz"))
POSITION_ROWS = frozenset(("x", "y", "z"))
_IDENTITY = np.eye(3)


@dataclass(frozen=True)
class DlsRun:
    """The damped least squares' answer: ``q``, whether it converged, its effort, which
    backend ran and the errors at ``q``."""

    q: np.ndarray
    converged: bool
    iterations: int
    restarts: int
    backend: str
    position_error: float  # |p_t - p| at q (m)
    rotation_error: float  # the angle of R_t R^T at q (rad)


def fits_dls(method: str, rows: tuple[str, ...], weights: object, target: np.ndarray) -> bool:
    """Whether the damped least squares can solve the request (see the module docstring)."""
    if method != "lm" or weights is not None or frozenset(rows) not in (ALL_ROWS, POSITION_ROWS):
        return False
    R = target[:3, :3]
    return bool(np.abs(R.T @ R - _IDENTITY).max() <= ORTHONORMAL_TOLERANCE["double"])


def choose_backend(backend: str, fits: bool) -> str:
    """``backend`` as asked, ``"python"`` for an ``"auto"`` request that does not fit."""
    if backend not in BACKENDS:
        raise ParameterError(
            f"unknown IK {{backend}} {backend!r}; expected one of {', '.join(BACKENDS)}"
        )
    if backend == "python" or (backend == "auto" and not fits):
        return "python"
    if not fits:
        raise ParameterError(
            f"the {{backend}} {backend!r} runs damped least squares: method 'lm', all six "
            "task rows or x y z, no weights, an orthonormal target rotation; use 'python'"
        )
    return backend


def dls_extension(model: Model, backend: str) -> ModuleType | None:
    """The compiled solver for ``"c"`` and ``"auto"`` (``None`` for ``"auto"`` when it cannot
    be built: then NumPy runs); ``None`` for ``"numpy"`` and ``"python"``."""
    if backend not in ("auto", "c"):
        return None
    try:
        return ik_extension(model)
    except SymkinError:
        if backend == "c":
            raise
        return None


@lru_cache(maxsize=64)
def _settings(
    max_iterations: int, restarts: int, tolerance: float, seed: int
) -> DampedLeastSquares:
    return DampedLeastSquares(
        max_iterations=max_iterations,
        max_restarts=restarts,
        position_tolerance=tolerance,
        rotation_tolerance=tolerance,
        seed=seed,
    )


def dls_settings(
    max_iterations: int, restarts: int, tolerance: float, seed: int | None
) -> DampedLeastSquares:
    """The solver's settings for ``solve_ik``'s arguments (``seed=None``: a fresh one)."""
    if seed is None:
        seed = int(np.random.default_rng().integers(1, 2**63))
    return _settings(int(max_iterations), int(restarts), float(tolerance), int(seed))


def run_dls(
    model: Model,
    extension: ModuleType | None,
    target: np.ndarray,
    seed_q: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray],
    parameters: np.ndarray,
    settings: DampedLeastSquares,
    position_only: bool,
    overrides: Mapping[str, float] | None,
) -> DlsRun:
    """Solve by damped least squares: compiled when ``extension`` is given, else NumPy."""
    if extension is not None:
        q, status, iterations, restarts, position, rotation = extension.ik(
            target, seed_q, parameters, *limits,
            settings.max_iterations, settings.max_restarts,
            settings.position_tolerance, settings.rotation_tolerance,
            settings.damping, settings.error_damping, position_only, settings.seed,
        )  # fmt: skip
        if status == 2:  # the checks before the call make this unreachable
            raise SymkinError("the compiled IK solver rejected its input as invalid")
        return DlsRun(q, status == 0, iterations, restarts, "c", position, rotation)
    batch = solve_ik_batch(
        model,
        target[None],
        seed_q[None],
        position_only=position_only,
        settings=settings,
        limits=limits,
        overrides=overrides,
    )
    return DlsRun(
        batch.q[0].copy(),
        bool(batch.success[0]),
        int(batch.iterations[0]),
        int(batch.restarts[0]),
        "numpy",
        float(batch.position_error[0]),
        float(batch.rotation_error[0]),
    )


def solve_dls(
    model: Model,
    extension: ModuleType | None,
    target: np.ndarray,
    seed_q: np.ndarray,
    rows: tuple[str, ...],
    settings: DampedLeastSquares,
    overrides: Mapping[str, float] | None,
) -> IKResult:
    """``solve_ik`` by damped least squares alone (no rest posture to move toward).

    The errors are the solver's own at the returned ``q`` (the metric of ``solve_ik``: with
    ``x y z`` rows the rotation error is 0), and success is judged on them as ``solve_ik``
    judges (both at or below the tolerance).  Revolute joints without limits are wrapped to
    ``(-pi, pi]``; if that moved one, the errors are measured again at the wrapped values.
    """
    joints = joint_data(model)
    parameters = joints.parameters
    if overrides is not None or parameters is None:
        parameters = parameter_vector(model, overrides)  # names a missing value
    position_only = len(rows) == 3
    limits = (joints.lower, joints.upper)
    run = run_dls(
        model, extension, target, seed_q, limits, parameters, settings, position_only, overrides
    )
    q = run.q
    fk_jacobian = (
        extension.fk_jacobian
        if extension is not None
        else generated_numpy_module(model, "kinematics").fk_jacobian
    )
    position, rotation = run.position_error, run.rotation_error
    if joints.unlimited.any():
        wrapped = wrap_angles(q[joints.unlimited])
        if np.any(wrapped != q[joints.unlimited]):
            q[joints.unlimited] = wrapped
            _, position, rotation = pose_errors(target[None], fk_jacobian(q, parameters)[0][None])
            position, rotation = float(position[0]), float(rotation[0])
    pose = fk_jacobian(q, parameters)[0]
    rotation = 0.0 if position_only else rotation
    tolerance = settings.position_tolerance
    return IKResult(
        q=q,
        success=position <= tolerance and rotation <= tolerance,
        position_error=position,
        rotation_error=rotation,
        iterations=run.iterations,
        restarts=run.restarts,
        pose=pose,
        rows=rows,
        method="lm",
        backend=run.backend,
    )

"""Straight Cartesian paths: the lecture's Newton path scheme and a path follower.

**The lecture's scheme** (:func:`newton_path_table`).  The segment from ``X_0`` to ``X_end``
(task coordinates: the chosen position rows, e.g. ``x, y`` for a planar arm) is split into
``k`` equal steps, ``X_i = X_0 + i (X_end - X_0) / k``.  Starting from a known pair
``(X_0, Q_0)``, each waypoint costs one Newton step::

    Q_{i+1} = Q_i + J^-1(Q_i) (X_{i+1} - X_i,real)

where ``X_0,real`` is the given ``X_0`` and later ``X_i,real = FK(Q_i)``: each step aims from
where the arm really is, so the linearisation errors do not add up along the path.  At the end
point, Newton steps ``Q += J^-1(Q) (X_end - FK(Q))`` repeat until the error is below the
tolerance; these rows are labelled ``ka, kb, ...`` (``5a, 5b`` for ``k = 5``).  ``J`` is the
task rows of the geometric Jacobian; it is inverted when square, otherwise its pseudo-inverse
(least squares, minimum norm) is used.  Joint limits play no part in the scheme.

Each table row holds ``target = X_i``, ``q = Q_i``, ``real = X_i,real`` and, as the lecture's
``dx, dy`` columns "for Gl. (14.15)", ``delta``: the increment fed into the next Newton step,
``X_{i+1} - X_i,real`` (row 0: ``X_1 - X_0``), and at the end point (row ``k`` and the
correction rows ``ka, kb, ...``) ``X_k - X_k,real``.  Every row's step is therefore
``Q_next = Q_i + J^-1(Q_i) delta_i``, and the last row's ``delta`` is the error left at the end.
:attr:`PathRow.error` is the error left at a row, ``X_i - X_i,real``.

**The path follower** (:func:`follow_path`) solves every waypoint to tolerance with
:func:`symkin.solve.ik.numeric.solve_ik`, each seeded with the previous solution; positions are
interpolated linearly and orientations along the shortest rotation (``R_i = R_0 exp(i/k r)``,
``r`` the rotation vector of ``R_0^T R_end``).
"""

from __future__ import annotations

import string
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.emit.latex.number_table import number_table_document
from symkin.errors import ParameterError, SymkinError, literal
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.joints import parameter_vector
from symkin.solve.ik.numeric import (
    DEFAULT_TOLERANCE,
    IKResult,
    newton_step,
    rotation_vector,
    solve_ik,
)
from symkin.spatial import rotation_from_axis_angle

POSITION_ROWS = ("x", "y", "z")
DEFAULT_CORRECTIONS = 20
# A start pair whose FK misses X_0 by more than this (m) gets a warning.
START_MISMATCH = 1e-6


@dataclass(frozen=True)
class PathRow:
    """One row of the lecture's table (task coordinates in ``NewtonPath.task`` order);
    ``delta`` is the increment for the next step (module docstring)."""

    label: str
    target: np.ndarray
    q: np.ndarray
    real: np.ndarray
    delta: np.ndarray

    @property
    def error(self) -> np.ndarray:
        """``X_i - X_i,real``: how far the row's reached position misses its own target."""
        return self.target - self.real


@dataclass(frozen=True)
class NewtonPath:
    """The table of :func:`newton_path_table`; ``converged`` when the last ``delta`` is within
    the tolerance."""

    task: tuple[str, ...]
    rows: tuple[PathRow, ...]
    converged: bool


def correction_label(steps: int, index: int) -> str:
    """``"5a"``, ``"5b"``, ... ``"5z"``, ``"5aa"``: the ``index``-th (0-based) Newton row after
    the last step ``steps``."""
    letters = ""
    index += 1
    while index:
        index, remainder = divmod(index - 1, 26)
        letters = string.ascii_lowercase[remainder] + letters
    return f"{steps}{letters}"


def path_task_rows(model: Model, task: Sequence[str] | None = None) -> tuple[str, ...]:
    """Position rows of the path: ``task`` (a subset of x, y, z), else those among the robot's
    default task rows (planar 2R: ``x y``)."""
    if task is None:
        rows = tuple(r for r in model.task_rows if r in POSITION_ROWS) or POSITION_ROWS
    else:
        rows = tuple(task)
        rows_from_names(rows)
        if not rows or any(r not in POSITION_ROWS for r in rows):
            raise ParameterError(
                f"{{task}}: the path interpolates positions; choose rows from x, y, z, got "
                f"{literal(','.join(rows)) or 'none'}"
            )
    return rows


def newton_path_table(
    model: Model,
    x0: Sequence[float],
    q0: Sequence[float],
    x_end: Sequence[float],
    steps: int,
    *,
    task: Sequence[str] | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    max_corrections: int = DEFAULT_CORRECTIONS,
    overrides: Mapping[str, float] | None = None,
) -> NewtonPath:
    """The lecture's table from ``(x0, q0)`` to ``x_end`` in ``steps`` Newton steps, then Newton
    corrections at the end point (at most ``max_corrections``) until ``|delta| <= tolerance``.

    ``x0`` and ``x_end`` hold one value per task row (:func:`path_task_rows`).
    """
    rows = path_task_rows(model, task)
    indices = list(rows_from_names(rows))
    n = model.robot.dof
    start, end, q = (
        _values(x0, len(rows), f"path start ({','.join(rows)})"),
        _values(x_end, len(rows), f"path end ({','.join(rows)})"),
        _values(q0, n, "q0"),
    )
    if steps < 1:
        raise ParameterError(f"{{steps}}: need at least 1 step, got {steps}")
    fk_jacobian = generated_numpy_module(model, "kinematics").fk_jacobian
    p = parameter_vector(model, overrides)

    def position_and_jacobian(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        T, J = fk_jacobian(q, p)
        return T[indices, 3], J[indices]

    reached, J = position_and_jacobian(q)
    mismatch = float(np.linalg.norm(reached - start))
    if mismatch > START_MISMATCH:
        warnings.warn(
            f"q0 puts the tool {mismatch:.3g} m away from the path start; the table starts "
            "from the given pair all the same (row 0's real position is the given start)",
            stacklevel=2,
        )
    targets = [start + i * (end - start) / steps for i in range(steps)] + [end]
    # Row 0's real position is the given start (the known pair), not FK(q0).
    table = [PathRow("0", start, q, start, targets[1] - start)]
    for i in range(1, steps + 1):
        q = q + newton_step(J, table[-1].delta)
        real, J = position_and_jacobian(q)
        aim = targets[min(i + 1, steps)]
        table.append(PathRow(str(i), targets[i], q, real, aim - real))
    for k in range(max_corrections):
        if np.linalg.norm(table[-1].delta) <= tolerance:
            break
        q = q + newton_step(J, table[-1].delta)
        real, J = position_and_jacobian(q)
        table.append(PathRow(correction_label(steps, k), end, q, real, end - real))
    converged = bool(np.linalg.norm(table[-1].delta) <= tolerance)
    return NewtonPath(rows, tuple(table), converged)


def _values(values: Sequence[float], count: int, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float).reshape(-1)
    if array.size != count:
        raise SymkinError(f"{what}: expected {count} values, got {array.size}")
    return array


def path_table_text(path: NewtonPath, joint_names: Sequence[str]) -> str:
    """The table as the lecture prints it: ``i``, the targets, the joints, the reached
    position and ``delta``, the increment for the next step (Gl. (14.15))."""
    head = (
        [f"{r}_i" for r in path.task]
        + list(joint_names)
        + [f"{r}_real" for r in path.task]
        + [f"d{r}" for r in path.task]
    )
    lines = [f"{'i':>4}" + "".join(f"{h:>12}" for h in head)]
    for row in path.rows:
        values = [*row.target, *row.q, *row.real]
        lines.append(
            f"{row.label:>4}"
            + "".join(f"{v + 0.0:>12.6f}" for v in values)
            + "".join(f"{d + 0.0:>12.3e}" for d in row.delta)
        )
    return "\n".join(lines)


def path_table_json(path: NewtonPath) -> dict:
    """The table as JSON-ready data: rows with keys ``i``, ``target``, ``q``, ``real``,
    ``delta``."""
    return {
        "task": list(path.task),
        "converged": path.converged,
        "rows": [
            {
                "i": row.label,
                "target": row.target.tolist(),
                "q": row.q.tolist(),
                "real": row.real.tolist(),
                "delta": row.delta.tolist(),
            }
            for row in path.rows
        ],
    }


# The lecture's words over the dx, dy columns, by language of the document.
INCREMENT_HEADING = {"en": "for eq. (14.15)", "de": "für Gl. (14.15)"}
TABLE_TITLE = {
    "en": "Newton path of {name} in {steps} steps (Tabelle 14-2/14-3 layout)",
    "de": "Newton-Verfahren für {name} in {steps} Schritten",
}


def path_table_latex(path: NewtonPath, robot_name: str, steps: int, lang: str = "en") -> str:
    """The table as a standalone LaTeX document in the lecture's column layout: ``i``,
    ``x_i, y_i``, ``q_1 .. q_n``, ``x_i,real, y_i,real``, then ``dx, dy`` under the heading
    "for Gl. (14.15)" (German: decimal comma).  Units are the robot file's (m, rad)."""
    if lang not in INCREMENT_HEADING:
        raise ParameterError(f"{{lang}} must be one of en, de, got {literal(repr(lang))}")
    task = path.task
    n = len(path.rows[0].q)
    headings = (
        [f"{r}_{{i}}" for r in task]
        + [f"q_{{{j}}}" for j in range(1, n + 1)]
        + [rf"{r}_{{i,\mathrm{{real}}}}" for r in task]
        + [rf"\Delta {r}" for r in task]
    )
    rows = [(row.label, [*row.target, *row.q, *row.real, *row.delta]) for row in path.rows]
    return number_table_document(
        TABLE_TITLE[lang].format(name=robot_name, steps=steps),
        headings,
        rows,
        group=(INCREMENT_HEADING[lang], len(task)),
        decimal_comma=lang == "de",
        comment=f"Newton path table of {robot_name}, generated by symkin ik --table --latex",
    )


def waypoint_poses(start: np.ndarray, end: np.ndarray, steps: int) -> tuple[np.ndarray, ...]:
    """``steps + 1`` poses from ``start`` to ``end`` (4x4): positions on the straight segment,
    orientations along the shortest rotation between the two."""
    if steps < 1:
        raise ParameterError(f"{{steps}}: need at least 1 step, got {steps}")
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    rotation = rotation_vector(start[:3, :3].T @ end[:3, :3])
    angle = float(np.linalg.norm(rotation))
    poses = []
    for i in range(steps + 1):
        s = i / steps
        pose = np.eye(4)
        pose[:3, 3] = (1 - s) * start[:3, 3] + s * end[:3, 3]
        turn = np.eye(3) if angle == 0 else rotation_from_axis_angle(rotation, s * angle)
        pose[:3, :3] = start[:3, :3] @ turn
        poses.append(pose)
    return tuple(poses)


@dataclass(frozen=True)
class CartesianPath:
    """Waypoint poses and the solution at each (``success`` when every waypoint is met)."""

    targets: tuple[np.ndarray, ...]
    results: tuple[IKResult, ...]

    @property
    def success(self) -> bool:
        return all(r.success for r in self.results)


def follow_path(
    model: Model,
    start: np.ndarray,
    end: np.ndarray,
    steps: int,
    q0: Sequence[float] | None = None,
    *,
    restarts: int = 0,
    **solver_options: object,
) -> CartesianPath:
    """Solve every waypoint from ``start`` to ``end`` (4x4 poses) to tolerance.

    The first waypoint is seeded with ``q0``, each later one with the previous solution, so
    the arm stays on one branch.  ``restarts`` defaults to 0 for the same reason: a random
    restart could jump to another branch mid-path.  Other options go to
    :func:`symkin.solve.ik.numeric.solve_ik` (``position_only``, ``task``, ``tolerance``, ...).
    """
    targets = waypoint_poses(start, end, steps)
    results: list[IKResult] = []
    seed = q0
    for target in targets:
        result = solve_ik(model, target, seed, restarts=restarts, **solver_options)
        results.append(result)
        seed = result.q
    return CartesianPath(targets, tuple(results))

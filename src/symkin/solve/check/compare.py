"""Recompute each printed entry of a worked example and compare (``symkin check``).

Every quantity comes from symkin's numeric path (the generated kernels through
:func:`symkin.solve.evaluate.kinematic_state`, :func:`symkin.spatial` rotations, the lecture's
Newton scheme of :func:`symkin.solve.ik.path.newton_path_table`).  An entry matches when it is
within its printed tolerance (half a unit of the last printed digit).  A matrix printed
smaller than the quantity (``T`` as 3 x 4, the position rows of ``J``) is compared with the
upper-left block of that size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model, derive
from symkin.errors import SymkinError
from symkin.io.robot_file import load_robot
from symkin.robot import Robot
from symkin.solve.check.example import Check, WorkedExample, read_example
from symkin.solve.check.printed import PrintedNumber, printed_like
from symkin.solve.evaluate import kinematic_state
from symkin.solve.ik.path import newton_path_table
from symkin.spatial import rotation_from_euler_zyx, rotation_from_euler_zyz


@dataclass(frozen=True)
class EntryResult:
    """One printed entry (row and column from 1) against symkin's value."""

    row: int
    column: int
    printed: PrintedNumber
    computed: float

    @property
    def matches(self) -> bool:
        return abs(self.computed - self.printed.value) <= self.printed.tolerance * (1 + 1e-9)


@dataclass(frozen=True)
class CheckResult:
    check: Check
    entries: tuple[EntryResult, ...]
    latex: str

    @property
    def mismatches(self) -> tuple[EntryResult, ...]:
        return tuple(e for e in self.entries if not e.matches)


@dataclass(frozen=True)
class ExampleResult:
    example: WorkedExample
    results: tuple[CheckResult, ...]

    @property
    def matches(self) -> bool:
        return not any(r.mismatches for r in self.results)


def check_example(path: str) -> ExampleResult:
    """Read the example file at ``path`` and recompute every check."""
    example = read_example(path)
    model = derive(load_robot(example.robot)) if example.robot else None
    results = []
    for check in example.checks:
        computed = _block(_computed(check, example, model), check)
        results.append(_compare(check, computed, example.lang == "de"))
    return ExampleResult(example, tuple(results))


def _angle_scale(example: WorkedExample) -> float:
    return 180.0 / math.pi if example.degrees else 1.0


def _joint_vector(values, robot: Robot, example: WorkedExample) -> np.ndarray:
    """Printed joint values in SI (revolute joints from degrees when the file says so)."""
    if len(values) != robot.dof:
        raise SymkinError(f"{robot.name} has {robot.dof} joints, got {len(values)} values")
    scale = _angle_scale(example)
    return np.array(
        [
            v / scale if j.type == "revolute" else v
            for v, j in zip(values, robot.joints, strict=True)
        ]
    )


def _computed(check: Check, example: WorkedExample, model: Model | None) -> np.ndarray:
    scale = _angle_scale(example)
    where = f"{example.path}: check {check.index}"
    if check.quantity in ("rotation_zyx", "rotation_zyz"):
        angles = [float(a) / scale for a in check.options.get("euler", [])]
        if len(angles) != 3:
            raise SymkinError(f"{where}: 'euler' must hold three angles")
        rotation = (
            rotation_from_euler_zyx if check.quantity == "rotation_zyx" else rotation_from_euler_zyz
        )
        return np.asarray(rotation(*angles), dtype=float)
    assert model is not None
    if check.quantity == "path_table":
        return _path_table(check, example, model, where)
    try:
        return _state_quantity(check, example, model)
    except (SymkinError, ValueError, np.linalg.LinAlgError) as exc:
        raise SymkinError(f"{where}: {exc}") from None


def _state_quantity(check: Check, example: WorkedExample, model: Model) -> np.ndarray:
    robot, options, quantity = model.robot, check.options, check.quantity
    q = _joint_vector(check.q, robot, example)
    rows = options.get("rows")
    rows = tuple(r.strip() for r in rows.split(",")) if isinstance(rows, str) else None
    points = (
        [(int(options["link"]), [float(v) for v in options["point"]])] if "link" in options else []
    )
    dq = _joint_vector(options["dq"], robot, example) if "dq" in options else None
    ddq = _joint_vector(options["ddq"], robot, example) if "ddq" in options else None
    state = kinematic_state(model, q, dq, ddq, example.overrides, points, rows)
    task = state.jacobian[[("x", "y", "z", "wx", "wy", "wz").index(r) for r in state.task_rows]]
    values = {
        "T": lambda: state.transform,
        "position": lambda: state.position,
        "euler_zyx": lambda: state.euler_zyx * _angle_scale(example),
        "jacobian": lambda: state.jacobian,
        "task_jacobian": lambda: task,
        "det": lambda: np.linalg.det(task),
        "inverse": lambda: np.linalg.inv(task),
        "point_position": lambda: state.points[0].position,
        "point_velocity": lambda: state.points[0].velocity,
        "point_acceleration": lambda: state.points[0].acceleration,
    }
    return np.asarray(values[quantity](), dtype=float)


def _path_table(check: Check, example: WorkedExample, model: Model, where: str) -> np.ndarray:
    """Rows ``x_i.., q_1..q_n, x_i,real.., dx..`` of the lecture's table (q in the file's
    angle unit); the printed labels must match the table's (``0 .. k``, ``ka, kb, ...``)."""
    options = check.options
    rows = options.get("rows", "x,y")
    task = tuple(r.strip() for r in str(rows).split(","))
    q0 = _joint_vector(options.get("q0", []), model.robot, example)
    path = newton_path_table(
        model,
        options["from"],
        q0,
        options["to"],
        int(options["steps"]),
        task=task,
        overrides=example.overrides,
    )
    labels = [row.label for row in path.rows]
    if list(check.labels) != labels[: len(check.labels)]:
        raise SymkinError(
            f"{where}: printed rows {list(check.labels)}, symkin's table has {labels}"
        )
    scale = np.array(
        [_angle_scale(example) if j.type == "revolute" else 1.0 for j in model.robot.joints]
    )
    table = [
        np.concatenate([row.target, row.q * scale, row.real, row.delta])
        for row in path.rows[: len(check.labels)]
    ]
    return np.array(table)


def _block(computed: np.ndarray, check: Check) -> np.ndarray:
    """The computed value in the printed shape (upper-left block of a matrix)."""
    printed_rows, printed_columns = len(check.printed), len(check.printed[0])
    matrix = np.atleast_2d(computed) if computed.ndim < 2 else computed
    if check.shape == "vector" and computed.ndim == 1:
        matrix = computed[None, :]
    if matrix.shape[0] < printed_rows or matrix.shape[1] < printed_columns:
        raise SymkinError(
            f"check {check.index} ({check.quantity}): printed {printed_rows} x {printed_columns}, "
            f"but the quantity is {matrix.shape[0]} x {matrix.shape[1]}"
        )
    return matrix[:printed_rows, :printed_columns]


def _compare(check: Check, computed: np.ndarray, decimal_comma: bool) -> CheckResult:
    entries = tuple(
        EntryResult(i + 1, j + 1, number, float(computed[i, j]))
        for i, row in enumerate(check.printed)
        for j, number in enumerate(row)
    )
    return CheckResult(check, entries, corrected_latex(check, computed, decimal_comma))


def corrected_latex(check: Check, computed: np.ndarray, decimal_comma: bool = False) -> str:
    """symkin's values in the printed layout and digits: a number, a column ``bmatrix`` for a
    vector, a ``bmatrix`` for a matrix, ``tabular`` rows for a path table."""

    def number(value: float, model: PrintedNumber) -> str:
        text = printed_like(value + 0.0, model)
        return text.replace(".", "{,}") if decimal_comma else text

    cells = [
        [number(float(computed[i, j]), p) for j, p in enumerate(row)]
        for i, row in enumerate(check.printed)
    ]
    if check.quantity == "path_table":
        return "\n".join(
            " & ".join([label, *(f"${c}$" for c in row)]) + r" \\"
            for label, row in zip(check.labels, cells, strict=True)
        )
    if check.shape == "scalar":
        return cells[0][0]
    if check.shape == "vector":
        cells = [[c] for c in cells[0]]
    body = r" \\ ".join(" & ".join(row) for row in cells)
    return rf"\begin{{bmatrix}} {body} \end{{bmatrix}}"

"""The content of the LaTeX derivation: which formulas, which numbers, in which sections.

:func:`document_content` takes a :class:`~symkin.derive.Model` and the sections asked for
and returns plain data: the symbolic matrices and expressions each section shows and, when a
configuration ``q`` is given, their values there (evaluated by
:func:`~symkin.derive.numeric.numeric_function`). Nothing here prints or lays out; the
LaTeX backend (:mod:`symkin.emit.latex`) decides how it looks.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.budget import NOT_SQUARE
from symkin.derive.kinematics import (
    joint_dh_values,
    modified_dh_matrix,
    placement_xyz_rpy,
    standard_dh_matrix,
)
from symkin.derive.lagrange import READABLE_DOF
from symkin.derive.numeric import numeric_function
from symkin.errors import ParameterError, literal
from symkin.kernels.document_frames import (
    GraphContent,
    PointsContent,
    graph_content,
    points_content,
)
from symkin.robot import Joint

SECTIONS = (
    "dh", "transforms", "graph", "fk", "points", "euler", "jacobian", "det", "inverse",
    "dynamics",
)  # fmt: skip
# The equations of motion are asked for by name: they need inertial data and, by Lagrange,
# take seconds for three joints.  The point kinematics too: the twist matrices of a long
# chain add derivation time to every document.
DEFAULT_SECTIONS = tuple(s for s in SECTIONS if s not in ("dynamics", "points"))
# Symbolic inverse Jacobians are formed up to this many joints; beyond, the adjugate's
# entries (cofactors of (n-1) x (n-1) minors) run to pages and take minutes to form.
INVERSE_MAX_DOF = 4
ALL_TASK_ROWS = ("x", "y", "z", "wx", "wy", "wz")


def check_sections(names: Iterable[str]) -> tuple[str, ...]:
    """Validate section names (parameter ``sections``); order follows :data:`SECTIONS`."""
    chosen = {n.strip() for n in names if n.strip()}
    unknown = sorted(chosen - set(SECTIONS))
    if unknown:
        raise ParameterError(
            f"{{sections}}: unknown section(s) {literal(', '.join(unknown))}; "
            f"choose from {', '.join(SECTIONS)}"
        )
    if not chosen:
        raise ParameterError(f"{{sections}}: name at least one of {', '.join(SECTIONS)}")
    return tuple(s for s in SECTIONS if s in chosen)


def check_configuration(
    model: Model, q: Sequence[float] | None, overrides: Mapping[str, float] | None
) -> tuple[float, ...] | None:
    """``q`` as floats, one per joint (radians / metres), or None; with ``q``, every
    parameter must have a value (from the robot file or ``overrides``)."""
    if q is None:
        return None
    robot = model.robot
    if len(q) != robot.dof:
        raise ParameterError(f"{{q}} needs {robot.dof} values (one per joint), got {len(q)}")
    robot.parameter_values(overrides)  # unknown names or missing values: say so now
    return tuple(float(v) for v in q)


@dataclass(frozen=True)
class Shown:
    """A matrix or expression shown in the document and its value at ``q*`` (None without;
    a float for an expression)."""

    value: sp.MatrixBase | sp.Expr
    numbers: np.ndarray | float | None


@dataclass(frozen=True)
class DHRow:
    """Row of the DH table: the joint type and ``(theta, d, a, alpha)`` with ``q`` inserted."""

    joint_type: str
    values: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]
    #: placed joints: ``(x, y, z, roll, pitch, yaw)`` of the placement ``P_i``; else None
    placement: tuple[sp.Expr, ...] | None = None


@dataclass(frozen=True)
class DHContent:
    """The general link transform (in ``theta_i``, ``d_i``, ``a_i``, ``alpha_i``, or
    ``a_{i-1}``, ``alpha_{i-1}`` in modified DH), the table, the parameters with their
    values (None: none given) and the base and tool transforms (None: identity)."""

    general: sp.MatrixBase
    rows: tuple[DHRow, ...]
    parameters: tuple[tuple[sp.Symbol, float | None], ...]
    base: sp.MatrixBase | None
    tool: sp.MatrixBase | None


@dataclass(frozen=True)
class FKContent:
    """The product built up link by link: ``{}^0T_i`` for i = 1..n (the last one is ``T``
    unless there is a tool transform, then ``tool`` is ``T``), and the tool position."""

    has_base: bool
    frames: tuple[Shown, ...]
    tool: Shown | None
    position: Shown


@dataclass(frozen=True)
class JacobianColumn:
    """Column ``i`` of the geometric Jacobian with the axis ``z_f`` and origin ``o_f`` of
    frame ``f`` it is formed from (``f`` = i-1 in standard, i in modified DH)."""

    joint_type: str
    frame: int
    axis: sp.MatrixBase
    origin: sp.MatrixBase
    column: Shown


@dataclass(frozen=True)
class JacobianContent:
    """Columns, the whole Jacobian and, for a robot moving along fewer than all six task
    rows, the task Jacobian (None otherwise)."""

    columns: tuple[JacobianColumn, ...]
    jacobian: Shown
    task: Shown | None


@dataclass(frozen=True)
class DeterminantContent:
    """The factored determinant of the task Jacobian and the conditions that make it zero
    (``determinant`` is None when no closed form was found within the budget or attempted)."""

    determinant: Shown | None
    singular: tuple[sp.Eq, ...]


@dataclass(frozen=True)
class InverseContent:
    """The adjugate of the task Jacobian (None beyond :data:`INVERSE_MAX_DOF` joints), signs
    distributed over sums; the inverse at ``q*`` (None without ``q`` or where singular)."""

    adjugate: sp.MatrixBase | None
    numbers: np.ndarray | None


@dataclass(frozen=True)
class DynamicsContent:
    """Whether rotor inertias enter ``M``, and the terms shown (``key`` one of
    ``mass-matrix``, ``coriolis-matrix``, ``gravity-vector``, ``friction-vector``); no terms
    beyond :data:`~symkin.derive.lagrange.READABLE_DOF` joints, where they run to pages."""

    rotors: bool
    terms: tuple[tuple[str, Shown], ...]


@dataclass(frozen=True)
class DocumentContent:
    """Everything the document shows. ``sections`` are the keys asked for, in document order;
    the field of a section not asked for is None, as are ``det`` and ``inverse`` for a
    task Jacobian that is not square. ``parameter_values`` are given with ``q`` only."""

    model: Model
    sections: tuple[str, ...]
    q: tuple[float, ...] | None
    parameter_values: tuple[tuple[sp.Symbol, float], ...] = ()
    dh: DHContent | None = None
    transforms: tuple[Shown, ...] | None = None
    fk: FKContent | None = None
    euler: tuple[Shown, Shown, Shown] | None = None
    jacobian: JacobianContent | None = None
    det: DeterminantContent | None = None
    inverse: InverseContent | None = None
    dynamics: DynamicsContent | None = None
    graph: GraphContent | None = None
    points: PointsContent | None = None


@dataclass(frozen=True)
class _Evaluator:
    model: Model
    q: tuple[float, ...] | None
    overrides: Mapping[str, float] | None

    def numbers(self, expr: sp.MatrixBase | sp.Expr) -> np.ndarray | None:
        if self.q is None:
            return None
        function = numeric_function(self.model, expr, self.overrides)
        return function(np.asarray(self.q, dtype=float))

    def shown(self, expr: sp.MatrixBase | sp.Expr) -> Shown:
        return Shown(expr, self.numbers(expr))

    def scalar(self, expr: sp.Expr) -> Shown:
        values = self.numbers(expr)
        return Shown(expr, None if values is None else float(values))


def _is_identity(matrix: sp.MatrixBase) -> bool:
    return sp.ImmutableMatrix(matrix) == sp.ImmutableMatrix(sp.eye(matrix.rows))


def _placement_row(joint: Joint) -> tuple[sp.Expr, ...] | None:
    if joint.placement is None:
        return None
    xyz, rpy = placement_xyz_rpy(joint.placement)
    return (*xyz, *rpy)


def _dh(e: _Evaluator) -> DHContent:
    robot = e.model.robot
    theta, d = sp.Symbol("theta_i", real=True), sp.Symbol("d_i", real=True)
    if robot.convention == "standard":
        a, alpha = sp.Symbol("a_i", real=True), sp.Symbol("alpha_i", real=True)
        general = standard_dh_matrix(theta, d, a, alpha)
    elif robot.convention == "modified":
        a, alpha = sp.Symbol("a_{i-1}", real=True), sp.Symbol("alpha_{i-1}", real=True)
        general = modified_dh_matrix(theta, d, a, alpha)
    else:  # placed joints: the variable part Rz(theta_i) Tz(d_i) after the placement P_i
        general = modified_dh_matrix(theta, d, sp.S.Zero, sp.S.Zero)
    rows = tuple(
        DHRow(joint.type, joint_dh_values(joint, qi), _placement_row(joint))
        for joint, qi in zip(robot.joints, e.model.q, strict=True)
    )
    overrides = dict(e.overrides or {})
    parameters = tuple(
        (symbol, overrides.get(name, value))
        for symbol, (name, value) in zip(robot.parameter_symbols, robot.parameters, strict=True)
    )
    base = None if _is_identity(robot.base) else robot.base
    tool = None if _is_identity(robot.tool) else robot.tool
    return DHContent(general, rows, parameters, base, tool)


def _fk(e: _Evaluator) -> FKContent:
    model = e.model
    has_tool = not _is_identity(model.robot.tool)
    frames = tuple(e.shown(frame) for frame in model.frame_transforms[1:])
    tool = e.shown(model.forward_kinematics) if has_tool else None
    return FKContent(not _is_identity(model.robot.base), frames, tool, e.shown(model.tool_position))


def _jacobian(e: _Evaluator) -> JacobianContent:
    model = e.model
    offset = 1 if model.robot.convention == "standard" else 0
    jacobian = model.geometric_jacobian
    frames = model.kinematics.joint_frames
    columns = []
    for i, joint in enumerate(model.robot.joints, start=1):
        frame, column = frames[i - 1], e.shown(jacobian[:, i - 1])
        columns.append(JacobianColumn(joint.type, i - offset, frame[:3, 2], frame[:3, 3], column))
    task = None
    if tuple(model.task_rows) != ALL_TASK_ROWS:
        task = e.shown(model.task_jacobian(model.task_rows))
    return JacobianContent(tuple(columns), e.shown(jacobian), task)


def _determinant(e: _Evaluator) -> DeterminantContent | None:
    form = e.model.determinant_form()
    if form.status == NOT_SQUARE:
        return None
    if not form.found:
        return DeterminantContent(None, ())
    return DeterminantContent(e.scalar(form.value), tuple(e.model.singular_configurations()))


def _inverse(e: _Evaluator) -> InverseContent | None:
    model = e.model
    determinant = model.determinant()
    if determinant is None:
        return None
    numbers = None
    if e.q is not None:
        task = e.numbers(model.task_jacobian())
        numbers = None if abs(np.linalg.det(task)) < 1e-12 else np.linalg.inv(task)
    adjugate = None
    inverse = model.inverse_form() if model.robot.dof <= INVERSE_MAX_DOF else None
    if inverse is not None and inverse.found:
        adjugate = inverse.value.applyfunc(lambda x: _distribute_sign(sp.cancel(x * determinant)))
    return InverseContent(adjugate, numbers)


def _distribute_sign(expr: sp.Expr) -> sp.Expr:
    """``-(a + b)`` as ``-a - b``; other factors stay factored (``L_3 (a + b)``)."""
    expr = sp.factor_terms(expr)
    coefficient, rest = expr.as_coeff_Mul()
    if coefficient == -1 and rest.is_Add:
        return sp.Add(*(-term for term in rest.args))
    return expr


def _dynamics(e: _Evaluator) -> DynamicsContent:
    robot = e.model.robot
    # Reflected rotor inertias, where the file gives them, sit on M's diagonal.
    # An elastic joint's rotor is on the motor side (B), not in M.
    rotors = any(
        j.link and j.link.motor_inertia != 0 and not j.link.is_elastic for j in robot.joints
    )
    if robot.dof > READABLE_DOF:
        return DynamicsContent(rotors, ())
    dynamics = e.model.lagrange
    # Numbers at q* need every inertial value; a file without them leaves symbols.
    numeric = all(j.link is not None for j in robot.joints)
    terms = [
        ("mass-matrix", dynamics.mass_matrix, numeric),
        ("coriolis-matrix", dynamics.coriolis_matrix, False),
        ("gravity-vector", dynamics.gravity_vector, numeric),
    ]
    if any(x != 0 for x in dynamics.friction):
        terms.append(("friction-vector", dynamics.friction, False))
    return DynamicsContent(
        rotors,
        tuple(
            (key, e.shown(matrix) if with_numbers else Shown(matrix, None))
            for key, matrix, with_numbers in terms
        ),
    )


def document_content(
    model: Model,
    sections: Sequence[str],
    q: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> DocumentContent:
    """The content of the sections named in ``sections`` (see :func:`check_sections`), with
    values at ``q`` (radians / metres) and parameter values from the robot file updated by
    ``overrides`` when ``q`` is given."""
    chosen = check_sections(sections)
    q = check_configuration(model, q, overrides)
    e = _Evaluator(model, q, overrides)
    builders: dict[str, Callable[[_Evaluator], object]] = {
        "dh": _dh,
        "transforms": lambda e: tuple(e.shown(m) for m in model.link_transforms),
        "fk": _fk,
        "euler": lambda e: tuple(e.scalar(angle) for angle in model.euler_zyx),
        "jacobian": _jacobian,
        "det": _determinant,
        "inverse": _inverse,
        "dynamics": _dynamics,
        "graph": lambda e: graph_content(model),
        "points": lambda e: points_content(model),
    }
    content = {key: builders[key](e) for key in chosen}
    values: tuple[tuple[sp.Symbol, float], ...] = ()
    if q is not None:
        given = model.robot.parameter_values(overrides)
        values = tuple((s, given[s.name]) for s in model.robot.parameter_symbols)
    return DocumentContent(model, chosen, q, values, **content)

"""Analytic and geometric Jacobians, dJ/dt, task Jacobian, determinant and singularities.

Geometric Jacobian ``J = [Jv; Jw]`` (6 x n, linear rows first, base frame; Spong eq. 4.52)::

    revolute i:   [ z_{i-1} x (p - o_{i-1}) ;  z_{i-1} ]
    prismatic i:  [ z_{i-1}                 ;  0       ]

where ``z_{i-1}``, ``o_{i-1}`` are the axis and origin of joint i (frame i-1 in standard DH,
frame i in modified DH) and ``p`` the tool position.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se
import sympy as sp

from symkin.derive.kinematics import (
    Kinematics,
    euler_zyx_of_tool,
    joint_axis_sign,
    numeric_trig_constants,
)
from symkin.derive.orientation_rates import orientation_rates
from symkin.derive.pythagorean import fold_matrix
from symkin.derive.simplify import (
    contract_symengine,
    derivative_matrix,
    symengine_matrix,
    sympy_from_symengine,
)
from symkin.errors import SymkinError
from symkin.robot import Robot
from symkin.spatial import axis_angle_from_rotation, euler_zyz_from_rotation, transform_inverse

ROW_NAMES = ("x", "y", "z", "wx", "wy", "wz")
# Rows a task Jacobian draws from, in order of preference (planar arms: x, y, then wz).
TASK_ROW_PREFERENCE = ("x", "y", "z", "wz", "wx", "wy")


def _geometric_columns(
    robot: Robot, kinematics: Kinematics, point: sp.MatrixBase
) -> list[sp.Matrix]:
    columns = []
    for joint, frame in zip(robot.joints, kinematics.joint_frames, strict=True):
        axis, origin = frame[:3, 2], frame[:3, 3]
        if joint.type == "revolute":
            columns.append(sp.Matrix.vstack(axis.cross(point - origin), axis))
        else:
            columns.append(sp.Matrix.vstack(axis, sp.zeros(3, 1)))
    return columns


def geometric_jacobian(robot: Robot, kinematics: Kinematics) -> sp.ImmutableMatrix:
    """6 x n geometric Jacobian of the tool point, base frame, linear rows first.

    Simplified kinematics get :func:`_local_columns` (the same values, no ``sin^2 + cos^2``
    to fold); the product form keeps ``z x (p - o)`` as it is.
    """
    if kinematics.simplified:
        return _local_columns(robot, kinematics)
    columns = _geometric_columns(robot, kinematics, kinematics.tool_position)
    return kinematics.contract(sp.Matrix.hstack(*columns))


def _local_tool_points(robot: Robot, kinematics: Kinematics) -> list[se.DenseMatrix]:
    """The tool point in each joint's axis frame (homogeneous 4x1, SymEngine, expanded):
    ``p^n`` = the tool's translation, ``p^(k-1) = A_k p^k``, taken at frame i-1 (standard DH)
    or i (modified, placement) for joint i, ``y`` and ``z`` negated for a flipped joint."""
    point = symengine_matrix(numeric_trig_constants(robot.tool)[:, 3])
    points = [point]
    for link in reversed(kinematics.link_transforms):
        points.append((symengine_matrix(link) * points[-1]).applyfunc(se.expand))
    points.reverse()  # points[k] = tool point in DH frame k
    at_axes = points[:-1] if robot.convention == "standard" else points[1:]
    flip = se.DenseMatrix(4, 4, [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1])
    return [flip * p if joint.flip else p for joint, p in zip(robot.joints, at_axes, strict=True)]


def _local_columns(robot: Robot, kinematics: Kinematics) -> sp.ImmutableMatrix:
    """``[R (e_z x p_local); R e_z]`` (revolute) or ``[R e_z; 0]`` (prismatic) with ``R``
    the joint's axis frame and ``p_local`` the tool point in it: ``z x (p - o)`` equals
    ``R (e_z x R^T (p - o))``.  The rotation ``R`` holds joints 1..i and ``p_local`` joints
    i+1..n, so every product term is linear in each joint's sine and cosine and no
    ``sin^2 + cos^2`` arises (``z x (p - o)`` expanded has them, and folding them away took
    most of the Panda's derivation time).  Formed in SymEngine, brought back once."""
    columns = []
    points = _local_tool_points(robot, kinematics)
    for joint, frame, p in zip(robot.joints, kinematics.joint_frames, points, strict=True):
        rotation = symengine_matrix(frame[:3, :3])
        axis = rotation[:, 2]
        if joint.type == "revolute":
            linear = rotation[:, 1] * p[0] - rotation[:, 0] * p[1]
            columns.append(linear.col_join(axis))
        else:
            columns.append(axis.col_join(se.zeros(3, 1)))
    entries = [column[row] for row in range(6) for column in columns]
    matrix = se.DenseMatrix(6, len(columns), entries)
    symbols = {s.name: s for s in kinematics.forward_kinematics.free_symbols | set(kinematics.q)}

    def product_form(i: int, j: int) -> sp.Expr:  # an entry too long to contract
        return sympy_from_symengine(matrix[i, j], symbols)

    return contract_symengine(matrix, symbols, kinematics.angle_sums, product_form)


def frame_jacobian(robot: Robot, kinematics: Kinematics, index: int) -> sp.ImmutableMatrix:
    """6 x n geometric Jacobian of the origin of frame ``index`` (1..n), base frame: the
    joints past ``index`` do not move it (zero columns)."""
    point = kinematics.frame_transforms[index][:3, 3]
    columns = _geometric_columns(robot, kinematics, point)
    moving = [c if j < index else sp.zeros(6, 1) for j, c in enumerate(columns)]
    return sp.ImmutableMatrix(sp.Matrix.hstack(*moving))


def rotate_jacobian(
    kinematics: Kinematics, jacobian: sp.MatrixBase, rotation: sp.MatrixBase
) -> sp.ImmutableMatrix:
    """``diag(R, R) J``: a 6-row Jacobian expressed in another frame."""
    block = sp.diag(sp.Matrix(rotation), sp.Matrix(rotation))
    return kinematics.contract(block * jacobian)


def position_jacobian(kinematics: Kinematics) -> sp.ImmutableMatrix:
    """Analytic position Jacobian ``dp/dq`` (3 x n), differentiated by SymEngine (SymPy's
    ``diff`` took 20 s of a generic six-joint arm's 32 s of kinematics kernels)."""
    return kinematics.contract(derivative_matrix(kinematics.tool_position, kinematics.q))


def analytic_jacobian(kinematics: Kinematics, orientation: Sequence[sp.Expr]) -> sp.ImmutableMatrix:
    """Analytic Jacobian of ``[p; orientation]`` (e.g. Z-Y-X Euler angles), ``d/dq``."""
    pose = sp.Matrix.vstack(kinematics.tool_position, sp.Matrix(orientation))
    return sp.ImmutableMatrix(pose.jacobian(kinematics.q).applyfunc(sp.cancel))


@dataclass(frozen=True)
class AnalyticJacobian:
    """``J_a = [Jv; E(phi)^-1 Jw]`` (6 x n) for orientation coordinates ``phi`` of the tool.

    ``matrix`` is in ``q`` and the coordinate symbols ``coordinates`` (``phi`` enters through
    ``E^-1`` only); ``values`` are the tool's coordinates as expressions in ``q`` (principal
    branch: Z-Y-X ``theta`` in ``[-pi/2, pi/2]``, Z-Y-Z ``beta`` in ``[0, pi]``, rotation angle
    in ``[0, pi]``); :meth:`in_q` substitutes them.  ``singular`` are the conditions on the
    coordinates where ``E`` is singular and ``J_a`` does not exist (the representation's
    singular set, on top of the robot's own singular configurations); see
    :mod:`symkin.derive.orientation_rates`.
    """

    representation: str
    coordinates: tuple[sp.Symbol, ...]
    values: tuple[sp.Expr, ...]
    matrix: sp.ImmutableMatrix
    singular: tuple[sp.Eq, ...]

    def in_q(self) -> sp.ImmutableMatrix:
        """``matrix`` with the coordinates replaced by their expressions in ``q``."""
        return self.matrix.xreplace(dict(zip(self.coordinates, self.values, strict=True)))


def orientation_coordinates(kinematics: Kinematics, representation: str) -> tuple[sp.Expr, ...]:
    """The tool's orientation coordinates (regular-case formulas) as expressions in ``q``."""
    rotation = kinematics.tool_rotation
    if representation in ("zyx", "rpy"):
        angles = euler_zyx_of_tool(kinematics, "atan2")
        return angles if representation == "zyx" else angles[::-1]
    if representation == "zyz":
        alpha, beta, gamma, _ = euler_zyz_from_rotation(rotation)
        return alpha, beta, gamma
    axis, angle, _ = axis_angle_from_rotation(rotation)
    return tuple(angle * component for component in axis)


def analytic_jacobian_of(
    robot: Robot, kinematics: Kinematics, geometric: sp.MatrixBase, representation: str
) -> AnalyticJacobian:
    """``blockdiag(I, E^-1) J_g`` for ``representation`` (``zyx``, ``rpy``, ``zyz`` or
    ``rotation_vector``; conventions in :mod:`symkin.derive.orientation_rates`)."""
    rates = orientation_rates(representation)
    clashes = sorted({s.name for s in rates.coordinates} & {name for name, _ in robot.parameters})
    if clashes:
        raise SymkinError(
            f"{robot.name}: parameter(s) {', '.join(clashes)} share their names with the "
            f"{representation} coordinates; rename them to get this analytic Jacobian"
        )
    geometric = sp.Matrix(geometric)
    angular = rates.inverse * geometric[3:, :]
    return AnalyticJacobian(
        representation,
        rates.coordinates,
        orientation_coordinates(kinematics, representation),
        sp.ImmutableMatrix(sp.Matrix.vstack(geometric[:3, :], angular)),
        rates.singular,
    )


def jacobian_derivative(
    kinematics: Kinematics, jacobian: sp.MatrixBase, dq: Sequence[sp.Symbol]
) -> sp.ImmutableMatrix:
    """``dJ/dt = sum_i dJ/dq_i * dq_i``."""
    rate = sp.zeros(*jacobian.shape)
    for qi, dqi in zip(kinematics.q, dq, strict=True):
        rate += jacobian.diff(qi) * dqi
    return kinematics.contract(rate)


def rows_from_names(names: Sequence[str]) -> tuple[int, ...]:
    """Row indices of a geometric Jacobian from names such as ``("x", "y", "wz")``."""
    unknown = [n for n in names if n not in ROW_NAMES]
    if unknown:
        raise SymkinError(
            f"unknown task row(s) {', '.join(unknown)}; expected names from {', '.join(ROW_NAMES)}"
        )
    if len(set(names)) != len(names):
        raise SymkinError(f"task rows repeat: {', '.join(names)}")
    return tuple(ROW_NAMES.index(n) for n in names)


def default_task_rows(jacobian: sp.MatrixBase) -> tuple[str, ...]:
    """The rows of the task Jacobian when the user chooses none.

    All six when n = 6; otherwise the first n rows that are not identically zero, in the order
    x, y, z, wz, wx, wy (planar 2R: x, y; SCARA with prismatic z: x, y, z; planar 3R: x, y, wz).
    """
    n = jacobian.cols
    if n == 6:
        return ROW_NAMES
    nonzero = [
        name
        for name in TASK_ROW_PREFERENCE
        if any(e != 0 for e in jacobian.row(ROW_NAMES.index(name)))
    ]
    return tuple(nonzero[:n])


def task_jacobian(jacobian: sp.MatrixBase, rows: Sequence[str]) -> sp.ImmutableMatrix:
    """The rows ``rows`` (names) of a geometric Jacobian."""
    return sp.ImmutableMatrix(sp.Matrix.vstack(*(jacobian.row(i) for i in rows_from_names(rows))))


def _frames_seen_from(kinematics: Kinematics, k: int) -> list[sp.ImmutableMatrix]:
    """``T_k_j`` for ``j = 0..n``: every DH frame as seen from frame k (base and tool left
    out), built outward from k by link transforms and their closed-form inverses, contracted
    at each step like the forward kinematics."""
    links = kinematics.link_transforms
    frames: list[sp.ImmutableMatrix] = [sp.ImmutableMatrix(sp.eye(4))] * (len(links) + 1)
    for j in range(k + 1, len(links) + 1):
        frames[j] = kinematics.contract(frames[j - 1] * links[j - 1])
    for j in range(k - 1, -1, -1):
        frames[j] = kinematics.contract(frames[j + 1] * transform_inverse(links[j]))
    return frames


def middle_frame_jacobian(robot: Robot, kinematics: Kinematics) -> sp.Matrix:
    """The geometric Jacobian in frame ``k = n // 2``, about that frame's origin.

    It has the same determinant as the base-frame tool-point Jacobian: changing the frame
    multiplies ``J`` by ``diag(R, R)`` and moving the reference point by ``r`` by
    ``[[I, -[r]x], [0, I]]``, both of determinant 1 (Spong sec. 4.7; the base and tool
    transforms drop out the same way).  Seen from the middle of the chain every column is a
    product of at most about n/2 link transforms instead of n, so the entries are several
    times shorter (UR5: 53 terms in sines and cosines instead of 216).
    """
    k = robot.dof // 2
    frames = _frames_seen_from(kinematics, k)
    axis_frames = frames[:-1] if robot.convention == "standard" else frames[1:]
    columns = []
    for joint, frame in zip(robot.joints, axis_frames, strict=True):
        sign = joint_axis_sign(joint)
        axis, origin = sign * frame[:3, 2], frame[:3, 3]
        if joint.type == "revolute":
            columns.append(sp.Matrix.vstack(axis.cross(-origin), axis))
        else:
            columns.append(sp.Matrix.vstack(axis, sp.zeros(3, 1)))
    return sp.Matrix.hstack(*columns)


def determinant_matrix(
    robot: Robot, kinematics: Kinematics, jacobian: sp.MatrixBase, rows: Sequence[str]
) -> sp.Matrix:
    """A matrix with the task Jacobian's determinant (square) or Gram determinant
    ``det(J J^T)`` (wide): the middle-frame Jacobian when all six rows are taken (same
    determinants, shorter entries; see :func:`middle_frame_jacobian`), else the rows."""
    if tuple(rows) == ROW_NAMES:
        return middle_frame_jacobian(robot, kinematics)
    return sp.Matrix(task_jacobian(jacobian, rows))


def _solve_simple_factor(factor: sp.Expr, variable: sp.Symbol) -> list[sp.Expr] | None:
    """Roots of ``sin(q)``, ``cos(q)`` (in (-pi, pi]) or a low-degree polynomial in ``q``.

    Other factors are left as equations: ``solve`` would turn ``a3 sin(q3) + d4 cos(q3)``
    into ``2 atan(...)`` forms that read worse than the equation itself.
    """
    if isinstance(factor, sp.sin | sp.cos) and factor.args[0] == variable:
        roots = [sp.Integer(0), sp.pi] if isinstance(factor, sp.sin) else [-sp.pi / 2, sp.pi / 2]
        return roots
    if factor.is_polynomial(variable) and sp.degree(factor, variable) <= 2:
        return sorted(sp.solve(factor, variable), key=sp.default_sort_key)
    return None


def singular_configurations(determinant: sp.Expr, q: Sequence[sp.Symbol]) -> tuple[sp.Eq, ...]:
    """Conditions under which a factored determinant vanishes.

    A factor ``sin(qi)``, ``cos(qi)`` or polynomial in one joint variable is solved for it
    (``sin(q2)`` gives ``q2 = 0`` and ``q2 = pi``); any other factor is returned as the equation
    ``factor = 0``.  A determinant that is identically zero gives the one condition
    ``0 = 0``: singular in every configuration.
    """
    if determinant == 0:
        # Dependent rows: singular everywhere; an always-true condition says exactly that.
        return (sp.Eq(sp.Integer(0), sp.Integer(0), evaluate=False),)
    joint_set = set(q)
    conditions: list[sp.Eq] = []
    for factor in sp.Mul.make_args(determinant):
        base = factor.base if factor.is_Pow else factor
        variables = sorted(base.free_symbols & joint_set, key=lambda s: s.name)
        if not variables:
            continue
        roots = _solve_simple_factor(base, variables[0]) if len(variables) == 1 else None
        if roots is None:
            conditions.append(sp.Eq(base, 0))
        else:
            conditions.extend(sp.Eq(variables[0], root) for root in roots)
    return tuple(conditions)


def inverse_from_adjugate(
    kinematics: Kinematics, matrix: sp.MatrixBase, determinant: sp.Expr
) -> sp.ImmutableMatrix:
    """``J^-1 = adj(J) / det(J)``, the adjugate contracted entry by entry and
    ``sin^2 + cos^2`` folded (:mod:`symkin.derive.pythagorean`; the RPR arm's cofactors)."""
    adjugate = fold_matrix(kinematics.contract(sp.Matrix(matrix).adjugate(method="berkowitz")))
    return sp.ImmutableMatrix(adjugate / determinant)

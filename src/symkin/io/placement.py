"""URDF-style joints (``origin`` + ``axis``) -> the canonical placement form of a Robot.

A URDF joint is placed by a constant transform ``O_i`` from its parent link frame to its child
link frame (``origin``: ``xyz`` and fixed-axis ``rpy``, ``R = Rz(yaw) Ry(pitch) Rx(roll)``) and
turns about, or slides along, a unit ``axis`` given in the child link frame.  symkin's placement
form moves every joint about its own frame's z axis (``A_i = P_i Rz(q_i)`` or ``P_i Tz(q_i)``,
:mod:`symkin.robot`), so each child link frame L_i is replaced by the *canonical* frame
``C_i = L_i Rax_i``, where ``Rax_i`` is the rotation taking z to ``axis_i``
(:func:`rotation_taking_z_to`).  With ``T(R)`` the 4x4 transform of a rotation::

    P_i  = T(Rax_{i-1})^T O_i T(Rax_i)            (Rax_0 = I)
    tool = T(Rax_n)^T tool_L                       (tool_L: tip link in L_n)

so ``base * A_1 ... A_n * tool`` is the URDF's forward kinematics to the tip link for the same
joint values, and the intermediate frames differ from the URDF link frames only by the constant
rotations ``Rax_i``.  Inertial data given in L_i are re-expressed in C_i.  Both the TOML
placement form and the URDF reader go through :func:`canonical_joints`.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import replace

import sympy as sp

from symkin.errors import RobotError, RobotWarning
from symkin.robot import Joint, Link
from symkin.spatial import skew

# An rpy angle this close to a multiple of 90 degrees is taken as exact: URDF files print
# pi/2 with ten or so digits, and cos(1.5707963268) = -5e-11 would otherwise litter every
# expression with terms that only look like geometry.
RIGHT_ANGLE_TOLERANCE = 1e-9
# A placement entry this close to 0 or +-1 is taken as exact (see _tidy).
CHOP_TOLERANCE = 1e-12
# A unit-axis component this close to 0 or +-1 is taken as exact, for the same reason.
AXIS_TOLERANCE = 1e-12


def exact_number(value: float) -> sp.Expr:
    """A float from a file as SymPy: an integer value exactly, any other as a Float."""
    if float(value).is_integer():
        return sp.Integer(int(value))
    return sp.Float(repr(float(value)))


def exact_angle(angle: float) -> sp.Expr:
    """An angle in radians; one within :data:`RIGHT_ANGLE_TOLERANCE` of ``k pi/2`` exactly."""
    quarter_turns = round(angle / (math.pi / 2))
    if abs(angle - quarter_turns * math.pi / 2) <= RIGHT_ANGLE_TOLERANCE:
        return sp.pi * sp.Rational(quarter_turns, 2)
    return exact_number(angle)


def unit_axis(axis: Sequence[float], where: str) -> tuple[tuple[sp.Expr, ...], bool]:
    """``(unit axis, whether it had to be normalised)``; a zero or non-finite axis is an error.

    ``where`` starts the error message (``"arm.urdf: joint 'elbow'"``).
    """
    values = [float(v) for v in axis]
    norm = math.hypot(*values)  # scaled: squares of 1e200 overflow, of 1e-200 underflow
    if not all(math.isfinite(v) for v in values) or norm == 0.0:
        raise RobotError(f"{where}: 'axis' must be a nonzero direction, got {list(axis)}")
    unit = [v / norm for v in values]
    snapped = []
    for v in unit:
        nearest = round(v)
        snapped.append(sp.Integer(nearest) if abs(v - nearest) <= AXIS_TOLERANCE else sp.Float(v))
    return tuple(snapped), abs(norm - 1.0) > AXIS_TOLERANCE


def warn_normalised(where: str, axis: Sequence[float]) -> None:
    """Say once per joint that an axis was scaled to unit length (a :class:`RobotWarning`)."""
    warnings.warn(
        f"{where}: 'axis' {list(axis)} is not a unit vector; normalised", RobotWarning, stacklevel=3
    )


def rotation_taking_z_to(axis: Sequence[sp.Expr]) -> sp.Matrix:
    """The rotation ``R`` with ``R z = axis`` (unit), by the shortest turn (Rodrigues).

    About ``v = z x axis`` by the angle between them: ``R = I + [v]x + [v]x^2 / (1 + a_z)``;
    for ``axis = -z``, half a turn about x (``Rx(pi)``), as for a flipped DH joint.
    """
    a = sp.Matrix(axis)
    if a[2] == -1:
        return sp.diag(1, -1, -1)
    v = sp.Matrix([-a[1], a[0], 0])
    v_cross = sp.Matrix(skew(v))
    return sp.Matrix(sp.eye(3) + v_cross + v_cross * v_cross / (1 + a[2]))


def _homogeneous(rotation: sp.Matrix) -> sp.Matrix:
    return sp.diag(rotation, 1)


def link_in_rotated_frame(link: Link, rotation: sp.Matrix) -> Link:
    """The inertial data of ``link`` expressed in a frame turned by ``rotation`` (same origin):
    ``c' = R^T c``, ``I' = R^T I R`` (``R``: the new frame's axes in the old one)."""
    com = rotation.T * sp.Matrix(link.com)
    tensor = rotation.T * sp.Matrix(link.inertia_matrix) * rotation
    inertia = tuple(tensor[i, j] for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))
    return replace(link, com=tuple(com), inertia=inertia)  # type: ignore[arg-type]


def canonical_joints(
    joints: Sequence[Joint], axes: Sequence[Sequence[sp.Expr]], tool: sp.MatrixBase
) -> tuple[tuple[Joint, ...], sp.ImmutableMatrix]:
    """Placed joints in the URDF sense -> the canonical placement form (module docstring).

    ``joints[i].placement`` is the URDF ``origin`` ``O_i``, ``joints[i].link`` is given in the
    child link frame L_i, ``axes[i]`` is the unit axis in L_i, and ``tool`` is the tip link in
    L_n.  Returns the joints with ``P_i`` and links in C_i, and the tool in C_n.
    """
    previous = sp.eye(3)
    result = []
    for joint, axis in zip(joints, axes, strict=True):
        turn = rotation_taking_z_to(axis)
        placement = _homogeneous(previous.T) * sp.Matrix(joint.placement) * _homogeneous(turn)
        link = None if joint.link is None else link_in_rotated_frame(joint.link, turn)
        result.append(replace(joint, placement=_tidy(placement), link=link))
        previous = turn
    return tuple(result), _tidy(_homogeneous(previous.T) * sp.Matrix(tool))


def _tidy(matrix: sp.Matrix) -> sp.ImmutableMatrix:
    """Expanded entries with rounding residue removed: a number within :data:`CHOP_TOLERANCE`
    of 0 or +-1 becomes exact.  Products of Float rotations leave ``6e-17`` where the URDF
    means 0, and each such entry would add a term like ``6e-17 sin(q1) sin(q2)`` to the
    forward kinematics; the change is far below any tolerance the kinematics are checked to."""
    return sp.ImmutableMatrix(matrix.applyfunc(lambda e: _chop(sp.expand(e))))


def _chop(value: sp.Expr) -> sp.Expr:
    if not value.is_number:
        return value
    number = float(value)
    nearest = round(number)
    if nearest in (-1, 0, 1) and abs(number - nearest) <= CHOP_TOLERANCE:
        return sp.Integer(nearest)
    return value

"""The DH table of any serial chain, by the lecture's frame-assignment procedure.

From the joint axes of a robot at ``q = 0`` (each a line: a point and the direction in which
its variable grows, read from the model's joint frames) and the tool pose, assign frames
(Spong, Hutchinson and Vidyasagar, sec. 3.3; Craig, sec. 3.6 for modified DH):

* standard DH: ``z_{i-1}`` along joint i's axis; ``x_i`` along the common normal from
  ``z_{i-1}`` to ``z_i``, origin ``o_i`` where that normal meets ``z_i``.  The last frame's
  ``z_n`` is the tool's z axis (a line like any other).
* modified DH: ``z_i`` along joint i's axis; ``x_i`` along the common normal from ``z_i`` to
  ``z_{i+1}``, origin ``o_i`` where it leaves ``z_i``.

Frame 0 has its origin on axis 1 nearest the base origin and its x axis the base's, made
perpendicular (:func:`~symkin.derive.dh_lines.base_x_axis`).  Each row is then read off the
constant transform between successive frames at ``q = 0``; the constant ``base`` (frame 0 in
the source's world frame) and ``tool`` (the source's tool in frame n) make the table exact:
``T_source(q) = base * A_1(q_1) ... A_n(q_n) * tool``.  Values within
:data:`~symkin.derive.dh_lines.SNAP_TOLERANCE` of a multiple of 15 degrees become exact
(``pi/2``), lengths are rounded to 15 significant digits (``0.333`` stays ``0.333``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from symkin.derive.dh_lines import (
    SNAP_TOLERANCE,
    Case,
    Line,
    Normal,
    base_x_axis,
    common_normal,
    frame_from_axes,
    perpendicular_part,
    unit,
)
from symkin.derive.kinematics import joint_axis_frames, link_transform
from symkin.errors import RobotError
from symkin.robot import Convention, Joint, Link, Robot
from symkin.symbols import joint_symbols


@dataclass(frozen=True)
class AxisStep:
    """One step of the procedure: the pair of lines (axis ``index`` and the next axis, or the
    tool's z axis after the last joint), which case they are, and the row they give."""

    index: int
    case: Case
    normal_length: float
    row: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]  # theta, d, a, alpha of the DH row
    note: str


@dataclass(frozen=True)
class DhExtraction:
    """The DH model of ``source``: ``robot`` (its joints, base and tool) and the steps."""

    source: Robot
    robot: Robot
    steps: tuple[AxisStep, ...]
    lines: tuple[Line, ...]


def numeric_robot(robot: Robot) -> Robot:
    """``robot`` with its parameters replaced by their values (extraction works on numbers)."""
    return robot.with_parameter_values() if robot.parameters else robot


def _numbers(matrix: sp.MatrixBase, q: tuple[sp.Symbol, ...]) -> np.ndarray:
    return np.array(matrix.xreplace(dict.fromkeys(q, 0)).evalf(), dtype=float)


def zero_pose_frames(robot: Robot) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Joint axis frames, link frames (index 0: base) and tool pose of a numeric robot at
    ``q = 0``, multiplied as numbers (the symbolic chain of a long generic arm is large)."""
    q = joint_symbols(robot.dof)
    zero = dict.fromkeys(q, 0)
    frames = [np.array(robot.base.evalf(), dtype=float)]
    for joint, qi in zip(robot.joints, q, strict=True):
        link = link_transform(joint, qi, robot.convention).xreplace(zero).evalf()
        frames.append(frames[-1] @ np.array(link, dtype=float))
    axes = joint_axis_frames(robot, [sp.ImmutableMatrix(f) for f in frames])
    tool = frames[-1] @ np.array(robot.tool.evalf(), dtype=float)
    return [np.array(a, dtype=float) for a in axes], frames, tool


def snap_angle(value: float) -> sp.Expr:
    """An exact multiple of ``pi/12`` when ``value`` is one to the snap tolerance."""
    steps = value / (math.pi / 12)
    nearest = round(steps)
    if abs(steps - nearest) * math.pi / 12 < SNAP_TOLERANCE:
        nearest = (nearest + 12) % 24 - 12  # into (-pi, pi]
        return sp.pi * sp.Rational(12 if nearest == -12 else nearest, 12)
    return sp.Float(value, 15)


def snap_length(value: float) -> sp.Expr:
    """Zero below the snap tolerance, else ``value`` to 15 significant digits."""
    if abs(value) < SNAP_TOLERANCE:
        return sp.Integer(0)
    return sp.Float(float(f"{value:.15g}"), 15)


def snap_transform(matrix: np.ndarray) -> sp.ImmutableMatrix:
    """A constant transform with rotation entries near 0 and +-1 made exact and the
    translation snapped like a length."""

    def entry(value: float) -> sp.Expr:
        for exact in (0, 1, -1):
            if abs(value - exact) < 1e-12:
                return sp.Integer(exact)
        return sp.Float(value, 15)

    rotation = [[entry(v) for v in row] for row in matrix[:3, :3]]
    translation = [snap_length(v) for v in matrix[:3, 3]]
    rows = [[*rotation[i], translation[i]] for i in range(3)]
    return sp.ImmutableMatrix([*rows, [0, 0, 0, 1]])


def dh_row(step: np.ndarray, convention: Convention) -> tuple[float, float, float, float]:
    """``(theta, d, a, alpha)`` of a transform of DH form.

    Standard ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``: ``theta = atan2(A21, A11)``,
    ``alpha = atan2(A32, A33)``, ``d = A34``, ``a = A14 cos theta + A24 sin theta``.
    Modified ``Rx(alpha) Tx(a) Rz(theta) Tz(d)``: ``theta = atan2(-A12, A11)``,
    ``alpha = atan2(-A23, A33)``, ``a = A14``, ``d = -A24 sin alpha + A34 cos alpha``.
    """
    if convention == "standard":
        theta = math.atan2(step[1, 0], step[0, 0])
        alpha = math.atan2(step[2, 1], step[2, 2])
        a = step[0, 3] * math.cos(theta) + step[1, 3] * math.sin(theta)
        return theta, step[2, 3], a, alpha
    theta = math.atan2(-step[0, 1], step[0, 0])
    alpha = math.atan2(-step[1, 2], step[2, 2])
    d = -step[1, 3] * math.sin(alpha) + step[2, 3] * math.cos(alpha)
    return theta, d, step[0, 3], alpha


def axis_lines(joint_frames: list[np.ndarray], tool: np.ndarray) -> tuple[Line, ...]:
    """Joint axes (z of each joint frame) and, last, the tool's z axis, as lines."""
    return tuple(Line(f[:3, 3], unit(f[:3, 2])) for f in [*joint_frames, tool])


def chain_normals(lines: tuple[Line, ...], frame0: np.ndarray, tool: np.ndarray) -> list[Normal]:
    """The common normals between successive lines, each starting where the last ended."""
    scale = max(1.0, *(float(np.linalg.norm(line.point)) for line in lines))
    normals: list[Normal] = []
    start, previous_x = frame0[:3, 3], frame0[:3, 0]
    for first, second in itertools.pairwise(lines):
        normal = common_normal(first, second, start, previous_x, scale)
        if normal.case == "coincident" and second is lines[-1]:
            x = perpendicular_part(tool[:3, 0], first.direction)
            if np.linalg.norm(x) > 1e-6:
                normal = replace(normal, direction=unit(x))
        normals.append(normal)
        start, previous_x = normal.end, normal.direction
    return normals


def dh_frames(
    lines: tuple[Line, ...], normals: list[Normal], frame0: np.ndarray, convention: Convention
) -> list[np.ndarray]:
    """Frames 0..n: standard ``o_i`` at the normal's end on ``z_i`` (the next line);
    modified ``o_i`` at its start on ``z_i`` (this joint's axis)."""
    if convention == "standard":
        return [frame0] + [
            frame_from_axes(n.end, n.direction, line.direction)
            for n, line in zip(normals, lines[1:], strict=True)
        ]
    return [frame0] + [
        frame_from_axes(n.start, n.direction, line.direction)
        for n, line in zip(normals, lines[:-1], strict=True)
    ]


def check_not_redundant(source: Robot, normals: list[Normal], lines: tuple[Line, ...]) -> None:
    """Reject two joints that move the chain the same way (no table can tell them apart)."""
    joints = source.joints
    for k in range(len(joints) - 1):
        first, second = joints[k], joints[k + 1]
        named = [f" ({j.name})" if j.name else "" for j in (first, second)]
        label = f"{source.file or source.name}: joints {k + 1}{named[0]} and {k + 2}{named[1]}"
        if first.type == second.type == "revolute" and normals[k].case == "coincident":
            raise RobotError(
                f"{label} turn about the same line (coincident axes): the two joints are one "
                "rotation, the common normal and x axis are undefined, and a DH table would "
                "hide that the chain is redundant; merge them or move one axis"
            )
        parallel = abs(abs(np.dot(lines[k].direction, lines[k + 1].direction)) - 1) < 1e-12
        if first.type == second.type == "prismatic" and parallel:
            raise RobotError(
                f"{label} slide along the same direction (a prismatic joint along the previous "
                "axis): the two joints are one translation, so d and the common normal are "
                "undefined; merge them or tilt one axis"
            )


def step_note(case: Case, index: int, last: bool) -> str:
    """How a, alpha, d, theta follow in this case (the lecture's wording)."""
    target = "the tool's z axis" if last else f"axis {index + 1}"
    if case == "skew":
        return (
            f"axis {index} and {target} are skew: x along their unique common normal, "
            "a = its length"
        )
    if case == "parallel":
        return (
            f"axis {index} and {target} are parallel: infinitely many common normals; the one "
            f"through the previous origin is taken (d = 0 by the usual choice), a = their distance"
        )
    if case == "intersecting":
        return (
            f"axis {index} and {target} intersect: a = 0, x = +-z_prev x z_next, "
            "origin at the intersection"
        )
    choice = "the tool's x axis" if last else "the previous x axis"
    return (
        f"axis {index} and {target} coincide: the common normal is not unique; a = 0, alpha = 0 "
        f"or 180 deg, x is chosen along {choice}"
    )


def dh_matrix(theta: float, d: float, a: float, alpha: float, convention: Convention) -> np.ndarray:
    """The numeric DH link transform (standard or modified, see :mod:`symkin.robot`)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    if convention == "standard":
        rows = [[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d]]
    else:
        rows = [[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d]]
    return np.array([*rows, [0, 0, 0, 1]], dtype=float)


def _row_of(step: np.ndarray, convention: Convention, index: int) -> tuple[sp.Expr, ...]:
    """The snapped DH row of one frame step, checked to reproduce it."""
    values = dh_row(step, convention)
    if not np.allclose(dh_matrix(*values, convention), step, atol=1e-9):
        raise ArithmeticError(f"DH extraction: frame {index} is not of DH form (a bug)")
    theta, d, a, alpha = values
    return snap_angle(theta), snap_length(d), snap_length(a), snap_angle(alpha)


def rounded(value: float) -> sp.Expr:
    """An inertial number to 15 significant digits (exact zero below 1e-15)."""
    return sp.Integer(0) if abs(value) < 1e-15 else sp.Float(float(f"{value:.15g}"), 15)


def link_in_frame(link: Link | None, frame_from_link: np.ndarray) -> Link | None:
    """The link's inertial data in a new frame fixed to the same body.

    ``frame_from_link`` is the pose of the old link frame in the new one, ``[R p]``: the
    centre of mass becomes ``R c + p`` and the tensor about it ``R I R^T``.
    """
    if link is None:
        return None
    try:
        com = np.array([float(c) for c in link.com])
        inertia = np.array(link.inertia_matrix.evalf(), dtype=float)
    except TypeError as error:
        raise RobotError("DH extraction needs numeric inertial data") from error
    rotation, offset = frame_from_link[:3, :3], frame_from_link[:3, 3]
    com_new = rotation @ com + offset
    tensor = rotation @ inertia @ rotation.T
    elements = (tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2])
    return replace(
        link,
        com=tuple(rounded(c) for c in com_new),
        inertia=tuple(rounded(e) for e in elements),
    )


def dh_joints(
    source: Robot, rows: list[tuple[sp.Expr, ...]], frame0: np.ndarray, convention: Convention
) -> tuple[tuple[Joint, ...], np.ndarray]:
    """The DH joints (offsets, limits, inertial data in the DH frames) and the pose of frame
    n at ``q = 0``, both from the snapped rows; ``source`` has numeric parameters."""
    link_frames = zero_pose_frames(source)[1]
    frame = frame0
    joints = []
    for k, (joint, row) in enumerate(zip(source.joints, rows, strict=True)):
        frame = frame @ dh_matrix(*(float(v) for v in row), convention)
        theta, d, a, alpha = row
        joints.append(
            Joint(
                type=joint.type,
                theta=theta,
                d=d,
                a=a,
                alpha=alpha,
                name=joint.name,
                limits=joint.limits,
                max_velocity=joint.max_velocity,
                max_effort=joint.max_effort,
                link=link_in_frame(joint.link, np.linalg.solve(frame, link_frames[k + 1])),
            )
        )
    return tuple(joints), frame


def extract_dh(source: Robot, convention: Convention = "standard") -> DhExtraction:
    """The DH model of ``source`` by the lecture's procedure (module docstring).

    Raises :class:`RobotError` for a redundant chain (two revolute joints on one line, two
    prismatic joints along one direction) and when a parameter has no value.
    """
    robot = numeric_robot(source)
    joint_frames, link_frames, tool = zero_pose_frames(robot)
    lines = axis_lines(joint_frames, tool)
    z0 = lines[0].direction
    base = link_frames[0]
    frame0 = frame_from_axes(lines[0].foot_of(base[:3, 3]), base_x_axis(base, z0), z0)
    normals = chain_normals(lines, frame0, tool)
    check_not_redundant(source, normals, lines)
    frames = dh_frames(lines, normals, frame0, convention)
    rows = [
        _row_of(np.linalg.solve(frames[k], frames[k + 1]), convention, k + 1)
        for k in range(robot.dof)
    ]
    base_exact = snap_transform(frame0)
    joints, last = dh_joints(robot, rows, np.array(base_exact, dtype=float), convention)
    steps = tuple(
        AxisStep(k + 1, n.case, n.length, row, step_note(n.case, k + 1, k == robot.dof - 1))
        for k, (n, row) in enumerate(zip(normals, rows, strict=True))
    )
    model = Robot(
        name=source.name,
        joints=joints,
        convention=convention,
        gravity=robot.gravity,
        base=base_exact,
        tool=snap_transform(np.linalg.solve(last, tool)),
        title=f"{source.title or source.name}: DH table extracted by symkin dh",
        source=source.source,
    )
    return DhExtraction(source, model, steps, lines)

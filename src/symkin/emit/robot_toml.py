"""A numeric DH robot as the text of a symkin robot file (docs/robot-files.md).

Used by ``symkin dh --toml``: the extracted DH model, with limits, inertial data (in the DH
frames) and friction carried.  Angles are written in radians, as ``pi`` expressions when
they are exact multiples of ``pi/12`` and as the shortest decimal text of the float
otherwise, so the file loads back to the same numbers.
"""

from __future__ import annotations

import json

import numpy as np
import sympy as sp

from symkin.robot import Joint, Link, Robot
from symkin.spatial import rpy_from_rotation


def number_text(value: sp.Expr | float) -> str:
    """A TOML value: ``"pi/2"``-like strings for exact multiples of pi, else a decimal."""
    expr = sp.sympify(value)
    if expr.has(sp.pi):
        return json.dumps(str(expr))
    number = float(expr)
    return repr(int(number)) if number.is_integer() and abs(number) < 1e15 else repr(number)


def angle_text(value: float) -> str:
    """An angle in radians, exact (``"-pi/2"``) at multiples of 15 degrees to 1e-12."""
    steps = value / (np.pi / 12)
    if abs(steps - round(steps)) < 1e-12 * 12 / np.pi:
        return number_text(sp.pi * sp.Rational(round(steps), 12))
    return number_text(value)


def vector_text(values: list[str]) -> str:
    return "[" + ", ".join(values) + "]"


def frame_lines(key: str, transform: sp.ImmutableMatrix) -> list[str]:
    """``[base]``/``[tool]`` as ``xyz`` and fixed-axis ``rpy``; nothing for the identity."""
    if transform == sp.eye(4):
        return []
    matrix = np.array(transform.evalf(), dtype=float)
    rpy = rpy_from_rotation(matrix[:3, :3])[:3]
    return [
        "",
        f"[{key}]",
        f"xyz = {vector_text([number_text(v) for v in transform[:3, 3]])}",
        f"rpy = {vector_text([angle_text(float(v)) for v in rpy])}",
    ]


def link_lines(link: Link) -> list[str]:
    """A ``[joints.link]`` table: mass, COM, inertia about it, motor inertia, friction."""
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    inertia = ", ".join(f"{n} = {number_text(v)}" for n, v in zip(names, link.inertia, strict=True))
    lines = [
        "",
        "[joints.link]",
        f"mass = {number_text(link.mass)}",
        f"com = {vector_text([number_text(c) for c in link.com])}",
        f"inertia = {{ {inertia} }}",
    ]
    if link.motor_inertia != 0:
        lines.append(f"motor_inertia = {number_text(link.motor_inertia)}")
    if link.stiffness is not None:
        lines.append(f"stiffness = {number_text(link.stiffness)}")
    lines += friction_lines(link) + drive_lines(link)
    return lines


def drive_lines(link: Link) -> list[str]:
    """The ``drive`` table without ``rotor_inertia``: ``motor_inertia`` already holds the
    reflected ``G^2 Jm`` (giving both is an error)."""
    if link.drive is None:
        return []
    keys = ("gear_ratio", "torque_constant", "back_emf_constant", "resistance", "inductance")
    items = [
        f"{key} = {number_text(getattr(link.drive, key))}"
        for key in keys
        if getattr(link.drive, key) is not None
    ]
    return [f"drive = {{ {', '.join(items)} }}"]


def friction_lines(link: Link) -> list[str]:
    """The friction table when the link has any friction."""
    items = []
    if link.coulomb_negative is not None:
        items += [f"coulomb_positive = {number_text(link.coulomb)}"]
        items += [f"coulomb_negative = {number_text(link.coulomb_negative)}"]
    elif link.coulomb != 0:
        items.append(f"coulomb = {number_text(link.coulomb)}")
    if link.viscous != 0:
        items.append(f"viscous = {number_text(link.viscous)}")
    if link.stribeck_static is not None and link.stribeck_velocity is not None:
        static, velocity = number_text(link.stribeck_static), number_text(link.stribeck_velocity)
        items.append(f"stribeck = {{ static = {static}, velocity = {velocity} }}")
    if link.coulomb_width is not None:
        items.append(f"smoothing = {number_text(link.coulomb_width)}")
    if link.stiction is not None:
        items.append(f"stiction = {number_text(link.stiction)}")
    return [f"friction = {{ {', '.join(items)} }}"] if items else []


def joint_lines(joint: Joint) -> list[str]:
    lines = ["", "[[joints]]", f'type = "{joint.type}"']
    if joint.name is not None:
        lines.append(f'name = "{joint.name}"')
    for key in ("theta", "d", "a", "alpha"):
        value = getattr(joint, key)
        if value != 0:
            text = angle_text(float(value)) if key in ("theta", "alpha") else number_text(value)
            lines.append(f"{key} = {text}")
    if joint.limits is not None:
        lines.append(f"limits = {vector_text([repr(float(v)) for v in joint.limits])}")
    for key in ("max_velocity", "max_effort"):
        if getattr(joint, key) is not None:
            lines.append(f"{key} = {float(getattr(joint, key))!r}")
    return lines + (link_lines(joint.link) if joint.link is not None else [])


def robot_toml(robot: Robot, header: str) -> str:
    """The robot file text of a DH robot with numeric entries (no parameters)."""
    gravity = vector_text([number_text(g) for g in robot.gravity])
    lines = [
        *(f"# {line}" for line in header.splitlines()),
        f'name = "{robot.name}"',
        f"title = {json.dumps(robot.title)}",
        f"source = {json.dumps(robot.source)}",
        f'convention = "{robot.convention}"',
        'angles = "rad"',
        f"gravity = {gravity}",
    ]
    for joint in robot.joints:
        lines += joint_lines(joint)
    lines += frame_lines("base", robot.base) + frame_lines("tool", robot.tool)
    return "\n".join(lines) + "\n"

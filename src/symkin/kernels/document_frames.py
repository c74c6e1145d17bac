"""Content of the document's frame sections: the transform graph and the point kinematics.

* ``graph``: the frames of the chain (world ``W`` when the robot has a base transform,
  ``0 .. n``, and the tool ``E`` when it has a tool transform) and the transform on each
  edge (``T_base``, ``A_1(q_1) .. A_n(q_n)``, ``T_tool``).  Nothing is derived: the section
  states how the poses compose.
* ``points``: the U-matrix method of :mod:`symkin.derive.motion` (Paul, ch. 6): the twist
  matrices ``D_j = Z_j Q_j Z_j^-1`` of every joint (``U_ij = D_j W_i``) and, up to
  :data:`POINT_MAX_DOF` joints, the velocity and acceleration of the tool point (the origin of
  frame n) in closed form; beyond that they run to pages.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from symkin.derive import Model
from symkin.derive.motion import twist_matrices

POINT_MAX_DOF = 3


@dataclass(frozen=True)
class GraphContent:
    """Frame names in chain order and, for each edge ``(i, i+1)``, its transform's kind:
    ``"base"``, ``"joint"`` (``A_j``) or ``"tool"``; ``joint_types[j]`` of joint j+1."""

    frames: tuple[str, ...]
    edges: tuple[str, ...]
    joint_types: tuple[str, ...]


@dataclass(frozen=True)
class PointsContent:
    """``twists[j] = D_{j+1}``; the tool point's ``velocity`` and ``acceleration`` (3x1, base
    frame) or None beyond :data:`POINT_MAX_DOF` joints."""

    twists: tuple[sp.ImmutableMatrix, ...]
    velocity: sp.ImmutableMatrix | None
    acceleration: sp.ImmutableMatrix | None


def graph_content(model: Model) -> GraphContent:
    """The transform graph of ``model``'s chain (see the module docstring)."""
    robot = model.robot
    has_base, has_tool = robot.base != sp.eye(4), robot.tool != sp.eye(4)
    frames = (["W"] if has_base else []) + [str(i) for i in range(robot.dof + 1)]
    edges = (["base"] if has_base else []) + ["joint"] * robot.dof
    if has_tool:
        frames.append("E")
        edges.append("tool")
    return GraphContent(tuple(frames), tuple(edges), tuple(j.type for j in robot.joints))


def points_content(model: Model) -> PointsContent:
    """Twist matrices and, for short chains, the tool point's velocity and acceleration."""
    twists = twist_matrices(model.robot, model.kinematics)
    if model.robot.dof > POINT_MAX_DOF:
        return PointsContent(twists, None, None)
    motion = model.point_motion(model.robot.dof, (0, 0, 0))
    return PointsContent(twists, motion.velocity, motion.acceleration)

"""Forward kinematics and geometric Jacobian as named intermediates, link by link.

The product form ``T = base A_1 ... A_n tool`` held as one SymPy expression per entry is a
tree as deep as the chain: every entry of ``T_0_k`` holds every entry of ``T_0_{k-1}``.
SymPy shares the subtrees in memory, but a walk that does not (conversion to SymEngine,
``cse``'s search for common arguments) pays for the tree: on a generic 12-joint arm the
Jacobian kernel's CSE alone took 34 s of CPU.  Here each entry of ``T_0_k = T_0_{k-1} A_k``
is named as it is formed, so every expression is a sum of at most four products of symbols,
and the Jacobian columns ``[z x (p - o); z]`` (revolute) or ``[z; 0]`` (prismatic) of
:func:`~symkin.derive.jacobians.geometric_jacobian` are short expressions in those names.
The values are the product form's; only the expression graph differs.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from symkin.derive import jacobians
from symkin.derive.kinematics import (
    Kinematics,
    joint_axis_frames,
    link_transform,
    numeric_trig_constants,
)
from symkin.robot import Robot
from symkin.symbols import joint_symbols


@dataclass(frozen=True)
class NamedPose:
    """``assignments`` (symbol, expression) in evaluation order, then ``T`` (4x4), the
    geometric Jacobian ``J`` (6xn, base frame, linear rows first) and the frames ``T_0_0 ..
    T_0_n`` in terms of them."""

    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    forward_kinematics: sp.ImmutableMatrix
    geometric_jacobian: sp.ImmutableMatrix
    frame_transforms: tuple[sp.ImmutableMatrix, ...]


def named_pose(robot: Robot) -> NamedPose:
    """:class:`NamedPose` of ``robot``: every frame ``T_0_k`` and ``T`` named entry by entry."""
    assignments: list[tuple[sp.Symbol, sp.Expr]] = []
    q = joint_symbols(robot.dof)
    links = tuple(
        link_transform(joint, qi, robot.convention)
        for joint, qi in zip(robot.joints, q, strict=True)
    )

    def named(matrix: sp.MatrixBase, frame: str) -> sp.ImmutableMatrix:
        def entry(i: int, j: int) -> sp.Expr:
            value = matrix[i, j]
            if value.is_Atom:
                return value
            symbol = sp.Dummy(f"T{frame}_{i}{j}", real=True)
            assignments.append((symbol, value))
            return symbol

        return sp.ImmutableMatrix(matrix.rows, matrix.cols, entry)

    frames = [numeric_trig_constants(robot.base)]
    for k, link in enumerate(links, start=1):
        frames.append(named(frames[-1] * link, str(k)))
    tool = named(frames[-1] * numeric_trig_constants(robot.tool), "tool")
    joint_frames = tuple(joint_axis_frames(robot, frames))
    # angle_sums and simplified off: Kinematics.contract keeps every product as it is.
    kinematics = Kinematics(q, links, tuple(frames), joint_frames, tool, False, simplified=False)
    jacobian = jacobians.geometric_jacobian(robot, kinematics)
    return NamedPose(tuple(assignments), tool, jacobian, tuple(frames))

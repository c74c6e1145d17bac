"""External wrenches: their joint torques and the statics.

Convention (docs/conventions.md, External wrench): the surroundings apply the wrench
``w = (f, n)`` to the tool, force ``f`` and moment ``n`` in base-frame components, ``f``
acting at the tool point.  The joint torques that produce the motion then read

    tau = M(q) ddq + C(q, dq) dq + G(q) + F(dq) - J(q)^T w

(Spong, Hutchinson, Vidyasagar, eq. 4.117 and section 7.5; Siciliano et al., eq. 7.83 with
``h_e = -w``), ``J`` the geometric Jacobian of the tool point.  At rest the torques that hold
the arm against gravity and ``w`` are ``G - J^T w``.  A wrench ``w_i`` on link ``i`` at its
frame's origin contributes ``-J_i^T w_i`` with ``J_i`` the Jacobian of that origin.

Newton–Euler reaches the same torques with ``-w`` (what the last link exerts on the
surroundings) as the outer boundary force of the inward pass (:func:`tip_load`); the tests
check that both ways agree.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from symkin.derive.jacobians import frame_jacobian
from symkin.derive.kinematics import Kinematics
from symkin.robot import Robot


def wrench_torque(jacobian: sp.MatrixBase, wrench: Sequence[sp.Expr]) -> sp.ImmutableMatrix:
    """``-J^T w``: the joint torques an external wrench ``w = (f, n)`` adds to ``tau``."""
    return sp.ImmutableMatrix(-sp.Matrix(jacobian).T * sp.Matrix(wrench))


def link_wrench_torque(
    robot: Robot, kinematics: Kinematics, link: int, wrench: Sequence[sp.Expr]
) -> sp.ImmutableMatrix:
    """``-J_i^T w_i`` of a wrench on link ``link`` (1..n) at its frame's origin, base-frame
    components; the joints past the link feel nothing."""
    if not 1 <= link <= robot.dof:
        raise ValueError(f"link must be 1..{robot.dof}, got {link}")
    return wrench_torque(frame_jacobian(robot, kinematics, link), wrench)


def tip_load(
    robot: Robot, kinematics: Kinematics, wrench: Sequence[sp.Expr]
) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix]:
    """The force and the moment about origin n that the last link exerts on its surroundings
    when they apply ``w = (f, n)`` (base frame) at the tool point, in frame-n axes:
    ``-R^T f`` and ``-R^T n + r x (-R^T f)``, with ``R = R_0_n`` and ``r`` the tool point in
    frame n (the Newton–Euler boundary ``f_{n+1}, m_{n+1}``)."""
    rotation = sp.Matrix(kinematics.frame_transforms[-1][:3, :3])
    force = -rotation.T * sp.Matrix(wrench[:3])
    tool_point = sp.Matrix(robot.tool[:3, 3])
    moment = -rotation.T * sp.Matrix(wrench[3:]) + tool_point.cross(force)
    return sp.ImmutableMatrix(force), sp.ImmutableMatrix(moment)

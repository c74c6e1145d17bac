"""Elastic joints: Spong's reduced model and its inverse dynamics to the motor side.

An elastic joint i (a link with ``stiffness`` K_i) is a spring between the link, at ``q_i``,
and the motor, at ``theta_i`` (the motor angle reflected through the gear, in joint units).
The motor-side inertia ``B_i`` (the link's ``motor_inertia``) sits behind the spring and is
not part of ``M`` (Spong 1987; seed 003, elastic joints)::

    link side:   M(q) ddq + c(q, dq) + g(q) + F(dq) = K (theta - q)
    motor side:  B ddtheta + K (theta - q)          = tau_m

Rigid joints keep ``tau_i`` as their drive torque.  Inverse dynamics along a planned
``q(t)`` (four times differentiable): ``tau_link`` is the rigid inverse dynamics, so
``theta = q + K^-1 tau_link`` and, differentiating twice,
``tau_m = B (ddq + K^-1 d2tau_link/dt2) + tau_link``.

``d2tau_link/dt2`` comes from the Newton–Euler recursion itself, differentiated in forward
mode: every named intermediate ``s_k`` of the recursion gets a named time derivative
``ds_k = sum_j (ds_k / dx_j) dx_j/dt`` with ``dq/dt = ddq``, ``d ddq/dt = d3q`` and
``d d3q/dt = d4q``; the second pass differentiates the first one's intermediates too.  The
cost is a fixed multiple of the recursion's (measured in docs/benchmarks.md), not the blow-up
of differentiating the expanded ``tau``.  Coulomb friction's ``sign(dq)`` has derivative 0
(valid away from ``dq = 0``; smooth it with ``friction.smoothing`` for a differentiable model).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.derive.recursion import Recorder, robot_recorder
from symkin.robot import Robot
from symkin.symbols import joint_symbols

Assignments = tuple[tuple[sp.Symbol, sp.Expr], ...]


def joint_stiffness(robot: Robot) -> tuple[sp.Expr, ...]:
    """``K_i`` of the elastic joints, in joint order."""
    return tuple(robot.joints[i].link.stiffness for i in robot.elastic_joints)  # type: ignore[union-attr]


def motor_side_inertia(robot: Robot) -> tuple[sp.Expr, ...]:
    """``B_i`` of the elastic joints (their ``motor_inertia``), in joint order."""
    return tuple(robot.joints[i].link.motor_inertia for i in robot.elastic_joints)  # type: ignore[union-attr]


def jerk_symbols(n: int) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
    """``(d3q1..d3qn, d4q1..d4qn)``: the third and fourth time derivatives of ``q``."""
    return joint_symbols(n, "d3q"), joint_symbols(n, "d4q")


def _total_derivative(expr: sp.Expr, rates: Mapping[sp.Symbol, sp.Expr]) -> sp.Expr:
    """``d expr / dt = sum_x (d expr / dx) dx/dt`` over the symbols with a known rate."""
    moving = sorted(expr.free_symbols & rates.keys(), key=lambda s: s.name)
    total = sp.Add(*(sp.diff(expr, x) * rates[x] for x in moving))
    # d sign(x)/dx = 2 DiracDelta(x): 0 away from x = 0, the only place it is defined.
    return total.replace(sp.DiracDelta, lambda *args: sp.Integer(0))


def time_derivative(
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    outputs: Sequence[sp.Expr],
    rates: Mapping[sp.Symbol, sp.Expr],
    recorder: Recorder,
) -> list[sp.Expr]:
    """Time derivatives of ``outputs`` through the named ``assignments`` (forward mode).

    ``rates`` holds ``dx/dt`` of the inputs; each intermediate's derivative is named by
    ``recorder`` (whose ``assignments`` then define them).  Returns the outputs' derivatives.
    """
    known = dict(rates)
    for symbol, expr in assignments:
        known[symbol] = recorder.name(_total_derivative(expr, known))
    return [_total_derivative(e, known) for e in outputs]


@dataclass(frozen=True)
class MotorSide:
    """Inverse dynamics of a robot with elastic joints, to the motor side.

    ``theta``: motor positions of the elastic joints (joint units); ``tau_motor``: the drive
    torque of every joint (motor torque of an elastic joint, joint torque of a rigid one);
    ``tau_link``: the rigid inverse dynamics and ``tau_link_dd`` its second time derivative.
    All in the named ``assignments``.
    """

    d3q: tuple[sp.Symbol, ...]
    d4q: tuple[sp.Symbol, ...]
    theta: sp.ImmutableMatrix
    tau_motor: sp.ImmutableMatrix
    tau_link_dd: sp.ImmutableMatrix
    assignments: Assignments


def motor_side_dynamics(
    robot: Robot,
    recursion: tuple[Assignments, sp.ImmutableMatrix],
    q: Sequence[sp.Symbol],
    dq: Sequence[sp.Symbol],
    ddq: Sequence[sp.Symbol],
) -> MotorSide:
    """``theta = q + K^-1 tau_link``, ``tau_m = B (ddq + K^-1 d2tau_link/dt2) + tau_link`` for
    the elastic joints (module docstring), from the recursion ``(assignments, tau_link)``."""
    assignments, tau_link = recursion
    d3q, d4q = jerk_symbols(robot.dof)
    elastic = robot.elastic_joints
    rates = dict(zip(q, dq, strict=True)) | dict(zip(dq, ddq, strict=True))
    first = robot_recorder(robot, "dts")
    rates_first = rates | dict(zip(ddq, d3q, strict=True))
    tau_dot = time_derivative(assignments, list(tau_link), rates_first, first)
    second = robot_recorder(robot, "ddts")
    rates_second = rates_first | dict(zip(d3q, d4q, strict=True))
    tau_ddot = time_derivative(
        (*assignments, *first.assignments),
        [tau_dot[i] for i in elastic],
        rates_second,
        second,
    )
    stiffness, inertia = joint_stiffness(robot), motor_side_inertia(robot)
    theta = [q[i] + tau_link[i] / k for i, k in zip(elastic, stiffness, strict=True)]
    motor = list(tau_link)
    for row, (i, k, b) in enumerate(zip(elastic, stiffness, inertia, strict=True)):
        motor[i] = b * (ddq[i] + tau_ddot[row] / k) + tau_link[i]
    return MotorSide(
        d3q=d3q,
        d4q=d4q,
        theta=sp.ImmutableMatrix(theta),
        tau_motor=sp.ImmutableMatrix(motor),
        tau_link_dd=sp.ImmutableMatrix(tau_ddot),
        assignments=(*assignments, *first.assignments, *second.assignments),
    )

"""Recursive Newton–Euler dynamics: ``c``, ``G`` from the pass in
:mod:`symkin.derive.recursion` (its docstring states the equations), ``M`` by the
composite-rigid-body algorithm and ``C`` from ``M``'s derivatives, run on the base
parameters of :mod:`symkin.derive.base_parameters` where the robot is numeric.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from symkin.derive.base_parameters import base_parameters
from symkin.derive.dynamics import (
    Dynamics,
    friction_vector,
    link_inertial_data,
    motor_inertia_matrix,
)
from symkin.derive.kinematics import Kinematics
from symkin.derive.recursion import (
    BarycentricParameters,
    Recorder,
    barycentric_definitions,
    joint_torques,
    robot_recorder,
)
from symkin.derive.regressor_mass import composite_mass_matrix
from symkin.robot import Robot


def newton_euler_dynamics(
    robot: Robot,
    kinematics: Kinematics,
    dq: Sequence[sp.Symbol],
    ddq: Sequence[sp.Symbol],
    coriolis_matrix: bool = True,
) -> Dynamics:
    """``M``, ``c``, ``G`` (and ``C``) by recursive Newton–Euler, intermediates named."""
    n = robot.dof
    zeros = [sp.Integer(0)] * n
    no_gravity = [sp.Integer(0)] * 3
    recorder = robot_recorder(robot, "r")
    inertial = base_parameters(robot, kinematics)
    gravity = joint_torques(robot, kinematics, recorder, zeros, zeros, robot.gravity, inertial)
    coriolis = joint_torques(robot, kinematics, recorder, dq, zeros, no_gravity, inertial)
    mass = mass_matrix(robot, kinematics, inertial, recorder)
    christoffel = None
    if coriolis_matrix:
        christoffel = coriolis_from_mass_matrix(mass, kinematics.q, dq, recorder)
    return Dynamics(
        method="newton-euler",
        q=kinematics.q,
        dq=tuple(dq),
        ddq=tuple(ddq),
        mass_matrix=sp.ImmutableMatrix(mass),
        coriolis_vector=sp.ImmutableMatrix(coriolis),
        gravity_vector=sp.ImmutableMatrix(gravity),
        friction=friction_vector(robot, dq),
        coriolis_matrix=christoffel,
        assignments=tuple(recorder.assignments),
    )


def mass_matrix(
    robot: Robot,
    kinematics: Kinematics,
    inertial: Sequence[BarycentricParameters] | None,
    recorder: Recorder,
) -> sp.Matrix:
    """``M(q)`` with the rotor inertias, by the composite-rigid-body algorithm of
    :mod:`symkin.derive.regressor_mass` (Featherstone, *Rigid Body Dynamics Algorithms*,
    Sec. 6.2), symmetric with each entry computed once.

    The links' barycentric parameters are ``inertial`` (the base parameters, say), or else the
    file's data moved to each frame origin by the parallel-axis theorem (Khalil & Dombre eq.
    9.4), named once.  Forming the composite inertias once costs fewer operations than ``n``
    unit-acceleration passes of the recursion (PUMA 560: 274 against 489).
    """
    if inertial is None:
        inertial = tuple(
            BarycentricParameters.from_values(
                {k: recorder.name(v) for k, v in barycentric_definitions(link).items()}
            )
            for link in (link_inertial_data(robot, i) for i in range(robot.dof))
        )
    links = composite_mass_matrix(robot, kinematics, inertial, recorder)
    return links + motor_inertia_matrix(robot)


def coriolis_from_mass_matrix(
    mass: sp.MatrixBase,
    q: Sequence[sp.Symbol],
    dq: Sequence[sp.Symbol],
    recorder: Recorder | None = None,
) -> sp.ImmutableMatrix:
    """``C_kj = sum_i 1/2 (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) dq_i`` (Christoffel symbols).

    With a ``recorder`` the derivatives go through its named intermediates.
    """
    n = len(q)

    def derivative(expr: sp.Expr, variable: sp.Symbol) -> sp.Expr:
        return recorder.derivative(expr, variable) if recorder else sp.diff(expr, variable)

    partial = {
        (r, c, k): derivative(mass[r, c], q[k])
        for r in range(n)
        for c in range(r, n)
        for k in range(n)
    }

    def dm(r: int, c: int, k: int) -> sp.Expr:
        return partial[(min(r, c), max(r, c), k)]

    coriolis = sp.Matrix(
        n,
        n,
        lambda k, j: sum((dm(k, j, i) + dm(k, i, j) - dm(i, j, k)) * dq[i] / 2 for i in range(n)),
    )
    return sp.ImmutableMatrix(coriolis)


def inverse_dynamics_recursion(
    robot: Robot,
    kinematics: Kinematics,
    dq: Sequence[sp.Symbol],
    ddq: Sequence[sp.Symbol],
    tip: tuple[sp.MatrixBase, sp.MatrixBase] | None = None,
) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], sp.ImmutableMatrix]:
    """``tau(q, dq, ddq)`` in one recursion (the cheapest form for code), with friction and
    rotor inertia added after it.  Returns the named intermediates and ``tau``.  ``tip``: the
    load of an external wrench as the outer boundary (:func:`symkin.derive.wrench.tip_load`)."""
    recorder = robot_recorder(robot, "s")
    inertial = base_parameters(robot, kinematics)
    rigid = joint_torques(robot, kinematics, recorder, dq, ddq, robot.gravity, inertial, tip)
    rotor = motor_inertia_matrix(robot) * sp.Matrix(ddq)
    torque = sp.Matrix(rigid) + rotor + friction_vector(robot, dq)
    return tuple(recorder.assignments), sp.ImmutableMatrix(torque)

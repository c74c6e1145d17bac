"""The kernels of a robot with elastic joints (none for a rigid robot, so they cost nothing
there): ``elastic_constants`` (``K_spring``, ``B_motor``) and ``elastic_inverse_dynamics``
(``theta_m``, ``tau_m``).

Vectors have one entry per joint so every backend shapes them like ``q``: a rigid joint has
``K_i = B_i = 0``, ``theta_i = q_i`` and its joint torque as ``tau_m_i``.  The 2n-state
forward dynamics is composed from these kernels, ``mass_matrix`` and ``inverse_dynamics`` by
the templates (``elastic_forward_dynamics``), as rigid forward dynamics is.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from symkin.derive import Model
from symkin.derive.elastic import joint_stiffness, motor_side_inertia
from symkin.kernels import units
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel, KernelInput, kernel_from_outputs


def _per_joint(model: Model, values: Sequence[sp.Expr]) -> sp.ImmutableMatrix:
    """``values`` of the elastic joints spread to a joint vector (0 at rigid joints)."""
    column = [sp.Integer(0)] * model.robot.dof
    for i, value in zip(model.robot.elastic_joints, values, strict=True):
        column[i] = value
    return sp.ImmutableMatrix(column)


def elastic_kernels(model: Model, inputs: Sequence[KernelInput]) -> tuple[Kernel, ...]:
    """The elastic kernels of ``model`` (empty without elastic joints); ``inputs`` are the
    dynamics inputs ``q, dq, ddq, p[, pi]``, extended here by ``d3q`` and ``d4q``."""
    robot = model.robot
    if not robot.elastic_joints:
        return ()
    n = robot.dof
    side = model.motor_side
    rates = [
        KernelInput("d3q", side.d3q, "third time derivatives of q (rad/s^3 or m/s^3)"),
        KernelInput("d4q", side.d4q, "fourth time derivatives of q (rad/s^4 or m/s^4)"),
    ]
    position = [i for i in inputs if i.name == "ddq"]
    at = inputs.index(position[0]) + 1
    jerk_inputs = (*inputs[:at], *rates, *inputs[at:])
    constant_inputs = tuple(i for i in inputs if i.name in ("q", "p"))
    stiffness_unit = units.per_joint(robot, "N m/rad", "N/m")
    inertia_unit = units.per_joint(robot, "kg m^2", "kg")
    force = units.generalized_force(robot)
    return (
        kernel_from_outputs(
            "elastic_constants",
            "joint stiffness K and motor-side inertia B (0 at rigid joints)",
            constant_inputs,
            [
                ("K_spring", _per_joint(model, joint_stiffness(robot)), f"K ({n}x1)", "vector",
                 stiffness_unit),
                ("B_motor", _per_joint(model, motor_side_inertia(robot)), f"B ({n}x1)", "vector",
                 inertia_unit),
            ],
        ),
        kernel_from_assignments(
            "elastic_inverse_dynamics",
            "elastic-joint inverse dynamics to the motor side",
            jerk_inputs,
            side.assignments,
            [
                ("theta_m", _theta(model), f"theta = q + K^-1 tau_link ({n}x1)", "vector",
                 units.per_joint(robot, "rad", "m")),
                ("tau_m", side.tau_motor,
                 f"tau_m = B (ddq + K^-1 d2tau_link/dt2) + tau_link ({n}x1)", "vector", force),
            ],
        ),
    )  # fmt: skip


def _theta(model: Model) -> sp.ImmutableMatrix:
    """Motor positions of every joint: ``q_i`` at a rigid joint."""
    theta = list(model.q)
    for row, i in enumerate(model.robot.elastic_joints):
        theta[i] = model.motor_side.theta[row]
    return sp.ImmutableMatrix(theta)

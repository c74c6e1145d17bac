"""Kernels of external wrenches, statics and energies (docs/conventions.md, External wrench).

* ``wrench_torque(q, wrench, p)``: ``-J^T w``, the torques a wrench ``w = (f, n)`` on the tool
  (base frame, at the tool point) adds to ``tau``; the torques of a motion under the wrench
  are ``inverse_dynamics + wrench_torque``.
* ``static_torque(q, wrench, p, pi)``: ``G - J^T w``, the torques that hold the arm at rest.
* ``energy(q, dq, p, pi)``: ``kinetic`` (T), ``potential`` (V) energy and the ``lagrangian``
  ``L = T - V``.

``J^T w`` reuses the Jacobian's expressions (the shorter of its two forms); the statics and
the energies reuse the Newton–Euler intermediates.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from symkin.derive import Model
from symkin.derive.wrench import wrench_torque
from symkin.kernels import units
from symkin.kernels.catalogue import cse_engine, dynamics_inputs, shortest_kernel, state_inputs
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel, KernelInput

ENERGY_UNIT = "J"
WRENCH_DESCRIPTION = (
    "external wrench on the tool (fx fy fz in N, nx ny nz in N m), base frame, at the tool point"
)


def with_wrench(model: Model, inputs: Sequence[KernelInput]) -> tuple[KernelInput, ...]:
    """``inputs`` with the ``wrench`` after the state inputs (before ``p``)."""
    wrench = KernelInput("wrench", model.wrench, WRENCH_DESCRIPTION)
    index = next(i for i, kernel_input in enumerate(inputs) if kernel_input.name == "p")
    return (*inputs[:index], wrench, *inputs[index:])


def statics_kernels(model: Model) -> tuple[Kernel, ...]:
    """``wrench_torque``, ``static_torque`` and ``energy`` (module docstring)."""
    return (wrench_torque_kernel(model), static_torque_kernel(model), energy_kernel(model))


def wrench_torque_kernel(model: Model) -> Kernel:
    """``-J^T w`` from the readable or the product form of ``J``, whichever is shorter; from
    the link-by-link named ``J`` when there is no readable form (as the pose kernels)."""
    n = model.robot.dof
    force = units.generalized_force(model.robot)
    inputs = with_wrench(model, state_inputs(model))
    description = "joint torques of an external wrench"

    def output(jacobian: sp.MatrixBase) -> tuple[str, sp.MatrixBase, str, str, str]:
        return ("tau_w", wrench_torque(jacobian, model.wrench), f"-J^T w ({n}x1)", "vector", force)

    if not model.kinematics.simplified:
        pose = model.named_pose
        outputs = [output(pose.geometric_jacobian)]
        return kernel_from_assignments(
            "wrench_torque", description, inputs, pose.assignments, outputs
        )
    forms = (model,) if model.product_form is model else (model, model.product_form)
    outputs_by_form = [[output(form.geometric_jacobian)] for form in forms]
    return shortest_kernel("wrench_torque", description, inputs, outputs_by_form)


def static_torque_kernel(model: Model) -> Kernel:
    """``G - J^T w`` by one Newton–Euler pass at rest with the wrench as the outer boundary."""
    n = model.robot.dof
    assignments, torque = model.static_torque_recursion
    return kernel_from_assignments(
        "static_torque",
        "static torques holding the arm against gravity and an external wrench",
        with_wrench(model, dynamics_inputs(model)),
        assignments,
        [
            (
                "tau_s",
                torque,
                f"G - J^T w ({n}x1)",
                "vector",
                units.generalized_force(model.robot),
            )
        ],
        cse_engine(model),
    )


def energy_kernel(model: Model) -> Kernel:
    """``T = 1/2 dq^T M dq``, ``V = -sum m g^T p_c`` and ``L = T - V``."""
    energies = model.energies
    outputs = [
        ("kinetic", energies.kinetic, "kinetic energy T = 1/2 dq^T M dq"),
        ("potential", energies.potential, "potential energy V = -sum m_i g^T p_ci"),
        ("lagrangian", energies.lagrangian, "Lagrangian L = T - V"),
    ]
    return kernel_from_assignments(
        "energy",
        "kinetic and potential energy and the Lagrangian",
        dynamics_inputs(model, "dq"),
        energies.assignments,
        [
            (name, sp.Matrix([[value]]), description, "scalar", ENERGY_UNIT)
            for name, value, description in outputs
        ],
        cse_engine(model),
    )

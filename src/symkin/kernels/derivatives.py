"""The derivative kernels (opt-in: ``symkin derive --derivatives``): ``inverse_dynamics_
derivatives`` (tau, dtau/dq, dtau/ddq in one kernel, so tau and its derivatives share one CSE)
and ``jacobian_derivative`` (dJ/dt and the tool's bias acceleration dJ/dt dq).

The forward dynamics' derivatives are composed by each backend from ``mass_matrix`` and
``inverse_dynamics_derivatives`` with a Cholesky solve (see
:func:`symkin.emit.render.forward_dynamics_context`); nothing here inverts ``M``.
"""

from __future__ import annotations

import sympy as sp

from symkin.derive import Model
from symkin.derive.derivatives import time_derivative
from symkin.kernels import units
from symkin.kernels.catalogue import dynamics_inputs, pose_kernels, state_inputs
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.schedule import scheduled
from symkin.kernels.spec import Kernel

# Kernel names, in the order they are generated.
DERIVATIVE_KERNELS = ("inverse_dynamics_derivatives", "jacobian_derivative")


def inverse_dynamics_derivatives_kernel(model: Model) -> Kernel:
    """``tau``, ``dtau/dq`` and ``dtau/ddq`` (entry (i, j) = d tau_i / d x_j), in the order of
    :func:`~symkin.kernels.schedule.scheduled` (the sweeps' columns stored as they finish)."""
    n = model.robot.dof
    derivatives = model.inverse_dynamics_derivatives
    force = units.generalized_force(model.robot)
    per_joint = f"row i in the unit of tau_i ({force}) per unit of joint j"
    kernel = kernel_from_assignments(
        "inverse_dynamics_derivatives",
        "inverse dynamics and its partial derivatives",
        dynamics_inputs(model, "dq", "ddq"),
        derivatives.assignments,
        [
            ("tau", derivatives.torque, f"tau = M ddq + C dq + G + F ({n}x1)", "vector", force),
            (
                "dtau_dq",
                derivatives.torque_q,
                f"d tau_i / d q_j ({n}x{n})",
                "matrix",
                f"{per_joint} ({units.joint_units(model.robot)})",
            ),
            (
                "dtau_ddq",
                derivatives.torque_dq,
                f"d tau_i / d dq_j ({n}x{n}; Coulomb friction's jump at dq = 0 left out)",
                "matrix",
                f"{per_joint} per second",
            ),
        ],
    )
    return scheduled(kernel)


def jacobian_derivative_kernel(model: Model) -> Kernel:
    """``dJ/dt`` of the base-frame geometric Jacobian and ``dJ/dt dq``, by one tangent sweep
    through the ``jacobian`` kernel's intermediates (seed ``qdot = dq``)."""
    n = model.robot.dof
    (jacobian,) = pose_kernels(model, ("jacobian",))
    (matrix,) = (o.matrix for o in jacobian.outputs)
    named, rate = time_derivative(jacobian.assignments, matrix, model.q, model.dq, "jd")
    bias = rate * sp.Matrix(model.dq)
    return kernel_from_assignments(
        "jacobian_derivative",
        "time derivative of the geometric Jacobian",
        state_inputs(model, "dq"),
        jacobian.assignments + named,
        [
            (
                "dJ",
                rate,
                f"dJ/dt ({6}x{n}, rows x y z wx wy wz, base frame)",
                "matrix",
                f"{units.jacobian(model.robot, angular=True)}, per second",
            ),
            (
                "dJ_dq",
                bias,
                "dJ/dt dq: the tool's acceleration at ddq = 0 (6x1, linear then angular)",
                "vector",
                "rows x y z in m/s^2, rows wx wy wz in rad/s^2",
            ),
        ],
    )


def derivative_kernels(model: Model) -> tuple[Kernel, ...]:
    """The derivative kernels of one robot (names :data:`DERIVATIVE_KERNELS`)."""
    return (inverse_dynamics_derivatives_kernel(model), jacobian_derivative_kernel(model))

"""The identification kernels (opt-in: ``symkin derive --regressor``): the regressor ``Y``
and the base regressor ``Y_b`` of :mod:`symkin.derive.regressor` and
:mod:`symkin.derive.regressor_base`, so that ``tau = Y pi = Y_b beta``.

Each output's description names its columns in order, so the generated code documents what
``pi`` and ``beta`` are; ``Y_b``'s base parameters are defined in ``symkin show --dynamics``
and ``symkin identify``.

With them come the dynamics of an identified parameter vector (:func:`barycentric_kernels`):
``mass_matrix_barycentric`` and ``inverse_dynamics_barycentric`` take ``pi`` itself as their
input ``delta`` (the regressor's columns, in its order), so ``tau = Y delta`` holds exactly.
"""

from __future__ import annotations

from symkin.derive import Model
from symkin.derive.regressor import barycentric_dynamics, regressor
from symkin.derive.regressor_base import base_regressor
from symkin.kernels import units
from symkin.kernels.catalogue import state_inputs
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel, KernelInput

KERNEL_NAMES = ("regressor", "base_regressor")
BARYCENTRIC_KERNEL_NAMES = ("mass_matrix_barycentric", "inverse_dynamics_barycentric")
# The units of the regressor's parameters, in its column order.
PARAMETER_UNITS = "kg m^2, kg m, kg; drives: ia kg m^2 (or kg), fv N m s/rad, fc N m"


def identification_kernels(model: Model) -> tuple[Kernel, ...]:
    """``regressor`` (``Y``, n x P) and ``base_regressor`` (``Y_b``, n x b), inputs ``q``,
    ``dq``, ``ddq`` and the geometry parameters ``p``."""
    robot = model.robot
    n = robot.dof
    full = regressor(robot, model.kinematics)
    base = base_regressor(robot, model.kinematics)
    inputs = state_inputs(model, "dq", "ddq")
    unit = (
        f"{units.generalized_force(robot)} per unit of the column's parameter "
        "(kg, kg m, kg m^2, N m s/rad, N m)"
    )
    at = ""
    if base.parameter_values:
        values = ", ".join(
            f"{name} = {v:g}"
            for (name, _), v in zip(robot.parameters, base.parameter_values, strict=True)
        )
        at = f"; columns chosen at {values}"
    outputs = {
        "regressor": (
            "dynamic regressor",
            [
                (
                    "Y",
                    full.matrix,
                    f"Y ({n}x{len(full.names)}, tau = Y pi), columns {' '.join(full.names)}",
                    "matrix",
                    unit,
                )
            ],
        ),
        "base_regressor": (
            "base regressor",
            [
                (
                    "Y_b",
                    base.matrix,
                    f"Y_b ({n}x{len(base.names)}, tau = Y_b beta), columns "
                    f"{' '.join(base.names)}{at}",
                    "matrix",
                    unit,
                )
            ],
        ),
    }
    return tuple(
        kernel_from_assignments(name, description, inputs, full.assignments, output)
        for name, (description, output) in outputs.items()
    )


def barycentric_kernels(model: Model) -> tuple[Kernel, ...]:
    """``mass_matrix_barycentric`` (``M``, n x n) and ``inverse_dynamics_barycentric``
    (``tau``, with rotor inertia and friction), inputs the state, the geometry parameters
    ``p`` and ``delta``: the regressor's parameter vector (module docstring)."""
    robot = model.robot
    n = robot.dof
    dynamics = barycentric_dynamics(robot, model.kinematics)
    names = " ".join(s.name for s in dynamics.symbols)
    delta = KernelInput(
        "delta",
        dynamics.symbols,
        f"barycentric parameters, the regressor's columns (tau = Y delta; {PARAMETER_UNITS}): "
        f"{names}",
    )
    return (
        kernel_from_assignments(
            "mass_matrix_barycentric",
            "mass matrix of barycentric parameters",
            (*state_inputs(model), delta),
            dynamics.mass_assignments,
            [
                (
                    "M",
                    dynamics.mass_matrix,
                    f"M(q) ({n}x{n}) of delta",
                    "matrix",
                    units.mass_matrix(robot),
                )
            ],
        ),
        kernel_from_assignments(
            "inverse_dynamics_barycentric",
            "inverse dynamics of barycentric parameters",
            (*state_inputs(model, "dq", "ddq"), delta),
            dynamics.torque_assignments,
            [
                (
                    "tau",
                    dynamics.torque,
                    f"tau = M ddq + C dq + G + F of delta ({n}x1)",
                    "vector",
                    units.generalized_force(robot),
                )
            ],
        ),
    )

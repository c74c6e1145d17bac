"""The identification kernels (opt-in: ``symkin derive --regressor``): the regressor ``Y``
and the base regressor ``Y_b`` of :mod:`symkin.derive.regressor` and
:mod:`symkin.derive.regressor_base`, so that ``tau = Y pi = Y_b beta``.

Each output's description names its columns in order, so the generated code documents what
``pi`` and ``beta`` are; ``Y_b``'s base parameters are defined in ``symkin show --dynamics``
and ``symkin identify``.
"""

from __future__ import annotations

from symkin.derive import Model
from symkin.derive.regressor import regressor
from symkin.derive.regressor_base import base_regressor
from symkin.kernels import units
from symkin.kernels.catalogue import state_inputs
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel

KERNEL_NAMES = ("regressor", "base_regressor")


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

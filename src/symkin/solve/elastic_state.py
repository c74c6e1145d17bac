"""Numeric motor-side inverse dynamics of a robot with elastic joints (Spong's reduced model,
:mod:`symkin.derive.elastic`): the motor positions ``theta`` and drive torques ``tau_m`` that
make the links follow a planned ``q(t)`` with its first four time derivatives.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError, literal
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.evaluate import dynamics_arguments


@dataclass(frozen=True)
class MotorSideState:
    """``theta`` (motor positions in joint units, ``q_i`` at a rigid joint) and ``tau_motor``
    (motor torque at an elastic joint, joint torque at a rigid one), one entry per joint."""

    elastic_joints: tuple[int, ...]
    theta: np.ndarray
    tau_motor: np.ndarray


def motor_side_state(
    model: Model,
    q: Sequence[float],
    dq: Sequence[float],
    ddq: Sequence[float],
    d3q: Sequence[float],
    d4q: Sequence[float],
    overrides: Mapping[str, float] | None = None,
) -> MotorSideState:
    """``theta = q + K^-1 tau_link`` and ``tau_m = B (ddq + K^-1 d2tau_link/dt2) + tau_link``
    from the generated ``elastic_inverse_dynamics`` kernel.

    Raises :class:`ParameterError` for a robot without elastic joints or a vector whose length
    is not the number of joints.
    """
    robot = model.robot
    if not robot.elastic_joints:
        where = f"{literal(robot.file)}: " if robot.file else ""
        raise ParameterError(
            f"{where}{robot.name} has no elastic joints (no link gives 'stiffness'), so "
            "{d3q} and {d4q} have no use"
        )
    for name, values in zip(("q", "dq", "ddq", "d3q", "d4q"), (q, dq, ddq, d3q, d4q), strict=True):
        if len(values) != robot.dof:
            raise ParameterError(
                f"{{{name}}} needs {robot.dof} values (one per joint), got {len(values)}"
            )
    module = generated_numpy_module(model)
    theta, tau_motor = module.elastic_inverse_dynamics(
        q, dq, ddq, d3q, d4q, **dynamics_arguments(model, overrides)
    )
    return MotorSideState(
        elastic_joints=tuple(i + 1 for i in robot.elastic_joints), theta=theta, tau_motor=tau_motor
    )

"""DC-motor drives in numbers (:class:`~symkin.robot.Drive`): the motor constants of a robot,
and the rigid robot driven by its motors' voltages as a CasADi function.

A joint with a DC motor gets the torque ``G k_t i``; the current follows
``L di/dt = u - R i - k_e G dq`` (``u`` the voltage), or ``i = (u - k_e G dq) / R`` at once
without an inductance.  The time integration is :mod:`symkin.solve.simulate`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import casadi
import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.errors import ParameterError
from symkin.robot import Robot
from symkin.runtime.modules import generated_casadi_module
from symkin.solve.evaluate import dynamics_arguments
from symkin.symbols import parameter_symbol


@dataclass(frozen=True)
class Motor:
    """The DC motor of joint ``joint`` (0-based), SI units; ``inductance`` None: ``L = 0``."""

    joint: int
    gear: float
    torque_constant: float
    back_emf: float
    resistance: float
    inductance: float | None


def parameter_values(robot: Robot, p: Sequence[float]) -> dict[sp.Symbol, float]:
    """``{symbol: value}`` of the robot's parameters from the vector ``p``."""
    names = [name for name, _ in robot.parameters]
    return {parameter_symbol(n): float(v) for n, v in zip(names, p, strict=True)}


def number_from(expr: sp.Expr | None, values: Mapping[sp.Symbol, float]) -> float | None:
    """A robot-file value as a float at the parameter ``values`` (None stays None)."""
    return None if expr is None else float(sp.sympify(expr).xreplace(values))


def motors_of(model: Model, values: Mapping[sp.Symbol, float]) -> tuple[Motor, ...]:
    """The DC motors of the robot's joints, in joint order."""
    motors = []
    for i, joint in enumerate(model.robot.joints):
        drive = joint.link.drive if joint.link else None
        if drive is not None and drive.has_motor:
            constants = (
                drive.gear_ratio, drive.torque_constant, drive.back_emf_constant, drive.resistance,
            )  # fmt: skip
            numbers = [number_from(c, values) for c in constants]
            motors.append(Motor(i, *numbers, number_from(drive.inductance, values)))  # type: ignore[arg-type]
    return tuple(motors)


def motor_dynamics_function(
    model: Model, overrides: Mapping[str, float] | None = None
) -> casadi.Function:
    """A rigid robot driven by DC motors as a ``casadi.Function``
    ``(q, dq, i, u) -> (ddq, di)``: ``u`` holds the voltage at a joint with a motor and the
    torque at one without; ``i`` the currents of the motors with an inductance (others
    ignored) and ``di`` their rates (0 elsewhere).  Parameters take the file's values (or
    ``overrides``); the rigid part is the generated ``forward_dynamics_function``."""
    if model.robot.elastic_joints:
        raise ParameterError(
            f"{model.robot.name}: motor_dynamics_function is for rigid robots; elastic joints "
            "with motors are simulated by symkin.solve.simulate"
        )
    arguments = dynamics_arguments(model, overrides)
    motors = motors_of(model, parameter_values(model.robot, arguments["p"]))
    n = model.robot.dof
    q, dq, current, u = (casadi.SX.sym(name, n) for name in ("q", "dq", "i", "u"))
    torque, rates = [u[k] for k in range(n)], [casadi.SX(0)] * n
    for m in motors:
        emf = m.back_emf * m.gear * dq[m.joint]
        j = m.joint
        if m.inductance is None:
            torque[j] = m.gear * m.torque_constant * (u[j] - emf) / m.resistance
        else:
            torque[j] = m.gear * m.torque_constant * current[j]
            rates[j] = (u[j] - m.resistance * current[j] - emf) / m.inductance
    forward = generated_casadi_module(model).forward_dynamics_function(casadi.SX)
    extra = [np.asarray(arguments["pi"])] if "pi" in arguments else []
    ddq = forward(q, dq, casadi.vertcat(*torque), np.asarray(arguments["p"]), *extra)
    return casadi.Function(
        f"{model.robot.name}_motor_dynamics",
        [q, dq, current, u],
        [ddq, casadi.vertcat(*rates)],
        ["q", "dq", "i", "u"],
        ["ddq", "di"],
    )

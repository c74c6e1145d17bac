"""A robot's generated CasADi and NumPy functions with its parameters filled in, built in
memory (nothing is written for the user to load): the route from a robot file to an optimal
control problem of one's own (docs/trajopt.md, "The open problem")."""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import ROW_NAMES
from symkin.runtime.modules import (
    generated_casadi_module,
    generated_numpy_module,
    generated_point_module,
)
from symkin.solve.evaluate import dynamics_arguments


@dataclass(frozen=True)
class RobotFunctions:
    """The generated functions of one robot, parameters and inertial data bound.

    CasADi (symbolic or numeric arguments; q, dq, ddq, tau are n x m, one state per column):
    ``forward_dynamics(q, dq, tau) -> ddq``, ``inverse_dynamics(q, dq, ddq) -> tau``,
    ``tool_position(q) -> 3 x m``, ``jacobian(q) -> 6 x n`` (geometric, rows x y z wx wy wz,
    one column state), ``link_origins(q) -> list of 3 x 1``: the frame origins 0..n and the
    tool, whose consecutive pairs bound the links.  ``coulomb`` (one value per joint, or
    ``None``) adds smoothed Coulomb friction ``tau_f = F_c tanh(dq / v_s)`` to both dynamics.
    ``forward_function`` and ``inverse_function`` are the same two as ``casadi.Function``
    objects of one state (numeric calls return a ``DM``; fast for integrators).
    NumPy: ``numpy_forward_dynamics(q, dq, tau)`` and ``numpy_inverse_dynamics(q, dq, ddq)``
    (the generated NumPy kernels, states along the first axis).  ``lower`` and ``upper`` are
    the joint limits of the robot file (infinite where it gives none); ``task_rows`` the rows
    of the Jacobian the tool can move (:attr:`symkin.Model.task_rows`).
    """

    dof: int
    forward_dynamics: Callable
    inverse_dynamics: Callable
    tool_position: Callable
    jacobian: Callable
    link_origins: Callable
    forward_function: Callable
    inverse_function: Callable
    numpy_forward_dynamics: Callable
    numpy_inverse_dynamics: Callable
    lower: np.ndarray
    upper: np.ndarray
    task_rows: tuple[int, ...]


def robot_functions(
    model: Model,
    overrides: Mapping[str, float] | None = None,
    coulomb: tuple[float, ...] | None = None,
    friction_velocity: float = 0.01,
) -> RobotFunctions:
    """The generated CasADi and NumPy functions of ``model``'s robot, rendered and loaded in
    memory, with the parameters (``overrides``: as ``symkin eval --set``) filled in."""
    import casadi

    args = dynamics_arguments(model, overrides)
    constants = [casadi.DM(value) for value in args.values()]
    n = model.robot.dof
    dynamics = generated_casadi_module(model)
    kinematics = generated_casadi_module(model, "kinematics")
    forward = dynamics.forward_dynamics_function(casadi.SX)
    inverse = dynamics.inverse_dynamics_function(casadi.SX)
    position = kinematics.position_function(casadi.SX)
    fk_jacobian = kinematics.fk_jacobian_function(casadi.SX)
    friction = _smoothed_coulomb(coulomb, friction_velocity)
    numpy_module = generated_numpy_module(model)

    def forward_dynamics(q, dq, tau):
        return _columns(forward, q, dq, tau - friction(dq), *constants)

    def inverse_dynamics(q, dq, ddq):
        return _columns(inverse, q, dq, ddq, *constants) + friction(dq)

    def numpy_forward(q, dq, tau):
        return numpy_module.forward_dynamics(q, dq, tau - friction(dq), **args)

    def numpy_inverse(q, dq, ddq):
        return numpy_module.inverse_dynamics(q, dq, ddq, **args) + friction(dq)

    limits = [joint.limits or (-np.inf, np.inf) for joint in model.robot.joints]
    q, dq, v = (casadi.SX.sym(name, n) for name in ("q", "dq", "v"))
    return RobotFunctions(
        dof=n,
        forward_dynamics=forward_dynamics,
        inverse_dynamics=inverse_dynamics,
        tool_position=lambda q: _columns(position, q, constants[0]),
        jacobian=lambda q: fk_jacobian(q, constants[0])[1],
        link_origins=_link_origins(model, constants[0]),
        forward_function=casadi.Function("fd", [q, dq, v], [forward_dynamics(q, dq, v)]),
        inverse_function=casadi.Function("id", [q, dq, v], [inverse_dynamics(q, dq, v)]),
        numpy_forward_dynamics=numpy_forward,
        numpy_inverse_dynamics=numpy_inverse,
        lower=np.array([lo for lo, _ in limits], dtype=float),
        upper=np.array([hi for _, hi in limits], dtype=float),
        task_rows=tuple(ROW_NAMES.index(row) for row in model.task_rows),
    )


def _columns(function, *arguments):
    """``function`` on every column of its first argument (``Function.map`` when there are
    several columns): the generated functions take one state."""
    count = arguments[0].shape[1] if len(arguments[0].shape) > 1 else 1
    if count == 1:
        return function(*arguments)
    return function.map(count)(*arguments)


def _smoothed_coulomb(coulomb: tuple[float, ...] | None, velocity: float) -> Callable:
    """``dq -> F_c tanh(dq / v_s)`` (zero without ``coulomb``): Coulomb friction made smooth
    for the solver; within ``v_s`` of rest it is viscous-like (slope ``F_c / v_s``)."""
    if coulomb is None:
        return lambda dq: 0.0
    import casadi

    force = np.array(coulomb, dtype=float)

    def friction(dq):
        if isinstance(dq, np.ndarray):
            return force * np.tanh(dq / velocity)
        return casadi.repmat(casadi.DM(force), 1, dq.shape[1]) * casadi.tanh(dq / velocity)

    return friction


def _link_origins(model: Model, parameters) -> Callable:
    """``q -> [o_0, .., o_n, p_tool]``, the frame origins from the generated point kernels
    (CasADi backend; velocities and accelerations fed zeros and pruned by CasADi).  The point
    kernels are derived on the first call only: problems without obstacles never pay for
    them."""
    import casadi

    n = model.robot.dof
    zeros = casadi.DM.zeros(n)

    @functools.cache
    def kernels() -> list:
        points = tuple((link, (0.0, 0.0, 0.0)) for link in range(n + 1))
        module = generated_point_module(model, points, backend="casadi")
        found = [getattr(module, f"point{k}_function")(casadi.SX) for k in range(1, n + 2)]
        return [*found, generated_casadi_module(model, "kinematics").position_function(casadi.SX)]

    def origins(q):
        *points, position = kernels()
        return [f(q, zeros, zeros, parameters)[0] for f in points] + [position(q, parameters)]

    return origins

"""Forward simulation: the equations of motion integrated with SciPy's ``solve_ivp``, with
elastic joints, DC motors and stick/slip friction.

The state is ``(q, dq)``, then ``(theta, dtheta)`` of the elastic joints (Spong's reduced
model, :mod:`symkin.derive.elastic`), then the current of each DC motor with an inductance.
A joint's drive torque is ``tau(t)`` (the motor torque of an elastic joint), or ``G k_t i``
for a joint with a DC motor driven by ``voltage(t)`` (:class:`~symkin.robot.Drive`):
``L di/dt = u - R i - k_e G w`` with ``w`` the joint speed (``dtheta`` when elastic);
without ``L`` the current is ``(u - k_e G w) / R`` at once.

Stick/slip (seed 003, friction): a rigid joint whose link gives ``friction.stiction``
(``gamma_s``) sticks when its speed reaches 0 while the torque ``Z`` that must hold it,
``Z_S = (u - bias)_S - M_SR ddq_R`` with the stuck set ``S`` held (``ddq_S = 0``), satisfies
``|Z| <= gamma_s``; it slips again when ``|Z|`` exceeds ``gamma_s``, starting against the
Coulomb level in the direction of ``Z``.  Sticking and slipping are events that end an
integration segment; each segment integrates a smooth system.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from symkin.derive import Model
from symkin.errors import ParameterError, SymkinError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.drives import Motor, motors_of, number_from, parameter_values
from symkin.solve.evaluate import dynamics_arguments

Input = Callable[[float], Sequence[float]]


@dataclass(frozen=True)
class Simulation:
    """Samples of a simulated motion: ``t`` (m), ``q``, ``dq`` (m x n); ``theta`` and
    ``dtheta`` of the elastic joints (m x e, None without any); ``current`` of the DC motors
    with an inductance (m x c, None without any); ``stuck`` (m x n, True where a joint is held
    by static friction)."""

    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    theta: np.ndarray | None
    dtheta: np.ndarray | None
    current: np.ndarray | None
    stuck: np.ndarray


@dataclass(frozen=True)
class _Plant:
    """The numbers of one simulation: generated kernels and their arguments, drive data."""

    module: object
    arguments: Mapping[str, np.ndarray]
    n: int
    elastic: tuple[int, ...]
    stiffness: np.ndarray
    motor_inertia: np.ndarray
    motors: tuple[Motor, ...]
    coulomb: np.ndarray
    stiction: np.ndarray  # gamma_s, NaN where a joint does not stick
    tau: Input
    voltage: Input

    @property
    def inductive(self) -> tuple[Motor, ...]:
        return tuple(m for m in self.motors if m.inductance is not None)


def _plant(
    model: Model, tau: Input | None, voltage: Input | None, overrides: Mapping[str, float] | None
) -> _Plant:
    robot = model.robot
    arguments = dynamics_arguments(model, overrides)
    values = parameter_values(robot, arguments["p"])
    module = generated_numpy_module(model)
    n = robot.dof
    stiffness = motor_inertia = np.zeros(n)
    if robot.elastic_joints:
        stiffness, motor_inertia = module.elastic_constants(np.zeros(n), arguments["p"])
    links = [j.link for j in robot.joints]
    coulomb = np.array([number_from(link.coulomb, values) if link else 0.0 for link in links])
    stiction = np.array(
        [
            np.nan
            if link is None or link.stiction is None or link.is_elastic
            else number_from(link.stiction, values)
            for link in links
        ]
    )
    motors = motors_of(model, values)
    if motors and voltage is None:
        raise ParameterError(f"{robot.name} has DC motors: give their {{voltage}}(t)")
    zeros = np.zeros(n)
    return _Plant(
        module=module,
        arguments=arguments,
        n=n,
        elastic=robot.elastic_joints,
        stiffness=np.asarray(stiffness, dtype=float),
        motor_inertia=np.asarray(motor_inertia, dtype=float),
        motors=motors,
        coulomb=coulomb,
        stiction=stiction,
        tau=tau or (lambda t: zeros),
        voltage=voltage or (lambda t: zeros),
    )


def _drive_torques(plant: _Plant, t: float, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drive torques of every joint and ``di/dt`` of the inductive motors."""
    n, e = plant.n, len(plant.elastic)
    torque = np.array(plant.tau(t), dtype=float).copy()
    voltage = np.asarray(plant.voltage(t), dtype=float)
    speeds = y[n : 2 * n].copy()
    speeds[list(plant.elastic)] = y[2 * n + e : 2 * n + 2 * e]
    currents = iter(y[2 * n + 2 * e :])
    rates = []
    for motor in plant.motors:
        emf = motor.back_emf * motor.gear * speeds[motor.joint]
        u = voltage[motor.joint]
        if motor.inductance is None:
            current = (u - emf) / motor.resistance
        else:
            current = next(currents)
            rates.append((u - motor.resistance * current - emf) / motor.inductance)
        torque[motor.joint] = motor.gear * motor.torque_constant * current
    return torque, np.array(rates)


def _held(
    plant: _Plant, q: np.ndarray, dq: np.ndarray, link_torque: np.ndarray, stuck: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``ddq`` with the ``stuck`` joints held (``ddq_S = 0``) and the holding torques ``Z``."""
    args = plant.arguments
    mass = plant.module.mass_matrix(q, **args)
    rhs = link_torque - plant.module.inverse_dynamics(q, dq, np.zeros(plant.n), **args)
    free = ~stuck
    ddq = np.zeros(plant.n)
    ddq[free] = np.linalg.solve(mass[np.ix_(free, free)], rhs[free])
    return ddq, rhs - mass @ ddq


def _rates(
    t: float, y: np.ndarray, plant: _Plant, stuck: np.ndarray, direction: np.ndarray
) -> np.ndarray:
    """``dy/dt`` in one mode: ``stuck`` joints held; a joint that has just slipped (speed
    still 0, where the kernel's ``sign(dq)`` is 0) feels Coulomb friction against its slip
    ``direction``."""
    n, e = plant.n, len(plant.elastic)
    q, dq = y[:n], y[n : 2 * n]
    torque, current_rates = _drive_torques(plant, t, y)
    link_torque = torque.copy()
    elastic = list(plant.elastic)
    spring = plant.stiffness[elastic] * (y[2 * n : 2 * n + e] - q[elastic])
    link_torque[elastic] = spring
    link_torque -= np.where(dq == 0, plant.coulomb * direction, 0.0)
    ddq, _ = _held(plant, q, dq, link_torque, stuck)
    ddtheta = (torque[elastic] - spring) / plant.motor_inertia[elastic]
    speeds = np.where(stuck, 0.0, dq)
    return np.concatenate([speeds, ddq, y[2 * n + e : 2 * n + 2 * e], ddtheta, current_rates])


def _holding_torque(plant: _Plant, t: float, y: np.ndarray, stuck: np.ndarray) -> np.ndarray:
    n = plant.n
    torque, _ = _drive_torques(plant, t, y)
    elastic = list(plant.elastic)
    e = len(elastic)
    torque[elastic] = plant.stiffness[elastic] * (y[2 * n : 2 * n + e] - y[:n][elastic])
    return _held(plant, y[:n], y[n : 2 * n], torque, stuck)[1]


def _events(
    plant: _Plant, stuck: np.ndarray, y: np.ndarray, direction: np.ndarray
) -> list[Callable[[float, np.ndarray], float]]:
    """One terminal event per stick/slip joint: its holding torque reaching ``gamma_s`` while
    stuck, or while sliding its speed returning to 0 from the side it moves on (``dq`` at the
    segment's start, or the slip ``direction`` when that is 0: the start itself is no event)."""
    events = []
    for i in np.flatnonzero(~np.isnan(plant.stiction)):
        if stuck[i]:

            def slip(t: float, x: np.ndarray, *_: object, i: int = i) -> float:
                return plant.stiction[i] - abs(_holding_torque(plant, t, x, stuck)[i])

            slip.direction = -1  # type: ignore[attr-defined]
            events.append(slip)
        else:

            def halt(t: float, x: np.ndarray, *_: object, i: int = i) -> float:
                return x[plant.n + i]

            moving = np.sign(y[plant.n + i]) or direction[i]
            halt.direction = -moving  # type: ignore[attr-defined]
            events.append(halt)
    for event in events:
        event.terminal = True  # type: ignore[attr-defined]
    return events


def _next_mode(
    plant: _Plant, t: float, y: np.ndarray, stuck: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stuck set and the slip directions (``sign Z`` of joints that start to slide, else
    0) after an event at ``(t, y)``; speeds of stuck joints are set to exactly 0."""
    n = plant.n
    candidates = ~np.isnan(plant.stiction) & (stuck | (np.abs(y[n : 2 * n]) < 1e-9))
    y = y.copy()
    y[n : 2 * n][candidates] = 0.0
    held = candidates.copy()
    z = _holding_torque(plant, t, y, held)
    slipping = held & (np.abs(z) > plant.stiction + 1e-12 * np.maximum(1.0, plant.stiction))
    return held & ~slipping, np.where(slipping, np.sign(z), 0.0), y


def simulate(
    model: Model,
    duration: float,
    q0: Sequence[float],
    dq0: Sequence[float],
    *,
    tau: Input | None = None,
    voltage: Input | None = None,
    theta0: Sequence[float] | None = None,
    dtheta0: Sequence[float] | None = None,
    current0: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
    samples: int = 201,
    rtol: float = 1e-9,
    atol: float = 1e-11,
) -> Simulation:
    """Integrate the robot's motion from ``t = 0`` to ``duration`` (module docstring).

    ``tau(t)``: drive torques of every joint (motor torques of elastic joints; zeros when
    omitted); ``voltage(t)``: DC-motor voltages, one per joint (entries of joints without a
    motor are ignored).  ``theta0``/``dtheta0`` are per joint (the elastic joints' entries are
    used; default ``q0``/``dq0``, the spring at rest), ``current0`` per inductive motor
    (default 0).  Returns ``samples`` evenly spaced samples of the state.
    """
    plant = _plant(model, tau, voltage, overrides)
    n, elastic = plant.n, list(plant.elastic)
    if len(q0) != n or len(dq0) != n:
        raise ParameterError(f"{{q0}} and {{dq0}} need {n} values each")
    theta0 = np.asarray(q0 if theta0 is None else theta0, dtype=float)[elastic]
    dtheta0 = np.asarray(dq0 if dtheta0 is None else dtheta0, dtype=float)[elastic]
    currents = np.zeros(len(plant.inductive)) if current0 is None else np.asarray(current0)
    y = np.concatenate([q0, dq0, theta0, dtheta0, currents]).astype(float)
    times = np.linspace(0.0, duration, samples)
    return _integrate(plant, times, y, rtol, atol)


def _integrate(
    plant: _Plant, times: np.ndarray, y: np.ndarray, rtol: float, atol: float
) -> Simulation:
    """Segments between stick/slip events, each a ``solve_ivp`` run (dense output sampled)."""
    t, end = 0.0, float(times[-1])
    states = np.full((len(times), y.size), np.nan)
    stuck_at = np.zeros((len(times), plant.n), dtype=bool)
    stuck, direction, y = _next_mode(plant, t, y, np.zeros(plant.n, dtype=bool))
    for _ in range(10_000):
        result = solve_ivp(
            _rates,
            (t, end),
            y,
            args=(plant, stuck, direction),
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=_events(plant, stuck, y, direction),
            dense_output=True,
        )
        if result.status == -1:
            raise SymkinError(f"simulation failed at t = {t:g} s: {result.message}")
        inside = (times >= t) & (times <= result.t[-1])
        states[inside] = result.sol(times[inside]).T
        stuck_at[inside] = stuck
        t, y = float(result.t[-1]), result.y[:, -1]
        if result.status == 0:
            return _simulation(plant, times, states, stuck_at)
        stuck, direction, y = _next_mode(plant, t, y, stuck)
    raise SymkinError(f"simulation stopped at t = {t:g} s: over 10000 stick/slip switches")


def _simulation(
    plant: _Plant, times: np.ndarray, states: np.ndarray, stuck: np.ndarray
) -> Simulation:
    n, e, c = plant.n, len(plant.elastic), len(plant.inductive)
    return Simulation(
        t=times,
        q=states[:, :n],
        dq=np.where(stuck, 0.0, states[:, n : 2 * n]),
        theta=states[:, 2 * n : 2 * n + e] if e else None,
        dtheta=states[:, 2 * n + e : 2 * n + 2 * e] if e else None,
        current=states[:, 2 * n + 2 * e :] if c else None,
        stuck=stuck,
    )

"""Point-to-point trajectory optimisation on the generated CasADi dynamics, solved with IPOPT.

The optimal control problem (docs/trajopt.md has the equations)::

    minimise     sum_k h |tau_k|^2       (effort: the integral of tau^2, tau piecewise constant)
            or   T                       (minimum time, h = T / N)
    subject to   x = (q, dq),  dx/dt = (dq, FD(q, dq, tau))     the robot's forward dynamics
                 q(0) = q_start, dq(0) = 0, q(T) = q_goal (or tool position = goal), dq(T) = 0
                 q_lo <= q <= q_hi,  |dq| <= dq_max,  |tau| <= tau_max

``FD`` solves ``M(q) ddq = tau - c - G - F`` (the CasADi backend's ``forward_dynamics``, friction
and rotor inertia included).  Two transcriptions on N intervals with piecewise-constant torques:
direct multiple shooting (Bock and Plitt 1984) with classical RK4 substeps, and direct
collocation at the Radau IIA points (Betts, Practical Methods for Optimal Control, 2nd ed.,
SIAM 2010, Sec. 4.5).  Both start from the straight joint-space line between the two
configurations.  Coulomb friction (``sign(dq)``) is not differentiable at rest; robots with it
may converge slowly.
"""

from __future__ import annotations

import io
import json
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.numeric import parameter_substitution
from symkin.errors import SymkinError
from symkin.output_folder import replace_file
from symkin.robot import Joint, Robot
from symkin.runtime.modules import generated_casadi_module, generated_numpy_module
from symkin.solve.evaluate import dynamic_state, dynamics_arguments

Objective = Literal["effort", "time"]
Method = Literal["multiple-shooting", "collocation"]
OBJECTIVES: tuple[str, ...] = ("effort", "time")
# IPOPT statuses that count as a solution; anything else is reported as a failure.
SOLVED = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
# Largest constraint violation (in the constraint's own unit) a returned solution may have;
# IPOPT's "acceptable" level alone would let 1e-2 through.
FEASIBILITY_TOLERANCE = 1e-6
MAX_ITERATIONS = 3000
# Minimum time minimises TIME_SCALE * (T + r * sum_k h |tau_k / tau_max|^2), r the problem's
# ``regularisation``.  With a gradient of 1, IPOPT crawled for hundreds of iterations on the
# PUMA 560 (collocation); at 100, IPOPT's default largest scaled gradient
# (nlp_scaling_max_gradient), it converges in tens.  Found by experiment.
TIME_SCALE = 100.0
COST_NAMES = {"effort": "integral of tau^2", "time": "final time"}
# The final time of a minimum-time problem stays above this many seconds (h > 0).
MIN_FINAL_TIME = 1e-3


class InfeasibleTrajectoryError(SymkinError):
    """No trajectory meets the limits: the message names the limits or constraints at fault."""


@dataclass(frozen=True)
class TrajectoryProblem:
    """A rest-to-rest motion from ``start`` to ``goal`` (joint values, radians or metres).

    With ``cartesian_goal`` (x, y, z of the tool in the base frame, metres) the final
    configuration is free and ``goal``, if given, is only its initial guess.  ``final_time``
    (seconds) is required for the effort objective and not allowed for minimum time.
    ``velocity_limits`` and ``torque_limits`` hold one positive value per joint (``None``: no
    limit); position limits come from the robot file.  ``overrides`` sets parameters and the
    inertial data a robot file leaves out (``m1``, ``cx1``, ...), as ``symkin eval --set``.
    ``substeps`` is the number of RK4 steps per interval (multiple shooting) and ``degree``
    the number of Radau points per interval (collocation).

    ``regularisation`` r weights a small effort term in the minimum-time objective,
    ``T + r sum_k h |tau_k / tau_max|^2``.  It picks one torque profile where T alone leaves
    torques undecided (joints that finish early, arcs at a velocity limit), which IPOPT
    otherwise resolves only slowly (hundreds of iterations for the PUMA 560 with collocation);
    it lengthens T a little (bench/trajopt_time.py measures by how much; docs/trajopt.md).
    """

    start: tuple[float, ...]
    goal: tuple[float, ...] | None = None
    cartesian_goal: tuple[float, float, float] | None = None
    intervals: int = 40
    final_time: float | None = None
    objective: Objective = "effort"
    method: Method = "multiple-shooting"
    velocity_limits: tuple[float, ...] | None = None
    torque_limits: tuple[float, ...] | None = None
    overrides: tuple[tuple[str, float], ...] = ()
    substeps: int = 2
    degree: int = 3
    regularisation: float = 1e-2

    def __post_init__(self) -> None:
        for name in ("start", "goal", "cartesian_goal", "velocity_limits", "torque_limits"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, tuple(float(v) for v in value))
        overrides = self.overrides
        if isinstance(overrides, Mapping):
            overrides = overrides.items()
        object.__setattr__(self, "overrides", tuple((k, float(v)) for k, v in overrides))


@dataclass(frozen=True)
class SolverStats:
    """IPOPT's return status and iteration count; ``solve_time`` is the wall time in seconds
    of ``Opti.solve`` (CasADi's derivative set-up plus IPOPT), not of building the problem."""

    status: str
    iterations: int
    solve_time: float


@dataclass(frozen=True)
class Trajectory:
    """An optimal trajectory on the grid ``t_k = k T / N``, k = 0..N.

    ``q`` and ``dq`` are (N+1) x n; ``tau`` is N x n, ``tau[k]`` held on ``[t_k, t_k+1)``.
    ``cost`` is the objective (effort in N^2 m^2 s for revolute joints, or T in s);
    ``effort`` is ``sum_k h |tau_k|^2`` for either objective.  ``max_violation`` is the
    largest constraint violation at the solution, in each constraint's own unit.
    """

    robot: Robot
    problem: TrajectoryProblem
    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    tau: np.ndarray
    cost: float
    effort: float
    max_violation: float
    stats: SolverStats

    @property
    def final_time(self) -> float:
        return float(self.t[-1])


@dataclass(frozen=True)
class _Group:
    """A group of constraints ``lower <= expr <= upper`` with a name for error messages."""

    label: str
    expr: Any
    lower: Any
    upper: Any
    unit: str = ""


# ---------------------------------------------------------------- model pieces


def units(joint: Joint) -> tuple[str, str, str]:
    """Position, velocity and torque (or force) units of a joint."""
    return ("rad", "rad/s", "N m") if joint.type == "revolute" else ("m", "m/s", "N")


def _check_vector(
    values: Sequence[float] | None, names: Sequence[str], what: str, positive: bool = False
) -> None:
    """``values`` holds one finite (or positive) number for each of ``names``."""
    if values is None:
        return
    if len(values) != len(names):
        raise SymkinError(
            f"{what}: expected {len(names)} values ({', '.join(names)}), got {len(values)}"
        )
    for name, value in zip(names, values, strict=True):
        if not math.isfinite(value) or (positive and value <= 0):
            kind = "a positive number" if positive else "a finite number"
            raise SymkinError(f"{what}: {name} needs {kind}, got {value:g}")


def check_problem(model: Model, problem: TrajectoryProblem) -> None:
    """Reject malformed problems and those that are infeasible on their face.

    Caught before any solve: wrong vector lengths, non-positive limits, a start or goal outside
    the joint limits, a gravity torque at the start or goal above the torque limit, a move that
    the velocity limit cannot make in the given time, and a Cartesian goal off a coordinate
    the tool cannot change (a planar arm's z).
    """
    robot = model.robot
    joints = [f"joint {i}" for i in range(1, robot.dof + 1)]
    _check_vector(problem.start, joints, "start")
    _check_vector(problem.goal, joints, "goal")
    _check_vector(problem.velocity_limits, joints, "velocity limit", positive=True)
    _check_vector(problem.torque_limits, joints, "torque limit", positive=True)
    _check_vector(problem.cartesian_goal, ("x", "y", "z"), "Cartesian goal")
    if problem.goal is None and problem.cartesian_goal is None:
        raise SymkinError("give a goal: joint values or a Cartesian tool position")
    if problem.objective not in OBJECTIVES:
        raise SymkinError(
            f"objective must be one of {', '.join(OBJECTIVES)}, got {problem.objective!r}"
        )
    if problem.method not in TRANSCRIPTIONS:
        methods = ", ".join(TRANSCRIPTIONS)
        raise SymkinError(f"method must be one of {methods}, got {problem.method!r}")
    for name, lowest in (("intervals", 1), ("substeps", 1), ("degree", 1)):
        if getattr(problem, name) < lowest:
            raise SymkinError(f"{name} must be at least {lowest}, got {getattr(problem, name)}")
    if not (math.isfinite(problem.regularisation) and problem.regularisation >= 0):
        raise SymkinError(f"regularisation must be 0 or positive, got {problem.regularisation:g}")
    if problem.objective == "effort":
        if problem.final_time is None:
            raise SymkinError("minimum effort needs a fixed final time (--time T, in seconds)")
        if not (math.isfinite(problem.final_time) and problem.final_time > 0):
            raise SymkinError(f"the final time must be positive, got {problem.final_time:g} s")
    else:
        if problem.final_time is not None:
            raise SymkinError(
                "minimum time leaves the final time free: drop the fixed time (--time)"
            )
        if problem.torque_limits is None:
            raise SymkinError(
                "minimum time needs torque limits (--torque-limit): without them any motion "
                "can be made arbitrarily fast"
            )

    joint_goal = problem.goal if problem.cartesian_goal is None else None
    for where, q in (("start", problem.start), ("goal", joint_goal)):
        if q is None:
            continue
        for i, (value, joint) in enumerate(zip(q, robot.joints, strict=True), start=1):
            if joint.limits is not None and not joint.limits[0] <= value <= joint.limits[1]:
                lo, hi = joint.limits
                raise InfeasibleTrajectoryError(
                    f"the {where} puts joint {i} at {value:.6g} {units(joint)[0]}, outside its "
                    f"limits [{lo:.6g}, {hi:.6g}] {units(joint)[0]}"
                )
    overrides = dict(problem.overrides)
    for where, q in (("start", problem.start), ("goal", joint_goal)):
        if q is None:
            continue
        hold = dynamic_state(model, q, overrides=overrides).gravity
        for i, need in enumerate(np.atleast_1d(hold), start=1):
            limit = None if problem.torque_limits is None else problem.torque_limits[i - 1]
            if limit is not None and abs(need) > limit:
                unit = units(robot.joints[i - 1])[2]
                raise InfeasibleTrajectoryError(
                    f"torque limit of joint {i} ({limit:g} {unit}) below the {abs(need):.4g} "
                    f"{unit} gravity needs at the {where}"
                )
    if joint_goal is not None and problem.velocity_limits and problem.final_time:
        for i, (a, b, limit) in enumerate(
            zip(problem.start, joint_goal, problem.velocity_limits, strict=True), start=1
        ):
            if abs(b - a) > limit * problem.final_time:
                unit, rate, _ = units(robot.joints[i - 1])
                raise InfeasibleTrajectoryError(
                    f"joint {i} must move {abs(b - a):.4g} {unit} in {problem.final_time:g} s, "
                    f"more than its velocity limit of {limit:g} {rate} allows (it needs at "
                    f"least {abs(b - a) / limit:.4g} s)"
                )
    if problem.cartesian_goal is not None:
        _check_cartesian_goal(model, problem.cartesian_goal, overrides)


def _fixed_tool_coordinates(model: Model, overrides: Mapping[str, float]) -> dict[int, float]:
    """Tool coordinates that no joint moves (row -> value), e.g. z of a planar arm."""
    kinematic = {k: v for k, v in overrides.items() if k in dict(model.robot.parameters)}
    substitution = parameter_substitution(model, kinematic)
    joints = set(model.q)
    return {
        row: float(expr.xreplace(substitution))
        for row, expr in enumerate(model.tool_position)
        if not (sp.sympify(expr).free_symbols & joints)
    }


def _check_cartesian_goal(
    model: Model, goal: Sequence[float], overrides: Mapping[str, float]
) -> None:
    for row, value in _fixed_tool_coordinates(model, overrides).items():
        if abs(goal[row] - value) > FEASIBILITY_TOLERANCE:
            raise InfeasibleTrajectoryError(
                f"the tool's {'xyz'[row]} is {value:.6g} m in every configuration of "
                f"{model.robot.name}; the Cartesian goal asks for {goal[row]:.6g} m"
            )


# ---------------------------------------------------------------- transcriptions


def _rk4_step(dynamics: Callable, n: int, substeps: int):
    """``x_next = F(x, tau, h)``: ``substeps`` classical RK4 steps of length ``h / substeps``
    with ``tau`` held constant."""
    import casadi

    x = casadi.SX.sym("x", 2 * n)
    tau = casadi.SX.sym("tau", n)
    h = casadi.SX.sym("h")
    step = h / substeps
    xk = x
    for _ in range(substeps):
        k1 = dynamics(xk, tau)
        k2 = dynamics(xk + step / 2 * k1, tau)
        k3 = dynamics(xk + step / 2 * k2, tau)
        k4 = dynamics(xk + step * k3, tau)
        xk = xk + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return casadi.Function("rk4", [x, tau, h], [xk])


def radau_coefficients(degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(points, C, D)`` of Radau IIA collocation on the unit interval (Betts 2010, Sec. 4.5).

    ``points = [0, s_1 .. s_d]`` with ``s_d = 1``.  With ``L_j`` the Lagrange polynomials on
    these points, ``C[j, r] = L_j'(s_r)`` (the state's slope at ``s_r`` is
    ``sum_j C[j, r] Z_j / h``) and ``D[j] = L_j(1)`` (the state at the interval's end).
    """
    import casadi

    points = np.append(0.0, casadi.collocation_points(degree, "radau"))
    size = degree + 1
    C = np.zeros((size, size))
    D = np.zeros(size)
    for j in range(size):
        basis = np.poly1d([1.0])
        for r in range(size):
            if r != j:
                basis *= np.poly1d([1.0, -points[r]]) / (points[j] - points[r])
        D[j] = basis(1.0)
        C[j] = np.polyder(basis)(points)
    return points, C, D


@dataclass(frozen=True)
class _Transcription:
    """Node states ``X`` (2n x N+1) and torques ``U`` (n x N) as decision variables;
    ``defects`` must vanish; ``guesses`` pairs further variables with the fractions of T at
    which their initial guess lies on the straight line.  Path limits apply at the nodes."""

    X: Any
    U: Any
    defects: Any
    guesses: tuple[tuple[Any, np.ndarray], ...] = ()


def _multiple_shooting(opti, dynamics: Callable, n: int, problem: TrajectoryProblem, h):
    """``x_k+1 = RK4(x_k, tau_k, h)`` on every interval, as defects ``RK4(...) - x_k+1``."""
    N = problem.intervals
    X = opti.variable(2 * n, N + 1)
    U = opti.variable(n, N)
    step = _rk4_step(dynamics, n, problem.substeps).map(N)
    return _Transcription(X, U, step(X[:, :-1], U, h) - X[:, 1:])


def _collocation(opti, dynamics: Callable, n: int, problem: TrajectoryProblem, h):
    """On interval k with ``Z = [x_k, x_k1 .. x_kd]``: ``Z C[:, r] = h f(x_kr, tau_k)`` at the
    d Radau points and ``x_k+1 = Z D`` (continuity)."""
    import casadi

    N, d = problem.intervals, problem.degree
    points, C, D = radau_coefficients(d)
    X = opti.variable(2 * n, N + 1)
    U = opti.variable(n, N)
    Xc = opti.variable(2 * n, N * d)  # the collocation states, d per interval, in time order
    x = casadi.SX.sym("x", 2 * n)
    tau = casadi.SX.sym("tau", n)
    slope = casadi.Function("f", [x, tau], [dynamics(x, tau)]).map(N * d)
    slopes = slope(Xc, casadi.repmat(U, d, 1).reshape((n, N * d)))
    defects = []
    for k in range(N):
        Z = casadi.horzcat(X[:, k], Xc[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, C[:, 1:]) - h * slopes[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, D) - X[:, k + 1])
    fractions = (np.arange(N)[:, None] + points[None, 1:]).ravel() / N
    return _Transcription(X, U, casadi.horzcat(*defects), ((Xc, fractions),))


TRANSCRIPTIONS: Mapping[str, Callable] = {
    "multiple-shooting": _multiple_shooting,
    "collocation": _collocation,
}


# ---------------------------------------------------------------- constraints


def _constraint_groups(
    model: Model, problem: TrajectoryProblem, transcription: _Transcription, tool_position
) -> list[_Group]:
    """Every constraint of the problem, in named groups (the names go into error messages)."""
    import casadi

    n = model.robot.dof
    X, U = transcription.X, transcription.U
    groups = [
        _Group("dynamics (transcription defects)", transcription.defects, 0.0, 0.0),
        _Group("start configuration", X[:n, 0], problem.start, problem.start),
        _Group("rest at the start", X[n:, 0], 0.0, 0.0),
        _Group("rest at the goal", X[n:, -1], 0.0, 0.0),
    ]
    if problem.cartesian_goal is None:
        groups.append(_Group("goal configuration", X[:n, -1], problem.goal, problem.goal))
    else:
        # Coordinates no joint can change were checked already; as constraints they would
        # be rows of zeros in the Jacobian.
        fixed = _fixed_tool_coordinates(model, dict(problem.overrides))
        rows = [r for r in range(3) if r not in fixed]
        end = tool_position(X[:n, -1])
        target = tuple(problem.cartesian_goal[r] for r in rows)
        expr = casadi.vertcat(*(end[r] for r in rows))
        groups.append(_Group("tool position at the goal", expr, target, target, "m"))
    for i, joint in enumerate(model.robot.joints):
        position, rate, force = units(joint)
        if joint.limits is not None:
            lo, hi = joint.limits
            label = f"position limits of joint {i + 1} [{lo:.6g}, {hi:.6g}] {position}"
            groups.append(_Group(label, X[i, :], lo, hi, position))
        if problem.velocity_limits is not None:
            v = problem.velocity_limits[i]
            label = f"velocity limit of joint {i + 1} ({v:g} {rate})"
            groups.append(_Group(label, X[n + i, :], -v, v, rate))
        if problem.torque_limits is not None:
            t = problem.torque_limits[i]
            label = f"torque limit of joint {i + 1} ({t:g} {force})"
            groups.append(_Group(label, U[i, :], -t, t, force))
    return groups


def _impose(opti, group: _Group) -> None:
    import casadi

    lower = casadi.DM(group.lower) if np.ndim(group.lower) else group.lower
    upper = casadi.DM(group.upper) if np.ndim(group.upper) else group.upper
    if group.lower is group.upper:
        opti.subject_to(group.expr == lower)
    else:
        opti.subject_to(opti.bounded(lower, group.expr, upper))


@dataclass(frozen=True)
class _Check:
    """A constraint group at a point: its largest violation (0 when met) and, for limits, at
    how many of its ``size`` entries the bound is reached (within 0.1 % of the range)."""

    group: _Group
    violation: float
    at_bound: int
    size: int


def _check(group: _Group, value: Callable) -> _Check:
    values = np.ravel(np.asarray(value(group.expr), dtype=float))
    lower = np.ravel(np.asarray(group.lower, dtype=float))
    upper = np.ravel(np.asarray(group.upper, dtype=float))
    excess = np.maximum(lower - values, values - upper)
    at_bound = 0
    if group.lower is not group.upper:  # a limit, not an equality
        at_bound = int(np.sum(excess >= -1e-3 * (upper - lower)))
    return _Check(group, float(max(excess.max(initial=0.0), 0.0)), at_bound, values.size)


def _failure_text(status: str, iterations: int, checks: list[_Check]) -> str:
    """IPOPT's verdict, the constraints violated at its last point (worst first) and the
    limits reached there: together they say which limits rule the motion out."""
    head = f"IPOPT: {status} after {iterations} iterations"
    violated = sorted(
        (c for c in checks if c.violation > FEASIBILITY_TOLERANCE), key=lambda c: -c.violation
    )
    if not violated:
        return f"{head}; no constraint is violated at its last point, but it did not converge"
    details = ", ".join(
        f"{c.group.label} by {c.violation:.3g}{' ' + c.group.unit if c.group.unit else ''}"
        for c in violated
    )
    text = f"{head}, no trajectory meets the constraints; violated at its last point: {details}"
    reached = sorted((c for c in checks if c.at_bound), key=lambda c: -c.at_bound / c.size)
    if reached:
        text += "; limits reached there: " + ", ".join(
            f"{c.group.label} at {c.at_bound} of {c.size} points" for c in reached
        )
    return text


# ---------------------------------------------------------------- initial guess


def _initial_final_time(model: Model, problem: TrajectoryProblem, goal: np.ndarray, args) -> float:
    """A guess for the free T of a minimum-time problem: the slowest joint's rest-to-rest
    bang-bang time ``2 sqrt(|dq| M_ii / tau_max)`` against its own inertia at the start
    (gravity ignored), or its velocity-limited time if longer; 1.5 times that, at least 0.5 s.
    """
    start = np.array(problem.start)
    mass = generated_numpy_module(model).mass_matrix(start, **args)
    inertia = np.diag(np.reshape(mass, (len(start), len(start))))
    distance = np.abs(goal - start)
    times = 2 * np.sqrt(distance * inertia / np.array(problem.torque_limits))
    if problem.velocity_limits is not None:
        times = np.maximum(times, distance / np.array(problem.velocity_limits))
    return max(0.5, 1.5 * float(times.max()))


def _line_states(start: np.ndarray, goal: np.ndarray, fractions, final_time: float) -> np.ndarray:
    """States (2n x m) on the straight joint-space line at ``fractions`` of T; dq is its slope."""
    q = start + np.outer(fractions, goal - start)
    dq = np.tile((goal - start) / final_time, (len(fractions), 1))
    return np.vstack([q.T, dq.T])


def _line_torques(model: Model, states: np.ndarray, limits, args) -> np.ndarray:
    """Torques (n x m) that hold the line's velocity against gravity, velocity terms and
    friction, ``tau = c + G + F`` (inverse dynamics at ddq = 0), clipped to the limits."""
    n = model.robot.dof
    q, dq = states[:n].T, states[n:].T
    module = generated_numpy_module(model)
    tau = np.reshape(module.inverse_dynamics(q, dq, np.zeros_like(q), **args), q.shape)
    if limits is not None:
        tau = np.clip(tau, -np.array(limits), np.array(limits))
    return tau.T


# ---------------------------------------------------------------- solve


def optimal_trajectory(model: Model, problem: TrajectoryProblem) -> Trajectory:
    """Solve ``problem`` for ``model``'s robot with CasADi ``Opti`` and IPOPT.

    Raises :class:`InfeasibleTrajectoryError` when a limit rules the motion out before solving
    (see :func:`check_problem`), when IPOPT stops without a solution (the message gives its
    status and the constraint groups violated at its last point), or when the returned point
    violates a constraint by more than :data:`FEASIBILITY_TOLERANCE`.
    """
    import casadi

    check_problem(model, problem)
    n, N = model.robot.dof, problem.intervals
    args = dynamics_arguments(model, dict(problem.overrides))
    module = generated_casadi_module(model)
    forward = module.forward_dynamics_function(casadi.SX)
    constants = [casadi.DM(value) for value in args.values()]  # p, then pi, as the inputs

    def dynamics(x, tau):
        return casadi.vertcat(x[n:], forward(x[:n], x[n:], tau, *constants))

    def tool_position(q):
        kinematics = generated_casadi_module(model, "kinematics")
        return kinematics.position_function(casadi.SX)(q, constants[0])

    start = np.array(problem.start)
    goal = np.array(problem.goal if problem.goal is not None else problem.start)
    opti = casadi.Opti()
    if problem.objective == "time":
        T = opti.variable()
        guess_time = _initial_final_time(model, problem, goal, args)
        opti.set_initial(T, guess_time)
        opti.subject_to(T >= MIN_FINAL_TIME)
    else:
        T = guess_time = problem.final_time
    transcription = TRANSCRIPTIONS[problem.method](opti, dynamics, n, problem, T / N)
    groups = _constraint_groups(model, problem, transcription, tool_position)
    for group in groups:
        _impose(opti, group)
    effort = T / N * casadi.sumsqr(transcription.U)
    if problem.objective == "effort":
        opti.minimize(effort)
    else:
        scaled = transcription.U / casadi.DM(problem.torque_limits)
        opti.minimize(TIME_SCALE * (T + problem.regularisation * T / N * casadi.sumsqr(scaled)))

    nodes = _line_states(start, goal, np.linspace(0, 1, N + 1), guess_time)
    opti.set_initial(transcription.X, nodes)
    middles = _line_states(start, goal, (np.arange(N) + 0.5) / N, guess_time)
    opti.set_initial(transcription.U, _line_torques(model, middles, problem.torque_limits, args))
    for variable, fractions in transcription.guesses:
        opti.set_initial(variable, _line_states(start, goal, fractions, guess_time))

    opti.solver(
        "ipopt",
        {"print_time": False},
        {
            "print_level": 0,
            "sb": "yes",
            "max_iter": MAX_ITERATIONS,
            "constr_viol_tol": FEASIBILITY_TOLERANCE / 100,
        },
    )
    began = time.perf_counter()
    try:
        opti.solve()
        value = opti.value
    except RuntimeError:  # IPOPT gave up; its last point is still there to diagnose
        value = opti.debug.value
    elapsed = time.perf_counter() - began
    raw = opti.stats()
    stats = SolverStats(str(raw["return_status"]), int(raw["iter_count"]), elapsed)
    checks = [_check(group, value) for group in groups]
    worst = max(c.violation for c in checks)
    if stats.status not in SOLVED or worst > FEASIBILITY_TOLERANCE:
        raise InfeasibleTrajectoryError(_failure_text(stats.status, stats.iterations, checks))

    final_time = float(value(T)) if problem.objective == "time" else float(T)
    states = np.reshape(value(transcription.X), (2 * n, N + 1))
    tau = np.reshape(value(transcription.U), (n, N)).T
    effort_value = final_time / N * float(np.sum(tau**2))
    return Trajectory(
        robot=model.robot,
        problem=problem,
        t=np.linspace(0.0, final_time, N + 1),
        q=states[:n].T,
        dq=states[n:].T,
        tau=tau,
        cost=effort_value if problem.objective == "effort" else final_time,
        effort=effort_value,
        max_violation=worst,
        stats=stats,
    )


# ---------------------------------------------------------------- output


def trajectory_rows(trajectory: Trajectory) -> tuple[list[str], np.ndarray]:
    """CSV header and rows ``t, q1..qn, dq1..dqn, tau1..taun`` at the N+1 nodes.

    ``tau`` at node k is the torque held on ``[t_k, t_k+1)``; the last node repeats the last
    interval's torque.
    """
    n = trajectory.robot.dof
    header = ["t"] + [f"{name}{i}" for name in ("q", "dq", "tau") for i in range(1, n + 1)]
    tau = np.vstack([trajectory.tau, trajectory.tau[-1:]])
    rows = np.column_stack([trajectory.t, trajectory.q, trajectory.dq, tau])
    return header, rows


def trajectory_json(trajectory: Trajectory) -> dict:
    """Problem settings, solver statistics and the trajectory, as JSON-ready values."""
    return {
        "robot": trajectory.robot.name,
        "problem": asdict(trajectory.problem) | {"overrides": dict(trajectory.problem.overrides)},
        "solver": asdict(trajectory.stats),
        "final_time": trajectory.final_time,
        "cost": trajectory.cost,
        "effort": trajectory.effort,
        "max_violation": trajectory.max_violation,
        "t": trajectory.t.tolist(),
        "q": trajectory.q.tolist(),
        "dq": trajectory.dq.tolist(),
        "tau": trajectory.tau.tolist(),
    }


def summary_text(trajectory: Trajectory) -> str:
    """A few lines: the problem, IPOPT's status and iterations, solve time, T and the cost."""
    problem, stats = trajectory.problem, trajectory.stats
    objective = {"effort": "minimum effort", "time": "minimum time"}[problem.objective]
    method = problem.method.replace("-", " ")
    return "\n".join(
        [
            f"{trajectory.robot.name}: {objective}, {method}, {problem.intervals} intervals",
            f"IPOPT: {stats.status}, {stats.iterations} iterations",
            f"solve time: {stats.solve_time:.3f} s",
            f"final time T = {trajectory.final_time:.6g} s",
            f"cost = {trajectory.cost:.6g} ({COST_NAMES[problem.objective]})",
            f"effort = {trajectory.effort:.6g}",
            f"max constraint violation = {trajectory.max_violation:.1e}",
        ]
    )


def write_trajectory(trajectory: Trajectory, out: str | Path, plot: bool = False) -> list[Path]:
    """``trajectory.csv``, ``trajectory.json`` and, with ``plot``, ``trajectory.png`` in ``out``."""
    out = Path(out)
    header, rows = trajectory_rows(trajectory)
    paths = [out / "trajectory.csv", out / "trajectory.json"]
    csv = io.StringIO()
    np.savetxt(csv, rows, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    try:
        text = json.dumps(trajectory_json(trajectory), indent=2, allow_nan=False) + "\n"
    except ValueError:
        raise SymkinError("the trajectory holds values that are not finite numbers") from None
    replace_file(out, paths[0].name, csv.getvalue())  # never through a link (security.md)
    replace_file(out, paths[1].name, text)
    if plot:
        from symkin.solve.trajopt.plot import plot_trajectory

        paths.append(plot_trajectory(trajectory, out / "trajectory.png"))
    return paths

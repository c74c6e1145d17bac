"""The solver's starting point: the joint-space polyline from the start through the waypoints
to the goal, travelled at constant speed on each piece, with the torques that hold that speed;
or an earlier solution (a warm start: a refined mesh, a nearby problem).  A tool position
(Cartesian goal or waypoint) enters the polyline through inverse kinematics: the closed-form
solution nearest the start where the arm has one, else the numeric solver started there."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.solve.ik import pose_from_target, solve_ik
from symkin.solve.ik.closed_form import closed_form_ik
from symkin.solve.trajopt.functions import RobotFunctions
from symkin.solve.trajopt.problem import TrajectoryProblem
from symkin.solve.trajopt.transcription import Transcription


def guess_goal(problem: TrajectoryProblem) -> np.ndarray:
    """The goal configuration of the guess: ``goal``, else (a bare Cartesian goal) the start."""
    return np.array(problem.goal if problem.goal is not None else problem.start)


def configuration_near(
    model: Model, position: Sequence[float], near: Sequence[float], problem: TrajectoryProblem
) -> np.ndarray | None:
    """Joint values that put the tool at ``position`` (metres), nearest ``near``: among the
    closed-form solutions within the joint limits, else by the numeric solver (position only)
    started at ``near``; ``None`` when neither reaches it."""
    overrides = dict(problem.overrides)
    kinematic = {k: v for k, v in overrides.items() if k in dict(model.robot.parameters)}
    target = pose_from_target(position)
    try:
        solutions = [s.q for s in closed_form_ik(model, target, kinematic) if s.within_limits]
    except SymkinError:  # no closed form for this arm
        solutions = []
    if solutions:
        return min(solutions, key=lambda q: float(np.sum((q - np.array(near)) ** 2)))
    result = solve_ik(model, target, near, position_only=True, overrides=kinematic)
    return result.q if result.success else None


def polyline_knots(
    model: Model, problem: TrajectoryProblem, fractions: Sequence[float]
) -> list[tuple[float, np.ndarray]]:
    """The corners of the first guess: (fraction of T, joint values) for the start, each
    waypoint (a tool position through :func:`configuration_near` the corner before) and the
    goal (with a Cartesian goal and no joint guess, by inverse kinematics too)."""
    knots = [(0.0, np.array(problem.start))]
    for fraction, waypoint in zip(fractions, problem.waypoints, strict=True):
        q = waypoint.q
        if q is None:
            q = configuration_near(model, waypoint.position, knots[-1][1], problem)
        if q is not None:
            knots.append((fraction, np.array(q)))
    goal = problem.goal
    if goal is None:
        goal = configuration_near(model, problem.cartesian_goal, knots[-1][1], problem)
    knots.append((1.0, knots[-1][1] if goal is None else np.array(goal)))
    return knots


def initial_final_time(
    model: Model, problem: TrajectoryProblem, functions: RobotFunctions
) -> float:
    """A guess for the free T of a minimum-time problem: the slowest joint's rest-to-rest
    bang-bang time ``2 sqrt(|dq| M_ii / tau_max)`` against its own inertia at the start
    (gravity ignored), or its velocity-limited time if longer; 1.5 times that, at least 0.5 s.
    ``M_ii = ID(q, 0, e_i)_i - ID(q, 0, 0)_i``, from the generated inverse dynamics.
    """
    start = np.array(problem.start)
    n = len(start)
    states = np.tile(start, (n, 1))
    rest = functions.numpy_inverse_dynamics(states, np.zeros((n, n)), np.zeros((n, n)))
    unit = functions.numpy_inverse_dynamics(states, np.zeros((n, n)), np.eye(n))
    inertia = np.diag(np.reshape(unit - rest, (n, n)))
    distance = np.abs(guess_goal(problem) - start)
    times = 2 * np.sqrt(distance * inertia / np.array(problem.torque_limits))
    if problem.velocity_limits is not None:
        times = np.maximum(times, distance / np.array(problem.velocity_limits))
    return max(0.5, 1.5 * float(times.max()))


def set_initial_guess(
    opti,
    problem: TrajectoryProblem,
    transcription: Transcription,
    functions: RobotFunctions,
    final_time: float,
    knots: Sequence[tuple[float, np.ndarray]],
    earlier: Any = None,
) -> None:
    """Start ``opti`` on the polyline through ``knots`` (:func:`polyline_knots`), or on
    ``earlier`` (anything with ``t``, ``q``, ``dq``, ``tau`` like a
    :class:`~symkin.solve.trajopt.Trajectory`) stretched to ``final_time``: the states at
    the nodes and the transcription's further points, the controls on the intervals."""
    mesh = problem.fractions
    path = _polyline(knots) if earlier is None else _earlier(earlier)
    opti.set_initial(transcription.X, path(mesh, final_time))
    middles = path((mesh[:-1] + mesh[1:]) / 2, final_time)
    n = len(problem.start)
    if problem.method == "inverse-dynamics":
        rates = np.diff(path(mesh, final_time)[n:], axis=1) / (np.diff(mesh) * final_time)
        opti.set_initial(transcription.U, rates)
    elif earlier is not None:
        opti.set_initial(transcription.U, _earlier_torques(earlier, mesh, problem.torque_limits))
    else:
        opti.set_initial(transcription.U, _holding_torques(functions, middles, problem))
    for variable, fractions in transcription.guesses:
        opti.set_initial(variable, path(fractions, final_time))


def _polyline(knots: Sequence[tuple[float, np.ndarray]]):
    """``(fractions, T) -> states (2n x m)`` on the polyline through ``knots``; dq is each
    piece's slope."""
    s = np.array([fraction for fraction, _ in knots])
    q = np.array([values for _, values in knots])

    def states(fractions, final_time):
        fractions = np.asarray(fractions)
        piece = np.clip(np.searchsorted(s, fractions, side="right") - 1, 0, len(s) - 2)
        slope = (q[piece + 1] - q[piece]) / ((s[piece + 1] - s[piece])[:, None] * final_time)
        position = q[piece] + slope * ((fractions - s[piece])[:, None] * final_time)
        return np.vstack([position.T, slope.T])

    return states


def _earlier(earlier: Any):
    """``(fractions, T) -> states`` of an earlier solution, interpolated linearly between its
    nodes at the same fraction of its own final time; velocities scaled to the new T."""
    fractions_then = np.asarray(earlier.t) / earlier.t[-1]

    def states(fractions, final_time):
        columns = [
            np.interp(fractions, fractions_then, values[:, i])
            for values in (earlier.q, earlier.dq * earlier.t[-1] / final_time)
            for i in range(values.shape[1])
        ]
        return np.array(columns)

    return states


def _earlier_torques(earlier: Any, mesh: np.ndarray, limits) -> np.ndarray:
    """The earlier solution's torque on the interval holding each new interval's midpoint."""
    fractions_then = np.asarray(earlier.t) / earlier.t[-1]
    middles = (mesh[:-1] + mesh[1:]) / 2
    k = np.clip(np.searchsorted(fractions_then, middles) - 1, 0, len(earlier.tau) - 1)
    tau = np.asarray(earlier.tau)[k]
    if limits is not None:
        tau = np.clip(tau, -np.array(limits), np.array(limits))
    return tau.T


def _holding_torques(
    functions: RobotFunctions, states: np.ndarray, problem: TrajectoryProblem
) -> np.ndarray:
    """Torques (n x m) that hold the line's velocity against gravity, velocity terms and
    friction, ``tau = c + G + F`` (inverse dynamics at ddq = 0), clipped to the limits."""
    n = functions.dof
    q, dq = states[:n].T, states[n:].T
    tau = np.reshape(functions.numpy_inverse_dynamics(q, dq, np.zeros_like(q)), q.shape)
    if problem.torque_limits is not None:
        tau = np.clip(tau, -np.array(problem.torque_limits), np.array(problem.torque_limits))
    return tau.T

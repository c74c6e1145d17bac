"""The solver's starting point: the straight joint-space line from the start to the goal,
travelled at constant speed, with the torques that hold that speed."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from symkin.derive import Model
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.trajopt.problem import TrajectoryProblem
from symkin.solve.trajopt.transcription import Transcription


def guess_goal(problem: TrajectoryProblem) -> np.ndarray:
    """The goal configuration of the guess: ``goal``, else (a bare Cartesian goal) the start."""
    return np.array(problem.goal if problem.goal is not None else problem.start)


def initial_final_time(
    model: Model, problem: TrajectoryProblem, args: Mapping[str, np.ndarray]
) -> float:
    """A guess for the free T of a minimum-time problem: the slowest joint's rest-to-rest
    bang-bang time ``2 sqrt(|dq| M_ii / tau_max)`` against its own inertia at the start
    (gravity ignored), or its velocity-limited time if longer; 1.5 times that, at least 0.5 s.
    """
    start = np.array(problem.start)
    mass = generated_numpy_module(model).mass_matrix(start, **args)
    inertia = np.diag(np.reshape(mass, (len(start), len(start))))
    distance = np.abs(guess_goal(problem) - start)
    times = 2 * np.sqrt(distance * inertia / np.array(problem.torque_limits))
    if problem.velocity_limits is not None:
        times = np.maximum(times, distance / np.array(problem.velocity_limits))
    return max(0.5, 1.5 * float(times.max()))


def set_initial_guess(
    opti,
    model: Model,
    problem: TrajectoryProblem,
    transcription: Transcription,
    final_time: float,
    args: Mapping[str, np.ndarray],
) -> None:
    """Start ``opti`` on the line travelled in ``final_time`` seconds: the states at the nodes
    (and at the transcription's further points), the torques at the intervals' midpoints."""
    start, goal, N = np.array(problem.start), guess_goal(problem), problem.intervals
    nodes = _line_states(start, goal, np.linspace(0, 1, N + 1), final_time)
    opti.set_initial(transcription.X, nodes)
    middles = _line_states(start, goal, (np.arange(N) + 0.5) / N, final_time)
    opti.set_initial(transcription.U, _line_torques(model, middles, problem.torque_limits, args))
    for variable, fractions in transcription.guesses:
        opti.set_initial(variable, _line_states(start, goal, fractions, final_time))


def _line_states(
    start: np.ndarray, goal: np.ndarray, fractions: Sequence[float], final_time: float
) -> np.ndarray:
    """States (2n x m) on the straight joint-space line at ``fractions`` of T; dq is its slope."""
    q = start + np.outer(fractions, goal - start)
    dq = np.tile((goal - start) / final_time, (len(fractions), 1))
    return np.vstack([q.T, dq.T])


def _line_torques(
    model: Model,
    states: np.ndarray,
    limits: Sequence[float] | None,
    args: Mapping[str, np.ndarray],
) -> np.ndarray:
    """Torques (n x m) that hold the line's velocity against gravity, velocity terms and
    friction, ``tau = c + G + F`` (inverse dynamics at ddq = 0), clipped to the limits."""
    n = model.robot.dof
    q, dq = states[:n].T, states[n:].T
    module = generated_numpy_module(model)
    tau = np.reshape(module.inverse_dynamics(q, dq, np.zeros_like(q), **args), q.shape)
    if limits is not None:
        tau = np.clip(tau, -np.array(limits), np.array(limits))
    return tau.T

"""The optimal trajectory: the problem transcribed on the generated CasADi dynamics, solved
with IPOPT, checked against every constraint, and returned as a :class:`Trajectory`."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.robot import Robot
from symkin.runtime.modules import generated_casadi_module
from symkin.solve.evaluate import dynamics_arguments
from symkin.solve.trajopt.constraints import (
    Group,
    check_group,
    constraint_groups,
    failure_text,
    impose,
)
from symkin.solve.trajopt.initial_guess import initial_final_time, set_initial_guess
from symkin.solve.trajopt.problem import (
    FEASIBILITY_TOLERANCE,
    InfeasibleTrajectoryError,
    TrajectoryProblem,
    check_problem,
)
from symkin.solve.trajopt.transcription import TRANSCRIPTIONS, Transcription

# IPOPT statuses that count as a solution; anything else is reported as a failure.
SOLVED = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
MAX_ITERATIONS = 3000
# Minimum time minimises TIME_SCALE * (T + r * sum_k h |tau_k / tau_max|^2), r the problem's
# ``regularisation``.  With a gradient of 1, IPOPT crawled for hundreds of iterations on the
# PUMA 560 (collocation); at 100, IPOPT's default largest scaled gradient
# (nlp_scaling_max_gradient), it converges in tens.  Found by experiment.
TIME_SCALE = 100.0
# The final time of a minimum-time problem stays above this many seconds (h > 0).
MIN_FINAL_TIME = 1e-3


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
class _Program:
    """The transcribed problem in ``opti``: the final time (a variable for minimum time, else
    the problem's number) and its initial guess, the decision variables, the constraints."""

    opti: Any
    final_time: Any
    guess_time: float
    transcription: Transcription
    groups: list[Group]


def optimal_trajectory(model: Model, problem: TrajectoryProblem) -> Trajectory:
    """Solve ``problem`` for ``model``'s robot with CasADi ``Opti`` and IPOPT.

    Raises :class:`InfeasibleTrajectoryError` when a limit rules the motion out before solving
    (see :func:`check_problem`), when IPOPT stops without a solution (the message gives its
    status and the constraint groups violated at its last point), or when the returned point
    violates a constraint by more than :data:`FEASIBILITY_TOLERANCE`.
    """
    check_problem(model, problem)
    args = dynamics_arguments(model, dict(problem.overrides))
    program = _transcribe(model, problem, args)
    set_initial_guess(program.opti, model, problem, program.transcription, program.guess_time, args)
    value, stats = _run_ipopt(program.opti)
    checks = [check_group(group, value) for group in program.groups]
    worst = max(c.violation for c in checks)
    if stats.status not in SOLVED or worst > FEASIBILITY_TOLERANCE:
        raise InfeasibleTrajectoryError(failure_text(stats.status, stats.iterations, checks))
    return _trajectory(model, problem, program, value, worst, stats)


def _casadi_functions(model: Model, args: Mapping[str, np.ndarray]) -> tuple[Callable, Callable]:
    """``dx/dt = f(x, tau)`` for ``x = (q, dq)`` and the tool position ``p(q)``, CasADi
    functions of the generated code with the robot's parameters ``args`` filled in."""
    import casadi

    n = model.robot.dof
    forward = generated_casadi_module(model).forward_dynamics_function(casadi.SX)
    constants = [casadi.DM(value) for value in args.values()]  # p, then pi, as the inputs

    def dynamics(x, tau):
        return casadi.vertcat(x[n:], forward(x[:n], x[n:], tau, *constants))

    def tool_position(q):
        kinematics = generated_casadi_module(model, "kinematics")
        return kinematics.position_function(casadi.SX)(q, constants[0])

    return dynamics, tool_position


def _transcribe(
    model: Model, problem: TrajectoryProblem, args: Mapping[str, np.ndarray]
) -> _Program:
    """A new ``Opti`` with the final time, the transcribed dynamics, every constraint group and
    the objective."""
    import casadi

    dynamics, tool_position = _casadi_functions(model, args)
    opti = casadi.Opti()
    if problem.objective == "time":
        T = opti.variable()
        guess_time = initial_final_time(model, problem, args)
        opti.set_initial(T, guess_time)
        opti.subject_to(T >= MIN_FINAL_TIME)
    else:
        T = guess_time = problem.final_time
    h = T / problem.intervals
    transcription = TRANSCRIPTIONS[problem.method](opti, dynamics, model.robot.dof, problem, h)
    groups = constraint_groups(model, problem, transcription, tool_position)
    for group in groups:
        impose(opti, group)
    opti.minimize(_objective(problem, transcription.U, T))
    return _Program(opti, T, guess_time, transcription, groups)


def _objective(problem: TrajectoryProblem, U, T):
    """Effort ``h sum |tau_k|^2``, or ``TIME_SCALE (T + r h sum |tau_k / tau_max|^2)``."""
    import casadi

    N = problem.intervals
    if problem.objective == "effort":
        return T / N * casadi.sumsqr(U)
    scaled = U / casadi.DM(problem.torque_limits)
    return TIME_SCALE * (T + problem.regularisation * T / N * casadi.sumsqr(scaled))


def _run_ipopt(opti) -> tuple[Callable, SolverStats]:
    """Solve with IPOPT; ``opti.value`` at the solution, or at IPOPT's last point if it gave
    up (to say why), and its statistics."""
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
    return value, SolverStats(str(raw["return_status"]), int(raw["iter_count"]), elapsed)


def _trajectory(
    model: Model,
    problem: TrajectoryProblem,
    program: _Program,
    value: Callable,
    worst: float,
    stats: SolverStats,
) -> Trajectory:
    """The solution read out of ``value``, on the time grid of its final time."""
    n, N = model.robot.dof, problem.intervals
    T = program.final_time
    final_time = float(value(T)) if problem.objective == "time" else float(T)
    states = np.reshape(value(program.transcription.X), (2 * n, N + 1))
    tau = np.reshape(value(program.transcription.U), (n, N)).T
    effort = final_time / N * float(np.sum(tau**2))
    return Trajectory(
        robot=model.robot,
        problem=problem,
        t=np.linspace(0.0, final_time, N + 1),
        q=states[:n].T,
        dq=states[n:].T,
        tau=tau,
        cost=effort if problem.objective == "effort" else final_time,
        effort=effort,
        max_violation=worst,
        stats=stats,
    )

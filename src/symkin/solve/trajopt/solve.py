"""The optimal trajectory: the problem transcribed on the generated CasADi dynamics, solved
with IPOPT, checked against every constraint, re-simulated, refined where the re-simulation
disagrees (:mod:`symkin.solve.trajopt.accuracy`), and returned as a :class:`Trajectory`."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.progress import note
from symkin.robot import Robot
from symkin.solve.trajopt.accuracy import Accuracy, accuracy, refined_mesh
from symkin.solve.trajopt.constraints import check_group, failure_text
from symkin.solve.trajopt.detour import GuessReport, clear_knots
from symkin.solve.trajopt.extras import add_problem_extras
from symkin.solve.trajopt.functions import RobotFunctions, robot_functions
from symkin.solve.trajopt.initial_guess import polyline_knots, set_initial_guess
from symkin.solve.trajopt.problem import (
    FEASIBILITY_TOLERANCE,
    InfeasibleTrajectoryError,
    TrajectoryProblem,
    check_problem,
)
from symkin.solve.trajopt.program import Program, transcribed_program, waypoint_fractions

# IPOPT statuses that count as a solution; anything else is reported as a failure.
SOLVED = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
MAX_ITERATIONS = 3000
# Minimum time minimises TIME_SCALE * (T + r * sum_k h |tau_k / tau_max|^2), r the problem's
# ``regularisation``.  With a gradient of 1, IPOPT crawled for hundreds of iterations on the
# PUMA 560 (collocation); at 100, IPOPT's default largest scaled gradient
# (nlp_scaling_max_gradient), it converges in tens.  Found by experiment.
TIME_SCALE = 100.0


@dataclass(frozen=True)
class SolverStats:
    """IPOPT's return status and iteration count (of the last round); wall times in seconds,
    summed over the refinement rounds: ``build_time`` (transcribing, constraint groups,
    first guess), ``solve_time`` (``Opti.solve``: CasADi's derivative set-up plus IPOPT) and
    ``check_time`` (the re-simulation); ``cpu_times`` the same three phases in CPU seconds of
    this process (what a shared machine's load does not inflate)."""

    status: str
    iterations: int
    solve_time: float
    build_time: float = 0.0
    check_time: float = 0.0
    cpu_times: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Round:
    """One solve of the refinement: its intervals, IPOPT's iterations and time, the cost, the
    largest local defect and the end error of the re-simulation."""

    intervals: int
    iterations: int
    solve_time: float
    cost: float
    max_defect: float
    end_error: float


@dataclass(frozen=True)
class Trajectory:
    """An optimal trajectory on the nodes ``t_0 = 0 < .. < t_N = T``.

    ``q`` and ``dq`` are (N+1) x n; ``tau`` is N x n, ``tau[k]`` held on ``[t_k, t_k+1)``
    (inverse-dynamics transcription: the torque at ``t_k``; it varies over the interval with
    the accelerations ``ddq``, N x n, held on it).  ``cost`` is the objective (effort in
    N^2 m^2 s for revolute joints plus any added costs, or T in s); ``effort`` is the integral
    of ``|tau|^2`` for either objective.  ``max_violation`` is the largest constraint
    violation at the solution, in each constraint's own unit.  ``accuracy`` is the
    re-simulation of the last round and ``rounds`` the refinement's history.  ``guess`` says
    where the first round started (the polyline, a detour around the obstacles, an earlier
    solution) and whether that guess was clear of the obstacles.
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
    ddq: np.ndarray | None = None
    accuracy: Accuracy | None = None
    rounds: tuple[Round, ...] = ()
    guess: GuessReport | None = None

    @property
    def final_time(self) -> float:
        return float(self.t[-1])

    @property
    def consistent(self) -> bool:
        """Whether the re-simulation agrees with the nodes to the problem's tolerance."""
        tolerance = self.problem.tolerance
        if self.accuracy is None or tolerance is None:
            return False
        return not self.accuracy.faulty(tolerance).any()


def optimal_trajectory(
    model: Model,
    problem: TrajectoryProblem,
    customise: Callable[[Program], None] | None = None,
    initial: Any = None,
    functions: RobotFunctions | None = None,
) -> Trajectory:
    """Solve ``problem`` for ``model``'s robot with CasADi ``Opti`` and IPOPT, re-simulate the
    solution and refine the mesh until every local defect is below ``problem.tolerance`` or
    ``problem.max_refinements`` rounds are spent (``Trajectory.consistent`` says which).

    ``customise(program)`` is called on each round's open :class:`Program` before it is
    solved, to add one's own constraints and costs (:mod:`symkin.solve.trajopt.extras`).
    ``initial`` (an earlier :class:`Trajectory`) is the first guess instead of the line.
    ``functions`` replaces the robot's generated functions (:func:`robot_functions`, built
    from ``problem.overrides`` and its friction by default), e.g. to reuse them.

    Raises :class:`InfeasibleTrajectoryError` when a limit rules the motion out before solving
    (see :func:`check_problem`), when IPOPT stops without a solution (the message gives its
    status and the constraint groups violated at its last point), or when the returned point
    violates a constraint by more than :data:`FEASIBILITY_TOLERANCE`.
    """
    check_problem(model, problem)
    if functions is None:
        functions = robot_functions(
            model, dict(problem.overrides), problem.coulomb_friction, problem.friction_velocity
        )
    rounds: list[Round] = []
    times = np.zeros((3, 2))  # build, solve, check; wall and CPU
    current, earlier, guess = problem, initial, None
    while True:
        trajectory, phases = solve_once(model, current, functions, customise, earlier)
        began = _clock()
        report = accuracy(trajectory, functions, current)
        times += np.vstack([phases, _clock() - began])
        rounds.append(_round(trajectory, report))
        guess = guess or trajectory.guess
        done = problem.tolerance is None or not report.faulty(problem.tolerance).any()
        if done or len(rounds) > problem.max_refinements:
            break
        mesh = refined_mesh(current.fractions, report, problem.tolerance)
        margin = current.obstacle_margin + 2 * max(-(report.min_clearance or 0.0), 0.0)
        current = replace(
            current, mesh=tuple(mesh), intervals=len(mesh) - 1, obstacle_margin=margin
        )
        earlier = trajectory
    build, solve, check = (float(x) for x in times[:, 0])
    cpu = tuple(float(x) for x in times[:, 1])
    stats = replace(
        trajectory.stats, solve_time=solve, build_time=build, check_time=check, cpu_times=cpu
    )
    return replace(trajectory, stats=stats, accuracy=report, rounds=tuple(rounds), guess=guess)


def _round(trajectory: Trajectory, report: Accuracy) -> Round:
    stats = trajectory.stats
    return Round(
        len(trajectory.t) - 1,
        stats.iterations,
        stats.solve_time,
        trajectory.cost,
        report.max_defect,
        report.end_error,
    )


def solve_once(
    model: Model,
    problem: TrajectoryProblem,
    functions: RobotFunctions,
    customise: Callable[[Program], None] | None = None,
    earlier: Any = None,
) -> tuple[Trajectory, tuple[float, float]]:
    """One transcription and IPOPT solve on ``problem``'s mesh, no re-simulation; the
    trajectory and the build and solve times (rows; wall and CPU seconds)."""
    began = _clock()
    program = transcribed_program(model, problem, functions)
    add_problem_extras(program)
    if customise is not None:
        customise(program)
    program.opti.minimize(_objective(program))
    knots, guess = _first_guess(model, problem, functions, program, earlier)
    set_initial_guess(
        program.opti,
        problem,
        program.transcription,
        functions,
        program.guess_time,
        knots,
        earlier,
    )
    built = _clock()
    value, stats = _run_ipopt(program.opti)
    solved = _clock()
    checks = [check_group(group, value) for group in program.groups]
    worst = max(c.violation for c in checks)
    if stats.status not in SOLVED or worst > FEASIBILITY_TOLERANCE:
        raise InfeasibleTrajectoryError(failure_text(stats.status, stats.iterations, checks))
    trajectory = replace(_trajectory(program, value, worst, stats), guess=guess)
    return trajectory, np.vstack([built - began, solved - built])


def _first_guess(
    model: Model,
    problem: TrajectoryProblem,
    functions: RobotFunctions,
    program: Program,
    earlier: Any,
) -> tuple[list, GuessReport]:
    """The polyline's knots (detoured around the obstacles, with ``problem.clear_guess``)
    and the report; with ``earlier`` the knots go unused."""
    knots = polyline_knots(model, problem, waypoint_fractions(problem, program.guess_time))
    if earlier is not None:
        return knots, GuessReport("earlier")
    if not problem.obstacles:
        return knots, GuessReport("line")
    knots, guess = clear_knots(functions, problem, knots, search=problem.clear_guess)
    if guess.note and problem.clear_guess:
        note(f"first guess: {guess.note}; starting from the straight polyline")
    return knots, guess


def _clock() -> np.ndarray:
    """Wall and CPU seconds, now."""
    return np.array([time.perf_counter(), time.process_time()])


def _effort(program: Program, scale=None):
    """``integral |tau / scale|^2 dt`` by the transcription's quadrature."""
    import casadi

    torques = program.torques
    if scale is not None:
        torques = torques / casadi.repmat(casadi.DM(scale), 1, torques.shape[1])
    return casadi.sum2(program.transcription.weights * casadi.sum1(torques**2))


def _objective(program: Program):
    """Effort plus the added costs, or ``TIME_SCALE (T + r effort(tau / tau_max))`` plus them."""
    problem = program.problem
    extra = sum(program.costs, 0)
    if problem.objective == "effort":
        return _effort(program) + extra
    regularised = program.final_time + problem.regularisation * _effort(
        program, problem.torque_limits
    )
    return TIME_SCALE * regularised + extra


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


def _trajectory(program: Program, value: Callable, worst: float, stats: SolverStats) -> Trajectory:
    """The solution read out of ``value``."""
    problem = program.problem
    n, N = program.model.robot.dof, problem.intervals
    t = np.ravel(np.asarray(value(program.times), dtype=float))
    states = np.reshape(value(program.transcription.X), (2 * n, N + 1))
    controls = np.reshape(value(program.controls), (n, N)).T
    inverse = problem.method == "inverse-dynamics"
    torques = np.reshape(value(program.torques), (n, -1))[:, :N].T
    effort = float(value(_effort(program)))
    cost = float(value(program.opti.f)) if problem.objective == "effort" else t[-1]
    return Trajectory(
        robot=program.model.robot,
        problem=problem,
        t=t,
        q=states[:n].T,
        dq=states[n:].T,
        tau=torques if inverse else controls,
        cost=float(cost),
        effort=effort,
        max_violation=worst,
        stats=stats,
        ddq=controls if inverse else None,
    )

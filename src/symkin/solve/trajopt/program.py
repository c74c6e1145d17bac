"""The open problem: a :class:`TrajectoryProblem` transcribed into a ``casadi.Opti`` whose
decision variables, node times, torques and the robot's generated functions are all in reach,
so that constraints and costs of one's own can be added before it is solved
(docs/trajopt.md, "The open problem")."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.errors import SymkinError
from symkin.solve.trajopt.constraints import Group, constraint_groups, impose
from symkin.solve.trajopt.functions import RobotFunctions, robot_functions
from symkin.solve.trajopt.initial_guess import initial_final_time
from symkin.solve.trajopt.problem import TrajectoryProblem
from symkin.solve.trajopt.transcription import TRANSCRIPTIONS, Dynamics, Transcription

# The final time of a minimum-time problem, and every stretch between waypoints of free time,
# stays above this many seconds (h > 0).
MIN_FINAL_TIME = 1e-3


@dataclass(frozen=True)
class Program:
    """A transcribed trajectory problem, open for additions.

    ``opti`` is the ``casadi.Opti`` instance; ``final_time`` is T (a variable for minimum time,
    else the number); ``times`` (1 x N+1) the node times and ``h`` (1 x N) the interval
    lengths, expressions of T and of the waypoints' free times; ``waypoint_nodes`` the node of
    each waypoint.  ``q`` and ``dq`` (n x N+1) are the node states, ``controls`` (n x N) the
    decisions per interval (torques, or accelerations for the inverse-dynamics
    transcription), ``torques`` (n x m) the torques where limits apply.  ``functions`` are
    the robot's generated CasADi functions (:class:`RobotFunctions`).  Constraints go in
    through :meth:`constrain` (named, so a failure names them), costs through
    :meth:`add_cost`; :mod:`symkin.solve.trajopt.extras` has ready-made ones.
    """

    opti: Any
    model: Model
    problem: TrajectoryProblem
    functions: RobotFunctions
    final_time: Any
    guess_time: float
    times: Any
    h: Any
    waypoint_nodes: tuple[int, ...]
    transcription: Transcription
    groups: list[Group] = field(default_factory=list)
    costs: list[Any] = field(default_factory=list)

    @property
    def q(self):
        return self.transcription.X[: self.model.robot.dof, :]

    @property
    def dq(self):
        return self.transcription.X[self.model.robot.dof :, :]

    @property
    def controls(self):
        return self.transcription.U

    @property
    def torques(self):
        return self.transcription.torques

    def constrain(self, label: str, expr, lower, upper=None, unit: str = "") -> None:
        """Impose ``lower <= expr <= upper`` (``upper`` left out: ``expr == lower``) under
        ``label``; it is checked at the solution and named in failure messages."""
        group = Group(label, expr, lower, lower if upper is None else upper, unit)
        impose(self.opti, group)
        self.groups.append(group)

    def add_cost(self, expr) -> None:
        """Add the scalar ``expr`` to the objective."""
        self.costs.append(expr)


def waypoint_fractions(problem: TrajectoryProblem, guess_time: float) -> list[float]:
    """Where each waypoint sits on the mesh, as a fraction of T: ``time / T`` for a fixed
    time (T: the fixed or guessed final time), evenly between its neighbours for a free one."""
    anchors = (
        [0.0] + [None if w.time is None else w.time / guess_time for w in problem.waypoints] + [1.0]
    )
    for i, value in enumerate(anchors):
        if value is None:  # a run of free ones: spread evenly between the known neighbours
            j = next(k for k in range(i, len(anchors)) if anchors[k] is not None)
            anchors[i] = anchors[i - 1] + (anchors[j] - anchors[i - 1]) / (j - i + 1)
    return anchors[1:-1]


def waypoint_nodes(problem: TrajectoryProblem, guess_time: float) -> tuple[int, ...]:
    """The mesh node of each waypoint: the one nearest its fraction, all distinct, none at
    the ends."""
    mesh = problem.fractions
    nodes = tuple(int(np.argmin(np.abs(mesh - f))) for f in waypoint_fractions(problem, guess_time))
    if any(not 0 < k < len(mesh) - 1 for k in nodes) or any(np.diff(nodes) <= 0):
        raise SymkinError(
            f"the waypoints fall on nodes {list(nodes)} of 0..{len(mesh) - 1}: they must be "
            "in time order, strictly inside the motion and on distinct nodes (more intervals)"
        )
    return nodes


def _node_times(opti, problem: TrajectoryProblem, T, guess_time: float, nodes):
    """Node times, piecewise linear in the mesh fraction between anchors: (0, 0), each
    waypoint's node at its time (a number, or a variable for a free time) and (1, T)."""
    import casadi

    mesh = problem.fractions
    anchors = [(0, 0.0)]
    for k, waypoint in zip(nodes, problem.waypoints, strict=True):
        time = waypoint.time
        if time is None:
            time = opti.variable()
            opti.set_initial(time, mesh[k] * guess_time)
        anchors.append((k, time))
    anchors.append((len(mesh) - 1, T))
    pieces = []
    for (k0, t0), (k1, t1) in itertools.pairwise(anchors):
        if not (isinstance(t0, float | int) and isinstance(t1, float | int)):
            opti.subject_to(t1 - t0 >= MIN_FINAL_TIME)
        elif t1 <= t0:
            raise SymkinError(f"waypoint times must increase within (0, T), got {t0:g}, {t1:g}")
        span = (mesh[k0:k1] - mesh[k0]) / (mesh[k1] - mesh[k0])
        pieces.append(t0 + (t1 - t0) * casadi.DM(span).T)
    times = casadi.horzcat(*pieces, T)
    return times, times[1:] - times[:-1]


def transcribed_program(
    model: Model, problem: TrajectoryProblem, functions: RobotFunctions | None = None
) -> Program:
    """A new ``Opti`` with the final time, the node times, the transcribed dynamics and the
    problem's own constraint groups (boundary conditions and limits), not yet an objective:
    :func:`symkin.solve.trajopt.solve.solve_program` sets that from the problem and the added
    costs."""
    import casadi

    if functions is None:
        functions = robot_functions(model, dict(problem.overrides), *_friction(problem))
    opti = casadi.Opti()
    if problem.objective == "time":
        T = opti.variable()
        guess_time = initial_final_time(model, problem, functions)
        opti.set_initial(T, guess_time)
        opti.subject_to(T >= MIN_FINAL_TIME)
    else:
        T = guess_time = problem.final_time
    nodes = waypoint_nodes(problem, guess_time)
    times, h = _node_times(opti, problem, T, guess_time, nodes)
    dynamics = Dynamics(
        lambda x, tau: casadi.vertcat(
            x[model.robot.dof :],
            functions.forward_dynamics(x[: model.robot.dof], x[model.robot.dof :], tau),
        ),
        functions.inverse_dynamics,
    )
    transcription = TRANSCRIPTIONS[problem.method](opti, dynamics, model.robot.dof, problem, h)
    program = Program(
        opti, model, problem, functions, T, guess_time, times, h, nodes, transcription
    )
    for group in constraint_groups(model, problem, transcription, functions.tool_position):
        program.constrain(group.label, group.expr, group.lower, group.upper, group.unit)
    return program


def _friction(problem: TrajectoryProblem) -> tuple:
    """``robot_functions``' friction arguments from the problem."""
    return problem.coulomb_friction, problem.friction_velocity

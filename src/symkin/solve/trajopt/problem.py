"""The trajectory problem: what to move where, under which limits, and the checks made on it
before anything is transcribed or solved (docs/trajopt.md has the optimal control problem)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.numeric import parameter_substitution
from symkin.errors import ParameterError, SymkinError
from symkin.robot import Joint
from symkin.solve.evaluate import dynamic_state

Objective = Literal["effort", "time"]
Method = Literal["multiple-shooting", "collocation", "inverse-dynamics"]
OBJECTIVES: tuple[str, ...] = ("effort", "time")
# The transcriptions, in the order messages and the command line list them: the two on the
# forward dynamics (torques are the decisions), then the one on the inverse dynamics
# (accelerations are the decisions, the torque an expression of them).
METHODS: tuple[str, ...] = ("multiple-shooting", "collocation", "inverse-dynamics")
# Largest local defect (joint units: rad, rad/s, m, m/s) a refined trajectory may keep: the
# distance from node k+1 of the state re-simulated from node k under the interval's torque.
DEFAULT_TOLERANCE = 1e-4
DEFAULT_MAX_REFINEMENTS = 4
# Largest constraint violation (in the constraint's own unit) a returned solution may have;
# IPOPT's "acceptable" level alone would let 1e-2 through.
FEASIBILITY_TOLERANCE = 1e-6


class InfeasibleTrajectoryError(SymkinError):
    """No trajectory meets the limits: the message names the limits or constraints at fault."""


@dataclass(frozen=True)
class Waypoint:
    """A configuration (``q``, joint values) or tool position (``position``, x y z in metres,
    base frame) to pass through: at ``time`` seconds (snapped to the nearest node), or, with
    ``time=None``, at any node (a free time: the node closest to the target on the first guess
    is chosen by the solver's continuous relaxation, see docs/trajopt.md)."""

    q: tuple[float, ...] | None = None
    position: tuple[float, float, float] | None = None
    time: float | None = None

    def __post_init__(self) -> None:
        if (self.q is None) == (self.position is None):
            raise SymkinError("a waypoint needs joint values q or a tool position, not both")
        for name in ("q", "position"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, tuple(float(v) for v in getattr(self, name)))


@dataclass(frozen=True)
class Obstacle:
    """A sphere (centre in metres, base frame; radius in metres) that every link's capsule
    (the segment between consecutive frame origins, thickened by ``clearance``) must avoid."""

    centre: tuple[float, float, float]
    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre", tuple(float(v) for v in self.centre))
        if len(self.centre) != 3 or not self.radius > 0:
            raise SymkinError(
                f"an obstacle is a centre x,y,z and a positive radius, got "
                f"{self.centre} and {self.radius:g}"
            )


@dataclass(frozen=True)
class TrajectoryProblem:
    """A rest-to-rest motion from ``start`` to ``goal`` (joint values, radians or metres).

    With ``cartesian_goal`` (x, y, z of the tool in the base frame, metres) the final
    configuration is free and ``goal``, if given, is only its initial guess.  ``final_time``
    (seconds) is required for the effort objective and not allowed for minimum time.
    ``velocity_limits`` and ``torque_limits`` hold one positive value per joint (``None``: no
    limit); position limits come from the robot file.  ``overrides`` sets parameters and the
    inertial data a robot file leaves out (``m1``, ``cx1``, ...), as the ``overrides`` of
    :func:`symkin.solve.evaluate.dynamic_state`.  ``substeps`` is the number of RK4 steps per
    interval (multiple shooting) and ``degree`` the number of Radau points per interval
    (collocation).

    ``regularisation`` r weights a small effort term in the minimum-time objective,
    ``T + r sum_k h |tau_k / tau_max|^2``.  It picks one torque profile where T alone leaves
    torques undecided (joints that finish early, arcs at a velocity limit), which IPOPT
    otherwise resolves only slowly (hundreds of iterations for the PUMA 560 with collocation);
    it lengthens T a little (bench/trajopt_time.py measures by how much; docs/trajopt.md).

    ``mesh`` gives the nodes as fractions of T (``intervals + 1`` increasing values from 0 to
    1; ``None``: uniform).  After each solve the trajectory is re-simulated and intervals whose
    local defect exceeds ``tolerance`` are split, at most ``max_refinements`` times
    (``tolerance=None``: solve once, still report the defects).  ``waypoints``, ``obstacles``
    (kept clear of capsules of radius ``clearance`` metres around the links) and
    ``min_manipulability`` (a lower bound on the Yoshikawa measure at every node) add
    constraints; the nodes keep ``obstacle_margin`` metres more (refinement raises it when
    the re-simulated path touches an obstacle between the nodes);
    :mod:`symkin.solve.trajopt.extras` adds them, and more, from Python.  With
    ``clear_guess`` the first guess detours around the obstacles where the straight polyline
    would run a link through one (:mod:`symkin.solve.trajopt.detour`).
    ``coulomb_friction`` (one value per joint, N m or N) adds smoothed Coulomb friction
    ``F_c tanh(dq / friction_velocity)`` to the model (solver and re-simulation alike).
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
    mesh: tuple[float, ...] | None = None
    tolerance: float | None = DEFAULT_TOLERANCE
    max_refinements: int = DEFAULT_MAX_REFINEMENTS
    waypoints: tuple[Waypoint, ...] = ()
    obstacles: tuple[Obstacle, ...] = ()
    min_manipulability: float | None = None
    clearance: float = 0.05
    obstacle_margin: float = 0.0
    clear_guess: bool = True
    coulomb_friction: tuple[float, ...] | None = None
    friction_velocity: float = 0.01

    def __post_init__(self) -> None:
        for name in (
            "start",
            "goal",
            "cartesian_goal",
            "velocity_limits",
            "torque_limits",
            "mesh",
            "coulomb_friction",
        ):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, tuple(float(v) for v in value))
        overrides = self.overrides
        if isinstance(overrides, Mapping):
            overrides = overrides.items()
        object.__setattr__(self, "overrides", tuple((k, float(v)) for k, v in overrides))
        object.__setattr__(self, "waypoints", tuple(self.waypoints))
        object.__setattr__(self, "obstacles", tuple(self.obstacles))

    @property
    def fractions(self) -> np.ndarray:
        """The nodes as fractions of T, ``0 = s_0 < .. < s_N = 1``: ``mesh``, else uniform."""
        if self.mesh is not None:
            return np.array(self.mesh)
        return np.linspace(0.0, 1.0, self.intervals + 1)

    @property
    def joint_goal(self) -> tuple[float, ...] | None:
        """The goal configuration the motion must reach (``None`` with a Cartesian goal)."""
        return self.goal if self.cartesian_goal is None else None


def units(joint: Joint) -> tuple[str, str, str]:
    """Position, velocity and torque (or force) units of a joint."""
    return ("rad", "rad/s", "N m") if joint.type == "revolute" else ("m", "m/s", "N")


def check_problem(model: Model, problem: TrajectoryProblem) -> None:
    """Reject malformed problems and those that are infeasible on their face.

    Caught before any solve: wrong vector lengths, non-positive limits, a start or goal outside
    the joint limits, a gravity torque at the start or goal above the torque limit, a move that
    the velocity limit cannot make in the given time, and a Cartesian goal off a coordinate
    the tool cannot change (a planar arm's z).
    """
    _check_vectors(model, problem)
    _check_settings(problem)
    _check_final_time(problem)
    _check_position_limits(model, problem)
    _check_gravity(model, problem)
    _check_velocity_limits(model, problem)
    if problem.cartesian_goal is not None:
        _check_cartesian_goal(model, problem.cartesian_goal, dict(problem.overrides))


def fixed_tool_coordinates(model: Model, overrides: Mapping[str, float]) -> dict[int, float]:
    """Tool coordinates that no joint moves (row -> value), e.g. z of a planar arm.

    Read off the product form (no contraction derived), where they are free of ``q`` too."""
    kinematic = {k: v for k, v in overrides.items() if k in dict(model.robot.parameters)}
    substitution = parameter_substitution(model, kinematic)
    joints = set(model.q)
    return {
        row: float(expr.xreplace(substitution))
        for row, expr in enumerate(model.product_form.tool_position)
        if not (sp.sympify(expr).free_symbols & joints)
    }


# ---------------------------------------------------------------- malformed problems


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


def _check_vectors(model: Model, problem: TrajectoryProblem) -> None:
    """One number per joint (three for the Cartesian goal), finite, limits positive."""
    joints = [f"joint {i}" for i in range(1, model.robot.dof + 1)]
    _check_vector(problem.start, joints, "start")
    _check_vector(problem.goal, joints, "goal")
    _check_vector(problem.velocity_limits, joints, "velocity limit", positive=True)
    _check_vector(problem.torque_limits, joints, "torque limit", positive=True)
    _check_vector(problem.cartesian_goal, ("x", "y", "z"), "Cartesian goal")
    _check_vector(problem.coulomb_friction, joints, "Coulomb friction")
    for k, waypoint in enumerate(problem.waypoints, start=1):
        _check_vector(waypoint.q, joints, f"waypoint {k}")
        _check_vector(waypoint.position, ("x", "y", "z"), f"waypoint {k}")


def _check_settings(problem: TrajectoryProblem) -> None:
    """A goal, a known objective and method, counts of at least 1, r >= 0."""
    if problem.goal is None and problem.cartesian_goal is None:
        raise SymkinError("give a goal: joint values or a Cartesian tool position")
    if problem.objective not in OBJECTIVES:
        raise SymkinError(
            f"objective must be one of {', '.join(OBJECTIVES)}, got {problem.objective!r}"
        )
    if problem.method not in METHODS:
        raise SymkinError(f"method must be one of {', '.join(METHODS)}, got {problem.method!r}")
    for name, lowest in (("intervals", 1), ("substeps", 1), ("degree", 1)):
        if getattr(problem, name) < lowest:
            raise SymkinError(f"{name} must be at least {lowest}, got {getattr(problem, name)}")
    if not (math.isfinite(problem.regularisation) and problem.regularisation >= 0):
        raise SymkinError(f"regularisation must be 0 or positive, got {problem.regularisation:g}")
    if problem.tolerance is not None and not problem.tolerance > 0:
        raise SymkinError(f"the tolerance must be positive, got {problem.tolerance:g}")
    if problem.max_refinements < 0:
        raise SymkinError(f"max_refinements must be 0 or more, got {problem.max_refinements}")
    _check_mesh(problem)


def _check_mesh(problem: TrajectoryProblem) -> None:
    """``mesh``: ``intervals + 1`` strictly increasing fractions from 0 to 1."""
    if problem.mesh is None:
        return
    mesh = np.array(problem.mesh)
    if (
        len(mesh) != problem.intervals + 1
        or mesh[0] != 0.0
        or mesh[-1] != 1.0
        or np.any(np.diff(mesh) <= 0)
    ):
        raise SymkinError(
            f"the mesh must hold {problem.intervals + 1} increasing fractions of T from 0 to 1 "
            f"(one per node), got {len(mesh)} values from {mesh[0]:g} to {mesh[-1]:g}"
        )


def _check_final_time(problem: TrajectoryProblem) -> None:
    """Minimum effort needs a positive final time; minimum time needs torque limits instead."""
    if problem.objective == "effort":
        if problem.final_time is None:
            raise ParameterError(
                "minimum effort needs a fixed final time ({final_time}, in seconds)"
            )
        if not (math.isfinite(problem.final_time) and problem.final_time > 0):
            raise SymkinError(f"the final time must be positive, got {problem.final_time:g} s")
        return
    if problem.final_time is not None:
        raise ParameterError(
            "minimum time leaves the final time free: drop the fixed time ({final_time})"
        )
    if problem.torque_limits is None:
        raise ParameterError(
            "minimum time needs torque limits ({torque_limits}): without them any motion "
            "can be made arbitrarily fast"
        )


# ---------------------------------------------------------------- infeasible on their face


def _end_configurations(problem: TrajectoryProblem) -> list[tuple[str, tuple[float, ...]]]:
    """The configurations fixed by the problem: the start and, unless Cartesian, the goal."""
    ends = [("start", problem.start), ("goal", problem.joint_goal)]
    return [(where, q) for where, q in ends if q is not None]


def _check_position_limits(model: Model, problem: TrajectoryProblem) -> None:
    """The start and the goal lie within the joint limits of the robot file."""
    for where, q in _end_configurations(problem):
        for i, (value, joint) in enumerate(zip(q, model.robot.joints, strict=True), start=1):
            if joint.limits is not None and not joint.limits[0] <= value <= joint.limits[1]:
                lo, hi = joint.limits
                raise InfeasibleTrajectoryError(
                    f"the {where} puts joint {i} at {value:.6g} {units(joint)[0]}, outside its "
                    f"limits [{lo:.6g}, {hi:.6g}] {units(joint)[0]}"
                )


def _check_gravity(model: Model, problem: TrajectoryProblem) -> None:
    """The torque limits can hold the robot at rest against gravity at the start and goal.

    The gravity torques are evaluated even without limits: missing inertial data is reported
    here, before any solve.
    """
    overrides = dict(problem.overrides)
    for where, q in _end_configurations(problem):
        hold = dynamic_state(model, q, overrides=overrides).gravity
        for i, need in enumerate(np.atleast_1d(hold), start=1):
            limit = None if problem.torque_limits is None else problem.torque_limits[i - 1]
            if limit is not None and abs(need) > limit:
                unit = units(model.robot.joints[i - 1])[2]
                raise InfeasibleTrajectoryError(
                    f"torque limit of joint {i} ({limit:g} {unit}) below the {abs(need):.4g} "
                    f"{unit} gravity needs at the {where}"
                )


def _check_velocity_limits(model: Model, problem: TrajectoryProblem) -> None:
    """Each joint can cover its distance to the goal in the final time at its velocity limit."""
    goal = problem.joint_goal
    if goal is None or not problem.velocity_limits or not problem.final_time:
        return
    for i, (a, b, limit) in enumerate(
        zip(problem.start, goal, problem.velocity_limits, strict=True), start=1
    ):
        if abs(b - a) > limit * problem.final_time:
            unit, rate, _ = units(model.robot.joints[i - 1])
            raise InfeasibleTrajectoryError(
                f"joint {i} must move {abs(b - a):.4g} {unit} in {problem.final_time:g} s, "
                f"more than its velocity limit of {limit:g} {rate} allows (it needs at "
                f"least {abs(b - a) / limit:.4g} s)"
            )


def _check_cartesian_goal(
    model: Model, goal: Sequence[float], overrides: Mapping[str, float]
) -> None:
    """The Cartesian goal agrees with the tool coordinates no joint can change."""
    for row, value in fixed_tool_coordinates(model, overrides).items():
        if abs(goal[row] - value) > FEASIBILITY_TOLERANCE:
            raise InfeasibleTrajectoryError(
                f"the tool's {'xyz'[row]} is {value:.6g} m in every configuration of "
                f"{model.robot.name}; the Cartesian goal asks for {goal[row]:.6g} m"
            )

"""Ready-made constraints and costs for an open :class:`~symkin.solve.trajopt.program.Program`.

Each ``add_*`` function adds to the program's ``Opti`` through ``Program.constrain`` (named,
checked at the solution, reported on failure) or ``Program.add_cost``.  Constraints hold at the
nodes; the re-simulation (:mod:`symkin.solve.trajopt.accuracy`) checks the obstacles between
them too and refines the mesh where a link touches one.  Pass a function calling these as
``customise`` to :func:`symkin.solve.trajopt.optimal_trajectory` so they are added again on
every refined mesh.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from symkin.solve.trajopt.accuracy import squared_segment_distance
from symkin.solve.trajopt.problem import InfeasibleTrajectoryError, Obstacle, Waypoint
from symkin.solve.trajopt.program import Program


def add_problem_extras(program: Program) -> None:
    """The waypoints, obstacles and manipulability margin of ``program.problem``."""
    problem = program.problem
    for k, waypoint in enumerate(problem.waypoints):
        add_waypoint(program, waypoint, program.waypoint_nodes[k], f"waypoint {k + 1}")
    for obstacle in problem.obstacles:
        add_obstacle(program, obstacle, problem.clearance + problem.obstacle_margin)
    if problem.min_manipulability is not None:
        _check_ends_manipulability(program, problem.min_manipulability)
        add_min_manipulability(program, problem.min_manipulability)


def _squared_manipulability(program: Program, q):
    """``det(J J^T)`` of the task rows (``det(J^T J)`` with more rows than joints)."""
    import casadi

    rows = list(program.functions.task_rows)
    J = program.functions.jacobian(q)[rows, :]
    gram = casadi.mtimes(J, J.T) if len(rows) <= J.shape[1] else casadi.mtimes(J.T, J)
    return casadi.det(gram)


def _check_ends_manipulability(program: Program, minimum: float) -> None:
    """The start and a joint goal must already have the manipulability asked for."""
    import casadi

    problem = program.problem
    for where, q in (("start", problem.start), ("goal", problem.joint_goal)):
        if q is None:
            continue
        value = float(casadi.sqrt(casadi.fmax(_squared_manipulability(program, casadi.DM(q)), 0)))
        if value < minimum:
            raise InfeasibleTrajectoryError(
                f"the {where}'s manipulability is {value:.4g}, below the minimum {minimum:g}"
            )


def add_waypoint(program: Program, waypoint: Waypoint, node: int, label: str = "waypoint") -> None:
    """Node ``node`` at the waypoint: its joint values, or the tool at its position (in the
    coordinates the tool can move, :attr:`RobotFunctions.task_rows`)."""
    import casadi

    q = program.q[:, node]
    if waypoint.q is not None:
        program.constrain(label, q, casadi.DM(waypoint.q))
        return
    rows = [r for r in program.functions.task_rows if r < 3]
    position = program.functions.tool_position(q)
    target = casadi.DM([waypoint.position[r] for r in rows])
    program.constrain(label, casadi.vertcat(*(position[r] for r in rows)), target, unit="m")


def add_obstacle(program: Program, obstacle: Obstacle, clearance: float) -> None:
    """Every link's capsule (the segment between consecutive frame origins, and from the last
    to the tool, thickened by ``clearance`` metres) clear of the sphere at every node:
    ``|c - segment|^2 >= (r + clearance)^2``."""
    import casadi

    reach = (obstacle.radius + clearance) ** 2
    squares = []
    for k in range(program.q.shape[1]):
        points = program.functions.link_origins(program.q[:, k])
        centre = casadi.DM(obstacle.centre)
        squares += [squared_segment_distance(centre, a, b) for a, b in itertools.pairwise(points)]
    x, y, z = obstacle.centre
    label = f"obstacle at ({x:g}, {y:g}, {z:g}) m, radius {obstacle.radius:g} m"
    program.constrain(label, casadi.vertcat(*squares), reach, np.inf, "m^2")


def add_min_manipulability(program: Program, minimum: float) -> None:
    """Yoshikawa's manipulability ``sqrt(det(J J^T))`` of the task rows of the Jacobian at least
    ``minimum`` at every node (``det(J^T J)`` when there are more rows than joints), imposed
    on its square to stay smooth: a margin from the singular configurations."""
    import casadi

    squares = [_squared_manipulability(program, program.q[:, k]) for k in range(program.q.shape[1])]
    label = f"manipulability at least {minimum:g}"
    program.constrain(label, casadi.vertcat(*squares), minimum**2, np.inf)


def add_tool_box(program: Program, lower: Sequence[float], upper: Sequence[float]) -> None:
    """The tool position inside the box ``lower <= p <= upper`` (metres, base frame) at every
    node."""
    import casadi

    position = program.functions.tool_position(program.q)
    label = f"tool inside the box {tuple(lower)} .. {tuple(upper)} m"
    lo = casadi.repmat(casadi.DM(lower), 1, position.shape[1])
    hi = casadi.repmat(casadi.DM(upper), 1, position.shape[1])
    program.constrain(label, position, lo, hi, "m")


def add_tool_corridor(
    program: Program, a: Sequence[float], b: Sequence[float], radius: float
) -> None:
    """The tool within ``radius`` metres of the straight segment from ``a`` to ``b`` at every
    node: a Cartesian path with a tolerance."""
    import casadi

    ends = casadi.DM(a), casadi.DM(b)
    position = program.functions.tool_position(program.q)
    squares = [squared_segment_distance(position[:, k], *ends) for k in range(position.shape[1])]
    label = f"tool within {radius:g} m of the segment {tuple(a)} .. {tuple(b)} m"
    program.constrain(label, casadi.vertcat(*squares), 0.0, radius**2, "m^2")


def add_joint_limits(
    program: Program,
    velocity: Sequence[float] | None = None,
    torque: Sequence[float] | None = None,
) -> None:
    """Velocity and torque limits per joint (``inf`` for none) at every node / torque sample,
    on top of the problem's own."""
    import casadi

    pairs = ((velocity, program.dq, "velocity"), (torque, program.torques, "torque"))
    for values, expr, name in pairs:
        if values is None:
            continue
        bound = casadi.repmat(casadi.DM(values), 1, expr.shape[1])
        program.constrain(f"extra {name} limits {tuple(values)}", expr, -bound, bound)


def add_torque_rate_cost(program: Program, weight: float = 1.0) -> None:
    """``weight sum_k |tau_k+1 - tau_k|^2 / h_k``: the integral of the squared torque rate
    for torques changing linearly across a node (smooth commands for the drives)."""
    import casadi

    U = program.torques[:, : program.h.shape[1]]
    rates = U[:, 1:] - U[:, :-1]
    spans = (program.h[:-1] + program.h[1:]) / 2
    program.add_cost(weight * casadi.sum2(casadi.sum1(rates**2) / spans))


def add_jerk_cost(program: Program, weight: float = 1.0) -> None:
    """``weight sum |(a_k+1 - a_k)|^2 / h``: squared jerk of the node accelerations, ``a_k``
    the forward dynamics at node k under its interval's torque (or the interval's acceleration
    in the inverse-dynamics transcription)."""
    import casadi

    N = program.h.shape[1]
    if program.problem.method == "inverse-dynamics":
        a = program.controls
    else:
        f = program.functions.forward_dynamics
        a = f(program.q[:, :N], program.dq[:, :N], program.controls)
    jumps = a[:, 1:] - a[:, :-1]
    spans = (program.h[:-1] + program.h[1:]) / 2
    program.add_cost(weight * casadi.sum2(casadi.sum1(jumps**2) / spans))


def add_energy_cost(program: Program, weight: float = 1.0, smoothing: float = 1e-3) -> None:
    """``weight sum_k h_k sum_i sqrt((tau_i dq_i)^2 + eps^2)``: the mechanical energy the drives
    deliver or absorb (the absolute joint power, smoothed by ``eps`` = ``smoothing`` W)."""
    import casadi

    N = program.h.shape[1]
    power = program.torques[:, :N] * program.dq[:, :N]
    absolute = casadi.sqrt(power**2 + smoothing**2)
    program.add_cost(weight * casadi.sum2(program.h * casadi.sum1(absolute)))

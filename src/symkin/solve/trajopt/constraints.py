"""The constraints of a transcribed problem in named groups: imposed on ``Opti``, checked at the
solver's point, and turned into the message that says which limits rule a motion out."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.solve.trajopt.problem import (
    FEASIBILITY_TOLERANCE,
    TrajectoryProblem,
    fixed_tool_coordinates,
    units,
)
from symkin.solve.trajopt.transcription import Transcription


@dataclass(frozen=True)
class Group:
    """A group of constraints ``lower <= expr <= upper`` with a name for error messages;
    ``lower is upper`` marks an equality."""

    label: str
    expr: Any
    lower: Any
    upper: Any
    unit: str = ""


@dataclass(frozen=True)
class Check:
    """A constraint group at a point: its largest violation (0 when met) and, for limits, at
    how many of its ``size`` entries the bound is reached (within 0.1 % of the range)."""

    group: Group
    violation: float
    at_bound: int
    size: int


def constraint_groups(
    model: Model, problem: TrajectoryProblem, transcription: Transcription, tool_position: Callable
) -> list[Group]:
    """Every constraint of the problem, in named groups (the names go into error messages)."""
    n = model.robot.dof
    X = transcription.X
    groups = [
        Group("dynamics (transcription defects)", transcription.defects, 0.0, 0.0),
        Group("start configuration", X[:n, 0], problem.start, problem.start),
        Group("rest at the start", X[n:, 0], 0.0, 0.0),
        Group("rest at the goal", X[n:, -1], 0.0, 0.0),
    ]
    if problem.cartesian_goal is None:
        groups.append(Group("goal configuration", X[:n, -1], problem.goal, problem.goal))
    else:
        groups.append(_tool_goal(model, problem, tool_position(X[:n, -1])))
    return groups + _limit_groups(model, problem, transcription)


def _tool_goal(model: Model, problem: TrajectoryProblem, end) -> Group:
    """The tool at the Cartesian goal, in the coordinates some joint can change: the others
    were checked already and as constraints would be rows of zeros in the Jacobian."""
    import casadi

    fixed = fixed_tool_coordinates(model, dict(problem.overrides))
    rows = [r for r in range(3) if r not in fixed]
    target = tuple(problem.cartesian_goal[r] for r in rows)
    expr = casadi.vertcat(*(end[r] for r in rows))
    return Group("tool position at the goal", expr, target, target, "m")


def _limit_groups(
    model: Model, problem: TrajectoryProblem, transcription: Transcription
) -> list[Group]:
    """Position, velocity and torque limits at the nodes, one group per joint and kind."""
    n = model.robot.dof
    X, torques = transcription.X, transcription.torques
    groups = []
    for i, joint in enumerate(model.robot.joints):
        position, rate, force = units(joint)
        if joint.limits is not None:
            lo, hi = joint.limits
            label = f"position limits of joint {i + 1} [{lo:.6g}, {hi:.6g}] {position}"
            groups.append(Group(label, X[i, :], lo, hi, position))
        if problem.velocity_limits is not None:
            v = problem.velocity_limits[i]
            label = f"velocity limit of joint {i + 1} ({v:g} {rate})"
            groups.append(Group(label, X[n + i, :], -v, v, rate))
        if problem.torque_limits is not None:
            t = problem.torque_limits[i]
            label = f"torque limit of joint {i + 1} ({t:g} {force})"
            groups.append(Group(label, torques[i, :], -t, t, force))
    return groups


def impose(opti, group: Group) -> None:
    """Add ``group`` to ``opti``: an equality, or bounds on both sides."""
    import casadi

    lower = group.lower if isinstance(group.lower, int | float) else casadi.DM(group.lower)
    upper = group.upper if isinstance(group.upper, int | float) else casadi.DM(group.upper)
    if group.lower is group.upper:
        opti.subject_to(group.expr == lower)
    else:
        opti.subject_to(opti.bounded(lower, group.expr, upper))


def check_group(group: Group, value: Callable) -> Check:
    """``group`` at the point where ``value`` (``Opti.value`` or its debug twin) evaluates."""
    try:
        values = np.ravel(np.asarray(value(group.expr), dtype=float))
    except RuntimeError:  # not evaluable at IPOPT's last point (a NaN in the model)
        return Check(group, float("inf"), 0, 1)
    lower = np.ravel(np.asarray(group.lower, dtype=float))
    upper = np.ravel(np.asarray(group.upper, dtype=float))
    excess = np.maximum(lower - values, values - upper)
    at_bound = 0
    if group.lower is not group.upper:  # a limit, not an equality
        at_bound = int(np.sum(excess >= -1e-3 * (upper - lower)))
    return Check(group, float(max(excess.max(initial=0.0), 0.0)), at_bound, values.size)


def failure_text(status: str, iterations: int, checks: list[Check]) -> str:
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

"""All IK solutions of a target: the closed form where the robot has one, else a numeric search.

The closed forms (:mod:`symkin.solve.ik.closed_form`) give every solution with its branch flags.
Without one, the numeric solver runs from many seeds and the distinct solutions it finds are
collected: a sample, not a proof that no other solution exists (``SolutionSet.complete`` is
False and the command line says so).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError
from symkin.solve.ik.joints import random_configuration
from symkin.solve.ik.numeric import DEFAULT_TOLERANCE, solve_ik, task_errors, task_rows_for

DEFAULT_SEEDS = 64
# Two numeric solutions closer than this in every joint (angles modulo 2 pi) are one.
DISTINCT = 1e-6


@dataclass(frozen=True)
class Solution:
    """One solution: joint values, branch flags (closed form only) and whether every joint is
    within its limits."""

    q: np.ndarray
    branch: Mapping[str, str] = field(default_factory=dict)
    within_limits: bool = True


@dataclass(frozen=True)
class SolutionSet:
    """The solutions found and how: ``method`` is ``"closed form"`` or ``"numeric"``,
    ``description`` says which family or how many seeds."""

    solutions: tuple[Solution, ...]
    method: str
    description: str
    complete: bool


def _distinct(q: np.ndarray, found: Sequence[Solution], revolute: np.ndarray) -> bool:
    for other in found:
        difference = np.abs(q - other.q)
        difference[revolute] = np.abs(np.angle(np.exp(1j * (q - other.q)[revolute])))
        if np.all(difference <= DISTINCT):
            return False
    return True


def all_solutions(
    model: Model,
    target: np.ndarray,
    q0: Sequence[float] | None = None,
    *,
    position_only: bool = False,
    task: Sequence[str] | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    seeds: int = DEFAULT_SEEDS,
    seed: int | None = 0,
    overrides: Mapping[str, float] | None = None,
) -> SolutionSet:
    """Every solution for ``target`` (4x4) on the task rows (as in
    :func:`symkin.solve.ik.numeric.solve_ik`).

    The closed form is used when the robot has one and the rows include the robot's own task
    rows (its closed form solves those); each of its solutions is kept if it also meets any
    further rows (a planar arm asked for ``z``).  Otherwise ``seeds`` numeric solves (the first
    from ``q0`` if given, the others from random configurations) give the distinct solutions.
    A task with fewer rows than joints has infinitely many solutions and is rejected.
    """
    from symkin.solve.ik.closed_form import closed_form_family, closed_form_ik, has_closed_form

    rows = task_rows_for(model, task, position_only)
    robot = model.robot
    if len(rows) < robot.dof:
        raise ParameterError(
            f"{{all_solutions}}: the task rows {','.join(rows)} leave {robot.dof - len(rows)} of "
            f"{robot.name}'s {robot.dof} joints free: infinitely many solutions"
        )
    if has_closed_form(robot, overrides) and set(model.task_rows) <= set(rows):
        solutions = tuple(
            Solution(np.array(s.q), dict(s.branch), s.within_limits)
            for s in closed_form_ik(model, target, overrides)
            if max(task_errors(model, s.q, target, rows, overrides)) <= tolerance
        )
        return SolutionSet(solutions, "closed form", closed_form_family(robot, overrides), True)
    rng = np.random.default_rng(seed)
    revolute = np.array([j.type == "revolute" for j in robot.joints])
    found: list[Solution] = []
    for k in range(seeds):
        start = q0 if k == 0 and q0 is not None else random_configuration(model, rng)
        result = solve_ik(
            model, target, start, task=rows, tolerance=tolerance, restarts=0, overrides=overrides
        )
        if result.success and _distinct(result.q, found, revolute):
            found.append(Solution(result.q))
    return SolutionSet(
        tuple(found), "numeric", f"distinct solutions from {seeds} seeds, possibly not all", False
    )

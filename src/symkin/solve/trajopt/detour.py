"""A first guess clear of the obstacles: the joint-space polyline of
:func:`~symkin.solve.trajopt.initial_guess.polyline_knots` with detours where it runs a link
through a sphere.

Each piece of the polyline is checked at configurations no more than ``MAX_STEP`` (rad or m,
largest joint) apart, with the distances of the obstacle constraint (the link capsules of
:func:`~symkin.solve.trajopt.accuracy.configuration_clearance`) evaluated numerically, and
must keep ``GUESS_MARGIN`` metres more than the constraint asks.  A piece that does not gets
one via configuration: candidates are drawn around the piece's midpoint (normal, spread growing
from a tenth to twice the piece's length round by round, within the joint limits, seeded so the
guess is reproducible) and the shortest detour whose two halves are clear wins.  When no
candidate clears both halves, the candidates that clear one half best are kept and the other
half gets a detour of its own, up to ``MAX_DEPTH`` nested vias.  Within ``MAX_CHECKS``
configuration checks it gives up, and the straight polyline stays the guess (the report says
so).  The vias share their piece's time in proportion to joint-space length.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from symkin.solve.trajopt.accuracy import configuration_clearance, origins_function
from symkin.solve.trajopt.functions import RobotFunctions
from symkin.solve.trajopt.problem import TrajectoryProblem

GUESS_MARGIN = 0.02  # metres the guess keeps beyond the obstacle constraint's reach
MAX_STEP = 0.02  # largest joint step between the configurations checked along a line
BATCH = 48  # via candidates drawn per round
ROUNDS = 6  # rounds of candidates per piece, the spread growing
MAX_DEPTH = 3  # nested vias on one piece of the polyline
NESTED = 3  # candidates clearing one half that are tried with a nested detour
MAX_CHECKS = 400_000  # configurations checked before giving up
SEED = 20  # the candidates' random generator: the same problem gets the same guess

Knots = list[tuple[float, np.ndarray]]


@dataclass(frozen=True)
class GuessReport:
    """Where the solver started: ``source`` is ``"line"`` (the straight polyline),
    ``"detour"`` (with ``vias`` via configurations added) or ``"earlier"`` (a warm start);
    ``clear`` whether every checked configuration of the guess keeps the obstacle constraint
    plus ``GUESS_MARGIN`` (``None``: no obstacles, or a warm start, not checked);
    ``min_clearance`` the smallest distance beyond the constraint's reach (metres, before the
    margin) along the guess; ``note`` one line when no clear guess was found."""

    source: str
    clear: bool | None = None
    vias: int = 0
    min_clearance: float | None = None
    note: str = ""


class _Checker:
    """Clearance of configurations and of straight lines between them, counting the checks."""

    def __init__(self, functions: RobotFunctions, problem: TrajectoryProblem) -> None:
        origins = origins_function(functions)
        margin = GUESS_MARGIN + problem.obstacle_margin
        self.clearance = lambda q: configuration_clearance(origins, q, problem, margin)
        self.lower, self.upper = functions.lower, functions.upper
        self.checks = 0

    def lines(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The smallest clearance along each line ``a[j]``-``b[j]`` (rows), ends included."""
        steps = max(1, math.ceil(float(np.abs(b - a).max()) / MAX_STEP))
        s = np.linspace(0.0, 1.0, steps + 1)
        q = a[:, None, :] + s[None, :, None] * (b - a)[:, None, :]  # lines x samples x n
        self.checks += q.shape[0] * q.shape[1]
        values = self.clearance(q.reshape(-1, q.shape[-1]).T)
        return values.reshape(q.shape[0], q.shape[1]).min(axis=1)

    def line(self, a: np.ndarray, b: np.ndarray) -> float:
        return float(self.lines(a[None], b[None])[0])

    def exhausted(self) -> bool:
        return self.checks >= MAX_CHECKS


def clear_knots(
    functions: RobotFunctions,
    problem: TrajectoryProblem,
    knots: Sequence[tuple[float, np.ndarray]],
    search: bool = True,
) -> tuple[Knots, GuessReport]:
    """``knots`` with via configurations inserted where a piece's links would meet an
    obstacle, and the report; the knots unchanged (and a note) when no clear detour is found,
    a knot itself is not clear, or ``search`` is off (the straight polyline only checked)."""
    checker = _Checker(functions, problem)
    if not search:
        return list(knots), _line_report(checker, knots, "detour search off")
    rng = np.random.default_rng(SEED)
    corners = np.array([q for _, q in knots], dtype=float)
    at_corners = checker.clearance(corners.T)
    if at_corners.min() < 0:
        k = int(np.argmin(at_corners))
        where = "the start" if k == 0 else "the goal" if k == len(knots) - 1 else f"corner {k}"
        return list(knots), _line_report(
            checker, knots, f"{where} is within {GUESS_MARGIN} m of an obstacle's reach"
        )
    result: Knots = [knots[0]]
    for (s0, a), (s1, b) in itertools.pairwise(knots):
        vias = _detour(checker, np.asarray(a, float), np.asarray(b, float), rng, 0)
        if vias is None:
            note = f"no path clear of the obstacles found in {checker.checks} configurations"
            return list(knots), _line_report(checker, knots, note)
        result += _timed(s0, s1, [np.asarray(a, float), *vias, np.asarray(b, float)])[1:]
    vias = len(result) - len(knots)
    smallest = _smallest(checker, result)
    source = "detour" if vias else "line"
    return result, GuessReport(source, smallest >= 0, vias, smallest + GUESS_MARGIN)


def _smallest(checker: _Checker, knots: Sequence[tuple[float, np.ndarray]]) -> float:
    """The smallest clearance (beyond the reach and the margin) along the polyline (a single
    knot: at that configuration, a line of length zero)."""
    q = np.array([values for _, values in knots], dtype=float)
    if len(q) == 1:
        q = np.vstack([q, q])
    return float(checker.lines(q[:-1], q[1:]).min())


def _line_report(checker: _Checker, knots, note: str) -> GuessReport:
    smallest = _smallest(checker, knots)
    return GuessReport("line", smallest >= 0, 0, smallest + GUESS_MARGIN, note)


def _detour(
    checker: _Checker, a: np.ndarray, b: np.ndarray, rng: np.random.Generator, depth: int
) -> list[np.ndarray] | None:
    """Via configurations (possibly none) that make ``a``, vias, ``b`` clear, or ``None``."""
    if checker.line(a, b) >= 0:
        return []
    if depth >= MAX_DEPTH:
        return None
    mid, length = (a + b) / 2, max(float(np.linalg.norm(b - a)), 0.2)
    partial = []
    for spread in np.geomspace(0.1, 2.0, ROUNDS) * length:
        if checker.exhausted():
            return None
        draws = mid + spread * rng.standard_normal((BATCH, len(a)))
        candidates = np.clip(draws, checker.lower, checker.upper)
        first = checker.lines(np.tile(a, (BATCH, 1)), candidates)
        second = checker.lines(candidates, np.tile(b, (BATCH, 1)))
        lengths = np.linalg.norm(candidates - a, axis=1) + np.linalg.norm(b - candidates, axis=1)
        both = np.flatnonzero((first >= 0) & (second >= 0))
        if both.size:
            return [candidates[both[np.argmin(lengths[both])]]]
        one = np.flatnonzero(np.maximum(first, second) >= 0)
        partial += [(float(min(first[j], second[j])), candidates[j]) for j in one]
        partial = sorted(partial, key=lambda item: -item[0])[:NESTED]
    return _nested(checker, a, b, rng, depth, [via for _, via in partial])


def _nested(
    checker: _Checker,
    a: np.ndarray,
    b: np.ndarray,
    rng: np.random.Generator,
    depth: int,
    vias: list[np.ndarray],
) -> list[np.ndarray] | None:
    """A detour through one of ``vias`` (each clears one half of ``a``-``b``; the one whose
    other half comes closest to clear first), the blocked half detoured in turn."""
    for via in vias:
        head = _detour(checker, a, via, rng, depth + 1)
        tail = None if head is None else _detour(checker, via, b, rng, depth + 1)
        if tail is not None:
            return [*head, via, *tail]
    return None


def _timed(s0: float, s1: float, corners: list[np.ndarray]) -> Knots:
    """``corners`` placed on ``[s0, s1]`` in proportion to the joint-space length before them."""
    steps = [float(np.linalg.norm(b - a)) for a, b in itertools.pairwise(corners)]
    total = sum(steps)
    if total == 0:
        return [(s0, corners[0]), (s1, corners[-1])]
    cumulative = np.concatenate([[0.0], np.cumsum(steps)]) / total
    fractions = s0 + (s1 - s0) * cumulative
    fractions[-1] = s1
    return list(zip((float(f) for f in fractions), corners, strict=True))

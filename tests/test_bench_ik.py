"""The IK benchmark's bookkeeping (bench/ik_speed.py): its checks and its alternation.

No timing is judged here.  The checks are compared with hand values on the planar 2R arm
(unit links: the tool at ``(cos q1 + cos(q1 + q2), sin q1 + sin(q1 + q2))``, rotated by
``q1 + q2`` about z), and the alternation with solvers that only record their calls.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parent.parent / "bench"
sys.path.insert(0, str(BENCH))

import ik_speed  # noqa: E402 - the bench folder is not a package

Q = np.array([0.3, 0.4])


def planar_pose(q: np.ndarray, dx: float = 0.0, turn: float = 0.0) -> np.ndarray:
    """The 2R tool pose at ``q`` by hand, moved by ``dx`` along x and turned by ``turn``."""
    angle = q[0] + q[1] + turn
    T = np.eye(4)
    T[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    T[0, 3] = math.cos(q[0]) + math.cos(q[0] + q[1]) + dx
    T[1, 3] = math.sin(q[0]) + math.sin(q[0] + q[1])
    return T


@pytest.mark.parametrize(
    ("dx", "turn", "expected"),
    [
        # E = (dx^2 + turn^2) / 2 against RTB's tol; 1e-9 on each error for the first column.
        (0.0, 0.0, (True, True, True)),
        (1e-6, 0.0, (False, True, True)),  # E = 5e-13
        (2e-6, 0.0, (False, False, True)),  # E = 2e-12
        (0.0, 1e-3, (False, False, True)),  # E = 5e-7
        (1.1e-3, 1e-3, (False, False, False)),  # E = 1.105e-6
    ],
)
def test_the_checks_are_the_tolerance_and_rtbs_stopping_rule(dx, turn, expected, model_of):
    tests = ik_speed.checks(model_of("planar_2r"))
    target = planar_pose(Q, dx, turn)
    assert tuple(test(Q, target) for test in tests) == expected
    assert not any(test(None, target) for test in tests)


def test_solvers_alternate_by_rounds_in_rotating_order(monkeypatch, model_of) -> None:
    calls: list[tuple[str, int]] = []
    targets = [planar_pose(Q + 0.01 * k) for k in range(6)]

    def recorder(label: str):
        def prepare(model):
            def solve(target, seed):
                calls.append((label, next(k for k, t in enumerate(targets) if t is target)))
                return Q, True

            return solve

        return prepare

    solvers = [ik_speed.Solver(label, recorder(label), reference=label == "a") for label in "ab"]
    monkeypatch.setattr(ik_speed, "SOLVERS", solvers)
    monkeypatch.setattr(ik_speed, "load_model", lambda name: model_of(name))
    monkeypatch.setattr(ik_speed, "poses", lambda model, count, seed: [(t, Q) for t in targets])
    monkeypatch.setattr(ik_speed, "child_peak_mb", lambda *args: 0.0)
    monkeypatch.setattr(ik_speed, "c_loop_row", lambda *args: ik_speed.Row("c"))
    monkeypatch.setattr(ik_speed, "c_closed_loop_row", lambda *args: None)
    rows, _ = ik_speed.measure("planar_2r", 6, 0, peers=False, round_size=2)
    timed = calls[2:]  # the first two calls warm up, outside the timing
    assert timed == [
        ("a", 0), ("a", 1), ("b", 0), ("b", 1),
        ("b", 2), ("b", 3), ("a", 2), ("a", 3),
        ("a", 4), ("a", 5), ("b", 4), ("b", 5),
    ]  # fmt: skip
    assert [len(row.times_ns) for row in rows[:2]] == [6, 6]
    assert rows[0].passed[0] == 1  # only pose 0 is Q itself

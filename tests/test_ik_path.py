"""The lecture's Newton path table and the Cartesian path follower (``symkin.solve.ik.path``).

The table is recomputed here step by step from its definition, with the forward kinematics
and the Jacobian of ``tests/numeric_dh.py`` (an independent product of elementary transforms;
Jacobian by complex-step differentiation, exact to rounding), never with symkin's kinematics.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from numeric_dh import NumericRobot, reference, robot, vee
from symkin import derive
from symkin.errors import SymkinError
from symkin.solve.ik.path import (
    correction_label,
    follow_path,
    newton_path_table,
    path_table_json,
    path_table_text,
    waypoint_poses,
)
from symkin.solve.ik.target import pose_from_target

ROWS = {"x": 0, "y": 1, "z": 2}


# The PUMA 560 file's lumped link inertias raise a data warning unrelated to IK.
pytestmark = pytest.mark.filterwarnings("ignore::symkin.errors.RobotWarning")


def lecture_table(name, x0, q0, x_end, steps, rows, tolerance=1e-10, corrections=20):
    """The scheme as the issue defines it, written out again with the reference model:
    X_i = X0 + i (X_end - X0) / k; Q_{i+1} = Q_i + J^-1(Q_i) (X_{i+1} - X_i,real) with
    X_0,real = X0 and X_i,real = FK(Q_i); then Newton at X_end until |X_end - FK| <= tol.
    Rows are (label, X_i, Q_i, X_i,real, dx): dx is the lecture's column "for Gl. (14.15)",
    X_{i+1} - X_i,real before the end point and X_k - X_k,real from row k on."""
    ref = reference(name)
    index = [ROWS[r] for r in rows]

    def fk(q):
        return ref.fk(q)[index, 3]

    def inverse(q):
        J = ref.jacobian(q, method="complex")[index]
        return np.linalg.inv(J) if J.shape[0] == J.shape[1] else np.linalg.pinv(J)

    x0, x_end, q = np.array(x0, float), np.array(x_end, float), np.array(q0, float)
    table = [("0", x0, q, x0)]
    real = x0
    for i in range(1, steps + 1):
        target = x0 + i * (x_end - x0) / steps
        q = q + inverse(q) @ (target - real)
        real = fk(q)
        table.append((str(i), target, q, real))
    for letter in "abcdefghijklmnopqrst"[:corrections]:
        if np.linalg.norm(x_end - real) <= tolerance:
            break
        q = q + inverse(q) @ (x_end - real)
        real = fk(q)
        table.append((f"{steps}{letter}", x_end, q, real))
    following = [row[1] for row in table[1:]] + [x_end]
    return [(*row, aim - row[3]) for row, aim in zip(table, following, strict=True)]


def assert_same_table(path, expected) -> None:
    assert [row.label for row in path.rows] == [row[0] for row in expected]
    for row, (_, target, q, real, dx) in zip(path.rows, expected, strict=True):
        np.testing.assert_allclose(row.target, target, atol=1e-12)
        np.testing.assert_allclose(row.q, q, atol=1e-9)
        np.testing.assert_allclose(row.real, real, atol=1e-9)
        np.testing.assert_allclose(row.delta, dx, atol=1e-9)
        np.testing.assert_allclose(row.error, target - real, atol=1e-9)


def test_lecture_table_planar_2r() -> None:
    """The lecture's setting: planar 2R, x and y, five steps, then Newton at the end point."""
    q0 = np.radians([30.0, 60.0])
    x0 = reference("planar_2r").fk(q0)[:2, 3]
    x_end = [1.0, 1.2]
    path = newton_path_table(derive(robot("planar_2r")), x0, q0, x_end, 5)
    expected = lecture_table("planar_2r", x0, q0, x_end, 5, ("x", "y"))
    assert_same_table(path, expected)
    assert path.task == ("x", "y") and path.converged
    assert len(path.rows) > 6  # one step per waypoint leaves an error: corrections follow
    # Row 0's dx, dy are x_1 - x_0: one fifth of the path.
    np.testing.assert_allclose(path.rows[0].delta, (np.array(x_end) - x0) / 5, atol=1e-15)
    assert path.rows[0].error.tolist() == [0.0, 0.0]
    assert np.linalg.norm(path.rows[-1].delta) <= 1e-10
    # Aiming from the real position keeps the error from adding up along the path.
    errors = [np.linalg.norm(row.error) for row in path.rows[1:6]]
    assert max(errors) < 5e-3


def test_row_zero_uses_the_given_start_even_if_q0_misses_it() -> None:
    """Row 0's real position is the given X0 (the known pair), not FK(Q0); a mismatch warns."""
    q0 = np.array([0.2, 1.0])
    x0 = [1.0, 1.0]  # FK(q0) is elsewhere
    m = derive(robot("planar_2r"))
    with pytest.warns(UserWarning, match="away from the path start"):
        path = newton_path_table(m, x0, q0, [0.5, 1.4], 4)
    np.testing.assert_array_equal(path.rows[0].real, x0)
    assert_same_table(path, lecture_table("planar_2r", x0, q0, [0.5, 1.4], 4, ("x", "y")))


@pytest.mark.parametrize(
    ("name", "rows", "q0"),
    [
        ("planar_3r", ("x", "y"), (0.3, 0.8, 0.6)),  # 2 x 3: pseudo-inverse
        ("scara", ("x", "y", "z"), (0.4, 1.0, 0.1)),  # square with a prismatic joint
        ("puma560", ("x", "y", "z"), (0.3, -0.4, 0.3, 0.0, 0.5, 0.0)),  # 3 x 6
    ],
)
def test_table_on_other_arms(name: str, rows: tuple[str, ...], q0: tuple[float, ...]) -> None:
    index = [ROWS[r] for r in rows]
    x0 = reference(name).fk(np.array(q0))[index, 3]
    x_end = x0 * np.array([0.85, 0.85, 1.0])[: len(rows)]  # inward, well inside the reach
    x_end[-1] += 0.05
    path = newton_path_table(derive(robot(name)), x0, q0, x_end, 4, task=rows)
    assert_same_table(path, lecture_table(name, x0, q0, x_end, 4, rows))
    assert path.converged


def test_corrections_stop_at_the_limit_and_report_it() -> None:
    """An end point out of reach: Newton never gets there; the table stops after the allowed
    corrections and says it did not converge."""
    m = derive(robot("planar_2r"))
    q0 = np.radians([10.0, 90.0])
    x0 = reference("planar_2r").fk(q0)[:2, 3]
    path = newton_path_table(m, x0, q0, [2.5, 0.0], 3, max_corrections=4)
    assert not path.converged
    assert [row.label for row in path.rows][-4:] == ["3a", "3b", "3c", "3d"]
    assert all(np.all(np.isfinite(row.q)) for row in path.rows)


def test_correction_labels() -> None:
    assert [correction_label(5, k) for k in (0, 1, 25, 26, 27)] == ["5a", "5b", "5z", "5aa", "5ab"]


def test_table_text_and_json() -> None:
    q0 = np.radians([30.0, 60.0])
    x0 = reference("planar_2r").fk(q0)[:2, 3]
    path = newton_path_table(derive(robot("planar_2r")), x0, q0, [1.0, 1.2], 5)
    text = path_table_text(path, ["q1", "q2"]).splitlines()
    assert text[0].split() == ["i", "x_i", "y_i", "q1", "q2", "x_real", "y_real", "dx", "dy"]
    assert [line.split()[0] for line in text[1:]] == [row.label for row in path.rows]
    assert float(text[2].split()[3]) == pytest.approx(path.rows[1].q[0], abs=1e-6)
    data = path_table_json(path)
    assert data["task"] == ["x", "y"] and data["converged"] is True
    assert all(set(row) == {"i", "target", "q", "real", "delta"} for row in data["rows"])
    assert data["rows"][-1]["i"] == path.rows[-1].label


@pytest.mark.parametrize(
    ("task", "message"),
    [(("x", "wz"), "interpolates positions"), (("x", "x"), "repeat")],
)
def test_table_rejects_bad_rows(task: tuple[str, ...], message: str) -> None:
    with pytest.raises(SymkinError, match=message):
        newton_path_table(derive(robot("planar_3r")), [1, 1], [0, 0, 0], [1, 2], 3, task=task)


def test_table_rejects_bad_sizes() -> None:
    m = derive(robot("planar_2r"))
    with pytest.raises(SymkinError, match="q0: expected 2 values"):
        newton_path_table(m, [1, 1], [0, 0, 0], [1, 2], 3)
    with pytest.raises(SymkinError, match="path end"):
        newton_path_table(m, [1, 1], [0, 0], [1, 2, 3], 3)
    with pytest.raises(SymkinError, match="at least 1 step"):
        newton_path_table(m, [1, 1], [0, 0], [1, 2], 0)


# ---------------------------------------------------------------------------------------------
# Path follower
# ---------------------------------------------------------------------------------------------


def rotation_angle(R: np.ndarray) -> float:
    return math.atan2(np.linalg.norm(vee(R)), (np.trace(R) - 1) / 2)


def test_follower_solves_every_waypoint_of_a_pose_path() -> None:
    """PUMA 560 along a straight line with a turning tool: every waypoint within tolerance by
    the independent FK, waypoints equally spaced in position and in rotation angle, and the
    joints move continuously (one branch)."""
    q0 = np.array([0.3, 0.5, -2.5, 0.2, 0.6, 0.1])
    start = reference("puma560").fk(q0)
    end = start @ pose_from_target([0.1, -0.1, 0.05, 0.3, -0.2, 0.4])
    path = follow_path(derive(robot("puma560")), start, end, 8, q0)
    assert path.success and len(path.results) == 9
    reached = [reference("puma560").fk(r.q) for r in path.results]
    for T, target in zip(reached, path.targets, strict=True):
        assert np.linalg.norm(T[:3, 3] - target[:3, 3]) < 1e-9
        assert rotation_angle(target[:3, :3].T @ T[:3, :3]) < 1e-9
    np.testing.assert_allclose(path.targets[0], start, atol=1e-12)
    np.testing.assert_allclose(path.targets[-1], end, atol=1e-12)
    steps = np.diff([t[:3, 3] for t in path.targets], axis=0)
    np.testing.assert_allclose(steps, np.tile(steps[0], (8, 1)), atol=1e-12)
    turns = [
        rotation_angle(a[:3, :3].T @ b[:3, :3])
        for a, b in zip(path.targets[:-1], path.targets[1:], strict=True)
    ]
    np.testing.assert_allclose(turns, turns[0], atol=1e-12)
    total = rotation_angle(start[:3, :3].T @ end[:3, :3])
    assert sum(turns) == pytest.approx(total, abs=1e-12)  # the shortest rotation
    jumps = np.abs(np.diff([r.q for r in path.results], axis=0))
    assert jumps.max() < 0.3


def test_follower_position_only_planar() -> None:
    m = derive(robot("planar_2r"))
    start, end = pose_from_target([1.5, 0.2, 0.0]), pose_from_target([0.2, 1.5, 0.0])
    path = follow_path(m, start, end, 6, (0.1, 1.0), task=("x", "y"))
    assert path.success
    for target, result in zip(path.targets, path.results, strict=True):
        reached = reference("planar_2r").fk(result.q)[:2, 3]
        assert np.linalg.norm(reached - target[:2, 3]) < 1e-9


def test_follower_reports_an_unreachable_waypoint() -> None:
    """With L2 = 0.5 the 2R arm reaches the ring 0.5 <= r <= 1.5; the path at y = 0.3 from
    x = 1 to x = -1 crosses the hole: its middle waypoint (0, 0.3) fails, the others succeed."""
    m = derive(robot("planar_2r"))
    overrides = {"L2": 0.5}
    ref = NumericRobot.from_robot(robot("planar_2r"), overrides)
    start, end = pose_from_target([1.0, 0.3, 0.0]), pose_from_target([-1.0, 0.3, 0.0])
    path = follow_path(m, start, end, 4, (0.0, 1.0), task=("x", "y"), overrides=overrides)
    assert [r.success for r in path.results] == [True, True, False, True, True]
    assert not path.success
    for target, result in zip(path.targets, path.results, strict=True):
        error = np.linalg.norm(ref.fk(result.q)[:2, 3] - target[:2, 3])
        assert error == pytest.approx(result.position_error, abs=1e-12)
    assert path.results[2].position_error == pytest.approx(0.5 - 0.3, abs=1e-3)


def test_waypoints_without_rotation() -> None:
    poses = waypoint_poses(pose_from_target([0, 0, 0]), pose_from_target([1, 2, 3]), 2)
    np.testing.assert_allclose(poses[1][:3, 3], [0.5, 1.0, 1.5])
    np.testing.assert_allclose(poses[1][:3, :3], np.eye(3))

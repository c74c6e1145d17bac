"""Numeric IK (``symkin.solve.ik.numeric``) against an independent forward kinematics.

Every solution is checked with ``tests/numeric_dh.py`` (a product of elementary transforms
written from the conventions text, with the Jacobian by complex-step differentiation), never
with the generated code the solver iterates on.  Targets come from that same independent FK
at random joint values within the limits, from textbook closed forms (law of cosines for the
planar 2R arm), or from plain geometry (the closest point of a disc).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from numeric_dh import Rx, Ry, Rz, reference, robot, vee
from symkin.errors import SymkinError
from symkin.solve.ik.joints import joint_bounds, random_configuration
from symkin.solve.ik.numeric import (
    IKResult,
    rotation_vector,
    solve_ik,
    task_errors,
)
from symkin.solve.ik.target import pose_from_target

TOL = 1e-10
CHECK = 1e-9  # what the independent FK must confirm (rounding differs between the two FKs)


# The PUMA 560 file's lumped link inertias raise a data warning unrelated to IK.
pytestmark = pytest.mark.filterwarnings("ignore::symkin.errors.RobotWarning")


def pose_error(name: str, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """Position error (m) and rotation angle (rad) between FK(q) and ``target``, independently:
    the angle from ``acos((tr(R_t^T R) - 1) / 2)`` evaluated as an atan2 for accuracy."""
    T = reference(name).fk(np.asarray(q, dtype=float))
    position = float(np.linalg.norm(T[:3, 3] - target[:3, 3]))
    relative = target[:3, :3].T @ T[:3, :3]
    sine = np.linalg.norm(vee(relative))  # |sin angle|
    cosine = (np.trace(relative) - 1) / 2
    return position, math.atan2(sine, cosine)


def within_limits(name: str, q: np.ndarray) -> bool:
    for value, joint in zip(q, robot(name).joints, strict=True):
        if joint.limits is not None:
            low, high = joint.limits
            if not low - 1e-12 <= value <= high + 1e-12:
                return False
    return True


def random_within_limits(name: str, rng: np.random.Generator) -> np.ndarray:
    """Uniform joint values within the robot file's limits (written here, not symkin's)."""
    values = []
    for joint in robot(name).joints:
        low, high = joint.limits if joint.limits is not None else (-math.pi, math.pi)
        values.append(rng.uniform(low, high))
    return np.array(values)


# ---------------------------------------------------------------------------------------------
# Reachable targets: solved, confirmed by the independent FK, within the limits
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "count"), [("puma560", 40), ("panda", 15), ("stanford", 15)])
def test_random_reachable_poses_are_solved(name: str, count: int, model_of) -> None:
    rng = np.random.default_rng(5)
    m = model_of(name)
    for _ in range(count):
        target = reference(name).fk(random_within_limits(name, rng))
        seed = random_within_limits(name, rng)
        result = solve_ik(m, target, seed, tolerance=TOL)
        position, rotation = pose_error(name, result.q, target)
        assert result.success, (name, result)
        assert position < CHECK and rotation < CHECK
        assert within_limits(name, result.q)
        assert np.all(np.isfinite(result.q))
        assert result.residual <= TOL


def test_reported_errors_match_the_independent_fk(model_of) -> None:
    """Success means the FK of the returned q meets the tolerance: the reported errors are the
    real ones (to rounding), also for a failed, closest-pose result."""
    rng = np.random.default_rng(11)
    m = model_of("puma560")
    target = reference("puma560").fk(random_within_limits("puma560", rng))
    for max_iterations in (2, 100):  # unfinished and finished
        result = solve_ik(m, target, np.zeros(6), max_iterations=max_iterations, restarts=0)
        position, rotation = pose_error("puma560", result.q, target)
        assert result.position_error == pytest.approx(position, rel=1e-6, abs=1e-12)
        assert result.rotation_error == pytest.approx(rotation, rel=1e-6, abs=1e-12)
        assert result.success == (max(position, rotation) <= TOL)
    assert task_errors(m, result.q, target) == pytest.approx((position, rotation), abs=1e-12)


def test_planar_2r_matches_the_law_of_cosines(model_of) -> None:
    """x, y target of the unit 2R arm: q2 = +-acos((x^2 + y^2 - 2) / 2) (Spong Sec. 5.1)."""
    m = model_of("planar_2r")
    for x, y, seed in [(1.2, 0.5, (0.1, 1.0)), (-0.3, 1.1, (2.0, -1.0)), (0.4, -1.6, (0.0, 0.5))]:
        result = solve_ik(m, pose_from_target([x, y, 0.0]), seed, task=("x", "y"))
        q2 = math.acos((x * x + y * y - 2) / 2)
        assert result.success
        assert abs(result.q[1]) == pytest.approx(q2, abs=1e-9)
        q1 = math.atan2(y, x) - math.atan2(math.sin(result.q[1]), 1 + math.cos(result.q[1]))
        assert math.remainder(result.q[0] - q1, 2 * math.pi) == pytest.approx(0, abs=1e-9)


@pytest.mark.parametrize("name", ["planar_2r", "scara", "puma560"])
def test_newton_raphson_on_square_problems(name: str, model_of) -> None:
    """Full Newton steps from a nearby seed converge fast (quadratically) to the target."""
    rng = np.random.default_rng(3)
    m = model_of(name)
    q_true = random_within_limits(name, rng)
    target = reference(name).fk(q_true)
    seed = q_true + rng.uniform(-0.1, 0.1, q_true.size)
    result = solve_ik(m, target, seed, method="newton", restarts=0)
    assert result.success and result.method == "newton"
    assert result.iterations <= 6
    rows = m.task_rows
    position = np.linalg.norm(reference(name).fk(result.q)[:3, 3] - target[:3, 3])
    assert position < CHECK, rows


def test_position_only_target_ignores_the_orientation(model_of) -> None:
    rng = np.random.default_rng(8)
    m = model_of("puma560")
    q_true = random_within_limits("puma560", rng)
    point = reference("puma560").fk(q_true)[:3, 3]
    result = solve_ik(m, pose_from_target(point), position_only=True)
    assert result.success and result.rows == ("x", "y", "z")
    assert np.linalg.norm(reference("puma560").fk(result.q)[:3, 3] - point) < CHECK


def test_task_rows_select_what_counts(model_of) -> None:
    """Planar 3R: matching x, y, wz gives the heading; matching x, y leaves it free."""
    m = model_of("planar_3r")
    heading = 0.7
    target = pose_from_target([1.5, 0.8, 0.0, 0.0, 0.0, heading])
    full = solve_ik(m, target, (0.1, 0.2, 0.3))
    assert full.success and full.rows == ("x", "y", "wz")
    assert math.remainder(float(np.sum(full.q)) - heading, 2 * math.pi) == pytest.approx(
        0, abs=1e-9
    )
    position = solve_ik(m, target, (0.1, 0.2, 0.3), task=("x", "y"))
    assert position.success
    assert np.linalg.norm(reference("planar_3r").fk(position.q)[:2, 3] - [1.5, 0.8]) < CHECK


# ---------------------------------------------------------------------------------------------
# Singular configurations, unreachable targets, weights
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["lm", "newton"])
def test_singular_seed_gives_no_nan(method: str, model_of) -> None:
    """The stretched 2R arm (q2 = 0) has a singular Jacobian; both methods leave it."""
    m = model_of("planar_2r")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no division by zero, no invalid value
        result = solve_ik(m, pose_from_target([1.2, 0.4, 0.0]), (0.0, 0.0), method=method)
    assert np.all(np.isfinite(result.q)) and result.success


def test_puma_wrist_singular_seed(model_of) -> None:
    """q5 = 0 aligns the axes of joints 4 and 6 (rank-deficient Jacobian)."""
    rng = np.random.default_rng(4)
    m = model_of("puma560")
    target = reference("puma560").fk(random_within_limits("puma560", rng))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        result = solve_ik(m, target, (0.0, 0.5, -1.0, 0.0, 0.0, 0.0))
    assert result.success and np.all(np.isfinite(result.q))
    assert max(pose_error("puma560", result.q, target)) < CHECK


def test_singular_target_on_the_workspace_boundary(model_of) -> None:
    """(2, 0) is reached only stretched out (q = 0), where J is singular: finite, and within
    the tolerance or honestly flagged."""
    m = model_of("planar_2r")
    result = solve_ik(m, pose_from_target([2.0, 0.0, 0.0]), (0.5, 1.0))
    assert np.all(np.isfinite(result.q))
    assert result.position_error < 1e-9
    assert result.success == (result.position_error <= TOL)


def test_unreachable_target_fails_with_the_closest_pose(model_of) -> None:
    """(3, 1) is outside the unit 2R arm's disc of radius 2: the closest reachable point is
    2 (3, 1) / |(3, 1)|, at distance sqrt(10) - 2."""
    m = model_of("planar_2r")
    target = pose_from_target([3.0, 1.0, 0.0])
    result = solve_ik(m, target, (0.2, 0.3))
    assert not result.success
    assert np.all(np.isfinite(result.q))
    reached = reference("planar_2r").fk(result.q)[:2, 3]
    closest = 2 * np.array([3.0, 1.0]) / math.sqrt(10)
    assert np.linalg.norm(reached - closest) < 1e-2
    assert result.position_error == pytest.approx(math.sqrt(10) - 2, abs=1e-4)
    assert result.restarts == 30  # every restart was tried


def test_unreachable_pose_of_a_limited_arm_stays_within_limits(model_of) -> None:
    m = model_of("puma560")
    target = pose_from_target([2.0, 1.0, 1.5, 0.0, 0.0, 0.0])
    result = solve_ik(m, target, restarts=2)
    assert not result.success
    assert within_limits("puma560", result.q) and np.all(np.isfinite(result.q))
    position, _ = pose_error("puma560", result.q, target)
    reach = 0.4318 + math.hypot(0.0203, 0.4318) + 0.15005  # a2 + |(a3, d4)| + d3
    assert position == pytest.approx(result.position_error, rel=1e-9)
    assert position >= math.hypot(2.0, 1.0, 1.5) - reach - 1e-9


def test_weights_move_the_least_squares_compromise(model_of) -> None:
    """An unreachable target with x weighted 100 times more than y: the reached point is the
    minimiser of 100 ex^2 + ey^2 over the disc of radius 2, found here by a dense search."""
    m = model_of("planar_2r")
    target = np.array([2.5, 1.5])
    result = solve_ik(
        m, pose_from_target([*target, 0.0]), (0.3, 0.2), task=("x", "y"), weights=(100.0, 1.0)
    )
    assert not result.success
    angles = np.linspace(-np.pi, np.pi, 2_000_001)
    boundary = 2 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    cost = 100 * (boundary[:, 0] - target[0]) ** 2 + (boundary[:, 1] - target[1]) ** 2
    best = boundary[np.argmin(cost)]
    reached = reference("planar_2r").fk(result.q)[:2, 3]
    assert np.linalg.norm(reached - best) < 1e-3
    unweighted = solve_ik(m, pose_from_target([*target, 0.0]), (0.3, 0.2), task=("x", "y"))
    plain = reference("planar_2r").fk(unweighted.q)[:2, 3]
    assert np.linalg.norm(plain - 2 * target / np.linalg.norm(target)) < 1e-3
    assert np.linalg.norm(reached - plain) > 0.1  # the weights made a difference


# ---------------------------------------------------------------------------------------------
# Limits, restarts, rest posture
# ---------------------------------------------------------------------------------------------


def test_restarts_rescue_seeds_that_fail(model_of) -> None:
    """With joint limits, some seeds lead to a branch outside the limits; restarts (reproducible
    with the seed) then find one inside."""
    rng = np.random.default_rng(21)
    m = model_of("puma560")
    rescued = 0
    for _ in range(25):
        target = reference("puma560").fk(random_within_limits("puma560", rng))
        seed = random_within_limits("puma560", rng)
        alone = solve_ik(m, target, seed, restarts=0)
        again = solve_ik(m, target, seed, restarts=10, seed=7)
        assert again.success
        if not alone.success:
            assert again.restarts > 0
            rescued += 1
            repeat = solve_ik(m, target, seed, restarts=10, seed=7)
            np.testing.assert_array_equal(repeat.q, again.q)
    assert rescued > 0


def test_random_configurations_lie_within_the_limits(model_of) -> None:
    rng = np.random.default_rng(1)
    m = model_of("panda")
    lower, upper = joint_bounds(m)
    samples = np.array([random_configuration(m, rng) for _ in range(200)])
    assert np.all(samples >= lower) and np.all(samples <= upper)
    expected = [j.limits for j in robot("panda").joints]
    np.testing.assert_allclose(np.stack([lower, upper], axis=1), expected)


def null_space_gradient(name: str, q: np.ndarray, rest: np.ndarray) -> float:
    """|(I - J^+ J)(q - rest)| with J by complex-step differentiation of the reference FK."""
    J = reference(name).jacobian(q, method="complex")
    projector = np.eye(q.size) - np.linalg.pinv(J) @ J
    return float(np.linalg.norm(projector @ (q - rest)))


def test_redundant_robot_prefers_the_rest_posture(model_of) -> None:
    """Panda (7 joints, 6 task rows), targets of postures near the rest posture: the solution
    is where the self-motion leaves the distance to the rest posture stationary (no joint is at
    a limit there), it is no farther from the rest posture than the posture the target came
    from, and closer than the solution without a preference."""
    rng = np.random.default_rng(2)
    m = model_of("panda")
    rest = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.785])  # the Panda's "ready" posture
    lower, upper = np.array([j.limits for j in robot("panda").joints]).T
    for _ in range(5):
        q_true = np.clip(rest + rng.uniform(-0.4, 0.4, 7), lower, upper)
        target = reference("panda").fk(q_true)
        seed = q_true + rng.uniform(-0.2, 0.2, 7)
        preferred = solve_ik(m, target, seed, rest_posture=rest)
        plain = solve_ik(m, target, seed, rest_posture=None)
        assert preferred.success and plain.success
        assert max(pose_error("panda", preferred.q, target)) < CHECK
        assert np.all(np.minimum(preferred.q - lower, upper - preferred.q) > 1e-3)
        assert null_space_gradient("panda", preferred.q, rest) < 1e-3
        assert np.linalg.norm(preferred.q - rest) <= np.linalg.norm(q_true - rest) + 1e-6
        assert np.linalg.norm(preferred.q - rest) < np.linalg.norm(plain.q - rest)


def test_rest_posture_blocked_by_a_limit_keeps_the_solution(model_of) -> None:
    """Random targets and seeds: where a limit blocks the way to the rest posture, the solver
    still returns a solution within the limits, never a worse one than without preference."""
    rng = np.random.default_rng(2)
    m = model_of("panda")
    rest = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.785])
    for _ in range(3):
        target = reference("panda").fk(random_within_limits("panda", rng))
        seed = random_within_limits("panda", rng)
        preferred = solve_ik(m, target, seed, rest_posture=rest, restarts=0)
        plain = solve_ik(m, target, seed, rest_posture=None, restarts=0)
        assert preferred.success == plain.success
        if plain.success:
            assert max(pose_error("panda", preferred.q, target)) < CHECK
            assert within_limits("panda", preferred.q)
            assert np.linalg.norm(preferred.q - rest) <= np.linalg.norm(plain.q - rest) + 1e-9


# ---------------------------------------------------------------------------------------------
# Rotation error, targets, bad input
# ---------------------------------------------------------------------------------------------


def test_rotation_vector_matches_scipy() -> None:
    rng = np.random.default_rng(9)
    rotations = list(Rotation.random(200, random_state=7).as_matrix())
    for angle in (0.0, 1e-12, 1e-5, math.pi / 2, math.pi - 1e-9, math.pi):
        axis = rng.normal(size=3)
        rotations.append(Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix())
    for R in rotations:
        expected = Rotation.from_matrix(R).as_rotvec()
        actual = rotation_vector(R)
        if np.linalg.norm(expected) > math.pi - 1e-6:  # at pi, r and -r are the same rotation
            assert np.linalg.norm(actual) == pytest.approx(math.pi, abs=1e-6)
            assert abs(abs(actual @ expected) - np.linalg.norm(expected) ** 2) < 1e-5
        else:
            np.testing.assert_allclose(actual, expected, atol=1e-12)


def test_pose_from_target_is_zyx_euler() -> None:
    x, y, z, rx, ry, rz = 0.1, -0.2, 0.3, 0.4, -0.5, 0.6
    expected = Rz(rz) @ Ry(ry) @ Rx(rx)
    expected[:3, 3] = (x, y, z)
    np.testing.assert_allclose(pose_from_target([x, y, z, rx, ry, rz]), expected, atol=1e-15)
    np.testing.assert_allclose(pose_from_target([x, y, z])[:3, :3], np.eye(3))
    with pytest.raises(SymkinError, match="x,y,z or x,y,z,rx,ry,rz"):
        pose_from_target([1.0, 2.0, 3.0, 4.0])


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"method": "gauss"}, "unknown IK method 'gauss'"),
        ({"q0": [0.0] * 5}, "q0: expected 6 values, got 5"),
        ({"weights": [1.0, 1.0]}, "weights .*expected 6 values"),
        ({"weights": [1.0, 1.0, 1.0, 1.0, 1.0, -1.0]}, "weights must be positive"),
        ({"task": ("x", "q")}, "unknown task row"),
        ({"tolerance": 0.0}, "tolerance must be positive"),
        ({"restarts": -1}, "restarts >= 0"),
        ({"rest_posture": "ready"}, "rest posture"),
    ],
)
def test_bad_arguments_raise_one_clear_error(options: dict, message: str, model_of) -> None:
    with pytest.raises(SymkinError, match=message):
        solve_ik(model_of("puma560"), np.eye(4), **options)


def test_bad_target_shape(model_of) -> None:
    with pytest.raises(SymkinError, match="4x4"):
        solve_ik(model_of("puma560"), np.eye(3))


def test_result_is_frozen(model_of) -> None:
    result = solve_ik(model_of("planar_2r"), pose_from_target([1.0, 1.0, 0.0]), (0.1, 0.2))
    assert isinstance(result, IKResult)
    with pytest.raises(AttributeError):
        result.success = False  # type: ignore[misc]

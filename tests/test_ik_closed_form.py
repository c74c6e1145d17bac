"""Closed-form inverse kinematics (``symkin.solve.ik.closed_form``) against independent oracles.

* FK of every returned solution is evaluated with ``tests/numeric_dh.py`` (a naive product of
  elementary transforms written from the conventions text; base and tool of the hand-written
  robots built here from their xyz/rpy numbers) and must reproduce the target.
* The pose a target was made from must be among the solutions (angles modulo 2 pi).
* "All branches": a multi-start nonlinear least-squares solve (scipy, Levenberg-Marquardt on the
  same numeric FK) from many random seeds finds no solution outside the returned set.
* PUMA 560: Robotics Toolbox's hand-written solution (``Puma560.ikine_a``, after Paul and
  Zhang 1986) gives the same joint values for each of its eight configuration letters
  (l/r, u/d, n/f), and our branch flags carry the same names.
* Geometry typed in by hand: the reach of a planar 2R arm, the elbow side, joint limits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from functools import cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares

from numeric_dh import NumericRobot, frame, wrap
from symkin.derive import Model, derive
from symkin.errors import SymkinError
from symkin.io.robot_file import load_robot, robot_from_toml
from symkin.robot import Robot
from symkin.solve.ik.closed_form import (
    ClosedFormSolution,
    batched_forward_kinematics,
    closed_form_family,
    closed_form_ik,
    has_closed_form,
)

DEG = math.pi / 180
TOL = 1e-9  # FK of a solution vs. the target (metres, rotation entries, radians)
SAME_Q = 1e-7  # two joint vectors are the same solution (angles modulo 2 pi)

# ---------------------------------------------------------------------------------------------
# Hand-written robots: modified DH, base and tool transforms, offsets, negative lengths
# ---------------------------------------------------------------------------------------------

# Craig's PUMA 560 table (Introduction to Robotics, 3rd ed., Fig. 3.21), modified DH.
CRAIG_PUMA = """
name = "craig_puma"
convention = "modified"
angles = "deg"
[parameters]
a2 = 0.4318
a3 = 0.0203
d3 = 0.15005
d4 = 0.4318
[[joints]]
type = "revolute"
[[joints]]
type = "revolute"
alpha = -90
[[joints]]
type = "revolute"
a = "a2"
d = "d3"
[[joints]]
type = "revolute"
a = "a3"
d = "d4"
alpha = -90
[[joints]]
type = "revolute"
alpha = 90
[[joints]]
type = "revolute"
alpha = -90
[base]
xyz = [0.1, -0.2, 0.6]
rpy = [0, 0, 90]
[tool]
xyz = [0.01, 0.02, 0.15]
rpy = [0, 90, 0]
"""

# Articulated arm with a1, a shoulder offset d2, negative a3 and d4, joint offsets and a tool
# whose twist and offset a6 must be taken off the target.
KUKA_LIKE = """
name = "kuka_like"
angles = "deg"
[parameters]
d1 = 0.4
a1 = 0.025
a2 = 0.455
[[joints]]
type = "revolute"
d = "d1"
a = "a1"
alpha = -90
[[joints]]
type = "revolute"
theta = -90
d = 0.05
a = "a2"
[[joints]]
type = "revolute"
a = -0.035
alpha = 90
[[joints]]
type = "revolute"
d = -0.42
alpha = -90
[[joints]]
type = "revolute"
theta = 30
alpha = 90
[[joints]]
type = "revolute"
d = 0.08
a = 0.02
alpha = 90
[tool]
xyz = [0.0, 0.03, 0.1]
rpy = [90, 0, 0]
"""

# The UR5 in modified DH, mounted upside down, with a tool.
UR_MODIFIED = """
name = "ur_modified"
convention = "modified"
angles = "deg"
[parameters]
d1 = 0.089159
a2 = -0.425
a3 = -0.39225
d4 = 0.10915
d5 = 0.09465
d6 = 0.0823
[[joints]]
type = "revolute"
d = "d1"
[[joints]]
type = "revolute"
alpha = 90
[[joints]]
type = "revolute"
a = "a2"
[[joints]]
type = "revolute"
a = "a3"
d = "d4"
[[joints]]
type = "revolute"
d = "d5"
alpha = 90
[[joints]]
type = "revolute"
d = "d6"
alpha = -90
[base]
xyz = [0.0, 0.0, 0.5]
rpy = [180, 0, 0]
[tool]
xyz = [0.0, 0.0, 0.12]
rpy = [0, 0, 45]
"""

# Planar 3R with a prismatic joint (and a constant 45 deg turn) between joints 1 and 2,
# offsets, a base that stands the plane upright and a tool offset in and out of the plane.
PLANAR_MIXED = """
name = "planar_mixed"
angles = "deg"
[[joints]]
type = "revolute"
theta = 30
d = 0.1
a = 0.5
[[joints]]
type = "prismatic"
theta = 45
a = 0.1
[[joints]]
type = "revolute"
a = 0.4
[[joints]]
type = "revolute"
d = 0.05
a = 0.3
[base]
xyz = [0.2, -0.1, 0.3]
rpy = [90, 0, 0]
[tool]
xyz = [0.1, 0.05, 0.02]
rpy = [90, 0, 30]
"""

HAND = {
    "craig_puma": (
        CRAIG_PUMA,
        frame([0.1, -0.2, 0.6], [0, 0, 90 * DEG]),
        frame([0.01, 0.02, 0.15], [0, 90 * DEG, 0]),
    ),
    "kuka_like": (KUKA_LIKE, np.eye(4), frame([0.0, 0.03, 0.1], [90 * DEG, 0, 0])),
    "ur_modified": (
        UR_MODIFIED,
        frame([0.0, 0.0, 0.5], [180 * DEG, 0, 0]),
        frame([0.0, 0.0, 0.12], [0, 0, 45 * DEG]),
    ),
    "planar_mixed": (
        PLANAR_MIXED,
        frame([0.2, -0.1, 0.3], [90 * DEG, 0, 0]),
        frame([0.1, 0.05, 0.02], [90 * DEG, 0, 30 * DEG]),
    ),
}

# Target components each planar arm uses (docstring of closed_form_ik); the rest use the pose.
TASKS = {
    "planar_2r": "xy",
    "scara": "xyz",
    "planar_3r": "xy+heading",
    "planar_mixed": "xyz+heading",
}

# Number of solutions at a generic reachable pose, typed in from the geometry: 2 elbows;
# 2 shoulders x 2 elbows (or reaches) x 2 wrists; 2 reaches x 2 wrists for the cylindrical arm.
# UR-type arms and arms with a1 != 0 have 8 or fewer (the other shoulder moves the elbow's
# target, which can leave the elbow's reach): their count is checked by the multi-start solve.
SOLUTION_COUNT = {
    "planar_2r": 2,
    "scara": 2,
    "planar_3r": 2,
    "planar_mixed": 2,
    "puma560": 8,
    "craig_puma": 8,
    "stanford": 8,
    "cylindrical_rtt_wrist": 4,
}
CLOSED = (*SOLUTION_COUNT, "kuka_like", "ur5", "ur_modified")


@cache
def robot(name: str) -> Robot:
    return robot_from_toml(HAND[name][0], f"{name}.toml") if name in HAND else load_robot(name)


@cache
def model(name: str) -> Model:
    return derive(robot(name))


@cache
def reference(name: str) -> NumericRobot:
    if name in HAND:
        return NumericRobot.from_robot(robot(name), base=HAND[name][1], tool=HAND[name][2])
    return NumericRobot.from_robot(robot(name))


def revolute(name: str) -> np.ndarray:
    return np.array([j.type == "revolute" for j in robot(name).joints])


def random_q(name: str, rng: np.random.Generator) -> np.ndarray:
    """Inside the joint limits; revolute joints without limits in (-pi, pi), prismatic ones
    without limits in (0.2, 1)."""
    values = []
    for joint in robot(name).joints:
        default = (-math.pi, math.pi) if joint.type == "revolute" else (0.2, 1.0)
        low, high = joint.limits or default
        values.append(rng.uniform(low, high))
    return np.array(values)


def joint_distance(name: str, q: np.ndarray, other: np.ndarray) -> float:
    difference = np.asarray(q) - np.asarray(other)
    return float(np.abs(np.where(revolute(name), wrap(difference), difference)).max())


def task_values(name: str, pose: np.ndarray) -> np.ndarray:
    """The target components the robot's solver is asked to meet, from a tool pose."""
    task = TASKS.get(name, "pose")
    if task == "pose":
        return pose[:3, :].ravel()
    ref = reference(name)
    local = np.linalg.inv(ref.base) @ pose
    values = list(local[: 3 if "z" in task else 2, 3])
    if "heading" in task:
        last = local @ np.linalg.inv(ref.tool)  # the last joint frame
        values.append(math.atan2(last[1, 0], last[0, 0]))
    return np.array(values)


def task_error(name: str, pose: np.ndarray, target: np.ndarray) -> float:
    difference = task_values(name, pose) - task_values(name, target)
    if "heading" in TASKS.get(name, ""):
        difference[-1] = wrap(difference[-1])
    return float(np.abs(difference).max())


def solve(name: str, target: np.ndarray, **kwargs: object) -> tuple[ClosedFormSolution, ...]:
    return closed_form_ik(model(name), target, **kwargs)


def assert_reaches(name: str, solutions: tuple[ClosedFormSolution, ...], target: np.ndarray):
    for solution in solutions:
        assert task_error(name, reference(name).fk(solution.q), target) <= TOL, solution


def multistart(name: str, target: np.ndarray, seeds: int, rng: np.random.Generator) -> list:
    """Distinct solutions found by Levenberg-Marquardt from random seeds (q unbounded)."""
    ref, n = reference(name), robot(name).dof
    wanted = task_values(name, target)

    def residual(q: np.ndarray) -> np.ndarray:
        difference = task_values(name, ref.fk(q)) - wanted
        if "heading" in TASKS.get(name, ""):
            difference[-1] = wrap(difference[-1])
        return difference

    found: list[np.ndarray] = []
    for _ in range(seeds):
        seed = np.where(revolute(name), rng.uniform(-np.pi, np.pi, n), rng.uniform(-1.5, 1.5, n))
        fit = least_squares(residual, seed, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
        converged = np.abs(fit.fun).max() < 1e-10
        if converged and all(joint_distance(name, fit.x, q) > 1e-6 for q in found):
            found.append(fit.x)
    return found


# ---------------------------------------------------------------------------------------------
# Structure is recognised from the DH table
# ---------------------------------------------------------------------------------------------

FAMILIES = {
    "planar_2r": "planar 2R",
    "scara": "planar 2R + prismatic z",
    "planar_3r": "planar 3R",
    "planar_mixed": "planar 3R + prismatic z",
    "puma560": "spherical wrist, articulated RRR arm",
    "craig_puma": "spherical wrist, articulated RRR arm",
    "kuka_like": "spherical wrist, articulated RRR arm",
    "stanford": "spherical wrist, spherical RRP arm",
    "cylindrical_rtt_wrist": "spherical wrist, cylindrical RPP arm",
    "ur5": "three parallel axes (UR type)",
    "ur_modified": "three parallel axes (UR type)",
    "panda": None,
    "rpr": None,
}


@pytest.mark.parametrize("name", FAMILIES)
def test_family_is_recognised_from_the_table(name: str) -> None:
    assert closed_form_family(robot(name)) == FAMILIES[name]
    assert has_closed_form(robot(name)) == (FAMILIES[name] is not None)


def test_recognition_follows_the_table_not_the_name() -> None:
    # The PUMA with a wrist offset a5 != 0 has no spherical wrist any more.
    text = CRAIG_PUMA.replace("alpha = -90\n[base]", "alpha = -90\na = 0.05\n[base]")
    text = text.replace('name = "craig_puma"', 'name = "puma560"')
    assert not has_closed_form(robot_from_toml(text, "puma560.toml"))
    # A SCARA whose second axis is tilted is no longer planar.
    scara = load_robot("scara")
    tilted = replace(scara.joints[0], alpha=0.3)
    assert not has_closed_form(replace(scara, joints=(tilted, *scara.joints[1:])))


@pytest.mark.parametrize("name", ["panda", "rpr"])
def test_robot_without_closed_form_points_to_the_numeric_solver(name: str) -> None:
    with pytest.raises(SymkinError, match=rf"^{name}: no closed-form .* use the numeric solver"):
        solve(name, np.eye(4))


# ---------------------------------------------------------------------------------------------
# Every solution reaches the target; the pose it came from is among them; how many
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", CLOSED)
def test_solutions_reach_the_target_and_include_the_original_pose(name: str) -> None:
    rng = np.random.default_rng(11)
    for _ in range(12):
        q = random_q(name, rng)
        target = reference(name).fk(q)
        solutions = solve(name, target)
        assert_reaches(name, solutions, target)
        assert min(joint_distance(name, s.q, q) for s in solutions) <= SAME_Q
        if name in SOLUTION_COUNT:
            assert len(solutions) == SOLUTION_COUNT[name]
        else:
            assert 2 <= len(solutions) <= 8
        for solution in solutions:
            angles = solution.q[revolute(name)]
            limits = [j.limits for j in robot(name).joints if j.type == "revolute"]
            for angle, limit in zip(angles, limits, strict=True):
                in_range = -math.pi < angle <= math.pi
                assert in_range or (limit is not None and limit[0] <= angle <= limit[1])


@pytest.mark.slow
@pytest.mark.parametrize("name", CLOSED)
def test_a_multistart_numeric_solve_finds_no_other_branch(name: str) -> None:
    rng = np.random.default_rng(5)
    for _ in range(2):
        target = reference(name).fk(random_q(name, rng))
        ours = solve(name, target)
        found = multistart(name, target, seeds=24, rng=rng)
        for q in found:
            assert min(joint_distance(name, s.q, q) for s in ours) <= 1e-6, q
        # Not vacuous: the seeds reach most of the branches.
        assert len(found) >= len(ours) / 2


# ---------------------------------------------------------------------------------------------
# PUMA 560 against Robotics Toolbox's analytic solution (q and branch names)
# ---------------------------------------------------------------------------------------------

LETTERS = {"l": "left", "r": "right", "u": "up", "d": "down", "n": "no_flip", "f": "flip"}


@pytest.mark.oracle
def test_puma_matches_robotics_toolbox_for_every_configuration() -> None:
    import roboticstoolbox as rtb  # here, not at the top: the quick tier skips this oracle

    puma = rtb.models.DH.Puma560()  # same table plus a pedestal d1 (see puma560.toml)
    pedestal = np.eye(4)
    pedestal[2, 3] = puma.links[0].d
    rng = np.random.default_rng(2)
    for _ in range(5):
        target = reference("puma560").fk(rng.uniform(-np.pi, np.pi, 6))
        solutions = solve("puma560", target)
        assert len(solutions) == 8
        for config in ("lun", "luf", "ldn", "ldf", "run", "ruf", "rdn", "rdf"):
            theirs = puma.ikine_a(pedestal @ target, config=config)
            assert theirs.success
            flags = dict(zip(("shoulder", "elbow", "wrist"), map(LETTERS.get, config), strict=True))
            (match,) = [s for s in solutions if dict(s.branch) == flags]
            assert joint_distance("puma560", match.q, theirs.q) <= SAME_Q, config


# ---------------------------------------------------------------------------------------------
# Singular and boundary cases
# ---------------------------------------------------------------------------------------------


def test_puma_wrist_singularity_is_flagged_with_q4_zero() -> None:
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.0, -0.2])
    target = reference("puma560").fk(q)
    solutions = solve("puma560", target)
    assert_reaches("puma560", solutions, target)
    # Singular only for the arm branch the pose came from: the other three arm branches hold
    # the wrist centre with other link-3 orientations, so their wrists bend (2 solutions each).
    assert len(solutions) == 1 + 3 * 2
    (singular,) = [s for s in solutions if s.branch["wrist"] == "singular"]
    np.testing.assert_allclose(singular.q[:3], q[:3], atol=SAME_Q)
    assert singular.q[3] == 0.0 and abs(singular.q[4]) <= SAME_Q
    # Only q4 + q6 is defined at q5 = 0 (alpha_4 = -alpha_5: the wrist is Rz(q4 + q6)).
    assert abs(wrap(singular.q[5] - (q[3] + q[5]))) <= SAME_Q


def test_ur5_wrist_singularity_is_flagged_with_q6_zero() -> None:
    q = np.array([0.3, -1.1, 1.2, -0.4, 0.0, 0.8])
    target = reference("ur5").fk(q)
    solutions = solve("ur5", target)
    assert_reaches("ur5", solutions, target)
    # Axis 6 is parallel to axes 2, 3, 4 only for the waist angle the pose came from.
    singular = [s for s in solutions if s.branch["wrist"] == "singular"]
    assert len(singular) == 2  # two elbows
    for s in singular:
        assert abs(wrap(s.q[0] - q[0])) <= SAME_Q and abs(s.q[4]) <= SAME_Q and s.q[5] == 0.0
    assert all(abs(wrap(s.q[0] - q[0])) > 0.1 for s in solutions if s not in singular)


@pytest.mark.parametrize("name", ["puma560", "kuka_like", "stanford", "ur5"])
def test_near_the_wrist_singularity_both_wrist_branches_reach(name: str) -> None:
    q = random_q(name, np.random.default_rng(4))
    q[4] = 1e-7 - robot(name).joints[4].theta  # DH angle theta_5 = 1e-7 rad
    target = reference(name).fk(q)
    solutions = solve(name, target)
    assert_reaches(name, solutions, target)
    assert min(joint_distance(name, s.q, q) for s in solutions) <= 1e-6
    assert {s.branch["wrist"] for s in solutions} == {"flip", "no_flip"}


def test_unreachable_targets_give_no_solution() -> None:
    far = np.eye(4)
    far[:3, 3] = [3.0, 1.0, 0.5]
    for name in ("planar_2r", "planar_3r", "scara", "puma560", "kuka_like", "ur5"):
        assert solve(name, far) == (), name
    # PUMA: the wrist centre on the waist axis is closer to it than the shoulder offset d3.
    on_axis = np.eye(4)
    on_axis[:3, 3] = [0.0, 0.0, 0.3]
    assert solve("puma560", on_axis) == ()


@settings(deadline=None, max_examples=60, derandomize=True)
@given(
    radius=st.floats(1e-3, 2.5, allow_nan=False),
    angle=st.floats(-math.pi, math.pi, allow_nan=False),
)
def test_planar_2r_reach_is_the_disc_of_radius_l1_plus_l2(radius: float, angle: float) -> None:
    # L1 = L2 = 1: every point with |p| <= 2 is reached, two elbows unless fully stretched.
    target = np.eye(4)
    target[:2, 3] = radius * math.cos(angle), radius * math.sin(angle)
    solutions = solve("planar_2r", target)
    assert_reaches("planar_2r", solutions, target)
    if radius > 2.0 + 1e-9:
        assert solutions == ()
    elif radius < 2.0 - 1e-6:
        assert len(solutions) == 2


def test_fully_stretched_planar_2r_has_one_solution() -> None:
    target = reference("planar_2r").fk([0.7, 0.0])
    (solution,) = solve("planar_2r", target)
    np.testing.assert_allclose(solution.q, [0.7, 0.0], atol=1e-7)


def test_planar_elbow_up_means_the_elbow_is_left_of_the_line_to_the_hand() -> None:
    ref = reference("planar_2r")
    for q2 in (-2.0, -0.5, 0.5, 2.0):
        q = np.array([0.4, q2])
        target = ref.fk(q)
        solutions = solve("planar_2r", target)
        (solution,) = [s for s in solutions if joint_distance("planar_2r", s.q, q) < SAME_Q]
        elbow, hand = ref.frames(q)[1][:2, 3], target[:2, 3]
        left = hand[0] * elbow[1] - hand[1] * elbow[0] > 0
        assert solution.branch["elbow"] == ("up" if left else "down")


# ---------------------------------------------------------------------------------------------
# Joint limits, parameters, the result type, bad input
# ---------------------------------------------------------------------------------------------


def test_solutions_outside_the_limits_are_returned_and_flagged() -> None:
    for name in ("stanford", "puma560"):
        low = np.array([j.limits[0] for j in robot(name).joints])
        high = np.array([j.limits[1] for j in robot(name).joints])
        rng = np.random.default_rng(8)
        for _ in range(5):
            q = random_q(name, rng)
            solutions = solve(name, reference(name).fk(q))
            for s in solutions:
                assert s.within_limits == bool(np.all((low - 1e-9 <= s.q) & (s.q <= high + 1e-9)))
            (original,) = [s for s in solutions if joint_distance(name, s.q, q) <= SAME_Q]
            assert original.within_limits
    # Stanford: the backward reach is a negative prismatic extension, never within limits.
    target = reference("stanford").fk(random_q("stanford", rng))
    backward = [s for s in solve("stanford", target) if s.branch["extension"] == "backward"]
    assert len(backward) == 4 and all(s.q[2] < 0 and not s.within_limits for s in backward)


def test_cylindrical_arm_extension_is_the_sign_of_the_radial_slide() -> None:
    # Spong's cylindrical arm: q3 is the radial reach from the column, q2 the height.
    q = np.array([0.7, 0.4, 0.6, 0.3, -0.9, 1.1])
    target = reference("cylindrical_rtt_wrist").fk(q)
    for s in solve("cylindrical_rtt_wrist", target):
        assert s.branch["extension"] == ("forward" if s.q[2] > 0 else "backward")
        assert s.q[1] == pytest.approx(0.4, abs=SAME_Q)
        assert abs(s.q[2]) == pytest.approx(0.6, abs=SAME_Q)


def test_puma_shoulder_beyond_pi_is_given_inside_its_limits() -> None:
    q = np.array([0.2, 200 * DEG, -0.8, 0.3, 0.6, -0.4])  # shoulder limits -45 .. 225 deg
    (original,) = [
        s
        for s in solve("puma560", reference("puma560").fk(q))
        if joint_distance("puma560", s.q, q) <= SAME_Q
    ]
    assert original.q[1] == pytest.approx(200 * DEG, abs=SAME_Q)
    assert original.within_limits


def test_parameter_overrides_are_used() -> None:
    overrides = {"a3": 0.05, "d3": 0.1}
    ref = NumericRobot.from_robot(robot("puma560"), overrides)
    q = np.array([0.5, 0.1, -0.3, 1.0, 0.8, -2.0])
    solutions = solve("puma560", ref.fk(q), overrides=overrides)
    assert len(solutions) == 8
    for s in solutions:
        np.testing.assert_allclose(ref.fk(s.q), ref.fk(q), atol=TOL)


def test_a_parameter_without_value_needs_one_for_numbers() -> None:
    text = 'name = "two_link"\n[parameters]\nL1 = 1.0\nL2 = "symbol"\n'
    text += '[[joints]]\ntype = "revolute"\na = "L1"\n[[joints]]\ntype = "revolute"\na = "L2"\n'
    two_link = robot_from_toml(text, "two_link.toml")
    assert has_closed_form(two_link)  # structure: a parameter without value is generic
    target = np.eye(4)
    target[:2, 3] = [1.2, 0.3]
    with pytest.raises(SymkinError, match="L2"):
        closed_form_ik(derive(two_link), target)
    solutions = closed_form_ik(derive(two_link), target, {"L2": 0.5})
    ref = NumericRobot.from_robot(two_link, {"L2": 0.5})
    assert len(solutions) == 2
    for s in solutions:
        np.testing.assert_allclose(ref.fk(s.q)[:2, 3], [1.2, 0.3], atol=TOL)


def test_solution_is_read_only() -> None:
    (solution, *_) = solve("puma560", reference("puma560").fk(np.full(6, 0.3)))
    with pytest.raises(ValueError):
        solution.q[0] = 1.0
    with pytest.raises(TypeError):
        solution.branch["elbow"] = "down"  # type: ignore[index]
    assert set(solution.branch) == {"shoulder", "elbow", "wrist"}


@pytest.mark.parametrize("name", ["craig_puma", "planar_mixed", "stanford"])
def test_batched_forward_kinematics_matches_numeric_dh(name: str) -> None:
    qs = np.array([random_q(name, np.random.default_rng(k)) for k in range(5)])
    reached = batched_forward_kinematics(model(name))(qs)
    for q, pose in zip(qs, reached, strict=True):
        np.testing.assert_allclose(pose, reference(name).fk(q), atol=1e-12)


BAD_TARGETS: dict[str, Callable[[], np.ndarray]] = {
    "shape": lambda: np.eye(3),
    "nan": lambda: np.full((4, 4), np.nan),
    "not a rotation": lambda: np.diag([2.0, 1.0, 1.0, 1.0]),
    "reflection": lambda: np.diag([-1.0, 1.0, 1.0, 1.0]),
    "last row": lambda: np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]),
}


@pytest.mark.parametrize("case", BAD_TARGETS)
def test_bad_target_is_one_clear_error(case: str) -> None:
    with pytest.raises(SymkinError, match="target must be a 4x4 homogeneous transform"):
        solve("puma560", BAD_TARGETS[case]())

"""Accuracy control, the open problem and the inverse-dynamics transcription of
``symkin.solve.trajopt``, checked against dynamics and geometry that do not come from symkin.

* The default 2R swing (``--from 0,0 --to 90deg,0 --time 2``) is refined until every interval,
  integrated from its node under its torque on Spong's closed-form equations of motion (typed
  in tests/test_trajopt.py), lands on the next node within the tolerance; the last two
  refinements' costs agree.
* An obstacle: the links, re-simulated on Spong's equations and sampled densely between the
  nodes, never enter the sphere inflated by the links' capsule radius (positions by hand:
  elbow ``l (c1, s1)``, tool ``+ l (c12, s12)``).
* Waypoints (joint at a fixed time, tool at a free time) are met.
* The inverse-dynamics transcription's torque, resampled, drives Spong's equations through
  every node.
* Small pure functions (mesh refinement, segment distance, problem checks) without a solver.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import symkin
from symkin.cli import main
from symkin.errors import SymkinError
from symkin.solve.trajopt import (
    Obstacle,
    TrajectoryProblem,
    Waypoint,
    optimal_trajectory,
    robot_functions,
)
from symkin.solve.trajopt.accuracy import Accuracy, refined_mesh, segment_distance
from symkin.solve.trajopt.extras import add_torque_rate_cost
from symkin.solve.trajopt.resample import resampled
from test_trajopt import ARM, LENGTH, resimulate, two_link_acceleration

DEG = math.pi / 180
TOLERANCE = 1e-4


@pytest.fixture(scope="module")
def arm() -> symkin.Model:
    return symkin.derive(symkin.load_robot(ARM))


def swing(**changes) -> TrajectoryProblem:
    """The default command's problem: from (0, 0) to (90 deg, 0) in 2 s, minimum effort."""
    settings = {"start": (0.0, 0.0), "goal": (90 * DEG, 0.0), "final_time": 2.0}
    return TrajectoryProblem(**(settings | changes))


def local_defect(trajectory) -> float:
    """Largest distance from node k+1 of interval k integrated from node k (Spong's 2R)."""
    nodes = np.hstack([trajectory.q, trajectory.dq])
    return float(np.abs(resimulate(trajectory, two_link_acceleration, True) - nodes).max())


def links(q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The two links as segments in the x-y plane (origin-elbow, elbow-tool), by hand."""
    elbow = LENGTH * np.array([math.cos(q[0]), math.sin(q[0]), 0.0])
    tool = elbow + LENGTH * np.array([math.cos(q[0] + q[1]), math.sin(q[0] + q[1]), 0.0])
    return [(np.zeros(3), elbow), (elbow, tool)]


def distance_to_segment(c: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """By projection (written here, not symkin's): the nearest point of a-b to c."""
    t = min(max(np.dot(c - a, b - a) / np.dot(b - a, b - a), 0.0), 1.0)
    return float(np.linalg.norm(a + t * (b - a) - c))


# ---------------------------------------------------------------- solves (slow)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["multiple-shooting", "collocation"])
def test_default_swing_is_consistent_to_the_tolerance(arm, method) -> None:
    trajectory = optimal_trajectory(arm, swing(method=method))
    assert trajectory.consistent
    assert len(trajectory.rounds) > 1  # 40 uniform intervals were not enough (9.5e-3, 5e-2)
    assert trajectory.rounds[0].max_defect > TOLERANCE
    assert local_defect(trajectory) < TOLERANCE
    # the refined mesh's cost has converged: refined ten times tighter, it moves by < 0.1 %
    # (on 40 uniform intervals it was 0.6 % off)
    tighter = optimal_trajectory(arm, swing(method=method, tolerance=TOLERANCE / 10))
    assert tighter.consistent and len(tighter.t) > len(trajectory.t)
    assert trajectory.cost == pytest.approx(tighter.cost, rel=1e-3)
    assert trajectory.rounds[0].cost != pytest.approx(tighter.cost, rel=3e-3)


@pytest.mark.slow
def test_obstacle_is_never_entered_along_the_resimulated_path(arm) -> None:
    obstacle = Obstacle((0.55, 0.55, 0.0), 0.15)
    problem = swing(obstacles=(obstacle,), torque_limits=(30.0, 30.0))
    trajectory = optimal_trajectory(arm, problem)
    assert trajectory.consistent
    reach = obstacle.radius + problem.clearance
    nodes = np.hstack([trajectory.q, trajectory.dq])
    closest = math.inf
    for k, tau in enumerate(trajectory.tau):
        solution = solve_ivp(
            lambda _, x, tau=tau: np.concatenate([x[2:], two_link_acceleration(x[:2], x[2:], tau)]),
            (trajectory.t[k], trajectory.t[k + 1]),
            nodes[k],
            method="DOP853",
            rtol=1e-10,
            atol=1e-10,
            dense_output=True,
        )
        for x in solution.sol(np.linspace(trajectory.t[k], trajectory.t[k + 1], 40)).T:
            for a, b in links(x[:2]):
                closest = min(closest, distance_to_segment(np.array(obstacle.centre), a, b))
    assert closest >= reach - 1e-9
    # ... and the obstacle mattered: the straight swing of the stretched arm passes through it
    straight = [
        distance_to_segment(np.array(obstacle.centre), *links([s, 0.0])[1])
        for s in np.linspace(0, 90 * DEG, 91)
    ]
    assert min(straight) < obstacle.radius


@pytest.mark.slow
def test_waypoints_are_met(arm) -> None:
    via = Waypoint(q=(45 * DEG, -60 * DEG), time=0.8)
    tool = Waypoint(position=(0.2, 0.6, 0.0))  # free time
    problem = swing(waypoints=(via, tool), max_refinements=2)
    trajectory = optimal_trajectory(arm, problem)
    k = int(np.argmin(np.abs(trajectory.t - 0.8)))
    assert trajectory.t[k] == pytest.approx(0.8, abs=1e-9)
    assert trajectory.q[k] == pytest.approx(via.q, abs=1e-6)
    tips = np.array([links(q)[1][1] for q in trajectory.q])
    assert np.linalg.norm(tips - tool.position, axis=1).min() < 1e-6
    j = int(np.argmin(np.linalg.norm(tips - tool.position, axis=1)))
    assert 0.8 < trajectory.t[j] < 2.0


@pytest.mark.slow
def test_inverse_dynamics_torques_drive_the_independent_model(arm) -> None:
    """The resampled feedforward torque at 2 kHz, held between samples, on Spong's
    equations from each node: lands on the next node to the sample-and-hold error."""
    trajectory = optimal_trajectory(arm, swing(method="inverse-dynamics"))
    assert trajectory.accuracy.max_defect < 1e-8  # exact quadratics, the integrator's error
    functions = robot_functions(arm)
    samples = resampled(trajectory, functions, rate=2000.0)
    # the resampled torque is the closed-form inverse dynamics along the quadratic
    ddq = np.array(
        [
            two_link_acceleration(q, dq, tau)
            for q, dq, tau in zip(samples["q"], samples["dq"], samples["tau"], strict=True)
        ]
    )
    assert np.abs(ddq - samples["ddq"]).max() < 1e-8
    k = np.clip(np.searchsorted(trajectory.t, samples["t"], side="right") - 1, 0, 39)
    assert np.abs(ddq - trajectory.ddq[k]).max() < 1e-6


@pytest.mark.slow
def test_custom_cost_through_the_open_problem(arm) -> None:
    """A torque-rate cost added from Python on every round smooths the torques."""
    plain = optimal_trajectory(arm, swing(tolerance=None, intervals=30))
    smooth = optimal_trajectory(
        arm, swing(tolerance=None, intervals=30), customise=lambda p: add_torque_rate_cost(p, 1.0)
    )
    rate = lambda t: np.abs(np.diff(t.tau, axis=0)).sum()  # noqa: E731
    assert rate(smooth) < 0.5 * rate(plain)
    assert smooth.effort > plain.effort  # the price: more effort than the least


# ---------------------------------------------------------------- pure functions (quick)


def test_refined_mesh_splits_only_the_faulty_intervals() -> None:
    mesh = np.linspace(0, 1, 5)
    report = Accuracy(np.array([1e-6, 3.2e-3, 1e-6, 1e-4 * 1.01]), 0.0)
    refined = refined_mesh(mesh, report, 1e-4)
    # 3.2e-3 / 1e-4 = 32 = 2^5: two parts would do, 1.2 * 2 -> three; 1.01: two parts
    assert refined == pytest.approx([0, 0.25, 1 / 3, 5 / 12, 0.5, 0.75, 0.875, 1.0])


def test_segment_distance_by_hand() -> None:
    a, b = np.array([0.0, 0, 0]), np.array([1.0, 0, 0])
    assert segment_distance(np.array([0.5, 2.0, 0]), a, b) == pytest.approx(2.0)
    assert segment_distance(np.array([-3.0, 4.0, 0]), a, b) == pytest.approx(5.0)
    assert segment_distance(np.array([1.0, 0, 0]), a, a) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"mesh": (0.0, 0.5, 1.0)}, "the mesh must hold 41"),
        ({"tolerance": 0.0}, "the tolerance must be positive"),
        ({"max_refinements": -1}, "max_refinements must be 0 or more"),
    ],
)
def test_bad_accuracy_settings_are_refused(arm, changes, message) -> None:
    from symkin.solve.trajopt import check_problem

    with pytest.raises(SymkinError, match=message):
        check_problem(arm, swing(**changes))


def test_waypoint_and_obstacle_need_their_data() -> None:
    with pytest.raises(SymkinError, match="joint values q or a tool position"):
        Waypoint()
    with pytest.raises(SymkinError, match="positive radius"):
        Obstacle((0, 0, 0), 0.0)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--obstacle", "1,2,3"], "--obstacle: expected X,Y,Z,R"),
        (["--via-tool", "1,2"], "--via-tool: expected x,y,z"),
        (["--rate", "100"], "--rate needs --out DIR"),
        (["--transcription", "inverse", "--method", "collocation"], "--method chooses"),
    ],
)
def test_cli_bad_trajopt_options_are_one_line(capsys, argv, message) -> None:
    base = ["trajopt", str(ARM), "--from", "0,0", "--to", "90deg,0", "--time", "2"]
    assert main([*base, *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


# ---------------------------------------------------------------- warm starts


def test_tool_positions_enter_the_first_guess_by_closed_form_ik(arm) -> None:
    """The 2R arm has a closed form: the goal's corner puts the tool at the Cartesian goal (by
    hand: l (c1 + c12, s1 + s12)) and is the elbow solution nearer the corner before it."""
    from symkin.solve.trajopt.initial_guess import polyline_knots

    problem = TrajectoryProblem(
        start=(0.0, 0.0),
        cartesian_goal=(0.3, 0.6, 0.0),
        final_time=2.0,
        waypoints=(Waypoint(position=(0.2, -0.6, 0.0)),),
    )
    knots = polyline_knots(arm, problem, [0.5])
    assert [fraction for fraction, _ in knots] == [0.0, 0.5, 1.0]
    for (_, q), target in zip(knots[1:], [(0.2, -0.6), (0.3, 0.6)], strict=True):
        assert links(q)[1][1][:2] == pytest.approx(target, abs=1e-9)
    # the other elbow: q2 -> -q2, q1 -> q1 + 2 atan2(l2 s2, l1 + l2 c2) (same tool point)
    before, (q1, q2) = knots[1][1], knots[2][1]
    flipped = np.array([q1 + 2 * math.atan2(math.sin(q2), 1 + math.cos(q2)), -q2])
    assert links(flipped)[1][1][:2] == pytest.approx((0.3, 0.6), abs=1e-9)
    assert np.linalg.norm(knots[2][1] - before) < np.linalg.norm(flipped - before)


@pytest.mark.slow
def test_warm_start_from_an_earlier_solution_saves_iterations(arm) -> None:
    """A nearby problem (goal 0.1 rad further, 0.1 s longer) from the earlier solution: the
    same optimum in fewer IPOPT iterations (measured: 11 against 25 on the first mesh)."""
    base = {"start": (-90 * DEG, 0.0), "torque_limits": (20.0, 10.0)}
    earlier = optimal_trajectory(
        arm, TrajectoryProblem(goal=(30 * DEG, 45 * DEG), final_time=1.5, **base)
    )
    nearby = TrajectoryProblem(goal=(30 * DEG + 0.1, 45 * DEG), final_time=1.6, **base)
    cold = optimal_trajectory(arm, nearby)
    warm = optimal_trajectory(arm, nearby, initial=earlier)
    assert warm.cost == pytest.approx(cold.cost, rel=1e-6)
    assert warm.rounds[0].iterations < cold.rounds[0].iterations


# ---------------------------------------------------------------- PUMA 560


@pytest.mark.oracle
@pytest.mark.slow
def test_puma560_inverse_dynamics_torques_drive_robotics_toolbox() -> None:
    """The PUMA 560 transfer of docs/trajopt.md with the inverse-dynamics transcription: the
    feedforward torque of each interval (symkin's, varying along the interval), integrated
    from its node on Robotics Toolbox's ``accel`` (Corke's model without friction), lands on
    the next node within the tolerance; the torque limits hold at 5 samples per interval."""
    import roboticstoolbox as rtb

    from symkin.solve.trajopt.accuracy import control_function

    # Link 3's published inertia breaks the triangle inequality; the file's inertia_note says
    # so, and the loader does not warn.
    model = symkin.derive(symkin.load_robot("puma560"))
    puma = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    limits = np.array([100.0, 180, 90, 25, 20, 20])
    problem = TrajectoryProblem(
        start=np.radians([0, 90, -90, 0, 0, 0]),
        goal=np.radians([90, 45, -135, 45, 45, 90]),
        final_time=2.0,
        method="inverse-dynamics",
        torque_limits=limits,
        velocity_limits=(3.0,) * 6,
    )
    trajectory = optimal_trajectory(model, problem)
    assert trajectory.consistent
    control = control_function(trajectory, robot_functions(model))
    nodes = np.hstack([trajectory.q, trajectory.dq])
    worst = 0.0
    for k in range(len(trajectory.t) - 1):
        h = trajectory.t[k + 1] - trajectory.t[k]
        solution = solve_ivp(
            lambda s, x, k=k: np.concatenate([x[6:], puma.accel(x[:6], x[6:], control(k, s))]),
            (0.0, h),
            nodes[k],
            method="DOP853",
            rtol=1e-10,
            atol=1e-10,
        )
        worst = max(worst, float(np.abs(solution.y[:, -1] - nodes[k + 1]).max()))
        for s in np.linspace(0.0, h, 5):
            assert np.all(np.abs(control(k, s)) <= limits * (1 + 1e-3))
    assert worst < TOLERANCE


@pytest.mark.slow
def test_cli_json_and_resampled_output(capsys, tmp_path) -> None:
    """``--json`` prints the result with the re-simulation's verdict; ``--rate 100`` writes
    101 samples over 1 s whose torque is the held torque of each sample's interval."""
    import json

    out = tmp_path / "swing"
    argv = ["trajopt", str(ARM), "--from", "-90deg,0", "--to", "0,0", "--time", "1",
            "--intervals", "20", "--json", "--out", str(out), "--rate", "100"]  # fmt: skip
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["accuracy"]["consistent"] is True
    assert data["accuracy"]["max_defect"] < TOLERANCE
    assert len(data["rounds"]) == data["accuracy"]["refinements"] + 1
    table = np.loadtxt(out / "trajectory_resampled.csv", delimiter=",", skiprows=1)
    assert table.shape == (101, 9)
    np.testing.assert_allclose(table[:, 0], np.linspace(0, 1, 101), atol=1e-12)
    t, tau = np.array(data["t"]), np.array(data["tau"])
    k = np.clip(np.searchsorted(t, table[:, 0], side="right") - 1, 0, len(tau) - 1)
    np.testing.assert_allclose(table[:, 7:], tau[k], atol=1e-12)
    # the sampled accelerations are Spong's for the sampled state and torque
    spong = [two_link_acceleration(r[1:3], r[3:5], r[7:]) for r in table]
    np.testing.assert_allclose(table[:, 5:7], spong, atol=1e-8)
    samples = json.loads((out / "trajectory_resampled.json").read_text())
    np.testing.assert_allclose(samples["q"], table[:, 1:3], atol=0)

"""The first guess of ``symkin.solve.trajopt`` around obstacles (``solve/trajopt/detour.py``),
checked with geometry that does not come from symkin.

* The 2R swing from (0, 0) to (90 deg, 0) runs the stretched arm through a ball at
  (0.55, 0.55, 0): the straight joint-space line's links, placed by hand (elbow
  ``l (c1, s1)``, tool ``+ l (c12, s12)``), pass within the ball's radius.  The detoured guess,
  sampled densely along its polyline (linear interpolation written here) and at the nodes
  IPOPT starts from (``Opti.initial()``), keeps every link's capsule out of the ball, with
  distances by projection onto each segment (written here).
* The PUMA 560 likewise, its link segments from the numeric DH product of
  ``tests/numeric_dh.py`` (frame origins of ``base A_1 ... A_i`` and the tool).
* The solves then converge from the clear guess; from the straight line they converge too, but
  need more IPOPT iterations in the first round (counted, not timed).
* No clear path (a ball the shoulder link must pass through within its limits) or a start
  within the ball's reach: the straight polyline stays, with a note.
"""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest

import symkin
from numeric_dh import NumericRobot
from symkin.cli import main
from symkin.solve.trajopt import Obstacle, TrajectoryProblem, optimal_trajectory, robot_functions
from symkin.solve.trajopt.accuracy import configuration_clearance, origins_function
from symkin.solve.trajopt.detour import GUESS_MARGIN, clear_knots
from symkin.solve.trajopt.initial_guess import polyline_knots, set_initial_guess
from symkin.solve.trajopt.program import transcribed_program
from test_trajopt import ARM, LENGTH

DEG = math.pi / 180
BALL = Obstacle((0.55, 0.55, 0.0), 0.15)


@pytest.fixture(scope="module")
def arm() -> symkin.Model:
    return symkin.derive(symkin.load_robot(ARM))


def swing(**changes) -> TrajectoryProblem:
    settings = {
        "start": (0.0, 0.0),
        "goal": (90 * DEG, 0.0),
        "final_time": 2.0,
        "torque_limits": (30.0, 30.0),
        "obstacles": (BALL,),
    }
    return TrajectoryProblem(**(settings | changes))


def arm_points(q: np.ndarray) -> list[np.ndarray]:
    """Shoulder, elbow and tool of the 2R arm in the x-y plane, by hand."""
    elbow = LENGTH * np.array([math.cos(q[0]), math.sin(q[0]), 0.0])
    tool = elbow + LENGTH * np.array([math.cos(q[0] + q[1]), math.sin(q[0] + q[1]), 0.0])
    return [np.zeros(3), elbow, tool]


def distance_to_segment(c: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """By projection, the nearest point of a-b to c (a segment of length 0 is a point)."""
    length = float(np.dot(b - a, b - a))
    t = 0.0 if length == 0 else min(max(float(np.dot(c - a, b - a)) / length, 0.0), 1.0)
    return float(np.linalg.norm(a + t * (b - a) - c))


def closest(points_of, configurations, obstacle: Obstacle) -> float:
    """The smallest distance from the obstacle's centre to a link of any configuration."""
    centre = np.array(obstacle.centre)
    return min(
        distance_to_segment(centre, a, b)
        for q in configurations
        for a, b in zip(points_of(q)[:-1], points_of(q)[1:], strict=True)
    )


def dense(knots, per_piece: int = 400) -> list[np.ndarray]:
    """Configurations along the polyline through the knots, ``per_piece`` steps a piece."""
    q = [np.asarray(values, dtype=float) for _, values in knots]
    steps = np.linspace(0.0, 1.0, per_piece + 1)
    return [a + s * (b - a) for a, b in itertools.pairwise(q) for s in steps]


# ---------------------------------------------------------------- the guess, no solve


def test_clearance_of_several_configurations_at_once(arm) -> None:
    """The batched link points and clearances, one configuration per column, against the
    hand positions (their order once mixed configurations and links up)."""
    problem = swing()
    configurations = np.array([[0.0, 0.0], [90 * DEG, 0.0], [0.3, 0.5], [45 * DEG, -1.0]])
    origins = origins_function(robot_functions(arm))
    points = origins(configurations.T)  # m x (links+1) x 3: frames 0, 1, 2 and the tool
    for q, found in zip(configurations, points, strict=True):
        shoulder, elbow, tool = arm_points(q)
        np.testing.assert_allclose(found, [shoulder, elbow, tool, tool], atol=1e-12)
    values = configuration_clearance(origins, configurations.T, problem, margin=0.01)
    reach = BALL.radius + problem.clearance + 0.01
    expected = [closest(arm_points, [q], BALL) - reach for q in configurations]
    np.testing.assert_allclose(values, expected, atol=1e-12)


def test_the_detour_keeps_the_two_link_arm_out_of_the_ball(arm) -> None:
    problem = swing()
    functions = robot_functions(arm)
    line = polyline_knots(arm, problem, [])
    reach = BALL.radius + problem.clearance
    assert closest(arm_points, dense(line), BALL) < BALL.radius  # the line passes through it
    knots, report = clear_knots(functions, problem, line)
    assert report.clear and report.source == "detour" and report.vias == len(knots) - 2 >= 1
    np.testing.assert_array_equal(knots[0][1], problem.start)
    np.testing.assert_array_equal(knots[-1][1], problem.goal)
    fractions = [s for s, _ in knots]
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and np.all(np.diff(fractions) > 0)
    vias = np.array([q for _, q in knots[1:-1]])
    assert np.all(np.abs(vias) <= np.array([180, 150]) * DEG)  # the joint limits of the file
    assert closest(arm_points, dense(knots), BALL) >= reach + GUESS_MARGIN - 1e-3
    assert report.min_clearance == pytest.approx(
        closest(arm_points, dense(knots), BALL) - reach, abs=2e-3
    )


def test_ipopt_starts_from_the_detour_at_every_node(arm) -> None:
    """The nodes (and the shooting states) handed to ``Opti`` lie on the clear polyline."""
    problem = swing()
    functions = robot_functions(arm)
    program = transcribed_program(arm, problem, functions)
    knots, _ = clear_knots(functions, problem, polyline_knots(arm, problem, []))
    set_initial_guess(
        program.opti, problem, program.transcription, functions, 2.0, knots, earlier=None
    )
    nodes = np.array(program.opti.value(program.q, program.opti.initial())).T
    assert nodes.shape == (problem.intervals + 1, 2)
    assert closest(arm_points, nodes, BALL) >= BALL.radius + problem.clearance


def test_a_blocked_path_leaves_the_straight_line_with_a_note(arm) -> None:
    # the shoulder link (0.5 m) must sweep through 45 deg, where this ball sits on it, and the
    # shoulder's limits (+-180 deg) rule out going round the other way
    ball = Obstacle((0.35, 0.35, 0.0), 0.1)
    problem = swing(obstacles=(ball,))
    line = polyline_knots(arm, problem, [])
    knots, report = clear_knots(robot_functions(arm), problem, line)
    assert knots == line
    assert not report.clear and report.vias == 0 and report.source == "line"
    assert "no path clear of the obstacles" in report.note
    assert report.min_clearance < 0


def test_a_start_in_reach_of_the_ball_is_said(arm) -> None:
    ball = Obstacle((1.0, 0.1, 0.0), 0.1)  # 0.1 m from the stretched arm's tool
    problem = swing(obstacles=(ball,))
    assert closest(arm_points, [np.zeros(2)], ball) < ball.radius + problem.clearance
    knots, report = clear_knots(robot_functions(arm), problem, polyline_knots(arm, problem, []))
    assert len(knots) == 2 and not report.clear
    assert report.note.startswith("the start is within")


def test_a_single_knot_reports_its_own_clearance(arm) -> None:
    """One knot (no piece to sweep) is checked where it stands: a finite clearance, the hand
    distance to the ball less the reach, so the JSON report never holds an infinity."""
    problem = swing()
    knot = [(0.0, np.array([0.3, 0.5]))]
    knots, report = clear_knots(robot_functions(arm), problem, knot, search=False)
    reach = BALL.radius + problem.clearance
    expected = closest(arm_points, [knot[0][1]], BALL) - reach
    assert len(knots) == 1 and math.isfinite(report.min_clearance)
    assert report.min_clearance == pytest.approx(expected, abs=1e-12)
    json.dumps(report.min_clearance, allow_nan=False)


@pytest.mark.slow
def test_the_detour_keeps_the_puma560_out_of_the_ball() -> None:
    model = symkin.derive(symkin.load_robot("puma560"))
    numeric = NumericRobot.from_robot(model.robot)

    def points(q):
        frames = numeric.frames(q)
        return [frame[:3, 3] for frame in frames] + [numeric.fk(q)[:3, 3]]

    start = np.array([0, 90, -90, 0, 0, 0]) * DEG
    goal = np.array([90, 45, -135, 45, 45, 90]) * DEG
    middle = points((start + goal) / 2)
    ball = Obstacle(tuple((middle[3] + middle[4]) / 2), 0.1)  # on the forearm, half-way
    problem = TrajectoryProblem(
        start=tuple(start), goal=tuple(goal), final_time=2.0, obstacles=(ball,)
    )
    line = polyline_knots(model, problem, [])
    assert closest(points, dense(line, 100), ball) < ball.radius
    knots, report = clear_knots(robot_functions(model), problem, line)
    assert report.clear and report.vias >= 1
    assert closest(points, dense(knots, 200), ball) >= ball.radius + problem.clearance


# ---------------------------------------------------------------- solves


@pytest.mark.slow
@pytest.mark.parametrize("method", ["multiple-shooting", "collocation", "inverse-dynamics"])
def test_solves_from_the_clear_guess_converge_in_fewer_iterations(arm, method) -> None:
    detour = optimal_trajectory(arm, swing(method=method, max_refinements=2))
    line = optimal_trajectory(arm, swing(method=method, max_refinements=2, clear_guess=False))
    assert detour.guess.clear and detour.guess.source == "detour"
    assert line.guess.clear is False and line.guess.source == "line"
    assert detour.consistent and line.consistent
    assert detour.rounds[0].iterations < line.rounds[0].iterations
    assert detour.cost <= line.cost * (1 + 1e-3)
    nodes = detour.q
    assert closest(arm_points, nodes, BALL) >= BALL.radius + detour.problem.clearance - 1e-6


def swing_command(obstacle: str, refinements: int) -> list[str]:
    """``symkin trajopt`` arguments of the swing with one ``--obstacle X,Y,Z,R``."""
    return [
        "trajopt", str(ARM), "--from", "0,0", "--to", "90deg,0", "--time", "2",
        "--torque-limit", "30", "--obstacle", obstacle, "--max-refinements", str(refinements),
    ]  # fmt: skip


@pytest.mark.slow
def test_cli_reports_the_first_guess(capsys) -> None:
    argv = swing_command("0.55,0.55,0,0.15", refinements=1)
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "first guess: clear of the obstacles (" in out and "via configurations" in out
    assert main([*argv, "--json"]) == 0
    guess = json.loads(capsys.readouterr().out)["initial_guess"]
    assert guess["clear"] is True and guess["source"] == "detour" and guess["vias"] >= 1
    assert guess["min_clearance"] >= GUESS_MARGIN - 1e-9


@pytest.mark.slow
def test_cli_notes_when_no_clear_guess_is_found(capsys) -> None:
    # the blocked ball of the test above; on 40 nodes and no refinement the solver still
    # returns, its links sweeping through the ball between two nodes (the re-simulation says so)
    argv = swing_command("0.35,0.35,0,0.1", refinements=0)
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "symkin: first guess: no path clear of the obstacles found in" in captured.err
    assert "starting from the straight polyline" in captured.err
    assert "first guess: not clear of the obstacles (the straight line;" in captured.out
    assert "smallest obstacle clearance along the path: -" in captured.out

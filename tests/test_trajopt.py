"""Trajectory optimisation (``symkin.solve.trajopt``, ``symkin trajopt``) against oracles.

* **Re-simulation.** The optimal torques, held constant on each interval exactly as the
  transcriptions assume, are integrated with SciPy's ``solve_ivp`` (DOP853, rtol = atol = 1e-10)
  on dynamics written independently of symkin: the two-link arm's closed-form equations of
  motion (Spong, Hutchinson, Vidyasagar, Robot Modeling and Control, 2006, Ch. 7, planar elbow
  manipulator) typed in below, and Robotics Toolbox's ``Puma560().accel`` for the PUMA 560.
  The end state must be the goal at rest.
* **Limits and boundary conditions** at every node, straight from the returned arrays.
* **Minimum time** on the 2R arm: bang-bang torques, a final time below the effort run's, and
  a fixed-time problem slightly shorter than it is reported infeasible.
* **Both transcriptions** reach the same optimal cost on the same problem.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import symkin
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.errors import ParameterError, SymkinError
from symkin.io import robot_from_toml
from symkin.solve.trajopt import (
    InfeasibleTrajectoryError,
    Trajectory,
    TrajectoryProblem,
    optimal_trajectory,
    radau_coefficients,
)

# IPOPT solves and re-simulations: the slow tier.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "examples" / "arm_2r.toml"
DEG = math.pi / 180
# The arm of examples/arm_2r.toml: uniform rods, m = 1 kg, l = 0.5 m, gravity -9.81 m/s^2 in y.
MASS, LENGTH, GRAVITY = 1.0, 0.5, 9.81
START = (-90 * DEG, 0.0)  # hanging straight down
GOAL = (30 * DEG, 45 * DEG)
TORQUE_LIMITS = (20.0, 10.0)
VELOCITY_LIMITS = (8.0, 8.0)
ALLOTTED_TIME = 1.5
# Re-simulated end states agree with the goal to 1e-5 (multiple shooting, 4 RK4 substeps) and
# 2e-4 (Radau collocation) on this 40-interval grid (h = 37.5 ms); the arm swings at up to
# 8 rad/s and amplifies the transcription's integration error open loop.
RESIMULATION_TOLERANCE = 1e-3
LIMIT_SLACK = 1e-6  # the solver's feasibility tolerance (symkin.solve.trajopt asks IPOPT for 1e-8)


# ---------------------------------------------------------------- independent dynamics


def two_link_acceleration(
    q: np.ndarray,
    dq: np.ndarray,
    tau: np.ndarray,
    gravity: float = GRAVITY,
    length: float = LENGTH,
    mass: float = MASS,
) -> np.ndarray:
    """ddq of the planar elbow arm with uniform rods (Spong et al. 2006, Ch. 7):
    M(q) ddq + C(q, dq) dq + G(q) = tau, centres of mass at l/2, I = m l^2 / 12."""
    m1 = m2 = mass
    l1 = length
    lc1 = lc2 = length / 2
    i1 = i2 = mass * length**2 / 12
    c2, s2 = math.cos(q[1]), math.sin(q[1])
    m11 = m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + i1 + i2
    m12 = m2 * (lc2**2 + l1 * lc2 * c2) + i2
    m22 = m2 * lc2**2 + i2
    h = m2 * l1 * lc2 * s2
    coriolis = np.array([-h * (2 * dq[0] * dq[1] + dq[1] ** 2), h * dq[0] ** 2])
    c1, c12 = math.cos(q[0]), math.cos(q[0] + q[1])
    weight = np.array(
        [(m1 * lc1 + m2 * l1) * gravity * c1 + m2 * lc2 * gravity * c12, m2 * lc2 * gravity * c12]
    )
    return np.linalg.solve([[m11, m12], [m12, m22]], tau - coriolis - weight)


def resimulate(trajectory: Trajectory, acceleration, from_nodes: bool = False) -> np.ndarray:
    """States (N+1 x 2n) from integrating the torques, each held on its interval, end to end
    or (``from_nodes``) each interval from its own node: the local defects' end points."""
    n = trajectory.robot.dof
    nodes = np.hstack([trajectory.q, trajectory.dq])
    state = nodes[0]
    states = [state]
    for k, tau in enumerate(trajectory.tau):
        solution = solve_ivp(
            lambda _, x, tau=tau: np.concatenate([x[n:], acceleration(x[:n], x[n:], tau)]),
            (trajectory.t[k], trajectory.t[k + 1]),
            nodes[k] if from_nodes else state,
            method="DOP853",
            rtol=1e-10,
            atol=1e-10,
        )
        state = solution.y[:, -1]
        states.append(state)
    return np.array(states)


def tool_position(q: np.ndarray) -> np.ndarray:
    """x, y of the two-link arm's tool: l1 c1 + l2 c12, l1 s1 + l2 s12."""
    return LENGTH * np.array(
        [math.cos(q[0]) + math.cos(q[0] + q[1]), math.sin(q[0]) + math.sin(q[0] + q[1])]
    )


# ---------------------------------------------------------------- solutions shared by tests


@pytest.fixture(scope="module")
def arm() -> symkin.Model:
    return symkin.derive(symkin.load_robot(ARM))


def swing(**changes) -> TrajectoryProblem:
    settings = {
        "start": START,
        "goal": GOAL,
        "intervals": 40,
        "final_time": ALLOTTED_TIME,
        "torque_limits": TORQUE_LIMITS,
        "velocity_limits": VELOCITY_LIMITS,
        "substeps": 4,
        "tolerance": None,  # the fixed 40-interval mesh: tests/test_trajopt_accuracy.py refines
    }
    return TrajectoryProblem(**(settings | changes))


@pytest.fixture(scope="module")
def solutions(arm: symkin.Model) -> dict[tuple[str, str], Trajectory]:
    """The swing solved for both objectives with both transcriptions."""
    return {
        (objective, method): optimal_trajectory(
            arm,
            swing(
                objective=objective,
                method=method,
                final_time=ALLOTTED_TIME if objective == "effort" else None,
            ),
        )
        for objective in ("effort", "time")
        for method in ("multiple-shooting", "collocation")
    }


CASES = [(o, m) for o in ("effort", "time") for m in ("multiple-shooting", "collocation")]


# ---------------------------------------------------------------- the checks of the issue


@pytest.mark.parametrize("case", CASES, ids=["-".join(c) for c in CASES])
def test_resimulated_torques_reach_the_goal(solutions, case) -> None:
    trajectory = solutions[case]
    states = resimulate(trajectory, two_link_acceleration)
    assert np.abs(states[-1] - [*GOAL, 0.0, 0.0]).max() < RESIMULATION_TOLERANCE
    # ... and pass through the transcription's nodes on the way.
    nodes = np.hstack([trajectory.q, trajectory.dq])
    assert np.abs(states - nodes).max() < RESIMULATION_TOLERANCE


@pytest.mark.parametrize("case", CASES, ids=["-".join(c) for c in CASES])
def test_limits_and_boundary_conditions_hold_at_every_node(solutions, case) -> None:
    trajectory = solutions[case]
    robot = trajectory.robot
    assert trajectory.stats.status in ("Solve_Succeeded", "Solved_To_Acceptable_Level")
    assert trajectory.tau.shape == (40, 2) and trajectory.q.shape == (41, 2)
    assert np.all(np.abs(trajectory.tau) <= np.array(TORQUE_LIMITS) + LIMIT_SLACK)
    assert np.all(np.abs(trajectory.dq) <= np.array(VELOCITY_LIMITS) + LIMIT_SLACK)
    # The file's limits: shoulder +-180 deg, elbow +-150 deg.
    for i, bound in enumerate((180 * DEG, 150 * DEG)):
        assert robot.joints[i].limits == pytest.approx((-bound, bound))
        assert np.all(np.abs(trajectory.q[:, i]) <= bound + LIMIT_SLACK)
    np.testing.assert_allclose(trajectory.q[0], START, atol=LIMIT_SLACK)
    np.testing.assert_allclose(trajectory.q[-1], GOAL, atol=LIMIT_SLACK)
    np.testing.assert_allclose(trajectory.dq[[0, -1]], 0.0, atol=LIMIT_SLACK)
    np.testing.assert_allclose(np.diff(trajectory.t), trajectory.final_time / 40, rtol=1e-12)
    h = trajectory.final_time / 40
    assert trajectory.effort == pytest.approx(h * np.sum(trajectory.tau**2), rel=1e-12)


def test_minimum_time_is_bang_bang_and_shorter(solutions) -> None:
    limits = np.array(TORQUE_LIMITS)
    for method in ("multiple-shooting", "collocation"):
        fastest = solutions["time", method]
        saturated = np.any(np.abs(fastest.tau) >= 0.98 * limits, axis=1)
        assert saturated.mean() > 0.7, f"{method}: torques at a limit on {saturated.mean():.0%}"
        assert fastest.final_time < solutions["effort", method].final_time == ALLOTTED_TIME
        assert fastest.cost == fastest.final_time


def test_less_than_the_minimum_time_is_infeasible(arm, solutions) -> None:
    """Local optimality from the other side: 5 % less time than the minimum cannot be done."""
    shortest = solutions["time", "multiple-shooting"].final_time
    with pytest.raises(InfeasibleTrajectoryError, match=r"^IPOPT: .*torque limit of joint"):
        optimal_trajectory(arm, swing(final_time=0.95 * shortest))


@pytest.mark.parametrize("objective", ["effort", "time"])
def test_both_transcriptions_reach_the_same_cost(solutions, objective) -> None:
    """Two discretisations of one continuous problem, with the same piecewise-constant
    torques: the costs differ by the integration error (RK4 with 4 substeps against Radau
    order 5), measured at about 3e-6 relative; 1e-3 leaves room for other platforms' IPOPT."""
    shooting = solutions[objective, "multiple-shooting"].cost
    collocation = solutions[objective, "collocation"].cost
    assert collocation == pytest.approx(shooting, rel=1e-3)


# ---------------------------------------------------------------- more of the problem


def test_cartesian_goal_puts_the_tool_there(arm) -> None:
    target = (0.3, 0.5, 0.0)
    trajectory = optimal_trajectory(arm, swing(goal=None, cartesian_goal=target))
    np.testing.assert_allclose(tool_position(trajectory.q[-1]), target[:2], atol=1e-7)
    np.testing.assert_allclose(trajectory.dq[-1], 0.0, atol=1e-7)
    states = resimulate(trajectory, two_link_acceleration)
    assert np.abs(tool_position(states[-1, :2]) - target[:2]).max() < RESIMULATION_TOLERANCE


def test_cartesian_goal_off_the_plane_is_refused(arm) -> None:
    with pytest.raises(InfeasibleTrajectoryError, match="tool's z is 0 m in every"):
        optimal_trajectory(arm, swing(goal=None, cartesian_goal=(0.3, 0.5, 0.2)))


def test_inertial_data_from_overrides(tmp_path) -> None:
    """planar_2r without its file's inertial data: the same rods given through ``overrides``
    (gravity along z, normal to the arm's plane, so no gravity torques) move as Spong's
    equations with g = 0 and l = 1 m predict."""
    model = symkin.derive(robot_from_toml(without_inertials("planar_2r"), "planar_2r.toml"))
    rod = {"m": 1.0, "cx": -0.5, "cy": 0.0, "cz": 0.0, "ixx": 0.0, "iyy": 1 / 12, "izz": 1 / 12}
    rod |= {"ixy": 0.0, "ixz": 0.0, "iyz": 0.0}
    overrides = {f"{name}{i}": value for i in (1, 2) for name, value in rod.items()}
    problem = TrajectoryProblem(
        start=(0.0, 0.0), goal=(1.0, -0.5), final_time=1.0, intervals=30, overrides=overrides
    )
    trajectory = optimal_trajectory(model, problem)
    states = resimulate(
        trajectory, lambda q, dq, tau: two_link_acceleration(q, dq, tau, gravity=0.0, length=1.0)
    )
    assert np.abs(states[-1] - [1.0, -0.5, 0.0, 0.0]).max() < RESIMULATION_TOLERANCE
    with pytest.raises(ParameterError, match=r"no inertial data for .* with overrides"):
        optimal_trajectory(model, TrajectoryProblem(start=(0, 0), goal=(1, 0), final_time=1.0))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"start": (0.0, 0.0), "torque_limits": (5.0, 10.0)},
            r"torque limit of joint 1 \(5 N m\) below the 9\.81 N m gravity needs at the start",
        ),
        (
            {"goal": (0.0, 0.0), "torque_limits": (20.0, 2.0)},
            r"torque limit of joint 2 \(2 N m\) below the 2\.453 N m gravity needs at the goal",
        ),
        (
            {"start": (0.0, 170 * DEG)},
            r"start puts joint 2 at 2\.96706 rad, outside its limits \[-2\.61799, 2\.61799\] rad",
        ),
        (
            {"final_time": 0.2},
            r"joint 1 must move 2\.094 rad in 0\.2 s, more than its velocity limit of 8 rad/s",
        ),
    ],
    ids=["gravity-start", "gravity-goal", "position-limit", "velocity-limit"],
)
def test_obvious_infeasibility_is_caught_before_solving(arm, changes, message) -> None:
    # Gravity at q = 0: (m1 l/2 + m2 l) g = 9.81 N m and m2 (l/2) g cos(0) = 2.4525 N m.
    with pytest.raises(InfeasibleTrajectoryError, match=message):
        optimal_trajectory(arm, swing(**changes))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"final_time": None}, "minimum effort needs a fixed final time"),
        ({"objective": "time"}, "minimum time leaves the final time free"),
        ({"objective": "time", "final_time": None, "torque_limits": None}, "needs torque limits"),
        ({"goal": (0.0, 0.0, 0.0)}, r"goal: expected 2 values \(joint 1, joint 2\), got 3"),
        ({"velocity_limits": (8.0, -1.0)}, "velocity limit: joint 2 needs a positive number"),
        ({"goal": None}, "give a goal"),
        ({"method": "shooting"}, "method must be one of multiple-shooting, collocation"),
        ({"intervals": 0}, "intervals must be at least 1"),
    ],
)
def test_malformed_problems_are_rejected(arm, changes, message) -> None:
    with pytest.raises(SymkinError, match=message):
        optimal_trajectory(arm, swing(**changes))


@pytest.mark.parametrize(
    ("changes", "parameter"),
    [
        ({"final_time": None}, "final_time"),
        ({"objective": "time"}, "final_time"),
        ({"objective": "time", "final_time": None, "torque_limits": None}, "torque_limits"),
    ],
)
def test_duration_errors_name_the_problem_field(arm, changes, parameter) -> None:
    """The library names the field of TrajectoryProblem; a front end spells it its own way."""
    with pytest.raises(ParameterError) as error:
        optimal_trajectory(arm, swing(**changes))
    assert error.value.parameters == (parameter,)
    assert f"({parameter}" in str(error.value) and "--" not in str(error.value)
    assert "(--flag" in error.value.message_for({parameter: "--flag"})


def test_radau_coefficients_differentiate_cubics_exactly() -> None:
    """Radau IIA with 3 points: s = (4 - sqrt 6)/10, (4 + sqrt 6)/10, 1 (Hairer and Wanner,
    Solving ODEs II, Table 5.6); on 4 points the Lagrange basis reproduces any cubic, so
    ``C`` gives its exact derivative and ``D`` its value at 1."""
    points, C, D = radau_coefficients(3)
    root = math.sqrt(6)
    np.testing.assert_allclose(points, [0, (4 - root) / 10, (4 + root) / 10, 1], atol=1e-15)
    cubic = 2 * points**3 - points**2 + 3 * points - 1
    np.testing.assert_allclose(cubic @ C, 6 * points**2 - 2 * points + 3, atol=1e-12)
    np.testing.assert_allclose(D, [0, 0, 0, 1], atol=1e-12)


# ---------------------------------------------------------------- command line


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_cli_writes_csv_json_and_plot(capsys, tmp_path) -> None:
    import matplotlib.image

    out = tmp_path / "swing"
    status, stdout, _ = run(
        capsys, "trajopt", str(ARM), "--from", "-90deg,0", "--to", "30deg,45deg",
        "--time", "1.5", "--torque-limit", "20,10", "--velocity-limit", "8",
        "--intervals", "20", "--max-refinements", "0", "--out", str(out), "--plot",
    )  # fmt: skip
    assert status == 0
    assert "arm_2r: minimum effort, multiple shooting, 20 intervals" in stdout
    assert "IPOPT: Solve_Succeeded" in stdout
    table = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    header = (out / "trajectory.csv").read_text().splitlines()[0]
    assert header == "t,q1,q2,dq1,dq2,tau1,tau2"
    assert table.shape == (21, 7)
    data = json.loads((out / "trajectory.json").read_text())
    assert data["robot"] == "arm_2r"
    assert data["problem"]["torque_limits"] == [20.0, 10.0]
    assert data["problem"]["velocity_limits"] == [8.0, 8.0]
    assert data["solver"]["status"] == "Solve_Succeeded" and data["solver"]["iterations"] > 0
    np.testing.assert_allclose(table[:, 0], np.linspace(0, 1.5, 21), atol=1e-12)
    np.testing.assert_allclose(table[:, 1:3], data["q"], atol=0)
    np.testing.assert_allclose(table[:-1, 5:], data["tau"], atol=0)
    np.testing.assert_allclose(table[0, 1:3], [-math.pi / 2, 0], atol=1e-7)
    np.testing.assert_allclose(table[-1, 1:3], [math.pi / 6, math.pi / 4], atol=1e-7)
    png = out / "trajectory.png"
    assert 20_000 < png.stat().st_size < 2_000_000
    pixels = matplotlib.image.imread(png)
    assert pixels.shape[0] > 400 and pixels.shape[1] > 400
    assert pixels[..., :3].std() > 0.05  # lines and text, not a blank canvas


def test_cli_prints_a_summary_for_minimum_time(capsys) -> None:
    status, stdout, _ = run(
        capsys, "trajopt", str(ARM), "--from", "-90deg,0", "--to", "30deg,45deg", "--min-time",
        "--torque-limit", "20,10", "--velocity-limit", "8", "--intervals", "20",
        "--method", "collocation",
    )  # fmt: skip
    assert status == 0
    lines = stdout.splitlines()
    assert lines[0] == "arm_2r: minimum time, collocation, 20 intervals"
    final_time = float(lines[3].removeprefix("final time T = ").removesuffix(" s"))
    assert 0.3 < final_time < ALLOTTED_TIME
    assert lines[4].startswith(f"cost = {final_time:.6g} (final time)")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--from", "0,0,0", "--to", "0,0", "--time", "1"],
         "--from: arm_2r has 2 joints, got 3 value(s)"),
        (["--from", "0,0", "--time", "1"], "give the goal: --to"),
        (["--from", "0,0", "--to", "1,0", "--time", "1", "--plot"], "--plot needs --out DIR"),
        (["--from", "0,0", "--to", "1,0", "--min-time"], "minimum time needs torque limits"),
        (["--from", "0,0", "--to", "1,0", "--time", "1", "--torque-limit", "5deg"],
         "--torque-limit: torques and forces are plain numbers"),
        (["--from", "0,0", "--to", "1,0", "--time", "1", "--torque-limit", "5,10"],
         "torque limit of joint 1 (5 N m) below the 9.81 N m gravity needs at the start"),
        (["--from", "0,0", "--cartesian-goal", "0.3,0.5", "--time", "1"],
         "--cartesian-goal: expected x,y,z"),
        (["--from", "0,0", "--to", "1,0", "--time", "1deg"], "--time: a time in seconds"),
        (["--from", "-90deg,0", "--to", "30deg,45deg", "--min-time", "--objective", "effort",
          "--torque-limit", "20"], "--min-time means --objective time"),
    ],
    ids=[
        "count", "no-goal", "plot", "min-time", "deg", "gravity", "cartesian", "time", "objective"
    ],
)  # fmt: skip
def test_cli_bad_input_is_one_line(capsys, argv, message) -> None:
    status, stdout, stderr = run(capsys, "trajopt", str(ARM), *argv)
    assert status == 2
    (line,) = stderr.splitlines()
    assert line.startswith("symkin: error: ") and message in line
    assert stdout == ""


def test_cli_reports_an_infeasible_time_with_the_limits(capsys) -> None:
    status, _, stderr = run(
        capsys, "trajopt", str(ARM), "--from", "-90deg,0", "--to", "30deg,45deg",
        "--time", "0.3", "--torque-limit", "20,10", "--intervals", "20",
    )  # fmt: skip
    assert status == 2
    (error,) = [line for line in stderr.splitlines() if "error" in line]
    assert error.startswith("symkin: error: IPOPT: ")
    assert "limits reached there: torque limit of joint" in error


# ---------------------------------------------------------------- PUMA 560


@pytest.mark.oracle
@pytest.mark.slow
def test_puma560_transfer_resimulated_with_robotics_toolbox() -> None:
    """A small PUMA 560 problem; Robotics Toolbox's ``accel`` (Corke's model without friction,
    the data of the catalogue file) integrates the torques.  On 20 intervals of 0.1 s the end
    states are off by 4e-4 (multiple shooting, 2 RK4 substeps) and 4e-5 (collocation)."""
    import roboticstoolbox as rtb

    # Link 3's published inertia breaks the triangle inequality; the file's inertia_note says
    # so, and the loader does not warn.
    model = symkin.derive(symkin.load_robot("puma560"))
    puma = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    start = np.radians([0, 90, -90, 0, 0, 0])
    goal = np.radians([90, 45, -135, 45, 45, 90])
    torque_limits = (100, 180, 90, 25, 20, 20)
    problems = {
        method: TrajectoryProblem(
            start=start,
            goal=goal,
            final_time=2.0,
            intervals=20,
            method=method,
            torque_limits=torque_limits,
            velocity_limits=(3.0,) * 6,
            tolerance=None,
        )
        for method in ("multiple-shooting", "collocation")
    }
    solved = {method: optimal_trajectory(model, p) for method, p in problems.items()}
    for trajectory in solved.values():
        states = resimulate(trajectory, lambda q, dq, tau: puma.accel(q, dq, tau))
        assert np.abs(states[-1] - [*goal, *np.zeros(6)]).max() < RESIMULATION_TOLERANCE
        assert np.all(np.abs(trajectory.tau) <= np.array(torque_limits) + LIMIT_SLACK)
        assert np.all(np.abs(trajectory.dq) <= 3.0 + LIMIT_SLACK)
    assert solved["collocation"].cost == pytest.approx(solved["multiple-shooting"].cost, rel=1e-3)

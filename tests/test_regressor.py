"""The regressor ``Y``, the base regressor ``Y_b`` and ``symkin identify``.

Expected values come from outside the regressor: the generated inverse dynamics (tau from the
robot file's parameters, run by the Newton–Euler recursion on the COM form), a planar 2R
arm's textbook equations of motion (Spong, Hutchinson, Vidyasagar, *Robot Modeling and
Control*, Sec. 7.4.1, typed in here), Pinocchio's ``computeJointTorqueRegressor`` and
Robotics Toolbox's ``rne`` (tests marked ``oracle``).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from symkin.cli import main
from symkin.derive.regressor import regressor, regressor_function
from symkin.derive.regressor_base import base_regressor
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.identify import identify

L1, L2, LC1, LC2, M1, M2, I1, I2 = 1.0, 1.0, 0.45, 0.55, 3.0, 2.0, 0.25, 0.15


def planar_torques(q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
    """Spong Sec. 7.4.1: the planar elbow arm (gravity normal to the plane), rows of states."""
    c2, s2 = np.cos(q[:, 1]), np.sin(q[:, 1])
    d11 = M1 * LC1**2 + M2 * (L1**2 + LC2**2 + 2 * L1 * LC2 * c2) + I1 + I2
    d12 = M2 * (LC2**2 + L1 * LC2 * c2) + I2
    d22 = M2 * LC2**2 + I2
    h = -M2 * L1 * LC2 * s2
    tau1 = d11 * ddq[:, 0] + d12 * ddq[:, 1] + 2 * h * dq[:, 0] * dq[:, 1] + h * dq[:, 1] ** 2
    tau2 = d12 * ddq[:, 0] + d22 * ddq[:, 1] - h * dq[:, 0] ** 2
    return np.column_stack([tau1, tau2])


def random_states(rng: np.random.Generator, count: int, dof: int) -> list[np.ndarray]:
    return [rng.uniform(-2.0, 2.0, (count, dof)) for _ in range(3)]


def test_planar_2r_base_regressor_spans_the_textbook_dynamics(model_of):
    model = model_of("planar_2r")
    rng = np.random.default_rng(4)
    q, dq, ddq = random_states(rng, 40, 2)
    fit = identify(model, q, dq, ddq, planar_torques(q, dq, ddq))
    assert fit.residual_rms.max() < 1e-10
    # A fresh motion: the fitted base parameters predict the textbook torques.
    base = base_regressor(model.robot, model.kinematics)
    evaluate = regressor_function(model.robot, model.kinematics)
    q, dq, ddq = random_states(rng, 5, 2)
    p = base.parameter_values
    for state in zip(q, dq, ddq, strict=True):
        predicted = evaluate(*state, p)[:, list(base.folding.kept)] @ fit.estimate
        expected = planar_torques(*(s[None] for s in state))[0]
        assert np.abs(predicted - expected).max() < 1e-9
    # Gravity normal to the plane: link 1's inertia about its axis, link 2's and its first
    # moment in the plane (the textbook's three parameters, plus a lateral offset of COM 2).
    assert sorted(base.names) == ["MX2R", "MY2", "ZZ1R", "ZZ2R"]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_regressor_times_file_parameters_is_the_generated_tau(model_of, name):
    model = model_of(name)
    full = regressor(model.robot, model.kinematics)
    base = base_regressor(model.robot, model.kinematics)
    evaluate = regressor_function(model.robot, model.kinematics)
    tau = generated_numpy_module(model).inverse_dynamics
    p = base.parameter_values
    rng = np.random.default_rng(7)
    for q, dq, ddq in zip(*random_states(rng, 5, model.robot.dof), strict=True):
        Y = evaluate(q, dq, ddq, p)
        expected = tau(q, dq, ddq, p)
        scale = np.abs(Y) @ np.abs(full.values)
        assert np.all(np.abs(Y @ np.array(full.values) - expected) <= 1e-10 * scale + 1e-12)
        Yb = Y[:, list(base.folding.kept)]
        assert np.all(np.abs(Yb @ np.array(base.values) - expected) <= 1e-9 * scale + 1e-12)


FRICTION_ARM = """
name = "friction_arm"
convention = "modified"
[[joints]]
type = "revolute"
[joints.link]
mass = 2.0
com = [0.1, 0.02, -0.05]
inertia = {ixx = 0.02, iyy = 0.03, izz = 0.025, ixy = 0.001}
motor_inertia = 0.4
friction = {viscous = 0.7, coulomb = 1.2}
[[joints]]
type = "prismatic"
alpha = -90
a = 0.3
[joints.link]
mass = 1.5
com = [0.0, 0.05, 0.1]
inertia = {ixx = 0.01, iyy = 0.012, izz = 0.008, ixz = -0.002}
friction = {viscous = 3.0, coulomb_positive = 2.0, coulomb_negative = 1.5}
[[joints]]
type = "revolute"
alpha = 90
d = 0.1
[joints.link]
mass = 0.8
com = [0.03, 0.0, 0.02]
inertia = {ixx = 0.004, iyy = 0.005, izz = 0.003}
motor_inertia = 0.05
"""


def test_friction_rotor_prismatic_and_modified_dh_columns():
    """Rotor inertia, viscous and (directional) Coulomb columns beside the link columns of a
    modified-DH arm with a prismatic joint: Y pi and Y_b beta are the generated tau."""
    from symkin import derive, robot_from_toml

    robot = robot_from_toml(FRICTION_ARM, "friction_arm.toml")
    model = derive(robot)
    full = regressor(robot, model.kinematics)
    assert {"ia1", "fv1", "fc1", "fv2", "fcp2", "fcn2", "ia3"} <= set(full.names)
    assert "fc3" not in full.names  # joint 3 has no friction in the file
    base = base_regressor(robot, model.kinematics)
    evaluate = regressor_function(robot, model.kinematics)
    tau = generated_numpy_module(model).inverse_dynamics
    rng = np.random.default_rng(3)
    for q, dq, ddq in zip(*random_states(rng, 6, 3), strict=True):
        Y = evaluate(q, dq, ddq, ())
        expected = tau(q, dq, ddq, ())
        assert np.abs(Y @ np.array(full.values) - expected).max() < 1e-10
        assert (
            np.abs(Y[:, list(base.folding.kept)] @ np.array(base.values) - expected).max() < 1e-10
        )


@pytest.mark.slow
def test_base_regressor_kernel_holds_for_other_parameter_values(model_of):
    """``Y_b`` is a column subset of ``Y`` chosen at the file's lengths; at other lengths its
    columns still span every column of ``Y`` (the grouping is structural)."""
    model = model_of("puma560")
    evaluate = regressor_function(model.robot, model.kinematics)
    kept = list(base_regressor(model.robot, model.kinematics).folding.kept)
    rng = np.random.default_rng(2)
    p = np.array([0.5, 0.1, 0.2, 0.35])  # a2 a3 d3 d4, none of them the file's
    Y = np.vstack([evaluate(*s, p) for s in zip(*random_states(rng, 30, 6), strict=True)])
    K, *_ = np.linalg.lstsq(Y[:, kept], Y, rcond=None)
    assert np.abs(Y[:, kept] @ K - Y).max() < 1e-9 * np.abs(Y).max()


def write_csv(path, header, rows) -> None:
    text = ",".join(header) + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows)
    path.write_text(text + "\n", encoding="utf-8")


def planar_rows(count: int, seed: int = 0):
    q, dq, ddq = random_states(np.random.default_rng(seed), count, 2)
    header = ["q1", "q2", "dq1", "dq2", "ddq1", "ddq2", "tau1", "tau2"]
    return header, np.hstack([q, dq, ddq, planar_torques(q, dq, ddq)])


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_identify_json_reports_every_base_parameter(tmp_path, capsys):
    header, rows = planar_rows(30)
    write_csv(tmp_path / "log.csv", header, rows)
    code, out, _ = run(
        capsys, "identify", "planar_2r", "--data", str(tmp_path / "log.csv"), "--json"
    )
    assert code == 0
    data = json.loads(out)
    assert {p["name"] for p in data["base_parameters"]} == {"MX2R", "MY2", "ZZ1R", "ZZ2R"}
    assert max(data["residual_rms"]) < 1e-10
    assert data["condition_number"] > 1
    definitions = {p["name"]: p["definition"] for p in data["base_parameters"]}
    assert "izz2" in definitions["ZZ2R"] and "m2" in definitions["ZZ2R"]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda h, r: (h[:-1], r[:, :-1]), "missing tau2"),
        (lambda h, r: (h, np.where(np.arange(len(r))[:, None] == 3, np.nan, r)), "NaN"),
        (lambda h, r: (h, r[:2]), "too few samples"),
        (lambda h, r: (h, r * np.array([0, 1, 0, 1, 0, 1, 1, 1])), "rank-deficient"),
    ],
    ids=["columns", "nan", "few", "rank"],
)
def test_identify_bad_input_is_one_clear_error(tmp_path, capsys, change, message):
    header, rows = change(*planar_rows(30))
    write_csv(tmp_path / "log.csv", header, rows)
    code, out, err = run(capsys, "identify", "planar_2r", "--data", str(tmp_path / "log.csv"))
    assert code == 2 and out == ""
    errors = [line for line in err.splitlines() if "error:" in line]
    assert len(errors) == 1 and message in errors[0] and "Traceback" not in err


def test_identify_from_positions_with_the_zero_phase_filter(tmp_path, capsys):
    """Positions of a smooth motion sampled at 200 Hz: the filtered, differentiated states
    fit the textbook torques to a small fraction of their size."""
    t = np.arange(0.0, 6.0, 0.005)
    q = np.column_stack([np.sin(1.3 * t) + 0.3 * np.sin(3.1 * t), np.cos(0.9 * t)])
    dq = np.column_stack([1.3 * np.cos(1.3 * t) + 0.93 * np.cos(3.1 * t), -0.9 * np.sin(0.9 * t)])
    ddq = np.column_stack(
        [-1.69 * np.sin(1.3 * t) - 2.883 * np.sin(3.1 * t), -0.81 * np.cos(0.9 * t)]
    )
    tau = planar_torques(q, dq, ddq)
    write_csv(tmp_path / "log.csv", ["t", "q1", "q2", "tau1", "tau2"], np.column_stack([t, q, tau]))
    code, out, err = run(
        capsys,
        "identify",
        "planar_2r",
        "--data",
        str(tmp_path / "log.csv"),
        "--filter",
        "10",
        "--json",
    )
    assert code == 0, err
    data = json.loads(out)
    assert max(data["residual_rms"]) < 1e-3 * np.abs(tau).max()
    assert "Butterworth" in data["derivatives"]


@pytest.mark.slow
def test_exciting_trajectory_is_better_conditioned_and_within_limits(tmp_path, capsys):
    out = tmp_path / "excite.csv"
    code, text, err = run(
        capsys,
        "identify",
        "planar_2r",
        "--excite",
        "--harmonics",
        "3",
        "--period",
        "4",
        "--velocity-limit",
        "1.5",
        "--out",
        str(out),
    )
    assert code == 0, err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert np.abs(data[:, 3:5]).max() <= 1.5 + 1e-9  # dq1, dq2
    assert np.abs(data[:, 1:3]).max() <= np.pi
    assert "condition number" in text
    # Periodic: the first sample continues the last one.
    assert np.abs(data[0, 1:3] - data[-1, 1:3]).max() < 0.1


def test_identify_needs_data_or_excite(capsys):
    code, _, err = run(capsys, "identify", "planar_2r")
    assert code == 2 and "--data" in err

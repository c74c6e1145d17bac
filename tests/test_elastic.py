"""Elastic joints (Spong's reduced model), drives and the motor side.

Expected values come from outside the generated code: finite differences of the rigid
inverse dynamics along a polynomial trajectory, a forward simulation that must recover the
planned motion, the hand-written energy of a planar 2R, and textbook reflected inertias.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symkin import load_robot
from symkin.cli import main
from symkin.derive import Model, derive
from symkin.errors import RobotError
from symkin.runtime.modules import generated_casadi_module, generated_numpy_module
from symkin.solve.elastic_state import motor_side_state
from symkin.solve.simulate import simulate

EXAMPLE = Path(__file__).parent.parent / "examples" / "elastic_2r.toml"
# examples/elastic_2r.toml, written out by hand: lengths, masses, izz, K and B.
L1, L2, M1, M2, IZZ1, IZZ2 = 1.0, 0.8, 2.0, 1.0, 0.2, 0.06
STIFFNESS = np.array([400.0, 250.0])
MOTOR_INERTIA = np.array([0.5, 50**2 * 1.2e-4])
GRAVITY = 9.81  # along -y


def example() -> Model:
    return derive(load_robot(EXAMPLE))


def polynomial_trajectory(seed: int) -> list[np.polynomial.Polynomial]:
    """A quintic per joint, seeded: smooth, with non-zero third and fourth derivatives."""
    rng = np.random.default_rng(seed)
    return [np.polynomial.Polynomial(rng.uniform(-1.0, 1.0, 6)) for _ in range(2)]


def derivatives(path: list[np.polynomial.Polynomial], t: float) -> list[np.ndarray]:
    """``[q, dq, ddq, d3q, d4q]`` at ``t``."""
    return [np.array([p.deriv(k)(t) if k else p(t) for p in path]) for k in range(5)]


def tau_link(module: object, path: list[np.polynomial.Polynomial], t: float) -> np.ndarray:
    q, dq, ddq, *_ = derivatives(path, t)
    return module.inverse_dynamics(q, dq, ddq)


def test_motor_side_matches_finite_differences_of_the_link_torques() -> None:
    model = example()
    module = generated_numpy_module(model)
    path = polynomial_trajectory(3)
    for t in (0.0, 0.37, 0.8):
        q, dq, ddq, d3q, d4q = derivatives(path, t)
        h = 1e-3
        tau = tau_link(module, path, t)
        second = (tau_link(module, path, t + h) - 2 * tau + tau_link(module, path, t - h)) / h**2
        state = motor_side_state(model, q, dq, ddq, d3q, d4q)
        np.testing.assert_allclose(state.theta, q + tau / STIFFNESS, rtol=1e-12, atol=1e-12)
        expected = MOTOR_INERTIA * (ddq + second / STIFFNESS) + tau
        np.testing.assert_allclose(state.tau_motor, expected, rtol=1e-5, atol=1e-6)


def test_forward_simulation_under_the_motor_torques_recovers_the_planned_motion() -> None:
    model = example()
    module = generated_numpy_module(model)
    path = polynomial_trajectory(5)

    def motor_torque(t: float) -> np.ndarray:
        return module.elastic_inverse_dynamics(*derivatives(path, t))[1]

    q0, dq0, *_ = derivatives(path, 0.0)
    h = 1e-5
    tau_rate = (tau_link(module, path, h) - tau_link(module, path, -h)) / (2 * h)
    theta0 = q0 + tau_link(module, path, 0.0) / STIFFNESS
    dtheta0 = dq0 + tau_rate / STIFFNESS
    run = simulate(model, 1.0, q0, dq0, tau=motor_torque, theta0=theta0, dtheta0=dtheta0)
    planned = np.array([derivatives(path, t)[0] for t in run.t])
    np.testing.assert_allclose(run.q, planned, atol=1e-6)
    assert not np.allclose(run.theta, run.q, atol=1e-3)  # the springs do deflect


def hand_energy(q: np.ndarray, dq: np.ndarray, theta: np.ndarray, dtheta: np.ndarray) -> float:
    """T + V of the planar 2R (centres of mass halfway along the links) + springs + rotors."""
    c1, s1, c12, s12 = math.cos(q[0]), math.sin(q[0]), math.cos(q[0] + q[1]), math.sin(q[0] + q[1])
    w1, w2 = dq[0], dq[0] + dq[1]
    v1 = L1 / 2 * w1 * np.array([-s1, c1])
    v2 = L1 * w1 * np.array([-s1, c1]) + L2 / 2 * w2 * np.array([-s12, c12])
    kinetic = M1 * v1 @ v1 / 2 + M2 * v2 @ v2 / 2 + IZZ1 * w1**2 / 2 + IZZ2 * w2**2 / 2
    potential = GRAVITY * (M1 * L1 / 2 * s1 + M2 * (L1 * s1 + L2 / 2 * s12))
    spring = STIFFNESS @ (theta - q) ** 2 / 2
    return kinetic + potential + spring + MOTOR_INERTIA @ dtheta**2 / 2


def test_elastic_model_without_input_or_friction_conserves_energy(tmp_path: Path) -> None:
    text = EXAMPLE.read_text().replace("friction = { viscous = 0.1 }", "")
    (tmp_path / "elastic_2r.toml").write_text(text)
    module = generated_numpy_module(derive(load_robot(tmp_path / "elastic_2r.toml")))

    def rates(t: float, x: np.ndarray) -> np.ndarray:
        q, dq, theta, dtheta = x.reshape(4, 2)
        ddq, ddtheta = module.elastic_forward_dynamics(q, dq, theta, np.zeros(2))
        return np.concatenate([dq, ddq, dtheta, ddtheta])

    start = np.array([0.3, -0.4, 0.1, 0.5, 0.35, -0.3, -0.2, 0.0])
    run = solve_ivp(rates, (0, 1), start, method="DOP853", rtol=1e-11, atol=1e-12)
    energies = [hand_energy(*x.reshape(4, 2)) for x in run.y.T]
    assert np.ptp(energies) < 1e-7 * max(1.0, abs(energies[0]))
    assert np.ptp(run.y[0]) > 0.1  # it did move


def test_backends_agree_on_the_elastic_model() -> None:
    model = example()
    numpy_module, casadi_module = generated_numpy_module(model), generated_casadi_module(model)
    rng = np.random.default_rng(7)
    q, dq, theta, tau, ddq, d3q, d4q = rng.uniform(-1, 1, (7, 2))
    p = numpy_module.DEFAULT_PARAMETERS
    forward = casadi_module.elastic_forward_dynamics_function()(q, dq, theta, tau, p)
    for ours, theirs in zip(
        numpy_module.elastic_forward_dynamics(q, dq, theta, tau), forward, strict=True
    ):
        np.testing.assert_allclose(ours, theirs.full().ravel(), rtol=1e-12)
    inverse = casadi_module.elastic_inverse_dynamics_function()(q, dq, ddq, d3q, d4q, p)
    ours = numpy_module.elastic_inverse_dynamics(q, dq, ddq, d3q, d4q)
    for a, b in zip(ours, inverse, strict=True):
        np.testing.assert_allclose(a, b.full().ravel(), rtol=1e-12)


def test_elastic_rotor_is_not_in_the_mass_matrix_and_rigid_rotor_is(tmp_path: Path) -> None:
    rigid = EXAMPLE.read_text().replace("stiffness = 400", "").replace("stiffness = 250", "")
    (tmp_path / "rigid_2r.toml").write_text(rigid.replace('"elastic_2r"', '"rigid_2r"'))
    q = np.array([0.4, 0.9])
    elastic_mass = generated_numpy_module(example()).mass_matrix(q)
    rigid_model = derive(load_robot(tmp_path / "rigid_2r.toml"))
    rigid_mass = generated_numpy_module(rigid_model).mass_matrix(q)
    # Rigid: rotor inertias on the diagonal, joint 2's reflected through the gear (G^2 Jm).
    np.testing.assert_allclose(rigid_mass - elastic_mass, np.diag(MOTOR_INERTIA), atol=1e-12)
    assert "elastic_inverse_dynamics" not in dir(generated_numpy_module(rigid_model))


@pytest.mark.parametrize(
    ("link", "fragment"),
    [
        ("stiffness = 10", "needs the motor-side inertia"),
        ("stiffness = -1\nmotor_inertia = 1", "joint 1: 'link.stiffness' must be > 0"),
        ("motor_inertia = 1\ndrive = { rotor_inertia = 1e-4 }", "both give the rotor"),
        ("drive = { torque_constant = 0.1 }", "needs torque_constant, back_emf_constant"),
        ("drive = { gearratio = 3 }", "did you mean"),
        ("friction = { coulomb = 1, smoothing = 0 }", "smoothing' must be > 0"),
    ],
)
def test_drive_keys_are_checked(tmp_path: Path, link: str, fragment: str) -> None:
    path = tmp_path / "arm.toml"
    path.write_text(
        f'name = "arm"\n[[joints]]\ntype = "revolute"\n[joints.link]\nmass = 1\n{link}\n'
    )
    with pytest.raises(RobotError, match=r"arm\.toml") as error:
        load_robot(path)
    assert fragment in str(error.value)


def test_eval_reports_theta_and_motor_torque(capsys: pytest.CaptureFixture[str]) -> None:
    q, dq, ddq, d3q, d4q = derivatives(polynomial_trajectory(3), 0.37)
    text = [",".join(repr(float(v)) for v in x) for x in (q, dq, ddq, d3q, d4q)]
    argv = [str(EXAMPLE), "--q", text[0], "--dq", text[1], "--ddq", text[2], "--dynamics"]
    assert main(["eval", *argv, "--d3q", text[3], "--d4q", text[4], "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(data["theta"], q + np.array(data["tau"]) / STIFFNESS, rtol=1e-12)
    assert data["elastic_joints"] == [1, 2] and len(data["tau_motor"]) == 2
    assert main(["eval", *argv, "--d3q", text[3]]) == 2
    assert "need --d4q as well" in capsys.readouterr().err
    assert main(["eval", "planar_2r", "--q", "0,0", "--d3q", "0,0"]) == 2
    assert "planar_2r has none" in capsys.readouterr().err


@pytest.mark.needs_cc
@pytest.mark.slow
def test_extension_agrees_with_numpy_on_the_elastic_model(tmp_path: Path) -> None:
    from symkin.generate import files_for_robot
    from symkin.output_folder import write_folder
    from symkin.runtime.extension import build_extension, load_extension

    model = example()
    write_folder(tmp_path, files_for_robot(model.robot, ("python",)))
    name = model.robot.name
    extension = load_extension(
        build_extension(tmp_path / "python" / f"{name}_ext.c", tmp_path / "c" / f"{name}.c")
    )
    numpy_module = generated_numpy_module(model)
    rng = np.random.default_rng(11)
    q, dq, theta, tau, ddq, d3q, d4q = rng.uniform(-1, 1, (7, 2))
    for ours, theirs in zip(
        numpy_module.elastic_forward_dynamics(q, dq, theta, tau),
        extension.elastic_forward_dynamics(q, dq, theta, tau),
        strict=True,
    ):
        np.testing.assert_allclose(theirs, ours, rtol=1e-12)
    for ours, theirs in zip(
        numpy_module.elastic_inverse_dynamics(q, dq, ddq, d3q, d4q),
        extension.elastic_inverse_dynamics(q, dq, ddq, d3q, d4q),
        strict=True,
    ):
        np.testing.assert_allclose(theirs, ours, rtol=1e-12)


@pytest.mark.slow
def test_puma_with_elastic_joints_matches_finite_differences() -> None:
    model = derive(load_robot(Path(__file__).parent / "data" / "puma560_elastic.toml"))
    module = generated_numpy_module(model)
    stiffness, inertia = module.elastic_constants(np.zeros(6))
    rng = np.random.default_rng(13)
    path = [np.polynomial.Polynomial(rng.uniform(-1.0, 1.0, 6)) for _ in range(6)]

    def state(t: float) -> list[np.ndarray]:
        return [np.array([p.deriv(k)(t) if k else p(t) for p in path]) for k in range(5)]

    def link_torque(t: float) -> np.ndarray:
        return module.inverse_dynamics(*state(t)[:3])

    h, t = 1e-3, 0.4
    second = (link_torque(t + h) - 2 * link_torque(t) + link_torque(t - h)) / h**2
    theta, motor = module.elastic_inverse_dynamics(*state(t))
    np.testing.assert_allclose(theta, state(t)[0] + link_torque(t) / stiffness, rtol=1e-12)
    expected = inertia * (state(t)[2] + second / stiffness) + link_torque(t)
    np.testing.assert_allclose(motor, expected, rtol=1e-5, atol=1e-6)


def test_drive_keys_survive_writing_the_robot_back_to_toml(tmp_path: Path) -> None:
    from symkin.emit.robot_toml import robot_toml

    path = tmp_path / "motor.toml"
    path.write_text(
        'name = "motor"\n[[joints]]\ntype = "revolute"\n[joints.link]\nmass = 1\nstiffness = 90\n'
        "friction = { coulomb = 0.7, smoothing = 0.05, stiction = 0.9 }\n"
        "drive = { gear_ratio = 10, rotor_inertia = 1e-4, torque_constant = 0.05, "
        "back_emf_constant = 0.05, resistance = 1.2, inductance = 2e-3 }\n"
    )
    robot = load_robot(path)
    (tmp_path / "again.toml").write_text(robot_toml(robot, "test"))
    again = load_robot(tmp_path / "again.toml")
    link, copy = robot.joints[0].link, again.joints[0].link
    assert float(copy.motor_inertia) == pytest.approx(10**2 * 1e-4)  # G^2 Jm, by hand
    assert (copy.stiffness, copy.coulomb_width, copy.stiction) == (
        link.stiffness, link.coulomb_width, link.stiction,
    )  # fmt: skip
    assert copy.drive.inductance == link.drive.inductance and copy.drive.gear_ratio == 10

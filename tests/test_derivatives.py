"""Derivative kernels (dtau/dq, dtau/ddq, the forward dynamics' derivatives, dJ/dt) against
independent references: central finite differences of the generated tau, forward dynamics and
Jacobian (step 1e-6, a second-order error far below the tolerance), a hand-derived pendulum,
and the same kernels printed to C, the CPython extension and CasADi.  Pinocchio's own
derivatives are in tests/test_derivatives_oracles.py.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

import symkin
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.derive.tangents import tangent_assignments
from symkin.io import robot_from_toml
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.evaluate import dynamics_arguments

STEP = 1e-6

# A prismatic joint between two revolute ones in modified DH, with viscous, Coulomb and
# Stribeck friction and a rotor inertia: every term of tau has a derivative to check.
PRISMATIC_ARM = """
name = "prismatic_arm"
convention = "modified"
[parameters]
L1 = 0.4
[[joints]]
type = "revolute"
[joints.link]
mass = 2.0
com = [0.1, 0.02, 0.0]
inertia = { ixx = 0.02, iyy = 0.03, izz = 0.04, ixy = 0.001, ixz = 0.0, iyz = 0.002 }
motor_inertia = 0.05
friction = { coulomb = 0.3, viscous = 0.1, stribeck = { static = 0.5, velocity = 0.2 } }
[[joints]]
type = "prismatic"
alpha = 90
a = "L1"
[joints.link]
mass = 1.5
com = [0.0, 0.05, -0.1]
inertia = { ixx = 0.02, iyy = 0.02, izz = 0.01, ixy = 0.0, ixz = 0.001, iyz = 0.0 }
friction = { coulomb = 0.2, viscous = 0.3 }
[[joints]]
type = "revolute"
alpha = -90
d = 0.1
[joints.link]
mass = 0.8
com = [0.05, 0.0, 0.03]
inertia = { ixx = 0.005, iyy = 0.006, izz = 0.004, ixy = 0.0, ixz = 0.0, iyz = 0.0005 }
"""


def prismatic_model() -> symkin.Model:
    return symkin.derive(symkin.robot_from_toml(PRISMATIC_ARM, "prismatic_arm.toml"))


def central(function, x: np.ndarray) -> np.ndarray:
    """d function / d x by central differences: column j is the derivative by x_j."""
    columns = [
        (function(x + STEP * e) - function(x - STEP * e)) / (2 * STEP) for e in np.eye(x.size)
    ]
    return np.stack(columns, axis=-1)


def assert_close(actual, expected, what: str, tolerance: float = 1e-6) -> None:
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(np.asarray(actual) - expected)))
    assert error <= tolerance * scale, f"{what}: max error {error:.3g} (scale {scale:.3g})"


def check_against_finite_differences(model: symkin.Model, seed: int, **extra) -> None:
    """Every output of :func:`symkin.dynamics_derivatives` at three random states against
    central differences of the generated tau, forward dynamics and Jacobian."""
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q, dq, ddq = rng.uniform(-1.5, 1.5, size=(3, model.robot.dof))
        check_state(model, q, dq, ddq, extra)


def check_state(model, q, dq, ddq, extra) -> None:
    module = generated_numpy_module(model, "derivatives")
    arguments = dynamics_arguments(model, extra)

    def inverse(*state):
        return module.inverse_dynamics(*state, **arguments)

    d = symkin.dynamics_derivatives(model, q, dq, ddq, extra)
    tau = inverse(q, dq, ddq)
    assert_close(d.torque, tau, "tau", 1e-12)
    assert_close(d.dtau_dq, central(lambda x: inverse(x, dq, ddq), q), "dtau/dq")
    assert_close(d.dtau_ddq, central(lambda x: inverse(q, x, ddq), dq), "dtau/ddq")
    assert_close(d.mass_matrix, central(lambda x: inverse(q, dq, x), ddq), "dtau/dddq = M")

    def forward(*state):
        return module.forward_dynamics(*state, **arguments)

    assert_close(d.dddq_dq, central(lambda x: forward(x, dq, tau), q), "dddq/dq")
    assert_close(d.dddq_ddq, central(lambda x: forward(q, x, tau), dq), "dddq/ddq")
    assert_close(d.dddq_dtau, central(lambda x: forward(q, dq, x), tau), "dddq/dtau")
    kinematics = generated_numpy_module(model, "kinematics")
    check_jacobian_rate(kinematics, d, q, dq, ddq, arguments["p"])


def check_jacobian_rate(kinematics, d, q, dq, ddq, p) -> None:
    """Along the trajectory q(t) = q + t dq + t^2/2 ddq: dJ/dt = d/dt J(q(t)) and
    d/dt (J dq(t)) = J ddq + dJ/dt dq at t = 0 (central differences in t)."""

    def jacobian(t: float) -> np.ndarray:
        return kinematics.fk_jacobian(q + t * dq + t * t / 2 * ddq, p)[1]

    rate = (jacobian(STEP) - jacobian(-STEP)) / (2 * STEP)
    assert_close(d.jacobian_dot, rate, "dJ/dt")
    twist_rate = (jacobian(STEP) @ (dq + STEP * ddq) - jacobian(-STEP) @ (dq - STEP * ddq)) / (
        2 * STEP
    )
    assert_close(jacobian(0.0) @ ddq + d.jacobian_dot_dq, twist_rate, "dJ/dt dq")


def test_tangent_sweep_is_the_chain_rule():
    """x -> s0 = x*y -> s1 = sin(s0) + y: ds1/dx = cos(x y) y, by hand."""
    x, y, s0, s1 = sp.symbols("x y s0 s1", real=True)
    named, (rate,) = tangent_assignments(
        [(s0, x * y), (s1, sp.sin(s0) + y)], [sp.Matrix([s1])], {x: 1}, "d"
    )
    values = {s0: x * y}
    for symbol, expr in named:
        values[symbol] = expr.xreplace(values)
    assert sp.simplify(rate[0].xreplace(values).xreplace(values) - sp.cos(x * y) * y) == 0


def test_pendulum_derivatives_match_the_hand_derivation():
    """One link, m = 2 kg, COM 0.5 m along x1, izz = 0.1, gravity -9.81 z0, joint about z0 with
    frame 1 tilted so gravity acts in the swing plane (alpha = 0, base rotated about x):
    tau = (I + m c^2) ddq + m g c cos(q) => dtau/dq = -m g c sin(q), dtau/ddq = 0."""
    text = """
name = "pendulum"
[base]
rpy = [90, 0, 0]
[[joints]]
type = "revolute"
[joints.link]
mass = 2.0
com = [0.5, 0.0, 0.0]
inertia = { ixx = 0.0, iyy = 0.1, izz = 0.1, ixy = 0.0, ixz = 0.0, iyz = 0.0 }
"""
    model = symkin.derive(symkin.robot_from_toml(text, "pendulum.toml"))
    q = 0.7
    d = symkin.dynamics_derivatives(model, [q], [0.3], [1.1])
    np.testing.assert_allclose(d.dtau_dq, [[-2.0 * 9.81 * 0.5 * np.sin(q)]], rtol=1e-12)
    np.testing.assert_allclose(d.dtau_ddq, [[0.0]], atol=1e-15)
    np.testing.assert_allclose(d.dddq_dtau, [[1 / (0.1 + 2.0 * 0.25)]], rtol=1e-12)


@pytest.mark.slow
def test_prismatic_arm_with_friction_matches_finite_differences():
    check_against_finite_differences(prismatic_model(), seed=3)


@pytest.mark.slow
def test_symbolic_inertial_data_passes_through():
    """rpr without its file's inertial data: every link's is given as values (``--set m1=...``)."""
    model = symkin.derive(robot_from_toml(without_inertials("rpr"), "rpr.toml"))
    rng = np.random.default_rng(5)
    values = {}
    for i in range(1, 4):
        principal = rng.uniform(0.01, 0.1, 3)
        values |= {f"m{i}": rng.uniform(0.5, 2.0)}
        values |= {f"c{a}{i}": rng.uniform(-0.1, 0.1) for a in "xyz"}
        values |= {f"i{a}{i}": v for a, v in zip(("xx", "yy", "zz"), principal, strict=True)}
        values |= {f"i{a}{i}": 0.0 for a in ("xy", "xz", "yz")}
    check_against_finite_differences(model, seed=4, **values)


@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_six_and_seven_joint_arms_match_finite_differences(name, model_of):
    check_against_finite_differences(model_of(name), seed=7)


@pytest.mark.slow
def test_urdf_loaded_ur5_matches_finite_differences():
    """The UR5 of example-robot-data, read from its URDF (placement form, not DH)."""
    from test_urdf_oracles import ROBOTS, urdf_path

    relative, tip = ROBOTS["ur5"]
    robot = symkin.load_robot(urdf_path(relative), tip=tip)
    check_against_finite_differences(symkin.derive(robot), seed=8)


def test_wrong_lengths_are_one_clear_error():
    with pytest.raises(symkin.SymkinError, match=r"needs 3 values"):
        symkin.dynamics_derivatives(prismatic_model(), [0, 0], [0, 0, 0], [0, 0, 0])


@pytest.mark.slow
def test_eval_derivatives_json_holds_every_key(capsys, tmp_path):
    path = tmp_path / "prismatic_arm.toml"
    path.write_text(PRISMATIC_ARM, encoding="utf-8")
    state = {"q": [0.3, 0.5, -0.2], "dq": [0.1, -0.2, 0.4], "ddq": [1.0, 2.0, -1.0]}
    values = [f"--{k}={','.join(map(str, v))}" for k, v in state.items()]
    code = main(["eval", str(path), *values, "--dynamics", "--derivatives", "--json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    data = json.loads(out.out)
    d = symkin.dynamics_derivatives(prismatic_model(), **state)
    for key in ("dtau_dq", "dtau_ddq", "dddq_dq", "dddq_ddq", "dddq_dtau"):
        np.testing.assert_allclose(data[key], getattr(d, key), rtol=1e-12, atol=1e-15)
    assert np.shape(data["jacobian_dot"]) == (6, 3)
    assert np.shape(data["jacobian_dot_dq"]) == (6,)
    np.testing.assert_allclose(data["tau"], d.torque, rtol=1e-12)


def test_eval_derivatives_without_rates_is_one_message(capsys):
    assert main(["eval", "planar_2r", "--q", "0.3,0.5", "--derivatives"]) == 2
    err = capsys.readouterr().err
    assert "--derivatives needs --dq and --ddq" in err
    assert "Traceback" not in err


def test_derive_derivatives_without_dynamics_is_one_message(capsys, tmp_path):
    arguments = ["derive", "planar_2r", "--out", str(tmp_path), "--derivatives"]
    assert main([*arguments, "--kinematics-only"]) == 2
    assert "--derivatives needs the dynamics" in capsys.readouterr().err

"""Numeric entry points derive and build only what they use, once (issue 15).

``kinematic_state``, ``solve_ik``, ``symkin eval`` and ``symkin ik`` run on the generated
kernels of the product form: they must not derive the factored determinant, the singular set
or the readable (contracted) kinematics, and a repeated call must not rebuild the module.
The checks are structural (a spy on the determinant and on the module builder, the model's
cached attributes), never timings; the numbers are checked against the independent numeric DH
product of ``tests/numeric_dh.py`` (complex-step Jacobian).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import symkin
from numeric_dh import NumericRobot
from symkin.cli import main
from symkin.derive import Model
from symkin.io import load_robot
from symkin.io.robot_file import robot_from_toml
from symkin.runtime import modules
from symkin.solve.evaluate import kinematic_state

JACO = Path(__file__).parent / "data" / "jaco_like.toml"
Q = np.array([0.3, -0.5, 0.5, -1.2, -0.6, 0.8])


def _forbidden(*_: object, **__: object) -> None:
    raise AssertionError("a numeric path derived a symbolic result it does not use")


@pytest.fixture
def no_symbolic_extras(monkeypatch: pytest.MonkeyPatch) -> None:
    """Any call of a closed form (determinant, singular set, adjugate inverse, symbolic
    manipulability) or of Lagrange's equations fails the test."""
    for method in (
        "determinant_form",
        "determinant",
        "singular_form",
        "singular_configurations",
        "inverse_form",
        "manipulability_form",
        "manipulability",
    ):
        monkeypatch.setattr(Model, method, _forbidden)
    monkeypatch.setattr(Model, "lagrange", property(_forbidden))


def _fresh_model(name: str) -> Model:
    """A planar 2R with inertial data under a name no other test uses, so that no module of it
    is built yet in this process."""
    text = f'''
name = "{name}"
convention = "standard"
gravity = [0, -9.81, 0]
[parameters]
L1 = 0.7
[[joints]]
type = "revolute"
a = "L1"
[joints.link]
mass = 1.5
com = [-0.35, 0, 0]
inertia = {{ ixx = 0.001, iyy = 0.06, izz = 0.06, ixy = 0, ixz = 0, iyz = 0 }}
[[joints]]
type = "revolute"
a = 0.4
[joints.link]
mass = 0.8
com = [-0.2, 0, 0]
inertia = {{ ixx = 0.001, iyy = 0.01, izz = 0.01, ixy = 0, ixz = 0, iyz = 0 }}
'''
    return Model(robot_from_toml(text, f"<{name}>"))


@pytest.fixture
def builds(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The stems of the generated modules built (imported from new source) during a test."""
    built: list[str] = []
    original = modules.module_from_source

    def spy(source: str, stem: str):
        built.append(stem)
        return original(source, stem)

    monkeypatch.setattr(modules, "module_from_source", spy)
    return built


def test_kinematic_state_builds_one_module_for_repeated_calls(builds: list[str]) -> None:
    model = _fresh_model("numeric_paths_reuse")
    first = kinematic_state(model, [0.2, 0.4])
    for q in ([0.1, 0.3], [0.2, 0.4], [-1.0, 2.0]):
        kinematic_state(model, q, overrides={"L1": 0.5})
    # An equal model (another object of the same robot) shares the module too.
    again = kinematic_state(Model(model.robot), [0.2, 0.4])
    assert builds == ["numeric_paths_reuse_numpy_kinematics"]
    np.testing.assert_array_equal(first.transform, again.transform)
    # Points get a module of their own, once per point set.
    for _ in range(3):
        kinematic_state(model, [0.2, 0.4], [1.0, -1.0], points=[(2, (0.1, 0.0, 0.0))])
    assert builds == [
        "numeric_paths_reuse_numpy_kinematics",
        "numeric_paths_reuse_numpy_points",
    ]


def test_kinematic_state_derives_no_determinant_and_no_readable_form(
    no_symbolic_extras: None,
) -> None:
    model = _fresh_model("numeric_paths_lean")
    state = kinematic_state(model, [0.2, 0.4], [1.0, -1.0], [0.5, 0.0], points=[(2, (0, 0, 0))])
    # The simplified model's own kinematics (the contraction) was never derived.
    assert "kinematics" not in model.__dict__
    assert "geometric_jacobian" not in model.__dict__
    # Planar 2R, L1 = 0.7, L2 = 0.4 (Spong eq. 3.19): det J = L1 L2 sin(q2).
    assert state.task_rows == ("x", "y")
    assert state.determinant == pytest.approx(0.7 * 0.4 * np.sin(0.4), rel=1e-12)
    tip = [0.7 * np.cos(0.2) + 0.4 * np.cos(0.6), 0.7 * np.sin(0.2) + 0.4 * np.sin(0.6), 0]
    np.testing.assert_allclose(state.points[0].position, tip, atol=1e-15)


def test_dynamics_and_trajectory_modules_leave_out_what_they_do_not_use(
    no_symbolic_extras: None,
) -> None:
    model = _fresh_model("numeric_paths_dynamics")
    numpy_dynamics = modules.generated_numpy_module(model)
    assert hasattr(numpy_dynamics, "forward_dynamics")
    assert not hasattr(numpy_dynamics, "coriolis_matrix")
    kinematics = modules.generated_numpy_module(model, "kinematics")
    assert {"fk", "position", "fk_jacobian"} <= set(vars(kinematics))
    assert not {"det", "manipulability"} & set(vars(kinematics))
    assert "kinematics" not in model.__dict__
    # Static balance of the 2R at q = (0, 0) by hand: G1 = g (m1 c1 + m2 (L1 + c2)) with
    # centres of mass c1 = 0.35, c2 = 0.2 along x, gravity -9.81 along y of the base.
    g = 9.81
    gravity = numpy_dynamics.gravity([0.0, 0.0], np.array([0.7]))
    assert gravity[0] == pytest.approx(g * (1.5 * 0.35 + 0.8 * (0.7 + 0.2)), rel=1e-12)
    assert gravity[1] == pytest.approx(g * 0.8 * 0.2, rel=1e-12)


def test_solve_ik_derives_no_determinant(no_symbolic_extras: None) -> None:
    model = Model(load_robot("planar_3r"))  # not derive(): its cached model may be used
    reference = NumericRobot.from_robot(model.robot)
    target = reference.fk([0.3, 0.6, -0.4])
    result = symkin.solve_ik(model, target, q0=[0.2, 0.5, -0.3])
    assert result.success
    np.testing.assert_allclose(reference.fk(result.q)[:2, 3], target[:2, 3], atol=1e-9)
    assert "kinematics" not in model.__dict__


@pytest.mark.slow
def test_jaco_like_numbers_without_its_determinant(no_symbolic_extras: None) -> None:
    """The issue's arm, whose factored determinant takes minutes: numbers in seconds, equal to
    the numeric DH product and its complex-step Jacobian."""
    model = Model(load_robot(str(JACO)))
    reference = NumericRobot.from_robot(model.robot)
    state = kinematic_state(model, Q)
    np.testing.assert_allclose(state.transform, reference.fk(Q), atol=1e-12)
    jacobian = reference.jacobian(Q, method="complex")
    np.testing.assert_allclose(state.jacobian, jacobian, atol=1e-12)
    assert state.determinant == pytest.approx(np.linalg.det(jacobian), rel=1e-9)
    target = reference.fk(Q + 0.2)
    result = symkin.solve_ik(model, target, q0=Q)
    assert result.success
    np.testing.assert_allclose(reference.fk(result.q), target, atol=1e-9)
    assert "kinematics" not in model.__dict__


@pytest.mark.slow
def test_eval_and_ik_commands_on_the_jaco_like_arm(
    no_symbolic_extras: None, capsys: pytest.CaptureFixture[str]
) -> None:
    q = ",".join(str(v) for v in Q)
    assert main(["eval", str(JACO), "--q", q, "--json"]) == 0
    reference = NumericRobot.from_robot(load_robot(str(JACO)))
    data = json.loads(capsys.readouterr().out)
    assert data["det"] == pytest.approx(np.linalg.det(reference.jacobian(Q, "complex")), rel=1e-9)
    target = ",".join(f"{v:.15g}" for v in reference.fk(Q + 0.2)[:3, 3])
    assert main(["ik", str(JACO), "--target", target, "--task", "x,y,z", "--q0", q]) == 0

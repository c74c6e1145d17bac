"""Base inertial parameters: fewer link parameters, the same joint torques, shorter code.

The torques with base parameters are compared with the recursion on the file's own data (centre
of mass form, a separate code path) and, for the PUMA 560, with Robotics Toolbox and Pinocchio
in ``test_dynamics_oracles.py``.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.derive import Model
from symkin.derive.base_parameters import (
    PARAMETER_NAMES,
    barycentric_definitions,
    barycentric_symbols,
    base_parameters,
    symbolic_base_parameters,
)
from symkin.derive.recursion import Recorder, joint_torques
from symkin.errors import RobotWarning
from symkin.kernels import dynamics_kernels
from symkin.robot import Link

pytestmark = pytest.mark.slow


def puma(numeric: bool) -> symkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotWarning)
        robot = symkin.load_robot("puma560")
    return robot.with_parameter_values() if numeric else robot


def random_link(rng: np.random.Generator) -> Link:
    """A physical rigid body: positive mass, principal moments meeting the triangle inequality,
    rotated by a random orthogonal matrix (so every product of inertia is non-zero)."""
    moments = rng.uniform(0.05, 0.2, 3)
    moments[2] = rng.uniform(abs(moments[0] - moments[1]) + 0.01, moments[0] + moments[1] - 0.01)
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    tensor = rotation @ np.diag(moments) @ rotation.T
    return Link(
        mass=sp.Float(rng.uniform(0.5, 3.0)),
        com=tuple(sp.Float(c) for c in rng.uniform(-0.2, 0.2, 3)),
        inertia=tuple(
            sp.Float(tensor[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
        ),
    )


def with_random_links(name: str, seed: int) -> symkin.Robot:
    rng = np.random.default_rng(seed)
    with warnings.catch_warnings():
        # The PUMA's own link 3 breaks the triangle inequality; its data are replaced here.
        warnings.simplefilter("ignore", RobotWarning)
        robot = symkin.load_robot(name)
    joints = tuple(dataclasses.replace(j, link=random_link(rng)) for j in robot.joints)
    return dataclasses.replace(robot, joints=joints).with_parameter_values()


def torque_function(robot: symkin.Robot, grouped: bool):
    model = Model(robot)
    recorder = Recorder("x")
    inertial = base_parameters(robot, model.kinematics) if grouped else None
    torque = joint_torques(
        robot, model.kinematics, recorder, model.dq, model.ddq, robot.gravity, inertial
    )
    return sp.lambdify(
        [model.q, model.dq, model.ddq],
        torque,
        modules="numpy",
        cse=lambda e: (recorder.assignments, e),
    )


@pytest.mark.parametrize("name", ["stanford", "cylindrical_rtt_wrist", "ur5"])
def test_base_parameters_give_the_same_torques(name):
    # Prismatic joints (Stanford, cylindrical) and three parallel axes (UR5) fold differently.
    robot = with_random_links(name, seed=len(name))
    model = Model(robot)
    grouped = base_parameters(robot, model.kinematics)
    assert grouped is not None
    nonzero = sum(
        1
        for link in grouped
        for value in (*link.inertia[:], *link.first_moment[:], link.mass)
        if value != 0
    )
    # Random data fill all ten parameters of each link; some must have been folded away.
    assert nonzero < 10 * robot.dof
    with_file_data, with_base = torque_function(robot, False), torque_function(robot, True)
    rng = np.random.default_rng(3)
    for _ in range(10):
        q, dq, ddq = rng.uniform(-2.0, 2.0, (3, robot.dof))
        expected = np.array(with_file_data(q, dq, ddq), dtype=float)
        actual = np.array(with_base(q, dq, ddq), dtype=float)
        np.testing.assert_allclose(actual, expected, rtol=0, atol=1e-9 * np.max(np.abs(expected)))


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford"])
def test_symbolic_base_parameters_give_the_same_torques(name):
    # Symbols for the kept parameters, defined in the barycentric ones: at random link data the
    # recursion on the symbols (their definitions evaluated) gives the torques of the recursion
    # on the file-form data (mass, centre of mass, inertia about it).
    robot = with_random_links(name, seed=7)
    model = Model(robot)
    links, definitions = symbolic_base_parameters(robot, model.kinematics)
    delta = barycentric_symbols(robot.dof)
    assert len(delta) == 10 * robot.dof
    assert {s for s, _ in definitions} == {
        v for link in links for v in (*link.inertia, *link.first_moment, link.mass) if v != 0
    }
    assert len(definitions) < 10 * robot.dof
    # A symbol is named for its own parameter (ZZ2R: zz2 plus others folded into it), and the
    # others are ones folded away, never another kept parameter.
    by_name = {s.name: s for s in delta}
    own = {symbol: by_name[symbol.name.rstrip("R").lower()] for symbol, _ in definitions}
    for symbol, expr in definitions:
        assert expr.coeff(own[symbol]) == 1, symbol
        assert expr.free_symbols.isdisjoint(set(own.values()) - {own[symbol]}), symbol
    values = {
        s: float(barycentric_definitions(j.link)[n])
        for s, (j, n) in zip(
            delta,
            ((j, n) for j in robot.joints for n in PARAMETER_NAMES),
            strict=True,
        )
    }
    beta = {symbol: expr.xreplace(values) for symbol, expr in definitions}
    recorder = Recorder("y")
    torque = joint_torques(
        robot, model.kinematics, recorder, model.dq, model.ddq, robot.gravity, links
    )
    with_beta = sp.lambdify(
        [model.q, model.dq, model.ddq, list(beta)],
        torque,
        modules="numpy",
        cse=lambda e: (recorder.assignments, e),
    )
    with_file_data = torque_function(robot, False)
    rng = np.random.default_rng(4)
    for _ in range(10):
        q, dq, ddq = rng.uniform(-2.0, 2.0, (3, robot.dof))
        expected = np.array(with_file_data(q, dq, ddq), dtype=float)
        actual = np.array(with_beta(q, dq, ddq, [float(v) for v in beta.values()]), dtype=float)
        np.testing.assert_allclose(actual, expected, rtol=0, atol=1e-9 * np.max(np.abs(expected)))


def test_symbolic_base_parameters_need_numeric_geometry():
    robot = puma(numeric=False)
    assert symbolic_base_parameters(robot, Model(robot).kinematics) is None


def test_parallel_axis_theorem_on_a_rod():
    # A uniform rod of mass m and length l along x, centre at (l/2, 0, 0): about its end the
    # moment about y and z is m l^2 / 3 (textbook), about x it stays 0; first moment m l / 2.
    m, length = 2.0, 0.6
    rod = Link(
        mass=m, com=(length / 2, 0, 0), inertia=(0, m * length**2 / 12, m * length**2 / 12, 0, 0, 0)
    )
    values = {k: float(v) for k, v in barycentric_definitions(rod).items()}
    assert values["yy"] == pytest.approx(m * length**2 / 3)
    assert values["zz"] == pytest.approx(m * length**2 / 3)
    assert values["xx"] == pytest.approx(0.0)
    assert values["mx"] == pytest.approx(m * length / 2)
    assert values["m"] == m


def test_robots_with_parameters_keep_their_link_data():
    # Folding depends on the geometry's numbers: with a parameter vector p it must not happen.
    robot = puma(numeric=False)
    assert base_parameters(robot, Model(robot).kinematics) is None


def test_numeric_puma_inverse_dynamics_is_shorter():
    counts = {
        numeric: {
            k.name: k.operation_counts["total"] for k in dynamics_kernels(Model(puma(numeric)))
        }
        for numeric in (False, True)
    }
    # The issue's target: under 400 operations with PUMA 560's numeric inertial parameters.
    assert counts[True]["inverse_dynamics"] < 400
    for kernel in ("mass_matrix", "gravity", "coriolis", "inverse_dynamics"):
        assert counts[True][kernel] < counts[False][kernel], kernel


# One very large first moment (the reproduction, taken from Robotics Toolbox's IRB140
# data): folding used to round every base parameter to 1e-13 of the largest one, which moved
# link 2's gravity torque from 115.1764 to 115.4567.
SCALE_ROBOT = """
name = "scale"
[[joints]]
type = "revolute"
alpha = 90
[joints.link]
mass = 16.0
com = [0, 0, 2.0e5]
[[joints]]
type = "revolute"
a = 0.36
[joints.link]
mass = 20.86205
com = [-4.56, -5.86, 0]
"""


def test_a_huge_parameter_does_not_coarsen_the_others():
    from symkin.solve.evaluate import dynamic_state

    robot = symkin.robot_from_toml(SCALE_ROBOT, "scale.toml")
    assert base_parameters(robot, symkin.derive(robot).kinematics) is not None  # folded
    q2 = 0.7
    # By hand: z_1 = Rz(q1) Rx(90) z, so link 2's centre of mass is at the height
    # (a2 + cx2) sin q2 + cy2 cos q2 and G2 = m2 g ((a2 + cx2) cos q2 - cy2 sin q2); link 1's
    # centre lies on the horizontal axis z_1 and neither link's height depends on q1.
    expected = 20.86205 * 9.81 * ((0.36 - 4.56) * np.cos(q2) + 5.86 * np.sin(q2))
    gravity = dynamic_state(symkin.derive(robot), [0.3, q2]).gravity
    np.testing.assert_allclose(gravity, [0.0, expected], rtol=1e-12, atol=1e-9)


def test_folded_torques_equal_unfolded_ones_each_to_its_own_size():
    from symkin.solve.evaluate import dynamic_state

    folded = symkin.robot_from_toml(SCALE_ROBOT, "scale.toml")
    # A named parameter (even an unused one) switches the folding off: the same robot,
    # computed the other way.
    unfolded = symkin.robot_from_toml(
        SCALE_ROBOT.replace('name = "scale"', 'name = "scale"\n[parameters]\nunused = 1.0'),
        "scale.toml",
    )
    assert base_parameters(unfolded, symkin.derive(unfolded).kinematics) is None
    rng = np.random.default_rng(22)
    for _ in range(20):
        q, dq, ddq = rng.uniform(-2, 2, (3, 2))
        ours = dynamic_state(symkin.derive(folded), q, dq, ddq)
        other = dynamic_state(symkin.derive(unfolded), q, dq, ddq)
        for name in ("torque", "gravity", "coriolis"):
            a, b = getattr(ours, name), getattr(other, name)
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9, err_msg=name)
        np.testing.assert_allclose(ours.mass_matrix, other.mass_matrix, rtol=1e-9, atol=1e-9)

"""The placement form (URDF-like joints: origin + axis) against an independent evaluation.

The expected poses are URDF's own rule evaluated with SciPy rotations, joint by joint,
``T = prod_i origin_i * motion_i(axis_i, q_i) * tool`` with ``motion_i`` a rotation by
``q_i`` about (or a translation by ``q_i`` along) the unit axis, never symkin's canonical
frames; the Jacobian against central differences of that pose; the dynamics Lagrange against
Newton–Euler (two derivations that share nothing past the link transforms).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

import symkin
from symkin.errors import RobotError, RobotWarning
from symkin.io.placement import rotation_taking_z_to

DATA = Path(__file__).parent / "data"
ARM = DATA / "placed_arm.toml"

# (xyz, rpy, axis, type) of tests/data/placed_arm.toml, as written there.
ARM_JOINTS = [
    ([0, 0, 0.25], [0, 0, 0], [0, 0, 1], "revolute"),
    ([0.05, 0, 0.2], [0.2, 0, 0], [0, 1, 0], "revolute"),
    ([0.3, 0.02, 0], [0, np.pi / 2, 0.4], [0, 0, -1], "revolute"),
    ([0, 0.25, 0.03], [0.1, -0.3, 0.2], [0.6, 0, 0.8], "prismatic"),
]
ARM_TOOL = ([0, 0, 0.1], [0, 0.5, 0])


def frame(xyz, rpy) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3] = Rotation.from_euler("xyz", rpy).as_matrix()  # extrinsic x, y, z = URDF rpy
    matrix[:3, 3] = xyz
    return matrix


def motion(axis, q: float, kind: str) -> np.ndarray:
    unit = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    matrix = np.eye(4)
    if kind == "revolute":
        matrix[:3, :3] = Rotation.from_rotvec(unit * q).as_matrix()
    else:
        matrix[:3, 3] = unit * q
    return matrix


def urdf_pose(q: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    for (xyz, rpy, axis, kind), qi in zip(ARM_JOINTS, q, strict=True):
        pose = pose @ frame(xyz, rpy) @ motion(axis, qi, kind)
    return pose @ frame(*ARM_TOOL)


@pytest.fixture(scope="module")
def arm_model() -> symkin.Model:
    return symkin.derive(symkin.load_robot(ARM))


def lambdified(model: symkin.Model, matrix: sp.MatrixBase):
    return sp.lambdify([model.q], matrix, modules="numpy")


def test_forward_kinematics_is_urdfs_product_of_origins_and_axis_motions(arm_model):
    fk = lambdified(arm_model, arm_model.forward_kinematics)
    rng = np.random.default_rng(16)
    for q in rng.uniform(-2.0, 2.0, (10, 4)):
        np.testing.assert_allclose(np.array(fk(q), dtype=float), urdf_pose(q), atol=1e-12)


def test_geometric_jacobian_is_central_differences_of_the_urdf_pose(arm_model):
    jacobian = lambdified(arm_model, arm_model.geometric_jacobian)
    rng = np.random.default_rng(17)
    step = 1e-6
    for q in rng.uniform(-2.0, 2.0, (5, 4)):
        expected = np.zeros((6, 4))
        for k in range(4):
            dq = np.zeros(4)
            dq[k] = step
            plus, minus = urdf_pose(q + dq), urdf_pose(q - dq)
            expected[:3, k] = (plus[:3, 3] - minus[:3, 3]) / (2 * step)
            rate = (plus[:3, :3] - minus[:3, :3]) / (2 * step) @ urdf_pose(q)[:3, :3].T
            expected[3:, k] = [rate[2, 1], rate[0, 2], rate[1, 0]]
        np.testing.assert_allclose(np.array(jacobian(q), dtype=float), expected, atol=1e-8)


@pytest.mark.slow
def test_lagrange_equals_newton_euler_on_placed_joints(arm_model):
    lagrange, ne = arm_model.lagrange, arm_model.newton_euler
    symbols = [arm_model.q, arm_model.dq, arm_model.ddq]
    by_lagrange = sp.lambdify(symbols, lagrange.expanded(lagrange.inverse_dynamics))
    by_ne = sp.lambdify(symbols, ne.expanded(ne.inverse_dynamics))
    rng = np.random.default_rng(18)
    for q, dq, ddq in rng.uniform(-2.0, 2.0, (4, 3, 4)):
        expected = np.array(by_ne(q, dq, ddq), dtype=float)
        np.testing.assert_allclose(by_lagrange(q, dq, ddq), expected, atol=1e-10)


@pytest.mark.parametrize(
    "axis", [(0, 0, 1), (0, 0, -1), (1, 0, 0), (0, -1, 0), (0.6, 0, 0.8), (-0.48, 0.6, -0.64)]
)
def test_rotation_taking_z_to_axis_is_a_rotation_onto_the_axis(axis):
    rotation = np.array(rotation_taking_z_to([sp.sympify(a) for a in axis]), dtype=float)
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(rotation) == pytest.approx(1.0)
    np.testing.assert_allclose(rotation[:, 2], axis, atol=1e-15)


def test_coordinate_axes_give_exact_placements():
    robot = symkin.load_robot(ARM)
    assert robot.convention == "placement"
    assert all(entry.is_Integer for entry in robot.joints[1].placement[:3, :3] if entry == 0)
    # Joint 2 turns about y: its canonical placement is Rx(0.2) * Rx(-pi/2), exactly.
    assert robot.joints[1].placement[0, :3].tolist() == [[1, 0, 0]]


HEADER = 'name = "bad"\nconvention = "placement"\n'


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("[[joints]]\ntype = 'revolute'\n", "joint 1: 'axis' is missing"),
        ("[[joints]]\ntype = 'revolute'\naxis = [0, 0, 0]\n", "joint 1: 'axis' must be a nonzero"),
        ("[[joints]]\ntype = 'revolute'\naxis = [0, 1]\n", "joint 1: 'axis' must be a list of 3"),
        ("[[joints]]\ntype = 'revolute'\naxis = [0, 0, 1]\nalpha = 90\n",
         "joint 1: unknown key 'alpha'"),
        ("[[joints]]\ntype = 'revolute'\naxis = [0, 0, 1]\norigin = { xyz = [1, 2] }\n",
         "joint 1: 'origin.xyz' must be a list of 3"),
    ],
)  # fmt: skip
def test_placement_file_errors_name_file_joint_and_key(body, message):
    with pytest.raises(RobotError, match=r"^bad\.toml: ") as caught:
        symkin.robot_from_toml(HEADER + body, "bad.toml")
    assert message in str(caught.value)


def test_non_unit_axis_is_normalised_and_said_once():
    text = HEADER + "[[joints]]\ntype = 'prismatic'\naxis = [0, 0, 2]\n"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = symkin.robot_from_toml(text, "bad.toml")
    messages = [str(w.message) for w in caught if issubclass(w.category, RobotWarning)]
    assert messages == [
        "bad.toml: joint 1: 'axis' [0.0, 0.0, 2.0] is not a unit vector; normalised"
    ]
    assert robot.joints[0].placement == sp.ImmutableMatrix(sp.eye(4))


def test_latex_prints_the_placement_table_instead_of_the_dh_table(tmp_path, capsys):
    from symkin.cli import main

    assert main(["latex", str(ARM), "-o", str(tmp_path / "arm.tex"), "--sections", "dh"]) == 0
    capsys.readouterr()
    text = (tmp_path / "arm.tex").read_text(encoding="utf-8")
    assert r"A_{i} = {}^{i-1}T_{i} &= P_{i}\, \mathrm{Rot}_{z}(\theta_{i})" in text
    assert r"\alpha_{i" not in text
    # Joint 2: xyz as written; roll 0.2 - pi/2 (the turn that puts its y axis on z).
    assert r"$2$ & revolute & $0.05$ & $0$ & $0.2$ & $-1.3708$ & $0$ & $0$ & $q_{2}$ & $0$" in text


@pytest.mark.slow  # show derives the determinant: ~50 s for this float-valued arm
def test_show_prints_the_placement_table(capsys):
    from symkin.cli import main

    assert main(["show", str(ARM)]) == 0
    out = capsys.readouterr().out
    assert "4 joints, placed joints" in out
    assert "Placed joints (A_i = P_i Rz(theta_i) Tz(d_i); angles in rad):" in out
    assert "DH table" not in out


def test_velocity_and_effort_limits_are_read_and_checked():
    text = HEADER + "[[joints]]\ntype = 'revolute'\naxis = [0, 0, 1]\nmax_velocity = 2.5\n"
    joint = symkin.robot_from_toml(text + "max_effort = 40\n", "arm.toml").joints[0]
    assert (joint.max_velocity, joint.max_effort) == (2.5, 40.0)
    with pytest.raises(RobotError, match=r"joint 1: 'max_effort' must be > 0, got -1"):
        symkin.robot_from_toml(text + "max_effort = -1\n", "arm.toml")


@pytest.mark.parametrize("scale", [1e200, 1e-200])
def test_a_huge_or_tiny_axis_is_the_same_direction(scale):
    """Normalised without squaring its entries (1e200 squared overflows, 1e-200 underflows):
    the joint turns about the same tilted axis as ``[1, 1, 0]``."""

    def placed(axis: str) -> sp.Matrix:
        text = HEADER + f"[[joints]]\ntype = 'revolute'\naxis = {axis}\n"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RobotWarning)
            return symkin.robot_from_toml(text, "arm.toml").joints[0].placement

    expected = np.array(placed("[1, 1, 0]").evalf(), dtype=float)
    found = np.array(placed(f"[{scale!r}, {scale!r}, 0]").evalf(), dtype=float)
    np.testing.assert_allclose(found, expected, atol=1e-12)
    # z of the placement is the axis: (1, 1, 0) / sqrt(2), by hand
    np.testing.assert_allclose(expected[:3, 2], [2**-0.5, 2**-0.5, 0.0], atol=1e-12)

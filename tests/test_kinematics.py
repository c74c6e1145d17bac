"""Forward kinematics of ``symkin.derive`` against independent references.

Expected values come from ``tests/numeric_dh.py`` (a NumPy product of elementary transforms
written from the conventions text), from textbook closed forms typed in by hand, and from
Franka's published zero pose of the Panda, never from symkin's own output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from numeric_dh import (
    ALL_ROBOTS,
    CATALOGUE,
    DEG,
    HAND_MODIFIED_BASE,
    HAND_MODIFIED_TOOL,
    HAND_STANDARD_BASE,
    HAND_STANDARD_TOOL,
    Rx,
    Ry,
    Rz,
    Tz,
    euler_zyx,
    function,
    model,
    numeric_function,
    reference,
    robot,
    samples,
    wrap,
)
from symkin.derive import derive
from symkin.errors import ParameterError
from symkin.io.robot_file import catalogue_names, robot_from_toml

FK_TOL = 1e-12


def test_catalogue_is_the_one_tested() -> None:
    assert tuple(catalogue_names()) == CATALOGUE


# ---------------------------------------------------------------------------------------------
# Forward kinematics == numeric DH product, every robot
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_forward_kinematics_matches_numeric_dh(name: str) -> None:
    fk = function(name, model(name).forward_kinematics)
    position = function(name, model(name).tool_position)
    for q in samples(name, 1):
        expected = reference(name).fk(q)
        np.testing.assert_allclose(fk(q), expected, rtol=0, atol=FK_TOL)
        np.testing.assert_allclose(position(q).reshape(3), expected[:3, 3], rtol=0, atol=FK_TOL)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_link_and_frame_transforms_match_numeric_dh(name: str) -> None:
    m = model(name)
    assert len(m.link_transforms) == robot(name).dof
    assert len(m.frame_transforms) == robot(name).dof + 1
    links = [function(name, a) for a in m.link_transforms]
    frames = [function(name, t) for t in m.frame_transforms]
    for q in samples(name, 2, 3):
        for i, expected in enumerate(reference(name).link_transforms(q)):
            np.testing.assert_allclose(links[i](q), expected, rtol=0, atol=FK_TOL, err_msg=f"A_{i}")
        for i, expected in enumerate(reference(name).frames(q)):
            np.testing.assert_allclose(
                frames[i](q), expected, rtol=0, atol=FK_TOL, err_msg=f"T_{i}"
            )


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_tool_rotation_is_a_rotation(name: str) -> None:
    fk = function(name, model(name).forward_kinematics)
    for q in samples(name, 3):
        T = fk(q)
        R = T[:3, :3]
        np.testing.assert_allclose(R.T @ R, np.eye(3), rtol=0, atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(T[3], [0, 0, 0, 1], rtol=0, atol=0)


# ---------------------------------------------------------------------------------------------
# The hand-written robots: file details that the numeric reference takes independently
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "base", "tool"),
    [
        ("hand_standard", HAND_STANDARD_BASE, HAND_STANDARD_TOOL),
        ("hand_modified", HAND_MODIFIED_BASE, HAND_MODIFIED_TOOL),
    ],
)
def test_base_and_tool_are_translation_then_fixed_axis_rpy(
    name: str, base: np.ndarray, tool: np.ndarray
) -> None:
    np.testing.assert_allclose(np.array(robot(name).base, dtype=float), base, atol=1e-15)
    np.testing.assert_allclose(np.array(robot(name).tool, dtype=float), tool, atol=1e-15)
    m = model(name)
    np.testing.assert_allclose(function(name, m.frame_transforms[0])([0.0] * 4), base, atol=1e-15)


def test_parameter_without_value_stays_a_symbol() -> None:
    h = sp.Symbol("h", real=True)
    m = model("hand_standard")
    assert h in m.forward_kinematics.free_symbols
    with pytest.raises(ParameterError, match="h"):
        robot("hand_standard").parameter_values()
    # Two values of h give poses that differ exactly by the change of d_1 along z_0.
    q = samples("hand_standard", 4, 1)[0]
    values = {name: value for name, value in robot("hand_standard").parameters if value is not None}
    first = numeric_function(m.tool_position, robot("hand_standard"), (m.q,), {"h": 0.1})(q)
    second = numeric_function(m.tool_position, robot("hand_standard"), (m.q,), {"h": 0.7})(q)
    z0 = HAND_STANDARD_BASE[:3, 2]
    np.testing.assert_allclose((second - first).reshape(3), 0.6 * z0, atol=1e-12)
    assert values == {"a1": -0.3, "d2": -0.2}


def test_negative_a_and_d_are_kept() -> None:
    text = """
    name = "negative"
    [[joints]]
    type = "revolute"
    a = -0.3
    d = -0.2
    """
    m = derive(robot_from_toml(text, "negative.toml"))
    q1 = m.q[0]
    expected = sp.Matrix([-0.3 * sp.cos(q1), -0.3 * sp.sin(q1), -0.2])
    assert sp.simplify(m.tool_position - expected) == sp.zeros(3, 1)


def test_prismatic_joint_keeps_its_constant_theta() -> None:
    text = """
    name = "slide"
    angles = "deg"
    [[joints]]
    type = "prismatic"
    theta = 30
    d = 0.05
    a = 0.2
    """
    m = derive(robot_from_toml(text, "slide.toml"))
    q1 = m.q[0]
    # Rz(30 deg) Tz(q1 + 0.05) Tx(0.2): x = 0.2 cos 30, y = 0.2 sin 30, z = q1 + 0.05
    expected = sp.Matrix([0.2 * sp.sqrt(3) / 2, sp.Rational(1, 10), q1 + 0.05])
    difference = (m.tool_position - expected).applyfunc(lambda e: sp.nsimplify(sp.expand(e)))
    assert difference == sp.zeros(3, 1)
    R = np.array(m.forward_kinematics[:3, :3], dtype=float)
    np.testing.assert_allclose(R, Rz(30 * DEG)[:3, :3], atol=1e-15)


def test_modified_dh_single_joint_closed_form() -> None:
    # Rx(90 deg) Tx(0.1) Rz(25 deg) Tz(q1): Rx(90) = [[1,0,0],[0,0,-1],[0,1,0]] maps the slide
    # (0, 0, q1) to (0, -q1, 0), so p = (0.1, -q1, 0) and R = Rx(90) Rz(25).
    text = """
    name = "craig"
    convention = "modified"
    angles = "deg"
    [[joints]]
    type = "prismatic"
    theta = 25
    a = 0.1
    alpha = 90
    """
    m = derive(robot_from_toml(text, "craig.toml"))
    q1 = m.q[0]
    position = m.tool_position.applyfunc(sp.nsimplify)
    assert sp.simplify(position - sp.Matrix([sp.Rational(1, 10), -q1, 0])) == sp.zeros(3, 1)
    R = np.array(m.forward_kinematics[:3, :3], dtype=float)
    np.testing.assert_allclose(R, (Rx(90 * DEG) @ Rz(25 * DEG))[:3, :3], atol=1e-15)


# ---------------------------------------------------------------------------------------------
# Textbook closed forms (symbolic)
# ---------------------------------------------------------------------------------------------


def _symbols(*names: str) -> list[sp.Symbol]:
    return [sp.Symbol(n, real=True) for n in names]


def _assert_zero(expr: sp.MatrixBase | sp.Expr) -> None:
    difference = sp.simplify(expr)
    assert difference == (sp.zeros(*expr.shape) if isinstance(expr, sp.MatrixBase) else 0)


def test_planar_2r_closed_form() -> None:
    m = model("planar_2r")
    L1, L2 = _symbols("L1", "L2")
    q1, q2 = m.q
    c1, s1, c12, s12 = sp.cos(q1), sp.sin(q1), sp.cos(q1 + q2), sp.sin(q1 + q2)
    expected = sp.Matrix(
        [
            [c12, -s12, 0, L1 * c1 + L2 * c12],
            [s12, c12, 0, L1 * s1 + L2 * s12],
            [0, 0, 1, 0],
            [0, 0, 0, 1],
        ]
    )
    _assert_zero(m.forward_kinematics - expected)


def test_scara_closed_form() -> None:
    m = model("scara")
    L1, L2 = _symbols("L1", "L2")
    q1, q2, q3 = m.q
    c1, s1, c12, s12 = sp.cos(q1), sp.sin(q1), sp.cos(q1 + q2), sp.sin(q1 + q2)
    expected = sp.Matrix(
        [
            [c12, -s12, 0, L1 * c1 + L2 * c12],
            [s12, c12, 0, L1 * s1 + L2 * s12],
            [0, 0, 1, q3],
            [0, 0, 0, 1],
        ]
    )
    _assert_zero(m.forward_kinematics - expected)


def test_planar_3r_closed_form_with_offsets() -> None:
    # theta1 = q1 + 90 deg, theta2 = q2 - 90 deg: link 1 along (cos(q1 + 90), sin(q1 + 90)).
    m = model("planar_3r")
    L1, L2, L3 = _symbols("L1", "L2", "L3")
    q1, q2, q3 = m.q
    x = -L1 * sp.sin(q1) + L2 * sp.cos(q1 + q2) + L3 * sp.cos(q1 + q2 + q3)
    y = L1 * sp.cos(q1) + L2 * sp.sin(q1 + q2) + L3 * sp.sin(q1 + q2 + q3)
    angle = q1 + q2 + q3
    expected = sp.Matrix(
        [
            [sp.cos(angle), -sp.sin(angle), 0, x],
            [sp.sin(angle), sp.cos(angle), 0, y],
            [0, 0, 1, 0],
            [0, 0, 0, 1],
        ]
    )
    _assert_zero(m.forward_kinematics - expected)


def test_rpr_hand_derived_product() -> None:
    # A1 = Rz(q1) Rx(90); A2 = Rz(90) Tz(q2) Rx(90); A3 = Rz(q3) Tx(L3), multiplied by hand:
    #   R = [[s1 s3, s1 c3, c1], [-c1 s3, -c1 c3, s1], [c3, -s3, 0]]
    #   p = ((q2 + L3 s3) s1, -(q2 + L3 s3) c1, L3 c3)
    m = model("rpr")
    (L3,) = _symbols("L3")
    q1, q2, q3 = m.q
    c1, s1, c3, s3 = sp.cos(q1), sp.sin(q1), sp.cos(q3), sp.sin(q3)
    reach = q2 + L3 * s3
    expected = sp.Matrix(
        [
            [s1 * s3, s1 * c3, c1, reach * s1],
            [-c1 * s3, -c1 * c3, s1, -reach * c1],
            [c3, -s3, 0, L3 * c3],
            [0, 0, 0, 1],
        ]
    )
    _assert_zero(m.forward_kinematics - expected)


# ---------------------------------------------------------------------------------------------
# Structure of the printed result
# ---------------------------------------------------------------------------------------------


def test_puma_forward_kinematics_uses_angle_sums() -> None:
    m = model("puma560")
    q2, q3 = m.q[1], m.q[2]
    fk = m.forward_kinematics
    assert fk.has(sp.sin(q2 + q3))
    assert fk.has(sp.cos(q2 + q3))
    split = {sp.sin(q2), sp.cos(q2)}, {sp.sin(q3), sp.cos(q3)}
    for node in sp.preorder_traversal(fk):
        if isinstance(node, sp.Mul):
            factors = set(node.args)
            assert not (factors & split[0] and factors & split[1]), f"uncontracted: {node}"


# ---------------------------------------------------------------------------------------------
# Euler Z-Y-X angles of the tool
# ---------------------------------------------------------------------------------------------


def _rotation_zyx(psi: float, theta: float, phi: float) -> np.ndarray:
    return (Rz(psi) @ Ry(theta) @ Rx(phi))[:3, :3]


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_euler_zyx_forms_agree_and_reproduce_rotation(name: str) -> None:
    m = model(name)
    atan2_form = function(name, sp.Matrix(m.euler_zyx))
    lecture_form = function(name, sp.Matrix(m.euler_zyx_lecture))
    for q in samples(name, 5):
        R = reference(name).fk(q)[:3, :3]
        angles = atan2_form(q).reshape(3)
        lecture = lecture_form(q).reshape(3)
        assert abs(np.cos(angles[1])) > 1e-3, "sample too close to gimbal lock"
        np.testing.assert_allclose(wrap(angles - lecture), 0, atol=1e-10)
        np.testing.assert_allclose(_rotation_zyx(*angles), R, atol=1e-12)
        np.testing.assert_allclose(wrap(angles - euler_zyx(R)), 0, atol=1e-10)
        assert -np.pi / 2 <= angles[1] <= np.pi / 2


# ---------------------------------------------------------------------------------------------
# Panda: modified DH against a standard-DH description and Franka's published zero pose
# ---------------------------------------------------------------------------------------------

# Franka's modified-DH table (a_{i-1}, alpha_{i-1}, d_i) regrouped into standard DH: since
# Rx(alpha) and Tx(a) commute and the first row has a0 = alpha0 = 0,
#   prod_i [Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)] Tz(d_F)
#   = prod_i [Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)]   with a_7 = alpha_7 = 0, d_7 += d_F.
# Rows: (d, a, alpha) in m and rad, typed in from the Franka documentation's table.
PANDA_STANDARD_DH = (
    (0.333, 0.0, -math.pi / 2),
    (0.0, 0.0, math.pi / 2),
    (0.316, 0.0825, math.pi / 2),
    (0.0, -0.0825, -math.pi / 2),
    (0.384, 0.0, math.pi / 2),
    (0.0, 0.088, math.pi / 2),
    (0.107, 0.0, 0.0),
)

PANDA_STANDARD_TOML = """
name = "panda_standard"
convention = "standard"
angles = "deg"
[[joints]]
type = "revolute"
d = 0.333
alpha = -90
[[joints]]
type = "revolute"
alpha = 90
[[joints]]
type = "revolute"
d = 0.316
a = 0.0825
alpha = 90
[[joints]]
type = "revolute"
a = -0.0825
alpha = -90
[[joints]]
type = "revolute"
d = 0.384
alpha = 90
[[joints]]
type = "revolute"
a = 0.088
alpha = 90
[[joints]]
type = "revolute"
d = 0.107
"""


def _panda_standard(q: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    for (d, a, alpha), qi in zip(PANDA_STANDARD_DH, q, strict=True):
        T = (
            T
            @ Rz(qi)
            @ Tz(d)
            @ np.array([[1, 0, 0, a], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
            @ Rx(alpha)
        )
    return T


def test_panda_modified_dh_equals_standard_dh_description() -> None:
    fk = function("panda", model("panda").forward_kinematics)
    standard_model = derive(robot_from_toml(PANDA_STANDARD_TOML, "panda_standard.toml"))
    standard = numeric_function(
        standard_model.forward_kinematics, standard_model.robot, (standard_model.q,)
    )
    for q in samples("panda", 6):
        expected = _panda_standard(q)
        np.testing.assert_allclose(fk(q), expected, rtol=0, atol=FK_TOL)
        np.testing.assert_allclose(standard(q), expected, rtol=0, atol=FK_TOL)


def test_panda_published_zero_pose() -> None:
    # Franka: at q = 0 the flange is at (0.088, 0, 0.926) pointing down, x along base x.
    expected = np.array([[1.0, 0, 0, 0.088], [0, -1.0, 0, 0], [0, 0, -1.0, 0.926], [0, 0, 0, 1.0]])
    fk = function("panda", model("panda").forward_kinematics)
    np.testing.assert_allclose(fk(np.zeros(7)), expected, rtol=0, atol=1e-12)

"""Tests for symkin.spatial.

Expected values come from sources independent of the code under test: hand-derived matrices,
products of elementary rotations, NumPy's general inverse, QR-generated random rotations,
and algebraic identities (orthonormality, round trips).  Hypothesis runs derandomised.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkin.errors import SymkinError
from symkin.spatial import (
    RPY,
    AxisAngle,
    EulerZYX,
    EulerZYZ,
    TransformGraph,
    axis_angle_from_rotation,
    euler_zyx_from_rotation,
    euler_zyz_from_rotation,
    quaternion_from_rotation,
    rot_x,
    rot_y,
    rot_z,
    rotation_from_axis_angle,
    rotation_from_euler_zyx,
    rotation_from_euler_zyz,
    rotation_from_quaternion,
    rotation_from_rpy,
    rpy_from_rotation,
    transform_from_rotation_translation,
    transform_inverse,
    transform_point,
)

PI = math.pi
EX, EY, EZ = np.eye(3)
ATOL = 1e-9
# Round trips through a singular branch are exact only up to SINGULAR_TOL-sized terms.
ATOL_SINGULAR = 1e-7

FAST = settings(deadline=None, max_examples=40, derandomize=True)

angles = st.floats(-PI, PI, allow_nan=False, allow_infinity=False)
# theta strictly inside (-pi/2, pi/2), away from gimbal lock, for angle round trips
inner_pitch = st.floats(-PI / 2 + 1e-3, PI / 2 - 1e-3)
seeds = st.integers(0, 2**32 - 1)
directions = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1)
quaternions = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda v: np.linalg.norm(v) > 0.1)

psi_s, theta_s, phi_s = sp.symbols("psi theta phi", real=True)
ENTRY_SYMBOLS = sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33", real=True)
GENERIC_R = sp.ImmutableMatrix(3, 3, ENTRY_SYMBOLS)


def random_rotation(seed: int) -> np.ndarray:
    """A random rotation from the QR decomposition of a Gaussian matrix (independent of spatial)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def assert_rotation(R: np.ndarray) -> None:
    assert isinstance(R, np.ndarray)
    assert R.dtype == np.float64
    assert R.shape == (3, 3)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)


def assert_no_nan(*values: object) -> None:
    for v in values:
        assert np.all(np.isfinite(np.asarray(v, dtype=float))), values


def angle_diff(a: float, b: float) -> float:
    """Distance between two angles modulo 2 pi."""
    return abs((a - b + PI) % (2 * PI) - PI)


def sym_equal(A: sp.MatrixBase, B: sp.MatrixBase) -> bool:
    return sp.simplify(sp.Matrix(A) - sp.Matrix(B)) == sp.zeros(*A.shape)


def evaluate(expr: object, subs: dict) -> np.ndarray:
    """Substitute numbers into a SymPy expression or matrix and return floats."""
    return np.array(sp.N(sp.sympify(expr).subs(subs)), dtype=float)


def entry_subs(R: np.ndarray) -> dict:
    return dict(zip(ENTRY_SYMBOLS, R.reshape(-1).tolist(), strict=True))


# --------------------------------------------------------------------------------------------
# Elementary rotations
# --------------------------------------------------------------------------------------------


def test_elementary_rotations_map_axes_by_right_hand_rule() -> None:
    # Hand-derived: a quarter turn about z takes x to y, about x takes y to z, about y z to x.
    np.testing.assert_allclose(rot_z(PI / 2) @ EX, EY, atol=1e-15)
    np.testing.assert_allclose(rot_x(PI / 2) @ EY, EZ, atol=1e-15)
    np.testing.assert_allclose(rot_y(PI / 2) @ EZ, EX, atol=1e-15)


def test_elementary_rotations_symbolic_exact() -> None:
    assert rot_z(sp.pi / 2) == sp.ImmutableMatrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert rot_x(sp.pi / 2) == sp.ImmutableMatrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert rot_y(sp.pi / 2) == sp.ImmutableMatrix([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    a = sp.Symbol("a")
    c, s = sp.cos(a), sp.sin(a)
    assert rot_z(a) == sp.ImmutableMatrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    assert isinstance(rot_x(a), sp.ImmutableMatrix)


@FAST
@given(angles)
def test_elementary_rotations_orthonormal(a: float) -> None:
    for R in (rot_x(a), rot_y(a), rot_z(a)):
        assert_rotation(R)


def test_numeric_input_gives_float_array_and_symbolic_input_gives_sympy() -> None:
    assert isinstance(rotation_from_rpy(0, 0, 0), np.ndarray)
    assert isinstance(rotation_from_rpy(0.1, sp.Symbol("p"), 0), sp.ImmutableMatrix)
    assert isinstance(rot_z(np.float64(0.3)), np.ndarray)
    eul = euler_zyx_from_rotation(np.eye(3))
    assert all(type(v) is float for v in eul[:3])


# --------------------------------------------------------------------------------------------
# Z-Y-X Euler / roll-pitch-yaw
# --------------------------------------------------------------------------------------------


def test_euler_zyx_closed_form_equals_product() -> None:
    R = rotation_from_euler_zyx(psi_s, theta_s, phi_s)
    assert sym_equal(R, rot_z(psi_s) * rot_y(theta_s) * rot_x(phi_s))


def test_rpy_is_fixed_axis_roll_then_pitch_then_yaw() -> None:
    # Roll 90 deg about X maps y to z; a following yaw 90 deg about the fixed Z maps x to y
    # and leaves z alone.  So R x = y and R y = z (hand-derived).
    R = rotation_from_rpy(PI / 2, 0.0, PI / 2)
    np.testing.assert_allclose(R @ EX, EY, atol=1e-15)
    np.testing.assert_allclose(R @ EY, EZ, atol=1e-15)
    roll, pitch, yaw = sp.symbols("roll pitch yaw")
    assert rotation_from_rpy(roll, pitch, yaw) == rotation_from_euler_zyx(yaw, pitch, roll)


@FAST
@given(angles, angles, angles)
def test_rpy_applies_rotations_about_fixed_axes_in_order(r: float, p: float, y: float) -> None:
    v = np.array([0.3, -1.2, 0.7])
    step_by_step = rot_z(y) @ (rot_y(p) @ (rot_x(r) @ v))
    np.testing.assert_allclose(rotation_from_rpy(r, p, y) @ v, step_by_step, atol=1e-12)
    assert_rotation(rotation_from_rpy(r, p, y))


@FAST
@given(angles, inner_pitch, angles)
def test_euler_zyx_round_trip_angles(psi: float, theta: float, phi: float) -> None:
    for method in ("atan2", "lecture"):
        e = euler_zyx_from_rotation(rotation_from_euler_zyx(psi, theta, phi), method=method)
        assert isinstance(e, EulerZYX)
        assert e.singular is False
        assert angle_diff(e.psi, psi) < ATOL
        assert e.theta == pytest.approx(theta, abs=ATOL)
        assert angle_diff(e.phi, phi) < ATOL


@FAST
@given(seeds)
def test_euler_zyx_round_trip_matrix_and_methods_agree(seed: int) -> None:
    R = random_rotation(seed)
    a = euler_zyx_from_rotation(R)
    b = euler_zyx_from_rotation(R, method="lecture")
    assert -PI / 2 <= a.theta <= PI / 2
    np.testing.assert_allclose(a[:3], b[:3], atol=1e-12)
    np.testing.assert_allclose(rotation_from_euler_zyx(*a[:3]), R, atol=ATOL)


@pytest.mark.parametrize("theta", [PI / 2, -PI / 2])
@pytest.mark.parametrize("method", ["atan2", "lecture"])
def test_euler_zyx_gimbal_lock_numeric(theta: float, method: str) -> None:
    R = rotation_from_euler_zyx(0.4, theta, -1.1)
    e = euler_zyx_from_rotation(R, method=method)
    assert e.singular is True
    assert e.phi == 0.0
    assert e.theta == pytest.approx(theta, abs=1e-12)
    assert_no_nan(*e[:3])
    np.testing.assert_allclose(rotation_from_euler_zyx(*e[:3]), R, atol=1e-12)
    # Only psi - phi (theta = +pi/2) or psi + phi (theta = -pi/2) is defined.
    expected_psi = 0.4 - (-1.1) if theta > 0 else 0.4 + (-1.1)
    assert angle_diff(e.psi, expected_psi) < 1e-12


@FAST
@given(angles, angles, st.floats(0, 1e-9), st.sampled_from([-1.0, 1.0]))
def test_euler_zyx_near_gimbal_lock_is_valid(psi: float, phi: float, eps: float, s: float) -> None:
    R = rotation_from_euler_zyx(psi, s * (PI / 2 - eps), phi)
    e = euler_zyx_from_rotation(R)
    assert e.singular is True
    assert_no_nan(*e[:3])
    np.testing.assert_allclose(rotation_from_euler_zyx(*e[:3]), R, atol=ATOL_SINGULAR)


@FAST
@given(seeds)
def test_rpy_round_trip_matches_euler_zyx(seed: int) -> None:
    R = random_rotation(seed)
    rpy = rpy_from_rotation(R)
    e = euler_zyx_from_rotation(R)
    assert isinstance(rpy, RPY)
    assert (rpy.roll, rpy.pitch, rpy.yaw, rpy.singular) == (e.phi, e.theta, e.psi, e.singular)
    np.testing.assert_allclose(rotation_from_rpy(rpy.roll, rpy.pitch, rpy.yaw), R, atol=ATOL)


def test_rpy_gimbal_lock() -> None:
    R = rotation_from_rpy(0.7, -PI / 2, 0.2)
    rpy = rpy_from_rotation(R)
    assert rpy.singular is True
    assert rpy.roll == 0.0
    np.testing.assert_allclose(rotation_from_rpy(*rpy[:3]), R, atol=1e-12)


def test_euler_zyx_symbolic_general_formulas() -> None:
    e = euler_zyx_from_rotation(GENERIC_R)
    assert e.singular is None
    r = {f"r{i}{j}": GENERIC_R[i - 1, j - 1] for i in (1, 2, 3) for j in (1, 2, 3)}
    assert e.phi == sp.atan2(r["r32"], r["r33"])
    assert e.psi == sp.atan2(r["r21"], r["r11"])
    assert e.theta == sp.atan2(-r["r31"], sp.sqrt(r["r11"] ** 2 + r["r21"] ** 2))


def test_euler_zyx_symbolic_matches_numeric_and_lecture_form() -> None:
    sym_a = euler_zyx_from_rotation(GENERIC_R)
    sym_b = euler_zyx_from_rotation(GENERIC_R, method="lecture")
    for seed in range(5):
        R = random_rotation(seed)
        num = euler_zyx_from_rotation(R)
        subs = entry_subs(R)
        for sym in (sym_a, sym_b):
            np.testing.assert_allclose([evaluate(v, subs) for v in sym[:3]], num[:3], atol=1e-12)


def test_euler_zyx_symbolic_exact_gimbal_lock() -> None:
    R = rotation_from_euler_zyx(psi_s, sp.pi / 2, phi_s)
    e = euler_zyx_from_rotation(R)
    assert e.singular is True
    assert e.theta == sp.pi / 2
    assert e.phi == 0
    assert sym_equal(rotation_from_euler_zyx(*e[:3]), R)


def test_euler_zyx_symbolic_round_trip_of_symbolic_angles() -> None:
    e = euler_zyx_from_rotation(rotation_from_euler_zyx(psi_s, theta_s, phi_s))
    assert e.singular is None
    subs = {psi_s: 0.3, theta_s: -0.4, phi_s: 1.3}
    np.testing.assert_allclose([evaluate(v, subs) for v in e[:3]], [0.3, -0.4, 1.3], atol=1e-12)


# --------------------------------------------------------------------------------------------
# Z-Y-Z Euler
# --------------------------------------------------------------------------------------------


def test_euler_zyz_closed_form_equals_product() -> None:
    a, b, g = sp.symbols("alpha beta gamma")
    assert sym_equal(rotation_from_euler_zyz(a, b, g), rot_z(a) * rot_y(b) * rot_z(g))


@FAST
@given(angles, st.floats(1e-3, PI - 1e-3), angles)
def test_euler_zyz_round_trip_angles(alpha: float, beta: float, gamma: float) -> None:
    e = euler_zyz_from_rotation(rotation_from_euler_zyz(alpha, beta, gamma))
    assert isinstance(e, EulerZYZ)
    assert e.singular is False
    assert angle_diff(e.alpha, alpha) < ATOL
    assert e.beta == pytest.approx(beta, abs=ATOL)
    assert angle_diff(e.gamma, gamma) < ATOL


@FAST
@given(seeds)
def test_euler_zyz_round_trip_matrix(seed: int) -> None:
    R = random_rotation(seed)
    e = euler_zyz_from_rotation(R)
    assert 0 <= e.beta <= PI
    np.testing.assert_allclose(rotation_from_euler_zyz(*e[:3]), R, atol=ATOL)


@pytest.mark.parametrize("beta", [0.0, PI])
def test_euler_zyz_singular(beta: float) -> None:
    R = rotation_from_euler_zyz(0.9, beta, -0.3)
    e = euler_zyz_from_rotation(R)
    assert e.singular is True
    assert e.gamma == 0.0
    assert e.beta == pytest.approx(beta, abs=1e-12)
    assert_no_nan(*e[:3])
    np.testing.assert_allclose(rotation_from_euler_zyz(*e[:3]), R, atol=1e-12)
    # beta = 0: R = Rz(alpha + gamma); beta = pi: only alpha - gamma is defined.
    expected_alpha = 0.9 + (-0.3) if beta == 0 else 0.9 - (-0.3)
    assert angle_diff(e.alpha, expected_alpha) < 1e-12


def test_euler_zyz_symbolic_matches_numeric() -> None:
    sym = euler_zyz_from_rotation(GENERIC_R)
    assert sym.singular is None
    for seed in range(5):
        R = random_rotation(seed)
        num = euler_zyz_from_rotation(R)
        got = [evaluate(v, entry_subs(R)) for v in sym[:3]]
        np.testing.assert_allclose(got, num[:3], atol=1e-12)


def test_euler_zyz_symbolic_exact_singular() -> None:
    a, g = sp.symbols("a g")
    R = rotation_from_euler_zyz(a, 0, g)
    e = euler_zyz_from_rotation(R)
    assert e.singular is True
    assert (e.beta, e.gamma) == (0, 0)
    assert sym_equal(rotation_from_euler_zyz(*e[:3]), R)


# --------------------------------------------------------------------------------------------
# Axis-angle
# --------------------------------------------------------------------------------------------


def test_axis_angle_hand_derived() -> None:
    # A third of a turn about (1,1,1) permutes the axes cyclically: x -> y -> z -> x.
    cyclic = sp.ImmutableMatrix([[0, 0, 1], [1, 0, 0], [0, 1, 0]])
    R = rotation_from_axis_angle([1, 1, 1], 2 * sp.pi / 3)
    assert sym_equal(R, cyclic)
    np.testing.assert_allclose(
        rotation_from_axis_angle([2, 2, 2], 2 * PI / 3), np.array(cyclic, dtype=float), atol=1e-15
    )
    # An unnormalised axis along z is rot_z.
    np.testing.assert_allclose(rotation_from_axis_angle([0, 0, 5], 0.7), rot_z(0.7), atol=1e-15)
    a = sp.Symbol("a")
    assert sym_equal(rotation_from_axis_angle([1, 0, 0], a), rot_x(a))


def test_axis_angle_symbolic_unit_axis_stays_simple() -> None:
    t, a = sp.symbols("t a")
    R = rotation_from_axis_angle([sp.cos(t), sp.sin(t), 0], a)
    assert not any(e.has(sp.sqrt(sp.sin(t) ** 2 + sp.cos(t) ** 2)) for e in R)
    assert sym_equal(R, rot_z(t) * rot_x(a) * rot_z(-t))


@FAST
@given(directions, angles)
def test_rotation_from_axis_angle_is_rotation_fixing_axis(axis: tuple, angle: float) -> None:
    R = rotation_from_axis_angle(axis, angle)
    assert_rotation(R)
    np.testing.assert_allclose(R @ np.array(axis), axis, atol=1e-12)


@FAST
@given(directions, st.floats(1e-6, PI - 1e-6))
def test_axis_angle_round_trip(axis: tuple, angle: float) -> None:
    k = np.array(axis) / np.linalg.norm(axis)
    aa = axis_angle_from_rotation(rotation_from_axis_angle(k, angle))
    assert isinstance(aa, AxisAngle)
    assert aa.singular is False
    assert aa.angle == pytest.approx(angle, abs=ATOL)
    np.testing.assert_allclose(aa.axis, k, atol=1e-7)


@FAST
@given(seeds)
def test_axis_angle_round_trip_matrix(seed: int) -> None:
    R = random_rotation(seed)
    aa = axis_angle_from_rotation(R)
    assert 0 <= aa.angle <= PI
    assert np.linalg.norm(aa.axis) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(rotation_from_axis_angle(aa.axis, aa.angle), R, atol=ATOL)


def test_axis_angle_identity() -> None:
    aa = axis_angle_from_rotation(np.eye(3))
    assert aa.singular is True
    assert aa.angle == 0.0
    np.testing.assert_array_equal(aa.axis, [0, 0, 1])


@pytest.mark.parametrize(
    "axis", [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, -2, 3], [-1, 1, 0], [0.3, 0.0, -0.9]]
)
@pytest.mark.parametrize("delta", [0.0, 1e-12, 1e-9, 1e-6, 1e-3])
def test_axis_angle_at_and_near_pi(axis: list, delta: float) -> None:
    k = np.array(axis, dtype=float) / np.linalg.norm(axis)
    R = rotation_from_axis_angle(k, PI - delta)
    aa = axis_angle_from_rotation(R)
    assert_no_nan(aa.axis, aa.angle)
    assert aa.singular is (delta < 1e-8)
    assert aa.angle == pytest.approx(PI - delta, abs=1e-12)
    if delta > 0:  # the sign of the axis is determined off pi
        np.testing.assert_allclose(aa.axis, k, atol=1e-9)
    else:  # at pi: +-k, with the correct relative signs
        assert abs(abs(float(aa.axis @ k)) - 1.0) < 1e-12
    np.testing.assert_allclose(rotation_from_axis_angle(aa.axis, aa.angle), R, atol=1e-12)


@pytest.mark.parametrize("delta", [1e-13, 1e-10, 1e-7])
def test_axis_angle_near_zero(delta: float) -> None:
    R = rotation_from_axis_angle([1, 2, 2], delta)
    aa = axis_angle_from_rotation(R)
    assert_no_nan(aa.axis, aa.angle)
    np.testing.assert_allclose(rotation_from_axis_angle(aa.axis, aa.angle), R, atol=ATOL_SINGULAR)


def test_axis_angle_symbolic_special_cases() -> None:
    ident = axis_angle_from_rotation(sp.eye(3))
    assert (ident.axis, ident.angle, ident.singular) == (sp.Matrix([0, 0, 1]), 0, True)
    half = axis_angle_from_rotation(rot_y(sp.pi))
    assert (half.axis, half.angle, half.singular) == (sp.Matrix([0, 1, 0]), sp.pi, True)
    # pi about (1, 1, 0)/sqrt(2): R = 2 k k^T - I, exact
    k = sp.Matrix([1, 1, 0]) / sp.sqrt(2)
    diag = axis_angle_from_rotation(2 * k * k.T - sp.eye(3))
    assert diag.singular is True
    assert sp.simplify(diag.axis - k) == sp.zeros(3, 1)
    third = axis_angle_from_rotation(rotation_from_axis_angle([1, 1, 1], 2 * sp.pi / 3))
    assert third.singular is False
    assert third.angle == 2 * sp.pi / 3
    assert sp.simplify(third.axis - sp.Matrix([1, 1, 1]) / sp.sqrt(3)) == sp.zeros(3, 1)


def test_axis_angle_symbolic_matches_numeric() -> None:
    sym = axis_angle_from_rotation(GENERIC_R)
    assert sym.singular is None
    for seed in range(5):
        R = random_rotation(seed)
        num = axis_angle_from_rotation(R)
        subs = entry_subs(R)
        assert evaluate(sym.angle, subs) == pytest.approx(num.angle, abs=1e-12)
        np.testing.assert_allclose(evaluate(sym.axis, subs).reshape(-1), num.axis, atol=1e-10)


def test_rotation_from_axis_angle_symbolic_matches_numeric() -> None:
    kx, ky, kz, a = sp.symbols("kx ky kz a", real=True)
    sym = rotation_from_axis_angle([kx, ky, kz], a)
    rng = np.random.default_rng(1)
    for _ in range(5):
        k, angle = rng.normal(size=3), rng.uniform(-PI, PI)
        subs = {kx: k[0], ky: k[1], kz: k[2], a: angle}
        np.testing.assert_allclose(
            evaluate(sym, subs), rotation_from_axis_angle(k, angle), atol=1e-12
        )


# --------------------------------------------------------------------------------------------
# Quaternions
# --------------------------------------------------------------------------------------------


def test_quaternion_hand_derived() -> None:
    a = sp.Symbol("a")
    R = rotation_from_quaternion([sp.cos(a / 2), 0, 0, sp.sin(a / 2)])
    assert sym_equal(R, rot_z(a))
    np.testing.assert_allclose(rotation_from_quaternion([0, 1, 0, 0]), np.diag([1, -1, -1]))
    np.testing.assert_allclose(rotation_from_quaternion([2, 0, 0, 0]), np.eye(3))  # normalised
    # The cyclic permutation (a third turn about (1,1,1)) is q = (1, 1, 1, 1)/2.
    cyclic = [[0, 0, 1], [1, 0, 0], [0, 1, 0]]
    np.testing.assert_allclose(quaternion_from_rotation(cyclic), [0.5] * 4, atol=1e-15)
    assert quaternion_from_rotation(sp.Matrix(cyclic)) == sp.Matrix([sp.S.Half] * 4)


@FAST
@given(quaternions)
def test_quaternion_round_trip(q: tuple) -> None:
    qn = np.array(q) / np.linalg.norm(q)
    R = rotation_from_quaternion(q)
    assert_rotation(R)
    back = quaternion_from_rotation(R)
    assert back.shape == (4,)
    assert back[0] >= 0
    if abs(qn[0]) > 1e-6:
        np.testing.assert_allclose(back, qn if qn[0] > 0 else -qn, atol=1e-9)
    else:  # w = 0: q and -q are the same rotation and both have w >= 0
        assert abs(abs(float(back @ qn)) - 1) < 1e-9


@FAST
@given(seeds)
def test_quaternion_round_trip_matrix(seed: int) -> None:
    R = random_rotation(seed)
    q = quaternion_from_rotation(R)
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(rotation_from_quaternion(q), R, atol=ATOL)


@FAST
@given(directions, st.floats(0, PI))
def test_quaternion_agrees_with_axis_angle(axis: tuple, angle: float) -> None:
    # Independent relation: q = (cos(a/2), sin(a/2) k).
    k = np.array(axis) / np.linalg.norm(axis)
    q = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * k])
    np.testing.assert_allclose(
        rotation_from_quaternion(q), rotation_from_axis_angle(k, angle), atol=1e-12
    )


@pytest.mark.parametrize(
    ("R", "q"),
    [
        (np.eye(3), [1, 0, 0, 0]),  # trace branch
        (np.diag([1.0, -1, -1]), [0, 1, 0, 0]),  # x branch, w = 0
        (np.diag([-1.0, 1, -1]), [0, 0, 1, 0]),  # y branch
        (np.diag([-1.0, -1, 1]), [0, 0, 0, 1]),  # z branch
    ],
)
def test_quaternion_shepperd_branches_exact(R: np.ndarray, q: list) -> None:
    np.testing.assert_allclose(quaternion_from_rotation(R), q, atol=1e-15)


@pytest.mark.parametrize("axis", [[1, 0.1, 0.1], [0.1, 1, -0.1], [-0.1, 0.1, 1], [1, 1, 1]])
@pytest.mark.parametrize("angle", [PI, PI - 1e-6, 3.0, 0.0])
def test_quaternion_from_rotation_near_pi_and_zero(axis: list, angle: float) -> None:
    k = np.array(axis) / np.linalg.norm(axis)
    R = rotation_from_axis_angle(k, angle)
    q = quaternion_from_rotation(R)
    assert_no_nan(q)
    assert q[0] >= 0
    np.testing.assert_allclose(rotation_from_quaternion(q), R, atol=1e-12)
    expected = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * k])
    assert abs(abs(float(q @ expected)) - 1) < 1e-12


def test_quaternion_symbolic_matches_numeric() -> None:
    w, x, y, z = sp.symbols("w x y z", real=True)
    sym_R = rotation_from_quaternion([w, x, y, z])
    sym_q = quaternion_from_rotation(GENERIC_R)
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = rng.normal(size=4)
        q[0] = abs(q[0]) + 0.5  # the symbolic w branch needs 1 + tr R well above 0
        got_R = evaluate(sym_R, dict(zip((w, x, y, z), q, strict=True)))
        np.testing.assert_allclose(got_R, rotation_from_quaternion(q), atol=1e-12)
        got_q = evaluate(sym_q, entry_subs(got_R)).reshape(-1)
        np.testing.assert_allclose(got_q, quaternion_from_rotation(got_R), atol=1e-12)


# --------------------------------------------------------------------------------------------
# Homogeneous transforms
# --------------------------------------------------------------------------------------------


def test_transform_layout_and_point() -> None:
    T = transform_from_rotation_translation(rot_z(PI / 2), [1, 0, 0])
    expected = [[0, -1, 0, 1], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    np.testing.assert_allclose(T, expected, atol=1e-15)
    # Hand-derived: x rotates to y, then the origin shift (1, 0, 0) is added.
    p = transform_point(T, [1, 0, 0])
    assert p.shape == (3,)
    np.testing.assert_allclose(p, [1, 1, 0], atol=1e-15)
    d = sp.Symbol("d")
    Ts = transform_from_rotation_translation(rot_z(sp.pi / 2), [d, 0, 0])
    assert Ts == sp.ImmutableMatrix([[0, -1, 0, d], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    assert transform_point(Ts, [1, 0, 0]) == sp.ImmutableMatrix([d, 1, 0])


@FAST
@given(seeds, st.tuples(*[st.floats(-10, 10)] * 3))
def test_transform_inverse_numeric(seed: int, p: tuple) -> None:
    T = transform_from_rotation_translation(random_rotation(seed), p)
    Ti = transform_inverse(T)
    np.testing.assert_allclose(Ti @ T, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(T @ Ti, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(Ti, np.linalg.inv(T), atol=1e-12)
    x = np.array([0.5, -2.0, 1.0])
    np.testing.assert_allclose(transform_point(Ti, transform_point(T, x)), x, atol=1e-11)


def test_transform_inverse_symbolic_exact() -> None:
    q, d = sp.symbols("q d")
    T = transform_from_rotation_translation(rotation_from_euler_zyx(q, q, 0), [d, 1, q])
    Ti = transform_inverse(T)
    assert isinstance(Ti, sp.ImmutableMatrix)
    # Closed form: no denominators, unlike a general inverse (which divides by det).
    assert all(sp.fraction(sp.together(e))[1] == 1 for e in Ti)
    assert sp.simplify(Ti * T) == sp.eye(4)


def test_transform_inverse_rejects_non_rigid() -> None:
    with pytest.raises(SymkinError, match="rotation"):
        transform_inverse(np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(SymkinError, match="bottom row"):
        transform_inverse(np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 1.0]]))
    with pytest.raises(SymkinError, match="4x4"):
        transform_inverse(np.eye(3))


# --------------------------------------------------------------------------------------------
# Transform graph
# --------------------------------------------------------------------------------------------


def _pose(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return transform_from_rotation_translation(random_rotation(seed), rng.normal(size=3))


def test_transform_graph_chain_and_reversed_edges() -> None:
    T_w_a, T_a_b, T_c_b = _pose(1), _pose(2), _pose(3)
    g = TransformGraph()
    g.add("world", "a", T_w_a)
    g.add("a", "b", T_a_b)
    g.add("c", "b", T_c_b)  # stored c -> b; world -> c runs against it
    assert g.frames == ("world", "a", "b", "c")
    assert "c" in g and "d" not in g
    np.testing.assert_allclose(g.transform("world", "b"), T_w_a @ T_a_b, atol=1e-12)
    expected = T_w_a @ T_a_b @ np.linalg.inv(T_c_b)
    np.testing.assert_allclose(g.transform("world", "c"), expected, atol=1e-12)
    np.testing.assert_allclose(g.transform("c", "world"), np.linalg.inv(expected), atol=1e-12)
    np.testing.assert_allclose(g.transform("b", "a"), np.linalg.inv(T_a_b), atol=1e-12)
    np.testing.assert_array_equal(g.transform("a", "a"), np.eye(4))


def test_transform_graph_shortest_path_is_deterministic() -> None:
    g = TransformGraph()
    g.add("w", "x", _pose(4))
    g.add("x", "y", _pose(5))
    g.add("w", "y", _pose(6))  # a redundant direct edge: the one-edge path wins
    np.testing.assert_allclose(g.transform("w", "y"), _pose(6), atol=1e-15)
    np.testing.assert_allclose(g.transform("w", "y"), g.transform("w", "y"), atol=0)


def test_transform_graph_stores_a_copy() -> None:
    T = _pose(7)
    g = TransformGraph()
    g.add("p", "c", T)
    T[0, 3] += 100.0
    assert g.transform("p", "c")[0, 3] == pytest.approx(T[0, 3] - 100.0)
    out = g.transform("p", "c")
    out[0, 3] = 0.0  # mutating a result must not change the graph
    assert g.transform("p", "c")[0, 3] == pytest.approx(T[0, 3] - 100.0)


def test_transform_graph_symbolic() -> None:
    q = sp.Symbol("q")
    T_0_1 = transform_from_rotation_translation(rot_z(q), [1, 0, 0])
    T_2_1 = _pose(8)
    g = TransformGraph()
    g.add(0, 1, T_0_1)
    g.add(2, 1, T_2_1)
    got = g.transform(0, 2)
    assert isinstance(got, sp.ImmutableMatrix)
    num = evaluate(got, {q: 0.3})
    expected = transform_from_rotation_translation(rot_z(0.3), [1, 0, 0]) @ np.linalg.inv(T_2_1)
    np.testing.assert_allclose(num, expected, atol=1e-12)
    assert g.transform(1, 1) == sp.eye(4)


def test_transform_graph_errors_name_the_frames() -> None:
    g = TransformGraph()
    g.add("base", "tool", np.eye(4))
    g.add("cam", "marker", np.eye(4))
    with pytest.raises(SymkinError, match="'nowhere'"):
        g.transform("base", "nowhere")
    with pytest.raises(SymkinError, match=r"'base'.*'marker'"):
        g.transform("base", "marker")
    with pytest.raises(SymkinError, match="already connected"):
        g.add("tool", "base", np.eye(4))
    with pytest.raises(SymkinError, match="two different frames"):
        g.add("x", "x", np.eye(4))
    with pytest.raises(SymkinError):
        g.add("x", "y", np.ones((4, 4)))
    assert "x" not in g  # a rejected add leaves the graph unchanged


# --------------------------------------------------------------------------------------------
# Errors
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: rotation_from_axis_angle([0, 0, 0], 1.0), "non-zero"),
        (lambda: rotation_from_axis_angle(sp.Matrix([0, 0, 0]), sp.Symbol("a")), "non-zero"),
        (lambda: rotation_from_axis_angle([1, 0], 1.0), "3-vector"),
        (lambda: rotation_from_quaternion([0, 0, 0, 0]), "non-zero"),
        (lambda: rotation_from_quaternion([1, 0, 0]), "4-vector"),
        (lambda: euler_zyx_from_rotation(np.eye(3), method="xyz"), "method"),
        (lambda: euler_zyx_from_rotation(np.diag([1.0, 1, -1])), "rotation"),
        (lambda: axis_angle_from_rotation(2 * np.eye(3)), "rotation"),
        (lambda: quaternion_from_rotation(np.full((3, 3), np.nan)), "finite"),
        (lambda: euler_zyz_from_rotation(np.eye(4)), "3x3"),
        (lambda: rot_x("ninety"), "real number"),
        (lambda: transform_from_rotation_translation(np.eye(3), [1, 2]), "3-vector"),
        (lambda: transform_point(np.eye(4), [1, 2, 3, 1]), "3-vector"),
    ],
)
def test_user_mistakes_raise_symkin_error(call: object, message: str) -> None:
    with pytest.raises(SymkinError, match=message):
        call()  # type: ignore[operator]

"""Tests for the spatial algebra: quaternions, exp/log of SO(3) and SE(3), screws, the adjoint.

Expected values come from outside the code under test: SciPy's general matrix exponential
``expm`` of the 3x3 / 4x4 Lie-algebra matrix, hand-derived cases, the 4x4 conjugation
``T [V] T^-1`` that defines the adjoint, NumPy's general inverse, algebraic identities, and
(``oracle``) spatialmath and pytransform3d on random inputs and at their singular cases.
Conventions compared through: symkin twists are ``(v, w)``, pytransform3d's ``(w, v)``;
quaternions are ``(w, x, y, z)`` in all three.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import expm

from symkin.errors import SymkinError
from symkin.spatial import (
    adjoint_from_transform,
    axis_angle_from_rotation,
    quaternion_canonical,
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_inverse,
    quaternion_product,
    quaternion_slerp,
    rot_x,
    rot_z,
    rotation_from_quaternion,
    rotation_from_rotation_vector,
    rotation_vector_from_rotation,
    screw_axis_from_line,
    skew,
    transform_from_rotation_translation,
    transform_from_twist,
    transform_inverse,
    transform_twist,
    transform_wrench,
    twist_from_screw,
    twist_from_transform,
    unit_quaternion,
)
from symkin.spatial.lie import SERIES_ANGLE

PI = math.pi
ATOL = 1e-12
FAST = settings(deadline=None, max_examples=40, derandomize=True)

seeds = st.integers(0, 2**32 - 1)
quaternions = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda v: np.linalg.norm(v) > 0.1)
ts = st.floats(0, 1)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random rotation from the QR decomposition of a Gaussian matrix."""
    Q, Rr = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q @ np.diag(np.sign(np.diag(Rr)))
    return Q if np.linalg.det(Q) > 0 else -Q


def random_transform(rng: np.random.Generator) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = random_rotation(rng), rng.normal(size=3)
    return T


def random_rotation_vector(rng: np.random.Generator, max_angle: float = PI - 1e-3) -> np.ndarray:
    d = rng.normal(size=3)
    return d / np.linalg.norm(d) * rng.uniform(0, max_angle)


def se3_matrix(twist: np.ndarray) -> np.ndarray:
    """The 4x4 Lie-algebra matrix ``[[ [w]x, v ], [0, 0]]`` of ``twist = (v, w)``, by hand."""
    v, (wx, wy, wz) = twist[:3], twist[3:]
    M = np.zeros((4, 4))
    M[:3, :3] = [[0, -wz, wy], [wz, 0, -wx], [-wy, wx, 0]]
    M[:3, 3] = v
    return M


def angle_between(R1: np.ndarray, R2: np.ndarray) -> float:
    """Rotation angle of ``R1^T R2`` from the trace (independent of the log map)."""
    return math.acos(np.clip((np.trace(R1.T @ R2) - 1) / 2, -1, 1))


def same_rotation_quaternion(p: np.ndarray, q: np.ndarray, atol: float = 1e-10) -> bool:
    return np.allclose(p, q, atol=atol) or np.allclose(p, -q, atol=atol)


# --------------------------------------------------------------------------------------------
# Quaternions
# --------------------------------------------------------------------------------------------


def test_hamilton_units():
    i, j, k = np.eye(4)[1], np.eye(4)[2], np.eye(4)[3]
    np.testing.assert_allclose(quaternion_product(i, j), k)
    np.testing.assert_allclose(quaternion_product(j, i), -k)
    np.testing.assert_allclose(quaternion_product(i, i), [-1, 0, 0, 0])


@FAST
@given(seeds)
def test_product_composes_rotations(seed):
    rng = np.random.default_rng(seed)
    R1, R2 = random_rotation(rng), random_rotation(rng)
    q = quaternion_product(quaternion_from_rotation(R1), quaternion_from_rotation(R2))
    np.testing.assert_allclose(rotation_from_quaternion(q), R1 @ R2, atol=ATOL)


@FAST
@given(quaternions)
def test_times_inverse_is_one(q):
    np.testing.assert_allclose(
        quaternion_product(q, quaternion_inverse(q)), [1, 0, 0, 0], atol=ATOL
    )
    np.testing.assert_allclose(
        quaternion_product(quaternion_inverse(q), q), [1, 0, 0, 0], atol=ATOL
    )


@FAST
@given(quaternions)
def test_conjugate_unit_and_canonical(q):
    R = rotation_from_quaternion(q)
    np.testing.assert_allclose(rotation_from_quaternion(quaternion_conjugate(q)), R.T, atol=ATOL)
    u = unit_quaternion(q)
    np.testing.assert_allclose(np.linalg.norm(u), 1, atol=ATOL)
    np.testing.assert_allclose(u * np.linalg.norm(q), q, atol=ATOL)  # the sign is kept
    c = quaternion_canonical(q)
    assert c[0] >= 0
    assert same_rotation_quaternion(c, u)


def test_zero_quaternion_is_an_error():
    for f in (quaternion_inverse, unit_quaternion, quaternion_canonical):
        with pytest.raises(SymkinError, match="q must be a non-zero vector"):
            f([0, 0, 0, 0])


@FAST
@given(seeds)
def test_from_rotation_has_canonical_sign(seed):
    q = quaternion_from_rotation(random_rotation(np.random.default_rng(seed)))
    assert q[0] >= 0
    np.testing.assert_allclose(quaternion_canonical(q), q, atol=ATOL)


@FAST
@given(quaternions, quaternions)
def test_slerp_endpoints_and_short_way(q0, q1):
    a, b = unit_quaternion(q0), unit_quaternion(q1)
    b_short = b if a @ b >= 0 else -b
    np.testing.assert_allclose(quaternion_slerp(q0, q1, 0), a, atol=1e-10)
    np.testing.assert_allclose(quaternion_slerp(q0, q1, 1), b_short, atol=1e-10)
    # Short way: the midpoint is half the rotation angle (at most pi) from each end.
    R0, R1 = rotation_from_quaternion(a), rotation_from_quaternion(b)
    Rm = rotation_from_quaternion(quaternion_slerp(q0, q1, 0.5))
    total = angle_between(R0, R1)
    assert math.isclose(angle_between(R0, Rm), total / 2, abs_tol=1e-7)
    assert math.isclose(angle_between(Rm, R1), total / 2, abs_tol=1e-7)


@FAST
@given(seeds)
def test_slerp_constant_angular_velocity(seed):
    rng = np.random.default_rng(seed)
    q0, q1 = rng.normal(size=4), rng.normal(size=4)
    Rs = [rotation_from_quaternion(quaternion_slerp(q0, q1, t)) for t in np.linspace(0, 1, 9)]
    # Each step turns by the same angle about the same axis (in the moving frame).
    steps = [axis_angle_from_rotation(a.T @ b) for a, b in itertools.pairwise(Rs)]
    total = angle_between(Rs[0], Rs[-1])
    for axis, angle, _ in steps:
        assert math.isclose(angle, total / 8, abs_tol=1e-9)
        np.testing.assert_allclose(axis, steps[0].axis, atol=1e-6)


def test_slerp_of_equal_and_nearly_equal_ends():
    q = unit_quaternion([0.3, -0.2, 0.9, 0.1])
    np.testing.assert_allclose(quaternion_slerp(q, q, 0.3), q, atol=ATOL)
    np.testing.assert_allclose(quaternion_slerp(q, -q, 0.3), q, atol=ATOL)  # same rotation
    near = unit_quaternion(q + 1e-10)
    s = quaternion_slerp(q, near, 0.5)
    assert np.all(np.isfinite(s))
    np.testing.assert_allclose(s, q, atol=1e-9)


def test_quaternion_symbolic_matches_numeric():
    a, b, t = sp.symbols("a b t", real=True)
    p = [sp.cos(a / 2), sp.sin(a / 2), 0, 0]
    q = [sp.cos(b / 2), 0, 0, sp.sin(b / 2)]
    values = {a: 0.7, b: -1.3, t: 0.4}
    num = {k: [float(sp.sympify(x).subs(values)) for x in v] for k, v in (("p", p), ("q", q))}
    for sym, ref in (
        (quaternion_product(p, q), quaternion_product(num["p"], num["q"])),
        (quaternion_inverse(p), quaternion_inverse(num["p"])),
        (quaternion_slerp(p, q, t), quaternion_slerp(num["p"], num["q"], 0.4)),
    ):
        got = np.array(sp.ImmutableMatrix(sym).subs(values).evalf(), dtype=float).ravel()
        np.testing.assert_allclose(got, ref, atol=ATOL)
    # Exact inputs stay exact: i j = k.
    assert quaternion_product([0, 1, 0, 0], [0, 0, sp.Integer(1), 0]) == sp.Matrix([0, 0, 0, 1])


# --------------------------------------------------------------------------------------------
# SO(3) exp / log
# --------------------------------------------------------------------------------------------


@FAST
@given(seeds)
def test_so3_exp_is_the_matrix_exponential(seed):
    w = random_rotation_vector(np.random.default_rng(seed), max_angle=3 * PI)
    np.testing.assert_allclose(rotation_from_rotation_vector(w), expm(skew(w)), atol=1e-12)


@FAST
@given(seeds)
def test_so3_log_of_exp(seed):
    w = random_rotation_vector(np.random.default_rng(seed))
    log = rotation_vector_from_rotation(rotation_from_rotation_vector(w))
    np.testing.assert_allclose(log.vector, w, atol=1e-9)
    assert math.isclose(log.angle, np.linalg.norm(w), abs_tol=1e-9)
    assert log.singular is False


@FAST
@given(seeds)
def test_so3_exp_of_log(seed):
    R = random_rotation(np.random.default_rng(seed))
    log = rotation_vector_from_rotation(R)
    assert 0 <= log.angle <= PI
    np.testing.assert_allclose(rotation_from_rotation_vector(log.vector), R, atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 1e-15, 1e-9, 1e-6, SERIES_ANGLE * (1 - 1e-9), 1e-2, 0.1])
def test_so3_small_angles_keep_their_digits(angle):
    w = angle * np.array([2, -3, 6]) / 7
    R = rotation_from_rotation_vector(w)
    np.testing.assert_allclose(R, expm(skew(w)), atol=1e-16, rtol=0)
    log = rotation_vector_from_rotation(R)
    np.testing.assert_allclose(log.vector, w, atol=1e-16 + 1e-14 * angle, rtol=0)
    assert log.singular is False


@pytest.mark.parametrize("axis", [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -2, 2]])
def test_so3_log_at_pi_is_flagged(axis):
    k = np.array(axis, dtype=float) / np.linalg.norm(axis)
    R = 2 * np.outer(k, k) - np.eye(3)  # rotation by pi about k, by hand
    log = rotation_vector_from_rotation(R)
    assert log.singular is True
    assert math.isclose(log.angle, PI)
    assert same_rotation_quaternion(np.r_[0, log.vector], np.r_[0, PI * k])
    np.testing.assert_allclose(rotation_from_rotation_vector(log.vector), R, atol=1e-12)
    np.testing.assert_allclose(rotation_from_rotation_vector(-log.vector), R, atol=1e-12)


def test_so3_log_near_pi():
    k = np.array([1.0, -2.0, 2.0]) / 3
    for gap, singular in ((1e-10, True), (1e-6, False), (1e-3, False)):
        w = (PI - gap) * k
        log = rotation_vector_from_rotation(expm(skew(w)))
        assert log.singular is singular
        tol = 1e-7 if singular else 1e-9
        np.testing.assert_allclose(log.vector, w, atol=tol)


def test_so3_symbolic():
    x, y, z, t = sp.symbols("x y z t", real=True)
    values = {x: 0.3, y: -1.2, z: 0.5}
    R = rotation_from_rotation_vector([x, y, z])
    got = np.array(R.subs(values).evalf(), dtype=float)
    np.testing.assert_allclose(got, expm(skew([0.3, -1.2, 0.5])), atol=ATOL)
    assert rotation_from_rotation_vector([0, 0, sp.Integer(0)]) == sp.eye(3)
    log = rotation_vector_from_rotation(rot_z(t))
    assert log.singular is None  # t = pi is not excluded
    got = np.array(log.vector.subs(t, 0.7).evalf(), dtype=float).ravel()
    np.testing.assert_allclose(got, [0, 0, 0.7], atol=ATOL)
    at_pi = rotation_vector_from_rotation(rot_x(sp.pi))
    assert at_pi.singular is True and at_pi.vector == sp.Matrix([sp.pi, 0, 0])


# --------------------------------------------------------------------------------------------
# SE(3) exp / log
# --------------------------------------------------------------------------------------------


def random_twist(rng: np.random.Generator, max_angle: float = PI - 1e-3) -> np.ndarray:
    return np.r_[rng.normal(size=3), random_rotation_vector(rng, max_angle)]


@FAST
@given(seeds)
def test_se3_exp_is_the_matrix_exponential(seed):
    V = random_twist(np.random.default_rng(seed), max_angle=3 * PI)
    np.testing.assert_allclose(transform_from_twist(V), expm(se3_matrix(V)), atol=1e-11)


@FAST
@given(seeds)
def test_se3_log_of_exp_and_exp_of_log(seed):
    rng = np.random.default_rng(seed)
    V = random_twist(rng)
    log = twist_from_transform(transform_from_twist(V))
    np.testing.assert_allclose(log.twist, V, atol=1e-8)
    assert log.singular is False
    T = random_transform(rng)
    np.testing.assert_allclose(transform_from_twist(twist_from_transform(T).twist), T, atol=1e-11)


@pytest.mark.parametrize(
    "angle", [0.0, 1e-12, 1e-7, SERIES_ANGLE * (1 - 1e-9), SERIES_ANGLE * (1 + 1e-9), 0.5]
)
def test_se3_small_angles(angle):
    V = np.r_[0.4, -0.1, 0.7, angle * np.array([2, -3, 6]) / 7]
    T = transform_from_twist(V)
    np.testing.assert_allclose(T, expm(se3_matrix(V)), atol=1e-15, rtol=0)
    np.testing.assert_allclose(twist_from_transform(T).twist, V, atol=1e-14, rtol=0)


def test_pure_translation_twist():
    T = transform_from_twist([1.0, -2.0, 3.0, 0, 0, 0])
    np.testing.assert_array_equal(T, [[1, 0, 0, 1], [0, 1, 0, -2], [0, 0, 1, 3], [0, 0, 0, 1]])
    log = twist_from_transform(T)
    np.testing.assert_array_equal(log.twist, [1, -2, 3, 0, 0, 0])
    assert log.angle == 0 and log.singular is False


def test_se3_log_at_pi_is_flagged_and_both_signs_work():
    T = transform_from_rotation_translation(rot_x(PI), [0.3, 1.0, -2.0])
    log = twist_from_transform(T)
    assert log.singular is True
    np.testing.assert_allclose(transform_from_twist(log.twist), T, atol=1e-12)
    # The other logarithm: -w, with v from the same formula (d = 1/pi² at pi).
    w = -log.twist[3:]
    K = skew(w)
    v = (np.eye(3) - K / 2 + K @ K / PI**2) @ T[:3, 3]
    np.testing.assert_allclose(transform_from_twist(np.r_[v, w]), T, atol=1e-12)


def test_se3_symbolic():
    syms = sp.symbols("v1 v2 v3 w1 w2 w3", real=True)
    values = dict(zip(syms, [0.1, 0.2, -0.3, 0.3, -1.2, 0.5], strict=True))
    T = transform_from_twist(syms)
    got = np.array(T.subs(values).evalf(), dtype=float)
    np.testing.assert_allclose(got, transform_from_twist(list(values.values())), atol=ATOL)
    # Log of an exact transform: a screw motion about z through (1, 0, 0).
    V = [0, -sp.Rational(1, 2), sp.Rational(1, 5), 0, 0, sp.Rational(1, 2)]
    log = twist_from_transform(transform_from_twist(V))
    assert log.singular is False
    assert sp.simplify(log.twist - sp.Matrix(V)) == sp.zeros(6, 1)
    pure = twist_from_transform(transform_from_twist([1, 2, sp.Integer(3), 0, 0, 0]))
    assert pure.twist == sp.Matrix([1, 2, 3, 0, 0, 0])


# --------------------------------------------------------------------------------------------
# Screws, the adjoint, twists and wrenches
# --------------------------------------------------------------------------------------------


def test_screw_axis_by_hand():
    S = screw_axis_from_line([1, 0, 0], [0, 0, 2], 0.1)
    np.testing.assert_allclose(S, [0, -1, 0.1, 0, 0, 1], atol=ATOL)
    # Half a turn about the line x = 1 (parallel to z) takes the origin to (2, 0, 0.1 pi).
    T = transform_from_twist(twist_from_screw(S, PI))
    np.testing.assert_allclose(T[:3, 3], [2, 0, 0.1 * PI], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], rot_z(PI), atol=1e-12)
    prismatic = screw_axis_from_line([5, 5, 5], [0, 3, 4], math.inf)
    np.testing.assert_allclose(prismatic, [0, 0.6, 0.8, 0, 0, 0])
    assert screw_axis_from_line([5, 5, 5], [0, 3, 4], sp.oo) == sp.Matrix(
        [0, sp.Rational(3, 5), sp.Rational(4, 5), 0, 0, 0]
    )
    with pytest.raises(SymkinError, match="direction must be a non-zero vector"):
        screw_axis_from_line([0, 0, 0], [0, 0, 0], 0)


@FAST
@given(seeds, st.floats(-2, 2), st.floats(-3, 3))
def test_screw_motion_moves_points_on_the_axis_along_it(seed, pitch, angle):
    rng = np.random.default_rng(seed)
    point, direction = rng.normal(size=3), rng.normal(size=3)
    u = direction / np.linalg.norm(direction)
    T = transform_from_twist(twist_from_screw(screw_axis_from_line(point, direction, pitch), angle))
    on_axis = point + 0.7 * u
    np.testing.assert_allclose(
        T[:3, :3] @ on_axis + T[:3, 3], on_axis + pitch * angle * u, atol=1e-9
    )
    np.testing.assert_allclose(T[:3, :3], expm(skew(angle * u)), atol=1e-12)


@FAST
@given(seeds)
def test_adjoint_is_conjugation(seed):
    rng = np.random.default_rng(seed)
    T, V = random_transform(rng), rng.normal(size=6)
    Va = transform_twist(T, V)
    np.testing.assert_allclose(se3_matrix(Va), T @ se3_matrix(V) @ np.linalg.inv(T), atol=1e-12)
    np.testing.assert_allclose(adjoint_from_transform(T) @ V, Va, atol=1e-12)


@FAST
@given(seeds)
def test_adjoint_of_product_and_inverse(seed):
    rng = np.random.default_rng(seed)
    T1, T2 = random_transform(rng), random_transform(rng)
    Ad = adjoint_from_transform
    np.testing.assert_allclose(Ad(T1 @ T2), Ad(T1) @ Ad(T2), atol=1e-12)
    np.testing.assert_allclose(Ad(transform_inverse(T1)), np.linalg.inv(Ad(T1)), atol=1e-10)


@FAST
@given(seeds)
def test_wrench_transform_keeps_power(seed):
    rng = np.random.default_rng(seed)
    T, V_b, F_b = random_transform(rng), rng.normal(size=6), rng.normal(size=6)
    F_a = transform_wrench(T, F_b)
    np.testing.assert_allclose(F_a, np.linalg.inv(adjoint_from_transform(T)).T @ F_b, atol=1e-10)
    assert math.isclose(F_a @ transform_twist(T, V_b), F_b @ V_b, abs_tol=1e-10)


def test_wrench_by_hand():
    # A force along y at b's origin, with b at (2, 0, 0) in a: moment (2, 0, 0) x (0, 1, 0) = z.
    T = transform_from_rotation_translation(np.eye(3), [2, 0, 0])
    np.testing.assert_allclose(transform_wrench(T, [0, 1, 0, 0, 0, 0]), [0, 1, 0, 0, 0, 2])
    # A body turning about b's z axis at 1 rad/s: a's origin sees v = w x (0 - p) = (0, -2, 0).
    np.testing.assert_allclose(transform_twist(T, [0, 0, 0, 0, 0, 1]), [0, -2, 0, 0, 0, 1])


def test_adjoint_symbolic_matches_numeric():
    t, x = sp.symbols("t x", real=True)
    T = transform_from_rotation_translation(rot_z(t), [x, 1, 0])
    values = {t: 0.8, x: -0.4}
    Tn = np.array(T.subs(values).evalf(), dtype=float)
    Ad = np.array(adjoint_from_transform(T).subs(values).evalf(), dtype=float)
    np.testing.assert_allclose(Ad, adjoint_from_transform(Tn), atol=ATOL)
    F = [1, 2, 3, 4, 5, 6]
    got = np.array(transform_wrench(T, F).subs(values).evalf(), dtype=float).ravel()
    np.testing.assert_allclose(got, transform_wrench(Tn, F), atol=ATOL)


# --------------------------------------------------------------------------------------------
# Outside oracles: spatialmath and pytransform3d
# --------------------------------------------------------------------------------------------

SINGULAR_ROTATIONS = [
    np.eye(3),
    np.diag([1.0, -1, -1]),
    np.diag([-1.0, 1, -1]),
    np.diag([-1.0, -1, 1]),
]


def oracle_rotations() -> list[np.ndarray]:
    rng = np.random.default_rng(22)
    return [random_rotation(rng) for _ in range(30)] + SINGULAR_ROTATIONS


@pytest.mark.oracle
def test_quaternions_against_spatialmath_and_pytransform3d():
    import pytransform3d.rotations as pr
    import spatialmath.base as smb

    rng = np.random.default_rng(7)
    for _ in range(30):
        p, q = rng.normal(size=4), rng.normal(size=4)
        np.testing.assert_allclose(quaternion_product(p, q), smb.qqmul(p, q), atol=ATOL)
        np.testing.assert_allclose(
            quaternion_product(p, q), pr.concatenate_quaternions(p, q), atol=ATOL
        )
        np.testing.assert_allclose(quaternion_conjugate(p), pr.q_conj(p), atol=ATOL)
        pu, qu = unit_quaternion(p), unit_quaternion(q)
        for t in (0.0, 0.3, 1.0):
            ours = quaternion_slerp(p, q, t)
            # spatialmath flips the start instead of the end: the same path, sign -1.
            assert same_rotation_quaternion(ours, smb.qslerp(pu, qu, t, shortest=True))
            np.testing.assert_allclose(
                ours, pr.quaternion_slerp(pu, qu, t, shortest_path=True), atol=1e-9
            )
    for R in oracle_rotations():
        assert same_rotation_quaternion(quaternion_from_rotation(R), pr.quaternion_from_matrix(R))
        assert same_rotation_quaternion(quaternion_from_rotation(R), smb.r2q(R))


@pytest.mark.oracle
def test_so3_against_spatialmath_and_pytransform3d():
    import pytransform3d.rotations as pr
    import spatialmath.base as smb

    for R in oracle_rotations():
        log = rotation_vector_from_rotation(R)
        # At pi the sign is a choice: compare the rotations and the angle there.
        for ref in (pr.compact_axis_angle_from_matrix(R), smb.trlog(R, twist=True)):
            if log.singular:
                assert math.isclose(np.linalg.norm(ref), PI)
                assert same_rotation_quaternion(np.r_[0, log.vector], np.r_[0, ref])
            else:
                np.testing.assert_allclose(log.vector, ref, atol=1e-9)
        np.testing.assert_allclose(
            rotation_from_rotation_vector(log.vector),
            pr.matrix_from_compact_axis_angle(log.vector),
            atol=ATOL,
        )
        np.testing.assert_allclose(
            rotation_from_rotation_vector(log.vector), smb.trexp(log.vector), atol=ATOL
        )


@pytest.mark.oracle
def test_se3_and_adjoint_against_spatialmath_and_pytransform3d():
    import pytransform3d.transformations as pt
    import spatialmath.base as smb

    rng = np.random.default_rng(11)
    transforms = [random_transform(rng) for _ in range(30)]
    transforms += [
        transform_from_rotation_translation(R, rng.normal(size=3)) for R in SINGULAR_ROTATIONS
    ]
    for T in transforms:
        log = twist_from_transform(T)
        v, w = log.twist[:3], log.twist[3:]
        pt_log = pt.exponential_coordinates_from_transform(T)  # (w, v)
        if log.singular:
            np.testing.assert_allclose(
                pt.transform_from_exponential_coordinates(pt_log), T, atol=1e-10
            )
        else:
            np.testing.assert_allclose(np.r_[w, v], pt_log, atol=1e-9)
            np.testing.assert_allclose(log.twist, smb.trlog(T, twist=True), atol=1e-9)
        np.testing.assert_allclose(
            transform_from_twist(log.twist),
            pt.transform_from_exponential_coordinates(np.r_[w, v]),
            atol=1e-11,
        )
        np.testing.assert_allclose(
            transform_from_twist(log.twist), smb.trexp(log.twist), atol=1e-11
        )
        Ad = adjoint_from_transform(T)
        np.testing.assert_allclose(Ad, smb.tr2adjoint(T), atol=ATOL)
        swap = np.r_[3:6, 0:3]  # (v, w) <-> (w, v)
        np.testing.assert_allclose(Ad[np.ix_(swap, swap)], pt.adjoint_from_transform(T), atol=ATOL)


@pytest.mark.oracle
def test_screw_axis_against_spatialmath_and_pytransform3d():
    import pytransform3d.transformations as pt
    import spatialmath as sm

    rng = np.random.default_rng(5)
    for _ in range(20):
        q, d, h = rng.normal(size=3), rng.normal(size=3), rng.normal()
        u = d / np.linalg.norm(d)
        S = screw_axis_from_line(q, d, h)
        np.testing.assert_allclose(S, sm.Twist3.UnitRevolute(u, q, h).S, atol=ATOL)
        np.testing.assert_allclose(
            np.r_[S[3:], S[:3]], pt.screw_axis_from_screw_parameters(q, u, h), atol=ATOL
        )
        np.testing.assert_allclose(
            screw_axis_from_line(q, d, math.inf), sm.Twist3.UnitPrismatic(u).S, atol=ATOL
        )

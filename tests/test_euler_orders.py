"""The twelve Euler/Tait-Bryan orders and the rotation vector (symkin.spatial).

Independent checks: SciPy's ``Rotation.as_euler``/``from_euler`` (uppercase = intrinsic,
lowercase = extrinsic) for every order and direction; the gimbal-lock cases worked by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from symkin.errors import SymkinError
from symkin.spatial import (
    EULER_ORDERS,
    ORIENTATIONS,
    euler_from_rotation,
    orientation_from_rotation,
    rot_x,
    rot_y,
    rot_z,
    rotation_from_euler,
    rotation_from_orientation,
)

orders = st.sampled_from(EULER_ORDERS)
seeds = st.integers(0, 2**32 - 1)


def scipy_name(order: str, extrinsic: bool) -> str:
    return order if extrinsic else order.upper()


def test_twelve_orders() -> None:
    assert len(set(EULER_ORDERS)) == 12
    assert {o for o in EULER_ORDERS if o[0] == o[2]} == {
        "xyx", "xzx", "yxy", "yzy", "zxz", "zyz"
    }  # fmt: skip


@settings(max_examples=60, deadline=None)
@given(orders, st.booleans(), seeds)
def test_round_trip_matrix_angles_matrix(order: str, extrinsic: bool, seed: int) -> None:
    R = Rotation.random(random_state=seed).as_matrix()
    angles = euler_from_rotation(R, order, extrinsic)
    assert angles.singular is False
    np.testing.assert_allclose(rotation_from_euler(order, angles.angles, extrinsic), R, atol=1e-12)


@pytest.mark.parametrize("extrinsic", [False, True])
@pytest.mark.parametrize("order", EULER_ORDERS)
def test_against_scipy(order: str, extrinsic: bool) -> None:
    rng = np.random.default_rng(21)
    for _ in range(20):
        rotation = Rotation.random(random_state=rng)
        angles = euler_from_rotation(rotation.as_matrix(), order, extrinsic).angles
        # Same branch as SciPy: middle angle in [-pi/2, pi/2] (Tait-Bryan) or [0, pi].
        np.testing.assert_allclose(angles, rotation.as_euler(scipy_name(order, extrinsic)))
        given_angles = rng.uniform(-3, 3, 3)
        np.testing.assert_allclose(
            rotation_from_euler(order, given_angles, extrinsic),
            Rotation.from_euler(scipy_name(order, extrinsic), given_angles).as_matrix(),
            atol=1e-14,
        )


def test_extrinsic_is_the_reversed_intrinsic_order() -> None:
    a, b, c = 0.3, -0.7, 1.1
    np.testing.assert_allclose(
        rotation_from_euler("xyz", (a, b, c), extrinsic=True),
        rotation_from_euler("zyx", (c, b, a)),
    )


def test_zyx_gimbal_lock_by_hand() -> None:
    # Rz(0.3) Ry(pi/2) Rx(0.2) = Rz(0.3 - 0.2) Ry(pi/2): only psi - phi = 0.1 is defined.
    R = rot_z(0.3) @ rot_y(math.pi / 2) @ rot_x(0.2)
    (psi, theta, phi), _, _, singular = euler_from_rotation(R, "zyx")
    assert singular is True
    assert (psi, theta, phi) == pytest.approx((0.1, math.pi / 2, 0.0))


def test_proper_euler_poles_by_hand() -> None:
    # X-Y-X at beta = 0: Rx(0.5) Rx(0.25) = Rx(0.75); at beta = pi only alpha - gamma counts.
    angles = euler_from_rotation(rot_x(0.5) @ rot_x(0.25), "xyx")
    assert angles.singular is True
    assert angles.angles == pytest.approx((0.75, 0.0, 0.0))
    R = rot_x(0.5) @ rot_y(math.pi) @ rot_x(0.25)
    angles = euler_from_rotation(R, "xyx")
    assert angles.singular is True
    assert angles.angles == pytest.approx((0.25, math.pi, 0.0))
    np.testing.assert_allclose(rotation_from_euler("xyx", angles.angles), R, atol=1e-12)


def test_extrinsic_lock_zeroes_the_first_fixed_axis_angle() -> None:
    R = rot_z(0.4) @ rot_y(-math.pi / 2)  # extrinsic xyz: roll, pitch = -pi/2, yaw
    angles = euler_from_rotation(R, "xyz", extrinsic=True)
    assert angles.singular is True
    assert angles.angles == pytest.approx((0.0, -math.pi / 2, 0.4))


def test_symbolic_round_trip_and_exact_lock() -> None:
    a, b, c = sp.symbols("a b c")
    R = rotation_from_euler("yzx", (a, b, c))
    assert isinstance(R, sp.ImmutableMatrix)
    angles = euler_from_rotation(R, "yzx")
    assert angles.singular is None  # cos b may vanish: undecidable
    values = {a: 0.4, b: -0.3, c: 1.2}
    assert [float(x.subs(values)) for x in angles.angles] == pytest.approx([0.4, -0.3, 1.2])
    pole = rot_y(a) @ rot_x(sp.pi) @ rot_y(c)
    angles = euler_from_rotation(pole, "yxy")
    assert angles.singular is True
    assert sp.simplify(rotation_from_euler("yxy", angles.angles) - pole) == sp.zeros(3, 3)


def test_bad_order_names_the_choices() -> None:
    with pytest.raises(SymkinError, match="xyz"):
        euler_from_rotation(np.eye(3), "xxy")
    with pytest.raises(SymkinError, match="rotvec"):
        orientation_from_rotation(np.eye(3), "quat")


@pytest.mark.parametrize("kind", ORIENTATIONS)
def test_orientation_by_name_round_trip(kind: str) -> None:
    R = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()
    values = orientation_from_rotation(R, kind).values
    np.testing.assert_allclose(rotation_from_orientation(kind, values), R, atol=1e-12)
    if kind == "rotvec":
        np.testing.assert_allclose(values, [0.3, -0.2, 0.5], atol=1e-12)

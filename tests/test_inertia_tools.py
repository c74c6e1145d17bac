"""symkin.spatial.inertia against textbook formulas, hand-done Steiner and point masses."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from symkin import (
    RigidBody,
    box_inertia,
    composite_body,
    cylinder_inertia,
    hollow_cylinder_inertia,
    inertia_about_com,
    inertia_about_point,
    rotated_inertia,
    sphere_inertia,
)
from symkin.errors import SymkinError
from symkin.spatial import rot_z


def test_solid_cylinder_textbook():
    # m (3 r^2 + h^2) / 12 across, m r^2 / 2 along (Gross et al., table 3.2)
    tensor = cylinder_inertia(2.0, 0.1, 0.5, axis="x")
    across = 2.0 * (3 * 0.01 + 0.25) / 12
    np.testing.assert_allclose(tensor, np.diag([2.0 * 0.01 / 2, across, across]))


def test_cylinder_symbolic():
    m, r, h = sp.symbols("m r h", positive=True)
    tensor = cylinder_inertia(m, r, h)
    assert sp.simplify(tensor[2, 2] - m * r**2 / 2) == 0
    assert sp.simplify(tensor[0, 0] - m * (3 * r**2 + h**2) / 12) == 0


def test_hollow_cylinder_thin_wall_limit():
    # a thin ring of radius r: m r^2 about its axis
    tensor = hollow_cylinder_inertia(3.0, 0.2, 0.2, 0.0)
    np.testing.assert_allclose(tensor[2, 2], 3.0 * 0.04)


def test_box_and_sphere_textbook():
    np.testing.assert_allclose(
        box_inertia(12.0, 1.0, 2.0, 3.0), np.diag([4 + 9, 1 + 9, 1 + 4]) * 1.0
    )
    np.testing.assert_allclose(sphere_inertia(5.0, 2.0), np.eye(3) * 2 * 5 * 4 / 5)


def test_box_against_point_cloud():
    # an independent check: integrate a uniform grid of point masses
    edges = np.array([0.4, 0.2, 0.1])
    k = 24
    grid = [(np.arange(k) + 0.5) / k * e - e / 2 for e in edges]
    points = np.stack(np.meshgrid(*grid, indexing="ij"), -1).reshape(-1, 3)
    dm = 3.0 / len(points)
    numeric = sum(dm * (p @ p * np.eye(3) - np.outer(p, p)) for p in points)
    np.testing.assert_allclose(box_inertia(3.0, *edges), numeric, rtol=2e-3, atol=1e-12)


def test_rotation_about_z_swaps_axes():
    # a rod along x turned 90 degrees about z lies along y
    rod = np.diag([0.0, 1.0, 1.0])
    np.testing.assert_allclose(
        rotated_inertia(rod, rot_z(np.pi / 2)), np.diag([1.0, 0.0, 1.0]), atol=1e-15
    )


def test_steiner_by_hand_and_back():
    # sphere m = 2, r = 0.5 (I_c = 0.2) with its centre at (1, 0, 0) from o:
    # about o: I_xx = 0.2, I_yy = I_zz = 0.2 + 2 * 1^2 = 2.2
    centre = sphere_inertia(2.0, 0.5)
    about_o = inertia_about_point(centre, 2.0, [1.0, 0.0, 0.0])
    np.testing.assert_allclose(about_o, np.diag([0.2, 2.2, 2.2]))
    np.testing.assert_allclose(inertia_about_com(about_o, 2.0, [1.0, 0.0, 0.0]), centre)


def test_steiner_products_sign():
    # a point mass m at (a, b, 0): I_xy = -m a b (tensor convention, minus the product)
    tensor = inertia_about_point(np.zeros((3, 3)), 2.0, [1.0, 3.0, 0.0])
    assert tensor[0, 1] == pytest.approx(-6.0)
    assert tensor[2, 2] == pytest.approx(2.0 * 10.0)


def test_composite_of_two_point_masses():
    # m1 = 1 at x = 0, m2 = 3 at x = 4: centre x = 3; I_yy = 1 * 9 + 3 * 1 = 12
    zero = np.zeros((3, 3))
    body = composite_body([RigidBody(1.0, [0.0, 0, 0], zero), RigidBody(3.0, [4.0, 0, 0], zero)])
    assert body.mass == pytest.approx(4.0)
    np.testing.assert_allclose(body.com, [3.0, 0, 0])
    np.testing.assert_allclose(body.inertia, np.diag([0.0, 12.0, 12.0]))


def test_composite_symbolic_dumbbell():
    m, a = sp.symbols("m a", positive=True)
    zero = sp.zeros(3, 3)
    body = composite_body([RigidBody(m, [a, 0, 0], zero), RigidBody(m, [-a, 0, 0], zero)])
    assert body.com == sp.ImmutableMatrix([0, 0, 0])
    assert sp.simplify(body.inertia[1, 1] - 2 * m * a**2) == 0


def test_bad_input_is_a_symkin_error():
    with pytest.raises(SymkinError, match="axis"):
        cylinder_inertia(1.0, 0.1, 0.2, axis="w")
    with pytest.raises(SymkinError, match="total mass is zero"):
        composite_body([RigidBody(0.0, [0, 0, 0], np.zeros((3, 3)))])
    with pytest.raises(SymkinError, match="3x3"):
        rotated_inertia(np.eye(2), np.eye(3))

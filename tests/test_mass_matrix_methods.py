"""The generated ``mass_matrix`` (composite-rigid-body algorithm, ``symkin.derive.newton_euler``)
against an independent derivation: Lagrange's ``M = sum m J_v^T J_v + J_w^T R I R^T J_w`` of
the link Jacobians (``symkin.derive.lagrange``), at random configurations and random values of
any symbolic lengths or inertial data.  The arms cover what the recursion handles apart: a
flipped (tilted) joint axis, URDF-placed joints, modified DH with a prismatic joint, elastic
joints with rotor inertia."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from test_derivatives import PRISMATIC_ARM

DATA = Path(__file__).parent / "data"


@pytest.mark.parametrize(
    "robot",
    [
        pytest.param(
            lambda: symkin.load_robot(DATA / "dh_tilted_arm.toml"),
            id="tilted",
            marks=pytest.mark.slow,
        ),
        pytest.param(lambda: symkin.load_robot(DATA / "placed_arm.toml"), id="placed"),
        pytest.param(lambda: symkin.load_robot(DATA / "puma560_elastic.toml"), id="elastic"),
        pytest.param(lambda: symkin.robot_from_toml(PRISMATIC_ARM, "p.toml"), id="prismatic"),
    ],
)
@pytest.mark.filterwarnings("ignore")
def test_composite_rigid_body_mass_matrix_is_lagranges(robot):
    model = symkin.derive(robot())
    matrices = [d.expanded(d.mass_matrix) for d in (model.newton_euler, model.lagrange)]
    free = sorted(set().union(*(m.free_symbols for m in matrices)) - set(model.q), key=str)
    symbols = [*model.q, *free]
    ours, theirs = (sp.lambdify(symbols, m, "numpy") for m in matrices)
    rng = np.random.default_rng(7)
    for _ in range(4):
        values = [*rng.uniform(-2.0, 2.0, len(model.q)), *rng.uniform(0.3, 2.0, len(free))]
        expected = np.array(theirs(*values), dtype=float)
        actual = np.array(ours(*values), dtype=float)
        assert np.abs(expected).max() > 0.1
        np.testing.assert_allclose(actual, expected, atol=1e-10 * np.abs(expected).max())

"""Determinants of robots written with decimal literals (inexact constants) still factor.

Expected values: NumPy's determinant of the numerically evaluated task Jacobian, and the
structure of the arm (the elbow, joint 3, stretched out or folded back is singular).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

import symkin

DECIMAL_ARM = """
name = "decimal_arm"
[[joints]]
type = "revolute"
d = 0.3
alpha = 90
[[joints]]
type = "revolute"
a = 0.4
[[joints]]
type = "revolute"
a = 0.35
"""


def test_decimal_literals_keep_their_exact_factors() -> None:
    model = symkin.derive(symkin.robot_from_toml(DECIMAL_ARM, "decimal_arm.toml"))
    determinant = model.determinant()
    q2, q3 = sp.Symbol("q2", real=True), sp.Symbol("q3", real=True)
    assert sp.sin(q3) in sp.Mul.make_args(determinant)
    conditions = {(c.lhs, c.rhs) for c in model.singular_configurations()}
    assert {(q3, sp.Integer(0)), (q3, sp.pi)} <= conditions
    evaluate = sp.lambdify(model.q, determinant)
    jacobian = symkin.numeric_function(model, model.task_jacobian())
    for q in np.random.default_rng(2).uniform(-np.pi, np.pi, size=(10, 3)):
        np.testing.assert_allclose(evaluate(*q), np.linalg.det(jacobian(q)), rtol=1e-12, atol=1e-15)
    assert q2 in determinant.free_symbols

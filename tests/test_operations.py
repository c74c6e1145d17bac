"""``symkin.kernels.operations.visual_counts`` gives what ``sympy.count_ops(visual=True)``
gives (the reference: SymPy's own function), on hand-picked expressions with every rule of
its walk (negative and rational coefficients, denominators, square roots, ``exp``, functions),
on random expressions (Hypothesis) and on every expression of a robot's generated kernels.
"""

from __future__ import annotations

from collections import Counter

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkin.generate import robot_kernels
from symkin.kernels.operations import visual_counts

x, y, z = sp.symbols("x y z", real=True)
f = sp.Function("f")

HAND_PICKED = [
    x + y,
    -x - y,
    -x + y,
    x - 2 * y + 3,
    x * y * z,
    -x * y,
    -2 * x,
    sp.Float(-0.5) * x * y,
    sp.Float(1.0) * x,
    x / y,
    -x / (2 * y),
    sp.Rational(-1, 3),
    sp.Rational(1, 3) * x,
    2 * x / 3,
    1 / (x + y),
    x**2 * y**-2,
    sp.sqrt(x**2 + y**2),
    1 / sp.sqrt(x),
    sp.sin(x) * sp.cos(y) - sp.sin(y) * sp.cos(x),
    sp.atan2(y, x),
    sp.exp(-sp.Abs(x / y)) * sp.sign(x) + sp.Float(0.3) * x,
    sp.exp(x),
    sp.E * x,
    f(x) + 1,
    sp.Max(x, y, z),
    sp.Mul(2, x + y, evaluate=False),
    sp.Mul(-1, x + y, evaluate=False),
    sp.Piecewise((x, x > 0), (-x, True)),
    x**y,
    sp.Integer(1),
    sp.Integer(-4),
]


def reference(expr: sp.Expr) -> Counter[str]:
    counts: Counter[str] = Counter()
    for term in sp.Add.make_args(sp.count_ops(expr, visual=True)):
        coefficient, symbol = term.as_coeff_Mul()
        if isinstance(symbol, sp.Symbol):
            counts[symbol.name] += int(coefficient)
    return +counts


@pytest.mark.parametrize("expr", HAND_PICKED, ids=str)
def test_hand_picked_expressions_count_as_in_sympy(expr):
    assert visual_counts(expr) == reference(expr)


def _expressions() -> st.SearchStrategy[sp.Expr]:
    leaves = st.sampled_from(
        [x, y, z, sp.Integer(2), sp.Integer(-3), sp.Rational(1, 2), sp.Float(-0.25)]
    )
    unary = [sp.sin, sp.cos, sp.sqrt, lambda e: 1 / e, lambda e: -e, lambda e: e**2]
    binary = [sp.Add, sp.Mul, lambda a, b: a - b, lambda a, b: a / b]
    return st.recursive(
        leaves,
        lambda inner: st.one_of(
            st.tuples(st.sampled_from(unary), inner).map(lambda t: t[0](t[1])),
            st.tuples(st.sampled_from(binary), inner, inner).map(lambda t: t[0](t[1], t[2])),
        ),
        max_leaves=12,
    )


@settings(max_examples=300, deadline=None)
@given(_expressions())
def test_random_expressions_count_as_in_sympy(expr):
    assert visual_counts(expr) == reference(expr)


@pytest.mark.parametrize("name", ["planar_2r", "rpr", "scara"])
def test_kernel_expressions_count_as_in_sympy(model_of, name):
    kernels = robot_kernels(model_of(name))
    expressions = [e for k in kernels for _, e in k.assignments]
    expressions += [e for k in kernels for output in k.outputs for e in output.matrix]
    assert len(expressions) > 50
    for expr in expressions:
        assert visual_counts(expr) == reference(expr), expr

"""``symkin.kernels.rename.renamed`` gives what SymPy's own ``xreplace`` (which re-evaluates
every sum and product) gives, argument order included, for renamings that change the order
SymPy sorts the arguments in."""

from __future__ import annotations

import sympy as sp
from hypothesis import given, settings

from expression_strategies import expressions
from symkin.kernels.rename import renamed, renamed_matrix

OLD = sp.symbols("r0:6", real=True)
Q = sp.symbols("q1:3", real=True)
# Reversed names: the order of the new symbols is the opposite of the old ones', and some
# sort before the joint symbols q1, q2 and some after.
NEW = tuple(sp.Symbol(name, real=True) for name in ("z9", "t4", "t3", "a2", "a1", "_a0"))
RENAMING = dict(zip(OLD, NEW, strict=True))


@settings(max_examples=200, deadline=None)
@given(expressions(OLD + Q, numbers=False))
def test_renamed_is_xreplace_argument_for_argument(expr):
    expected = expr.xreplace(RENAMING)
    actual = renamed(expr, RENAMING, {})
    assert actual == expected
    assert sp.srepr(actual) == sp.srepr(expected)


def test_shared_memo_and_matrices():
    r0, r1, *_ = OLD
    q1, q2 = Q
    shared = sp.Float(0.5) * r1 * q2 + r0
    matrix = sp.Matrix([[shared, shared * q1], [sp.cos(shared), 2]])
    memo: dict = {}
    actual = renamed_matrix(matrix, RENAMING, memo)
    assert actual == matrix.xreplace(RENAMING)
    # The shared sum is rebuilt once and reused.
    assert actual[0, 0] is actual[1, 0].args[0]
    assert renamed(q1 * q2, RENAMING, memo) == q1 * q2


def test_odd_function_of_a_renamed_difference_keeps_the_product_canonical():
    # The renaming swaps r0 and r1 in SymPy's order: sin(r0 - r1) becomes -sin(t4 - z9), whose
    # sign must merge into the product's coefficient, as SymPy's constructors merge it.
    r0, r1, *_ = OLD
    q1, q2 = Q
    for expr in (
        2 * q1 * sp.sin(r0 - r1),
        q1 * sp.sin(r0 - r1),
        2 * q1 * sp.cos(r0 - r1) - sp.sin(r0 - r1),
        sp.sin(r0 - r1) * q2 + q2,
        3 * sp.sign(r1 - r0) * sp.tanh(r0 - r1),
    ):
        expected = expr.xreplace(RENAMING)
        actual = renamed(expr, RENAMING, {})
        assert sp.srepr(actual) == sp.srepr(expected), expr

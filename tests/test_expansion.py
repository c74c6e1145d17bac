"""SymEngine expansion and products in the contraction policy (derive/simplify.py).

Expected values: SymPy's own ``expand`` and matrix product (another implementation), and
numbers for the product-form fallback.
"""

from __future__ import annotations

import pytest
import symengine as se
import sympy as sp

from symkin.derive import simplify
from symkin.derive.simplify import (
    contract_product,
    contract_trig,
    expand,
    sympy_from_symengine,
)

q1, q2, a = sp.symbols("q1 q2 a", real=True)


def test_expand_equals_sympy_and_keeps_the_symbols_assumptions():
    expr = (a * sp.cos(q1) + sp.Float(0.3) * sp.sin(q2)) ** 2 * (
        sp.cos(q1 + q2) - sp.Rational(1, 3)
    )
    result = expand(expr)
    assert sp.expand(result - sp.expand(expr)) == 0
    assert result.free_symbols == {q1, q2, a}
    assert all(s.is_real for s in result.free_symbols)


def test_expand_gives_none_past_the_term_limit():
    expr = sp.Add(*(sp.cos(q1) ** k for k in range(5))) * sp.Add(
        *(sp.sin(q2) ** k for k in range(5))
    )
    assert expand(expr, max_terms=24) is None
    assert len(sp.Add.make_args(expand(expr, max_terms=25))) == 25


def test_contract_product_is_the_contracted_sympy_product():
    left = sp.Matrix([[sp.cos(q1), -sp.sin(q1)], [sp.sin(q1), sp.cos(q1)]])
    right = sp.Matrix([[sp.cos(q2), -sp.sin(q2) * a], [sp.sin(q2), sp.Float(0.5) * sp.cos(q2)]])
    result = contract_product(left, right)
    expected = (left * right).applyfunc(contract_trig)
    assert result == sp.ImmutableMatrix(expected)
    assert result[0, 0] == sp.cos(q1 + q2)


def test_contract_product_keeps_long_entries_in_product_form(monkeypatch):
    monkeypatch.setattr(simplify, "MAX_CONTRACTED_TERMS", 1)
    left = sp.Matrix([[sp.cos(q1) + a, sp.sin(q1)]])
    right = sp.Matrix([[sp.cos(q2) + 1], [sp.sin(q2)]])
    result = contract_product(left, right)
    assert result[0, 0] == (sp.cos(q1) + a) * (sp.cos(q2) + 1) + sp.sin(q1) * sp.sin(q2)
    point = {q1: 0.3, q2: -1.1, a: 0.7}
    assert abs(float(result[0, 0].subs(point)) - float((left * right)[0, 0].subs(point))) < 1e-15


def _symengine_own_conversion(expr, symbols):
    """SymEngine's converter (``_sympy_``, SymPy's constructors throughout), then our symbols."""
    return expr._sympy_().xreplace({sp.Symbol(s.name): s for s in symbols})


@pytest.mark.parametrize(
    "expr",
    [
        (a * sp.cos(q1) + sp.Float(0.107) * sp.sin(q2) - 1) ** 3 * (sp.cos(q1 + q2) - a),
        sp.Float(1.0) * a * sp.sin(q1) + sp.Float(0.5) * sp.cos(q2) ** 2 * a**2 + 3,
        (sp.sqrt(2) / 2 * sp.cos(q1) - sp.sqrt(2) / 2 * sp.sin(q1)) * (a + sp.sin(q2)),
        sp.Rational(1, 3) * a * sp.sin(q1) ** 2 * sp.cos(q1) - a / 3 + sp.cos(q1 + 2 * q2),
        (a + sp.sin(q1)) * (a - sp.sin(q1)) + sp.sin(q1) ** 2,
    ],
)
def test_rebuilt_expansion_is_sympys_own_canonical_form(expr):
    """The rebuild assembles plain sums and products in SymPy's canonical order itself; the
    result must be the very object SymPy's constructors make (same args, same order)."""
    expanded = se.expand(se.sympify(expr))
    symbols = expr.free_symbols
    rebuilt = sympy_from_symengine(expanded, {s.name: s for s in symbols})
    expected = _symengine_own_conversion(expanded, symbols)
    assert sp.srepr(rebuilt) == sp.srepr(expected)
    assert rebuilt == expected and hash(rebuilt) == hash(expected)
    assert sp.expand(rebuilt - sp.expand(expr)) == 0

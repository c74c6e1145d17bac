"""``symkin.kernels.engine_cse``: SymEngine's CSE with SymPy's calling convention.  Its
conversion back to SymPy (``symkin.derive.simplify.sympy_from_symengine``) gives what
SymEngine's own converter (``sympy.sympify``, which re-evaluates every sum and product in
SymPy) gives, argument order included, and the replacements rebuild the original
expressions."""

from __future__ import annotations

import symengine as se
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from expression_strategies import expressions
from symkin.derive.simplify import sympy_from_symengine
from symkin.kernels.engine_cse import symengine_cse

SYMBOLS = sp.symbols("a b c q1 x0")  # x0: a name SymEngine's CSE also uses


@settings(max_examples=300, deadline=None)
@given(expressions(SYMBOLS))
def test_conversion_is_sympys_own_argument_for_argument(expr):
    converted = se.sympify(expr)
    expected = sp.sympify(converted)
    actual = sympy_from_symengine(converted, {s.name: s for s in SYMBOLS}, {})
    assert sp.srepr(actual) == sp.srepr(expected)


@settings(max_examples=100, deadline=None)
@given(st.lists(expressions(SYMBOLS, powers=(2, -1)), min_size=1, max_size=4))
def test_replacements_rebuild_the_expressions(exprs):
    # Integer powers only, as in the kernels: SymEngine writes sqrt(1/a) as 1/sqrt(a).
    matrix = sp.ImmutableMatrix([exprs[0], exprs[-1]])
    found, reduced = symengine_cse([*exprs, matrix], sp.numbered_symbols("_t"))
    # Substituted back in reverse order (each may use earlier ones), every expression returns.
    back = reduced
    for symbol, definition in reversed(found):
        back = [e.xreplace({symbol: definition}) for e in back]
    for original, rebuilt in zip([*exprs, matrix], back, strict=True):
        difference = (
            sp.ImmutableMatrix([original - rebuilt])
            if not isinstance(original, sp.MatrixBase)
            else original - rebuilt
        )
        assert difference.applyfunc(sp.simplify) == sp.zeros(*difference.shape)

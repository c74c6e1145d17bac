"""A Hypothesis strategy of random SymPy expressions (sums, products, sines, powers and
numbers over given symbols) for the tests of symkin's own constructions of SymPy objects."""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from hypothesis import strategies as st

COEFFICIENTS = (
    sp.Integer(1),
    sp.Integer(-1),
    sp.Integer(2),
    sp.Float(0.5),
    sp.Float(-1.0),
    sp.Float(1.0),
    sp.Float(-1.5),
    sp.Rational(-3, 7),
)
POWERS = (2, -1, sp.Rational(1, 2))


@st.composite
def expressions(
    draw,
    symbols: Sequence[sp.Symbol],
    depth: int = 3,
    powers: Sequence[sp.Expr] = POWERS,
    numbers: bool = True,
):
    """An expression over ``symbols`` of at most ``depth`` levels; bare numbers among the
    leaves only when ``numbers``."""
    atoms = st.sampled_from(tuple(symbols))
    if depth == 0:
        return draw(atoms)
    kinds = ("atom", "sum", "product", "sin", "power") + (("number",) if numbers else ())
    kind = draw(st.sampled_from(kinds))
    if kind == "atom":
        return draw(atoms)
    if kind == "number":
        return draw(st.sampled_from(COEFFICIENTS))
    inner = [
        draw(expressions(symbols, depth - 1, powers, numbers))
        for _ in range(draw(st.integers(1, 3)))
    ]
    coefficient = draw(st.sampled_from(COEFFICIENTS))
    if kind == "sum":
        return coefficient + sp.Add(*inner)
    if kind == "product":
        return coefficient * sp.Mul(*inner)
    if kind == "sin":
        return sp.sin(inner[0])
    return inner[0] ** draw(st.sampled_from(tuple(powers)))

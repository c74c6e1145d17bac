"""Common subexpressions found by SymEngine, with SymPy's calling convention.

``sympy.cse`` builds and re-evaluates many SymPy products on the way (its search for sums
and products sharing some of their terms, and the rebuilding of every expression), and each
new floating-point coefficient costs a deduction in SymPy's assumption system; SymEngine's
CSE shares equal subexpressions in C++ and comes back to SymPy once.  It does not look for
partly shared sums and products, so the result can have a few more operations.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import symengine as se
import sympy as sp

from symkin.derive.simplify import sympy_from_symengine


def symengine_cse(
    expressions: Sequence[sp.Expr | sp.MatrixBase], symbols: Iterator[sp.Symbol]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr | sp.ImmutableMatrix]]:
    """``sympy.cse(expressions, symbols=symbols)``'s result (replacements in evaluation
    order, then the reduced expressions, matrices kept as matrices), found by SymEngine.

    The new subexpressions are named from ``symbols``; the expressions' own symbols come
    back as the same SymPy objects (with their assumptions).
    """
    flat: list[sp.Expr] = []
    shapes: list[tuple[int, int] | None] = []
    for expr in expressions:
        if isinstance(expr, sp.MatrixBase):
            shapes.append(expr.shape)
            flat.extend(expr)
        else:
            shapes.append(None)
            flat.append(expr)
    names = {s.name: s for e in flat for s in e.free_symbols}
    replacements, reduced = se.cse([se.sympify(e) for e in flat])
    found = []
    seen: dict = {}  # converted once, shared by every expression
    for symbol, expr in replacements:
        # SymEngine names its symbols apart from the expressions' own (x0 taken: x1).
        names[symbol.name] = next(symbols)
        found.append((names[symbol.name], sympy_from_symengine(expr, names, seen)))
    entries = iter([sympy_from_symengine(e, names, seen) for e in reduced])
    result: list[sp.Expr | sp.ImmutableMatrix] = []
    for shape in shapes:
        if shape is None:
            result.append(next(entries))
        else:
            rows, columns = shape
            result.append(
                sp.ImmutableMatrix(rows, columns, [next(entries) for _ in range(rows * columns)])
            )
    return found, result

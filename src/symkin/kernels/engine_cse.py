"""Common subexpressions found by SymEngine, with SymPy's calling convention.

``sympy.cse`` builds and re-evaluates many SymPy products on the way (its search for sums
and products sharing some of their terms, and the rebuilding of every expression), and each
new floating-point coefficient costs a deduction in SymPy's assumption system; SymEngine's
CSE shares equal subexpressions in C++ and comes back to SymPy once.  It does not look for
partly shared sums and products, so the result can have a few more operations.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

import symengine as se
import sympy as sp
from sympy.core.basic import _args_sortkey

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
        found.append((names[symbol.name], _converted(expr, names, seen)))
    entries = iter([_converted(e, names, seen) for e in reduced])
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


def _converted(expr: se.Basic, names: dict[str, sp.Symbol], seen: dict) -> sp.Expr:
    """``expr`` in SymPy, as :func:`~symkin.derive.simplify.sympy_from_symengine` gives it,
    sums and products of CSE's output assembled directly where SymPy's constructor would
    only sort their arguments (:func:`_assembled`); ``seen`` converts each once."""
    done = seen.get(expr)
    if done is None:
        done = None
        if isinstance(expr, se.Add | se.Mul):
            args = [_converted(a, names, seen) for a in expr.args]
            done = _assembled(sp.Add if isinstance(expr, se.Add) else sp.Mul, args)
            if done is None:
                done = (sp.Add if isinstance(expr, se.Add) else sp.Mul)(*args)
        else:
            done = sympy_from_symengine(expr, names, seen)
        seen[expr] = done
    return done


def _assembled(kind: type, args: list[sp.Expr]) -> sp.Expr | None:
    """``kind(*args)`` for the arguments of a SymEngine sum or product (like terms and like
    factors already collected, numbers folded into one finite non-zero coefficient), when
    SymPy would only order them: no nested sum or product, no number times a sum (SymPy
    distributes it), no power of a number; ``None`` otherwise.  The number goes first, the
    rest in ``Basic.compare`` order, as SymPy's constructors leave them."""
    numbers = [a for a in args if a.is_Number]
    rest = [a for a in args if not a.is_Number]
    if len(numbers) > 1 or not rest or any(isinstance(a, kind) for a in rest):
        return None
    if kind is sp.Mul and (
        (numbers and len(rest) == 1 and rest[0].is_Add)
        or any(a.is_Pow and a.base.is_Number for a in rest)
    ):
        return None
    if numbers:
        value = float(numbers[0])
        if value == 0.0 or not math.isfinite(value):
            return None
        if numbers[0] == kind.identity:
            numbers = []
    if len(numbers) + len(rest) < 2:
        return None
    rest.sort(key=_args_sortkey)
    return kind._from_args(numbers + rest, True)

"""Symbols renamed in expressions without re-evaluating them.

``expr.xreplace({old: new})`` rebuilds every sum and product above a replaced symbol through
SymPy's ``Add``/``Mul`` constructors, which multiply the floating-point coefficient by one
again (a new ``Float``) and ask its assumptions, re-deducing SymPy's fact base for every new
number: on a generic arm's dynamics kernels this was a fifth of the passes' time.  A renaming
of symbols to *distinct* new symbols cannot merge or cancel terms, so the only thing
evaluation would change is the order of the arguments; :func:`renamed` rebuilds sums and
products with their arguments sorted as SymPy's constructors sort them (the number first,
the rest by ``Basic.compare``) and gives the same expressions as ``xreplace``.
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy as sp

from symkin.derive.simplify import canonical_sum_or_product


def renamed(expr: sp.Basic, renaming: Mapping[sp.Symbol, sp.Symbol], memo: dict) -> sp.Basic:
    """``expr.xreplace(renaming)`` for a one-to-one ``renaming`` of symbols to symbols.

    ``memo`` (by object identity, shared across calls over the same expressions) keeps a
    subexpression shared by several expressions from being rebuilt twice; the caller keeps
    the expressions alive while it is in use.
    """
    key = id(expr)
    if key in memo:
        return memo[key][1]
    if expr.is_Symbol:
        result = renaming.get(expr, expr)
    elif not expr.args:
        result = expr
    else:
        args = [renamed(a, renaming, memo) for a in expr.args]
        if all(new is old for new, old in zip(args, expr.args, strict=True)):
            result = expr
        elif (expr.is_Add or expr.is_Mul) and expr.is_commutative:
            result = _sorted(type(expr), args)
        else:
            result = expr.func(*args)
    memo[key] = (expr, result)  # the expression kept so its id is not reused
    return result


def renamed_matrix(
    matrix: sp.MatrixBase, renaming: Mapping[sp.Symbol, sp.Symbol], memo: dict
) -> sp.ImmutableMatrix:
    """:func:`renamed` applied to every entry of ``matrix``."""
    entries = [renamed(e, renaming, memo) for e in matrix]
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, entries)


def _sorted(kind: type, args: list[sp.Basic]) -> sp.Basic:
    """An ``Add`` or ``Mul`` of renamed arguments in the order its constructor gives them.

    A renamed argument that is no longer a plain term or factor (an odd function of a
    difference turns its sign over when the renaming swaps the order: ``sin(t4 - z9)`` is
    ``-sin(z9 - t4)``, a product with a coefficient) goes through the constructor instead,
    which merges the coefficient as ``xreplace`` would."""
    assembled = canonical_sum_or_product(kind, args)
    return kind(*args) if assembled is None else assembled

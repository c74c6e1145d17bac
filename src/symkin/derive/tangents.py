"""Forward-mode derivatives through named intermediates (the chain rule, one direction at a
time), so a derivative never expands what a recursion or a CSE kept short.

For assignments ``s_k = e_k(x, s_1 .. s_{k-1})`` and a direction ``xdot`` (a seed per input
symbol), the tangent of every intermediate is ``sdot_k = sum_y de_k/dy * ydot`` over the
symbols ``y`` of ``e_k`` with a non-zero tangent (Griewank & Walther, *Evaluating
Derivatives*, 2nd ed., section 3.1, the tangent propagation of an evaluation trace).  Each
``e_k`` is short, so each partial is a cheap SymPy ``diff``; intermediates that do not depend
on the direction get no tangent at all (a link before joint j does not move with ``q_j``).

``sign`` (Coulomb friction) differentiates to ``DiracDelta``; it is taken as 0: the derivative
away from ``dq = 0``, where the friction law has a jump and no derivative.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy as sp

from symkin.symbols import unused_prefix

Assignments = tuple[tuple[sp.Symbol, sp.Expr], ...]


def _without_impulses(expr: sp.Expr) -> sp.Expr:
    if not expr.has(sp.DiracDelta):
        return expr
    return expr.replace(sp.DiracDelta, lambda *_: sp.Integer(0))


def _directional(expr: sp.Expr, tangents: Mapping[sp.Symbol, sp.Expr]) -> sp.Expr:
    """``sum_y d expr/dy * ydot`` over the symbols of ``expr`` with a tangent."""
    moving = sorted(expr.free_symbols & tangents.keys(), key=lambda s: s.name)
    return _without_impulses(sp.Add(*(sp.diff(expr, y) * tangents[y] for y in moving)))


def tangent_assignments(
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    outputs: Sequence[sp.MatrixBase],
    seeds: Mapping[sp.Symbol, sp.Expr],
    prefix: str,
) -> tuple[Assignments, tuple[sp.ImmutableMatrix, ...]]:
    """The tangents of ``outputs`` along ``seeds`` (``{input symbol: its rate}``).

    Returns new named intermediates ``<prefix>0, <prefix>1, ...`` (after ``assignments`` in
    evaluation order; they may use them) and the tangent of each output matrix, entry by
    entry.  A tangent that is a number or a symbol is used in place, not named.
    """
    tangents: dict[sp.Symbol, sp.Expr] = {s: v for s, v in seeds.items() if v != 0}
    named: list[tuple[sp.Symbol, sp.Expr]] = []
    # A robot parameter named <prefix><k> would be taken for the intermediate: avoid it.
    used = {s.name for _, e in assignments for s in e.free_symbols}
    prefix = unused_prefix(prefix, used | {s.name for m in outputs for s in m.free_symbols})
    for symbol, expr in assignments:
        rate = _directional(expr, tangents)
        if rate == 0:
            continue
        if not rate.is_Atom:
            name = sp.Symbol(f"{prefix}{len(named)}", real=True)
            named.append((name, rate))
            rate = name
        tangents[symbol] = rate
    rates = tuple(
        sp.ImmutableMatrix(m.shape[0], m.shape[1], [_directional(e, tangents) for e in m])
        for m in outputs
    )
    return tuple(named), rates


def jacobian_columns(
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    vector: sp.MatrixBase,
    variables: Sequence[sp.Symbol],
    prefix: str,
) -> tuple[Assignments, sp.ImmutableMatrix]:
    """``d vector / d variables`` (rows: the vector's entries, columns: the variables), one
    tangent sweep per variable; the intermediates of sweep j are named ``<prefix><j>_<k>``."""
    columns: list[sp.ImmutableMatrix] = []
    named: list[tuple[sp.Symbol, sp.Expr]] = []
    for j, variable in enumerate(variables):
        sweep, (column,) = tangent_assignments(
            assignments, [vector], {variable: sp.Integer(1)}, f"{prefix}{j}_"
        )
        named += sweep
        columns.append(column)
    matrix = sp.Matrix.hstack(*columns) if columns else sp.zeros(len(vector), 0)
    return tuple(named), sp.ImmutableMatrix(matrix)

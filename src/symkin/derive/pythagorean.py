"""``sin(x)**2 + cos(x)**2 = 1`` applied where a sum holds both squares of one angle.

The angle-sum contraction (:mod:`symkin.derive.simplify`) leaves sums such as the PUMA's
``a2*sin(q1)**2*cos(q2) + a2*cos(q1)**2*cos(q2)`` (its Jacobian entry J(3,2): the z row of
``z_1 x (p - o_1)`` multiplies out the rotation about z_0) and, in the Euler angle of a planar
arm, ``atan2(0, sqrt(sin(q1 + q2)**2 + cos(q1 + q2)**2))``.  ``sympy.trigsimp`` removes them
but costs seconds per entry and rewrites everything else too.  This pass is targeted: bottom
up, in every sum that holds a power >= 2 of both ``sin(x)`` and ``cos(x)`` for one argument
``x``, it rewrites ``sin(x)**k = sin(x)**(k-2) (1 - cos(x)**2)`` (or the same with ``sin`` and
``cos`` exchanged), distributes the products of that sum only (not deeper), and keeps the
shorter of the two results by operation count.  Afterwards no sum holds both squares of the
same argument; the value is unchanged (an identity, applied exactly).  Terms are combined by
SymPy's own collection of like terms, so the cost is about linear in the number of terms.
"""

from __future__ import annotations

import sympy as sp
from sympy.core.sorting import default_sort_key


def fold_pythagorean(expr: sp.Basic) -> sp.Basic:
    """``expr`` with ``sin(x)**2 + cos(x)**2 = 1`` applied in every sum (module docstring)."""
    if not isinstance(expr, sp.Basic) or expr.is_Atom or not expr.has(sp.sin, sp.cos):
        return expr
    args = tuple(fold_pythagorean(a) for a in expr.args)
    if args != expr.args:
        expr = expr.func(*args)
    if expr.is_Add:
        return _fold_sum(expr)
    return expr


def fold_matrix(matrix: sp.MatrixBase) -> sp.ImmutableMatrix:
    """:func:`fold_pythagorean` entry by entry."""
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, [fold_pythagorean(e) for e in matrix])


def squared_arguments(sum_: sp.Expr, function: type[sp.Function]) -> set[sp.Expr]:
    """Arguments ``x`` with ``function(x)**k``, ``k >= 2``, in the terms of ``sum_``."""
    found = set()
    for term in sp.Add.make_args(sum_):
        for factor in sp.Mul.make_args(term):
            base, exponent = factor.as_base_exp()
            if isinstance(base, function) and exponent.is_Integer and exponent >= 2:
                found.add(base.args[0])
    return found


def _fold_sum(sum_: sp.Expr) -> sp.Expr:
    for _ in range(len(sum_.args)):  # each pass removes one angle; the sum has few of them
        both = squared_arguments(sum_, sp.sin) & squared_arguments(sum_, sp.cos)
        if not both:
            return sum_
        x = min(both, key=default_sort_key)
        variants = [_rewritten(sum_, x, sp.sin, sp.cos), _rewritten(sum_, x, sp.cos, sp.sin)]
        sum_ = min(variants, key=lambda e: (sp.count_ops(e), default_sort_key(e)))
        if not sum_.is_Add:
            return fold_pythagorean(sum_) if sum_.args else sum_
    return sum_


def _rewritten(sum_: sp.Expr, x: sp.Expr, gone: type, kept: type) -> sp.Expr:
    """``sum_`` with ``gone(x)**k = gone(x)**(k-2) (1 - kept(x)**2)``, distributed one level."""

    def one_minus(power: sp.Pow) -> sp.Expr:
        return power.base ** (power.exp - 2) * (1 - kept(x) ** 2)

    def squared(e: sp.Basic) -> bool:
        return bool(e.is_Pow and e.base == gone(x) and e.exp.is_Integer and e.exp >= 2)

    terms = []
    for term in sp.Add.make_args(sum_):
        factors = sp.Mul.make_args(term)
        if any(squared(f) for f in factors):
            # Only the term's own factors: inner sums were folded already.
            term = sp.expand_mul(
                sp.Mul(*(one_minus(f) if squared(f) else f for f in factors)), deep=False
            )
        terms.append(term)
    return sp.Add(*terms)

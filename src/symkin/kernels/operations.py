"""Operation counts of expressions: SymPy's ``count_ops(visual=True)``, tallied in a Counter.

:func:`visual_counts` walks an expression exactly as ``sympy.count_ops`` does (same rules,
same names: ``ADD``, ``SUB``, ``MUL``, ``NEG``, ``DIV``, ``POW``, ``SIN``, ...) but keeps the
tally in a :class:`collections.Counter` instead of building the symbolic sum
``3*ADD + 2*MUL + ...``, and asks ``sympy.fraction`` for a product's numerator and
denominator only when the product has a denominator.  Both were most of the cost: counting
the kernels of a generic 6-joint arm took seconds, about a sixth of ``symkin derive``.
``tests/test_operations.py`` checks the counts against ``sympy.count_ops`` itself.
"""

from __future__ import annotations

from collections import Counter

import sympy as sp
from sympy.core.function import UndefinedFunction, _coeff_isneg
from sympy.core.operations import LatticeOp
from sympy.simplify.radsimp import fraction


def visual_counts(expr: sp.Basic) -> Counter[str]:
    """``sympy.count_ops(expr, visual=True)`` of an expression as ``{name: count}``."""
    if not isinstance(expr, sp.Expr) or expr.is_Relational:
        # Booleans, relations, containers: rare in kernels; SymPy's own walk.
        return _from_visual(sp.count_ops(expr, visual=True))
    ops: Counter[str] = Counter()
    args = [expr]
    while args:
        a = args.pop()
        if a.is_Rational:
            if a is not sp.S.One:
                ops["NEG"] += a.p < 0
                ops["DIV"] += a.q != 1
                continue
        elif a.is_Mul:
            if _coeff_isneg(a):
                ops["NEG"] += 1
                a = a.as_two_terms()[1] if a.args[0] is sp.S.NegativeOne else -a
            n, d = _fraction(a)
            if n.is_Integer:
                ops["DIV"] += 1
                ops["NEG"] += int(n) < 0
                args.append(d)
                continue
            if d is not sp.S.One:
                if not d.is_Integer:
                    args.append(d)
                ops["DIV"] += 1
                args.append(n)
                continue
        elif a.is_Add:
            _add_counts(a, ops, args)
            continue
        _other_counts(a, ops, args)
    return +ops


def _add_counts(a: sp.Add, ops: Counter[str], args: list[sp.Expr]) -> None:
    """A sum of k terms: k - 1 additions or subtractions (a negative term is subtracted)."""
    terms = a.args
    negatives = 0
    for i, term in enumerate(terms):
        if _coeff_isneg(term):
            negatives += 1
            args.append(-term)
            ops["SUB"] += i > 0
        else:
            args.append(term)
            ops["ADD"] += i > 0
    if negatives == len(terms):  # -x - y = NEG + SUB
        ops["NEG"] += 1
    elif _coeff_isneg(terms[0]):  # -x + y = SUB, but already recorded ADD
        ops["SUB"] += 1
        ops["ADD"] -= 1


def _other_counts(a: sp.Expr, ops: Counter[str], args: list[sp.Expr]) -> None:
    """Powers, functions and atoms, and products without a denominator (sympy's rules)."""
    if a.is_Pow and a.exp is sp.S.NegativeOne:
        ops["DIV"] += 1
        args.append(a.base)
        return
    if a == sp.S.Exp1:
        ops["EXP"] += 1
        return
    if a.is_Pow and a.base == sp.S.Exp1:
        ops["EXP"] += 1
        args.append(a.exp)
        return
    if a.is_Mul or isinstance(a, LatticeOp):
        ops[a.func.__name__.upper()] += len(a.args) - 1
    elif a.args and (
        a.is_Pow or a.is_Function or isinstance(a, (sp.Derivative, sp.Integral, sp.Sum))
    ):
        prefix = "FUNC_" if isinstance(a.func, UndefinedFunction) else ""
        ops[prefix + a.func.__name__.upper()] += 1
    if not a.is_Symbol:
        args.extend(a.args)


def _fraction(a: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``sympy.fraction(a)``, without rebuilding a product that has no denominator: no
    factor is a non-integer rational, an ``exp`` or a power other than a positive number's."""
    # Mul(2, x + y) would distribute: such a product (built unevaluated) goes to SymPy.
    distributes = len(a.args) == 2 and a.args[0].is_Rational and a.args[1].is_Add
    if a.is_Mul and not distributes and all(_in_numerator(f) for f in a.args):
        return a, sp.S.One
    return fraction(a)


def _in_numerator(factor: sp.Expr) -> bool:
    if factor.is_Rational:
        return factor.is_Integer
    if isinstance(factor, sp.exp):
        return False
    if factor.is_Pow:
        return factor.exp.is_Number and factor.exp > 0
    return True


def _from_visual(visual: sp.Expr) -> Counter[str]:
    counts: Counter[str] = Counter()
    for term in sp.Add.make_args(visual):
        coefficient, symbol = term.as_coeff_Mul()
        if isinstance(symbol, sp.Symbol):
            counts[symbol.name] += int(coefficient)
    return counts

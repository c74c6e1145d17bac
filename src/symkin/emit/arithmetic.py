"""Sums and products printed as SymPy's code printers print them, without new SymPy objects.

SymPy's ``_print_Mul`` prints ``-2*x*y`` by building the product ``2*x*y`` first, and its
``precedence`` asks whether a product "could extract a minus sign" by building the negated
product and comparing the two.  Every such new object then answers assumption queries from
scratch (``facts.deduce_all_facts``), which made up most of the time of printing a generic
arm's kernels.  :class:`ArithmeticMixin` prints the same text from the arguments the
expression already has:

- a product whose leading number ``c`` is negative prints as ``-`` followed by the factors
  with ``-c`` in front (left out when ``-c`` is the integer 1), which is the argument list
  ``sympy.core.mul._keep_coeff(-c, rest)`` builds;
- a product's precedence is that of a sum when its leading number is negative, of a
  product otherwise (the test ``self == -self`` only matters for ``zoo`` and ``nan``
  coefficients, which go to SymPy's own code).

Everything else (number formats, powers, functions, the order of terms) is the printer's
own, so the text is the text SymPy prints: ``tests/test_emit_arithmetic.py`` compares the two
on many random expressions.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sympy as sp
from sympy.core.function import Function
from sympy.printing.precedence import (
    PRECEDENCE,
    PRECEDENCE_FUNCTIONS,
    PRECEDENCE_VALUES,
)
from sympy.printing.precedence import precedence as sympy_precedence

MUL, ADD, ATOM = PRECEDENCE["Mul"], PRECEDENCE["Add"], PRECEDENCE["Atom"]
# Python's unary minus binds between a product and a power (SymPy's weight for it).
UNARY_MINUS = 0.5 * (PRECEDENCE["Pow"] + PRECEDENCE["Mul"])


def _undefined(item: sp.Basic) -> bool:
    """``zoo`` or ``nan``: a product led by one is its own negative; SymPy's code decides."""
    return item is sp.S.ComplexInfinity or item is sp.S.NaN


def negative_number(item: sp.Basic) -> bool:
    """``item`` is a negative number (``is_extended_negative`` without the assumption system,
    which a fresh number would answer from scratch); ``zoo`` and ``nan`` are not."""
    if not item.is_Number or _undefined(item):
        return False
    if item.is_Rational:
        return item.p < 0
    if item.is_Float:
        return item._mpf_[0] == 1  # mpmath's sign bit (-inf too; nan and 0 have 0)
    return float(item) < 0


# Function classes whose own precedence is below a product's (SymPy then brackets nothing).
_LOW_FUNCTION: dict[type, bool] = {}


def _product_precedence(item: sp.Mul) -> float:
    if _undefined(item.args[0]):
        return sympy_precedence(item)
    for factor in item.args:
        kind = type(factor)
        low = _LOW_FUNCTION.get(kind)
        if low is None:
            low = _LOW_FUNCTION[kind] = issubclass(kind, Function) and (
                getattr(kind, "precedence", MUL) < MUL
            )
        if low:
            return MUL
    return ADD if negative_number(item.args[0]) else MUL


# Numbers and products by their rule in sympy.printing.precedence, without comparisons that
# build SymPy objects; other rules are SymPy's.
_RULES: dict[str, Callable[[Any], float]] = {
    "Integer": lambda item: ADD if item.p < 0 else ATOM,
    "Rational": lambda item: ADD if item.p < 0 else MUL,
    "Float": lambda item: ADD if negative_number(item) else ATOM,
    "Mul": _product_precedence,
}


def _rule(kind: type) -> float | Callable[[Any], float]:
    """The precedence of every instance of ``kind``, or the function that gives it (SymPy
    looks the class names up along the MRO; a class attribute ``precedence`` comes first)."""
    if not issubclass(kind, sp.Basic) or hasattr(kind, "precedence"):
        return sympy_precedence
    for base in kind.mro():
        if base.__name__ in PRECEDENCE_FUNCTIONS:
            return _RULES.get(base.__name__, sympy_precedence)
        if base.__name__ in PRECEDENCE_VALUES:
            return PRECEDENCE_VALUES[base.__name__]
    return ATOM


_RULE_OF_TYPE: dict[type, float | Callable[[Any], float]] = {}


def precedence(item: object) -> float:
    """``sympy.printing.precedence.precedence``, without building new SymPy objects."""
    kind = type(item)
    rule = _RULE_OF_TYPE.get(kind)
    if rule is None:
        rule = _RULE_OF_TYPE.setdefault(kind, _rule(kind))
    return rule(item) if callable(rule) else rule


def _factors(expr: sp.Mul) -> tuple[str, tuple[sp.Expr, ...]] | None:
    """The sign and the factors SymPy's ``_print_Mul`` prints (see the module doc), or
    ``None`` for an unevaluated product whose factors SymPy would merge first."""
    first, *rest = expr.args
    if not negative_number(first):
        return "", expr.args
    if any(f.is_Number or f.is_Mul for f in rest[1:]) or (rest and rest[0].is_Number):
        return None
    positive = -first
    factors = sp.Mul.make_args(rest[0]) if len(rest) == 1 else tuple(rest)
    if any(f.is_Number for f in factors):
        return None
    return "-", factors if positive is sp.S.One else (positive, *factors)


class ArithmeticMixin:
    """``_print_Mul``, ``_print_Add`` and ``parenthesize`` of SymPy's code printers (for
    ``order="none"``), the same text without new SymPy objects; put it first among the bases."""

    def _handle_UnevaluatedExpr(self, expr: sp.Basic) -> sp.Basic:
        # SymPy walks every expression to replace re(UnevaluatedExpr(x)) by x; symkin builds
        # no UnevaluatedExpr, and the walk cost a sixth of the printing time.
        return expr

    def parenthesize(self, item: sp.Basic, level: float, strict: bool = False) -> str:
        own = precedence(item)
        if own < level or (not strict and own <= level):
            return f"({self._print(item)})"
        return self._print(item)

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> str:
        level = precedence(expr)
        pieces: list[str] = []
        for term in self._as_ordered_terms(expr, order=order):
            text = self._print(term)
            sign = "+"
            if text.startswith("-") and not term.is_Add:
                sign, text = "-", text[1:]
            if term.is_Add or precedence(term) < level:
                text = f"({text})"
            pieces += [sign, text]
        first = pieces.pop(0)
        return ("" if first == "+" else first) + " ".join(pieces)

    def _print_Mul(self, expr: sp.Mul, **kwargs: object) -> str:
        if self._settings.get("order") not in ("old", "none") or _undefined(expr.args[0]):
            return super()._print_Mul(expr, **kwargs)
        parts = _factors(expr)
        if parts is None:
            return super()._print_Mul(expr, **kwargs)
        level = precedence(expr)
        sign, factors = parts
        numerator: list[sp.Expr] = []
        denominator: list[sp.Expr] = []
        bracketed: list[sp.Expr] = []  # a product's reciprocal: its base keeps brackets
        for item in factors:
            if not (
                item.is_Pow
                and item.exp.is_Rational
                and item.exp.is_negative
                and item.is_commutative
            ):
                numerator.append(item)
            elif item.exp != -1:
                denominator.append(sp.Pow(item.base, -item.exp, evaluate=False))
            else:
                if len(item.args[0].args) != 1 and isinstance(item.base, sp.Mul):
                    bracketed.append(item.base)
                denominator.append(item.base)
        numerator = numerator or [sp.S.One]
        if len(numerator) == 1 and sign == "-":
            top = [self.parenthesize(numerator[0], UNARY_MINUS)]
        else:
            top = [self.parenthesize(x, level) for x in numerator]
        bottom = [self.parenthesize(x, level) for x in denominator]
        for base in bracketed:
            index = denominator.index(base)
            bottom[index] = f"({bottom[index]})"
        if not denominator:
            return sign + "*".join(top)
        if len(denominator) == 1:
            return f"{sign}{'*'.join(top)}/{bottom[0]}"
        return f"{sign}{'*'.join(top)}/({'*'.join(bottom)})"

"""Formulas as plain text for people (``symkin show``): SymPy syntax with short numbers.

SymPy's string printer writes a standalone double-precision ``Float`` with all its 15
significant digits (``0.325600000000000``); here it is the fewest digits that read back as the
same 15-digit Float (``0.3256``, ``-0.0629``, ``1e-17``, ``0.04885628`` for the product
``0.3256 * 0.15005``), so a number typed into a robot file is shown as it was typed, and a
product of such numbers does not show the double's last-bit noise (``0.048856279999999995``).
A factor ``1.0`` or ``-1.0`` in a product (``1.0*izz1``, left by floating parameters) is not
shown.  The text still parses with ``sympy.sympify`` to the same value.
"""

from __future__ import annotations

import sympy as sp
from mpmath.libmp import prec_to_dps
from sympy.printing.str import StrPrinter

DOUBLE_BITS = 53
# SymPy's decimal precision of a double-precision Float.
DOUBLE_DIGITS = 15


def shortest_float(value: sp.Float) -> str | None:
    """The fewest significant digits (at most 15) that give ``value`` back as a 15-digit Float,
    when ``value`` is no more precise than a double, else None (it keeps all its digits)."""
    if value._prec > DOUBLE_BITS:
        return None
    # A Float of lower precision (sympy.N(x, 6)) is compared at its own decimal precision.
    precision = max(1, min(DOUBLE_DIGITS, prec_to_dps(value._prec)))
    number = float(value)
    for digits in range(1, precision + 1):
        text = f"{number:.{digits}g}"
        if float(f"{float(text):.{precision}g}") == float(f"{number:.{precision}g}"):
            break
    # "1e-05" -> "1e-5"; a whole number keeps a decimal point so that it reads as a Float.
    mantissa, _, exponent = text.partition("e")
    if "." not in mantissa and not exponent:
        mantissa += ".0"
    return mantissa + (f"e{int(exponent)}" if exponent else "")


def without_unit_floats(expr: sp.Basic) -> sp.Basic:
    """``expr`` with every product's coefficient ``1.0`` (``-1.0``) made ``1`` (``-1``)."""
    if not isinstance(expr, sp.Basic):
        return expr
    unit = {}
    for mul in expr.atoms(sp.Mul):
        coefficient, rest = mul.as_coeff_Mul()
        # Float(1.0) == 1 is False in SymPy >= 1.13: compare the double.
        if coefficient.is_Float and abs(float(coefficient)) == 1.0:
            unit[mul] = rest if coefficient > 0 else -rest
    return expr.xreplace(unit) if unit else expr


class ShortFloatStrPrinter(StrPrinter):
    """SymPy's string printer with :func:`shortest_float` numbers."""

    def _print_Float(self, expr: sp.Float) -> str:
        text = shortest_float(expr)
        return super()._print_Float(expr) if text is None else text


_PRINTER = ShortFloatStrPrinter()


def formula_text(expr: object) -> str:
    """``expr`` in SymPy syntax with the shortest round-trip numbers (module docstring)."""
    return _PRINTER.doprint(without_unit_floats(sp.sympify(expr)))

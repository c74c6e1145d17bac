"""SymPy printers for the backends: C99 (float or double), NumPy and CasADi.

Templates only lay code out; every expression is printed here.
"""

from __future__ import annotations

from functools import lru_cache

import numpy
import sympy as sp
from sympy.codegen.ast import float32, float64, real
from sympy.printing.c import C99CodePrinter
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import PythonCodePrinter

from symkin.emit.arithmetic import ArithmeticMixin
from symkin.emit.dispatch import DispatchMixin

C_TYPES = {"double": float64, "float": float32}
# Terms print in SymPy's own (deterministic) argument order: sorting every sum for display
# took a third of the time of emitting the dynamics.
SETTINGS = {"order": "none"}


def c_literal(value: float, precision: str) -> str:
    """The shortest decimal that reads back as the same ``double`` (``repr``), or as the same
    ``float`` with an ``F`` suffix: ``0.1F``, ``1.0F``, ``1e-30F``.  Like ``repr``, plain notation
    for magnitudes from 1e-4 to 1e16 and scientific notation outside; a plain number always
    has a decimal point, so that ``1.0F`` stays a floating constant in C."""
    if precision != "float":
        return repr(float(value))
    single = numpy.float32(value)
    if single == 0 or 1e-4 <= abs(single) < 1e16:
        text = numpy.format_float_positional(single, unique=True, trim="0")
    else:
        text = numpy.format_float_scientific(single, unique=True, trim="-", exp_digits=1)
    return f"{text}F"


class EmbeddedCPrinter(ArithmeticMixin, DispatchMixin, C99CodePrinter):
    """C99 for ``-std=c99 -pedantic``: no ``M_PI``, small integer powers as products."""

    def __init__(self, precision: str = "double") -> None:
        # No math_macros: M_SQRT2, M_PI_2 and friends are POSIX, not C99.
        super().__init__(
            {"type_aliases": {real: C_TYPES[precision]}, "math_macros": {}, **SETTINGS}
        )
        self.precision = precision

    def _print_NumberSymbol(self, expr: sp.Expr) -> str:
        # M_PI is POSIX, not C99; print the value at the chosen precision instead.
        return self._print(sp.Float(expr.evalf(20), 20))

    _print_Pi = _print_NumberSymbol  # noqa: N815 - SymPy dispatches on this name

    def _print_Float(self, expr: sp.Float) -> str:
        # The shortest literal of the value at the chosen precision (SymPy prints 17 digits).
        return c_literal(float(expr), self.precision)

    def _print_Pow(self, expr: sp.Pow) -> str:
        base, exponent = expr.as_base_exp()
        if exponent.is_Integer and 2 <= exponent <= 4:
            factor = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"])
            return "*".join([factor] * int(exponent))
        return super()._print_Pow(expr)


class BatchNumPyPrinter(ArithmeticMixin, DispatchMixin, NumPyPrinter):
    """NumPy expressions that broadcast over a leading batch dimension."""

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        base, exponent = expr.as_base_exp()
        if exponent == -1:
            return f"1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Pow'])}"
        return super()._print_Pow(expr, rational=rational)


class CasadiPrinter(ArithmeticMixin, DispatchMixin, PythonCodePrinter):
    """Python expressions on CasADi SX/MX symbols (``casadi.sin``, ``casadi.atan2``, ...)."""

    def _module_format(self, fqn: str, register: bool = True) -> str:
        module, _, name = fqn.rpartition(".")
        if module == "math":
            return f"casadi.{name}"
        return super()._module_format(fqn, register)

    def _print_sign(self, expr: sp.Expr) -> str:
        # Python's printer tests ``x == 0`` in an if-expression, which a symbolic SX cannot
        # answer; casadi.sign is -1, 0, 1 like SymPy's sign (Coulomb friction).
        return f"casadi.sign({self._print(expr.args[0])})"


@lru_cache(maxsize=4)
def _c_printer(precision: str) -> EmbeddedCPrinter:
    return EmbeddedCPrinter(precision)


@lru_cache(maxsize=1)
def _numpy_printer() -> BatchNumPyPrinter:
    return BatchNumPyPrinter(SETTINGS)


@lru_cache(maxsize=1)
def _casadi_printer() -> CasadiPrinter:
    return CasadiPrinter(SETTINGS)


def c_code(expr: sp.Expr, precision: str = "double") -> str:
    return _c_printer(precision).doprint(expr)


def numpy_code(expr: sp.Expr) -> str:
    return _numpy_printer().doprint(expr)


def casadi_code(expr: sp.Expr) -> str:
    return _casadi_printer().doprint(expr)

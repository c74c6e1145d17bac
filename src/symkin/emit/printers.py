"""SymPy printers for the backends: C99 (float or double), NumPy and CasADi.

Templates only lay code out; every expression is printed here.
"""

from __future__ import annotations

import sympy as sp
from sympy.codegen.ast import float32, float64, real
from sympy.printing.c import C99CodePrinter
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import PythonCodePrinter

C_TYPES = {"double": float64, "float": float32}


class EmbeddedCPrinter(C99CodePrinter):
    """C99 for ``-std=c99 -pedantic``: no ``M_PI``, small integer powers as products."""

    def __init__(self, precision: str = "double") -> None:
        super().__init__({"type_aliases": {real: C_TYPES[precision]}})
        self.precision = precision

    def _print_NumberSymbol(self, expr: sp.Expr) -> str:
        # M_PI is POSIX, not C99; print the value at the chosen precision instead.
        return self._print(sp.Float(expr.evalf(20), 20))

    _print_Pi = _print_NumberSymbol  # noqa: N815 - SymPy dispatches on this name

    def _print_Pow(self, expr: sp.Pow) -> str:
        base, exponent = expr.as_base_exp()
        if exponent.is_Integer and 2 <= exponent <= 4:
            factor = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"])
            return "*".join([factor] * int(exponent))
        return super()._print_Pow(expr)


class BatchNumPyPrinter(NumPyPrinter):
    """NumPy expressions that broadcast over a leading batch dimension."""

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        base, exponent = expr.as_base_exp()
        if exponent == -1:
            return f"1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Pow'])}"
        return super()._print_Pow(expr, rational=rational)


class CasadiPrinter(PythonCodePrinter):
    """Python expressions on CasADi SX/MX symbols (``casadi.sin``, ``casadi.atan2``, ...)."""

    def _module_format(self, fqn: str, register: bool = True) -> str:
        module, _, name = fqn.rpartition(".")
        if module == "math":
            return f"casadi.{name}"
        return super()._module_format(fqn, register)


def c_code(expr: sp.Expr, precision: str = "double") -> str:
    return EmbeddedCPrinter(precision).doprint(expr)


def numpy_code(expr: sp.Expr) -> str:
    return BatchNumPyPrinter().doprint(expr)


def casadi_code(expr: sp.Expr) -> str:
    return CasadiPrinter().doprint(expr)

"""SymPy's printer dispatch, looked up once per node type, and floats printed once per value.

``Printer._print`` finds the method for a node by walking the node's class hierarchy and
trying ``getattr(printer, "_print_" + name)`` for each class, on every node; a generic arm's
kernels have about 100,000 nodes per backend, of a dozen types.  :class:`DispatchMixin` keeps
the method name found for each (printer class, node class) pair.  Node classes the dispatch
treats specially (anything but a plain SymPy ``Basic``: functions, undefined functions, classes,
objects that print themselves through the printer's ``printmethod``) keep SymPy's own
dispatch.  ``_print_Float`` results are kept per value, precision and nesting (SymPy strips
trailing zeros only inside a larger expression): a kernel repeats the same few hundred
constants thousands of times.
"""

from __future__ import annotations

from typing import Any

import sympy as sp
from sympy.core.function import Function

# Entries kept before the float memo starts afresh (a printer lives as long as the process).
FLOAT_MEMO_SIZE = 4096


def method_name(printer: type, kind: type) -> str | None:
    """The ``_print_*`` method SymPy's dispatch picks for instances of ``kind``, or ``None``
    where the dispatch is not a plain walk of the class hierarchy."""
    if not issubclass(kind, sp.Basic) or issubclass(kind, Function):
        return None
    if printer.printmethod and hasattr(kind, printer.printmethod):
        return None
    for cls in kind.__mro__:
        if hasattr(printer, f"_print_{cls.__name__}"):
            return f"_print_{cls.__name__}"
    return None


_METHODS: dict[tuple[type, type], str | None] = {}


class DispatchMixin:
    """``_print`` with the method looked up once per node type, and a memo of printed floats;
    put it before SymPy's printer among the bases."""

    def _print(self, expr: Any, **kwargs: Any) -> str:
        key = (type(self), type(expr))
        if key not in _METHODS:
            _METHODS[key] = method_name(*key)
        name = _METHODS[key]
        if name is None:
            return super()._print(expr, **kwargs)
        self._print_level += 1
        try:
            return getattr(self, name)(expr, **kwargs)
        finally:
            self._print_level -= 1

    def _print_Float(self, expr: sp.Float) -> str:
        memo = self.__dict__.setdefault("_float_memo", {})
        key = (expr._mpf_, expr._prec, self._print_level > 1)
        text = memo.get(key)
        if text is None:
            if len(memo) >= FLOAT_MEMO_SIZE:
                memo.clear()
            text = memo[key] = super()._print_Float(expr)
        return text

"""The safe expression language of robot files: numbers and formula strings -> SymPy.

A value is a TOML number or a string such as ``"L1 + L2/2"`` or ``"pi/2"``.  Strings are parsed
by walking Python's ``ast`` with a small whitelist (numbers, declared parameter names, ``pi``,
unary ``+``/``-``, binary ``+ - * / **``, parentheses); user text is never passed to ``eval`` or
``sympify``.  Caps on length, exponents and constant magnitudes keep pathological input
(``9**9**9``, deep nesting) from exhausting time or memory, and keep every constant a double
the C backend can print.  Every violation is a :class:`~symkin.errors.RobotError` located by the
:class:`~symkin.io.context.Context`.
"""

from __future__ import annotations

import ast
import math
import warnings
from collections.abc import Callable, Mapping
from typing import Any

import sympy as sp

from symkin.io.context import Context, did_you_mean, show

# Expressions are short formulas; the caps keep pathological input (deep nesting, 9**9**9)
# from exhausting time or memory before it can be rejected.
MAX_EXPRESSION_LENGTH = 500
MAX_EXPONENT = 100
# A power of a parameter expression is expanded by the derivations: (L1 + L2)**100 would not
# finish.  Squares, cubes, square roots and the like are what robot geometry uses.
MAX_SYMBOLIC_EXPONENT = 4
# Integers beyond 2**53 are not exact in double precision and overflow C's integer literals.
MAX_EXACT_INTEGER = 2**53
MAX_MAGNITUDE = 1e300
# Constants closer to zero underflow in products and print as C constants truncated to zero.
MIN_MAGNITUDE = 1e-300


def numeric_value(expr: sp.Expr, ctx: Context) -> float | None:
    """The value with parameter defaults substituted, or None when a parameter has none."""
    values = ctx.values or {}
    substitutions = {}
    for symbol in expr.free_symbols:
        value = values.get(symbol.name)
        if value is None:
            return None
        substitutions[symbol] = sp.Float(value)
    return finite_float(expr.xreplace(substitutions))


def finite_float(expr: sp.Expr) -> float | None:
    """``float(expr)`` when expr is a finite real number, else None."""
    try:
        number = complex(expr.evalf())
    except (TypeError, ValueError, OverflowError, ZeroDivisionError):
        return None
    if number.imag != 0 or not math.isfinite(number.real):
        return None
    return number.real


def is_number(value: Any) -> bool:
    """True for a TOML integer or float (never for ``true``/``false``)."""
    # bool is an int subclass in Python, but `true` is never a number in a robot file
    return isinstance(value, int | float) and not isinstance(value, bool)


def finite_number(value: int | float, key: str, ctx: Context) -> int | float:
    """``value`` unchanged if a double represents it exactly enough, else a located error."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ctx.error(f"{ctx.key(key)!r} must be a finite number, got {show(value)}")
    if abs(value) > MAX_MAGNITUDE:
        raise ctx.error(f"{ctx.key(key)!r} is too large ({show(value)}); the limit is 1e300")
    if isinstance(value, int) and abs(value) > MAX_EXACT_INTEGER:
        raise ctx.error(f"{ctx.key(key)!r}: {_INEXACT_INTEGER}, got {show(value)}")
    if 0 < abs(value) < MIN_MAGNITUDE:
        raise ctx.error(f"{ctx.key(key)!r} is too small ({show(value)}); write 0 or >= 1e-300")
    return value


def sympy_value(value: Any, key: str, ctx: Context, *, angle: bool = False) -> sp.Expr:
    """A number or expression string as SymPy; angle constants follow the file's unit."""
    if is_number(value):
        number = finite_number(value, key, ctx)
        if angle and ctx.angles == "deg":
            return _degrees(sp.Rational(str(number)))
        return _sympy_number(number)
    if isinstance(value, str):
        expr, names = _parse_expression(value, key, ctx)
        # A string naming pi or a parameter is radians; a plain numeric string is a constant.
        if angle and ctx.angles == "deg" and not names:
            return _degrees(expr)
        return expr
    raise ctx.error(f"{ctx.key(key)!r} must be a number or an expression string, got {show(value)}")


def _sympy_number(value: int | float) -> sp.Expr:
    """Integers (also 2.0) exactly; other floats as SymPy Floats of their shortest decimal text."""
    if isinstance(value, int):
        return sp.Integer(value)
    if value.is_integer() and abs(value) <= MAX_EXACT_INTEGER:
        return sp.Integer(int(value))
    return sp.Float(repr(value))


def _degrees(number: sp.Expr) -> sp.Expr:
    """Degrees to radians exactly: 90 -> pi/2, 0.5 -> pi/360 (a Float via its decimal text)."""
    exact = number if number.is_Rational else sp.Rational(repr(float(number)))
    return exact * sp.pi / 180


def _parse_expression(text: str, key: str, ctx: Context) -> tuple[sp.Expr, frozenset[str]]:
    """Parse a whitelisted arithmetic expression; returns it and the names it uses."""
    shown = ctx.key(key)
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise ctx.error(f"{shown!r} is longer than {MAX_EXPRESSION_LENGTH} characters")
    if not text.strip():
        raise ctx.error(f"{shown!r} must be a number or an expression, got an empty string")
    try:
        with warnings.catch_warnings():
            # "invalid decimal literal" and the like: we report our own error instead
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise ctx.error(f"{shown!r} is not a valid expression: {show(text)}") from None
    builder = _ExpressionBuilder(ctx.symbols or {}, lambda why: _bad_expression(shown, text, why))
    try:
        expr = builder.build(tree.body)
    except RecursionError:
        raise ctx.error(f"{shown!r} is nested too deeply: {show(text)}") from None
    except _ExpressionError as exc:
        raise ctx.error(str(exc)) from None
    _check_nested_powers(expr, shown, text, ctx)
    _check_expression_value(expr, shown, text, ctx)
    return expr, frozenset(builder.names)


def _check_nested_powers(expr: sp.Expr, shown: str, text: str, ctx: Context) -> None:
    """SymPy merges nested powers ((x**4)**4 -> x**16): the cap holds for the result too."""
    for power in expr.atoms(sp.Pow):
        if power.base.free_symbols and abs(float(power.exp)) > MAX_SYMBOLIC_EXPONENT:
            raise ctx.error(
                f"{shown!r} is not a valid expression: {show(text)} raises parameters to the "
                f"power {sp.sstr(power.exp)}, outside [-{MAX_SYMBOLIC_EXPONENT}, "
                f"{MAX_SYMBOLIC_EXPONENT}]"
            )


def _check_expression_value(expr: sp.Expr, shown: str, text: str, ctx: Context) -> None:
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise ctx.error(f"{shown!r} is not finite (division by zero?): {show(text)}")
    # SymPy folds the numbers of a product (L1*1e-300*1e-300 -> 1e-600*L1): every constant
    # left in the formula must be a double, or the C compiler truncates or overflows it.
    numbers = expr.atoms(sp.Number)
    for number in numbers:
        magnitude = abs(number)  # compared exactly: float() would flush 1e-600 to 0
        if magnitude > MAX_MAGNITUDE or (magnitude != 0 and magnitude < MIN_MAGNITUDE):
            raise ctx.error(
                f"{shown!r} holds the constant {sp.sstr(number.evalf(3))}, outside "
                f"1e-300..1e300 in magnitude: {show(text)}"
            )
    for number in numbers:
        _check_exact_integers(number, shown, text, ctx)
    if not expr.is_number:
        _check_value_at_defaults(expr, shown, text, ctx)
        return
    number = finite_float(expr)
    if number is None or abs(number) > MAX_MAGNITUDE:
        raise ctx.error(
            f"{shown!r} is not a finite real number of magnitude <= 1e300: {show(text)}"
        )


def _check_exact_integers(number: sp.Number, shown: str, text: str, ctx: Context) -> None:
    """SymPy evaluates integer arithmetic exactly ("2**100", "L*3**60"): an integer it makes,
    or the numerator or denominator of a fraction, is held to the 2**53 of a literal, or the
    C backend would print an integer literal that overflows."""
    if not number.is_Rational:
        return
    for part in (number.p, number.q):
        if abs(part) > MAX_EXACT_INTEGER:
            raise ctx.error(
                f"{shown!r} holds the integer {part} ({_INEXACT_INTEGER}): {show(text)}"
            )


def _check_value_at_defaults(expr: sp.Expr, shown: str, text: str, ctx: Context) -> None:
    """A formula with a pole (or a complex value) at the parameters' own values gives NaN or
    inf in every backend: reject it when all its parameters have values."""
    values = ctx.values or {}
    if any(values.get(s.name) is None for s in expr.free_symbols):
        return
    number = numeric_value(expr, ctx)
    if number is None or abs(number) > MAX_MAGNITUDE:
        given = ", ".join(
            f"{s.name} = {values[s.name]:g}" for s in sorted(expr.free_symbols, key=str)
        )
        raise ctx.error(
            f"{shown!r} is not a finite real number at the parameters' values ({given}): "
            f"{show(text)}"
        )


_BINARY: Mapping[type[ast.operator], Callable[[sp.Expr, sp.Expr], sp.Expr]] = {
    ast.Add: lambda x, y: x + y,
    ast.Sub: lambda x, y: x - y,
    ast.Mult: lambda x, y: x * y,
    ast.Div: lambda x, y: x / y,
}


_INEXACT_INTEGER = (
    "integers beyond 2**53 are not exact in double precision; write the number as a float, "
    "such as 1e30"
)


class _ExpressionError(Exception):
    """Internal: an expression broke the whitelist; turned into a RobotError by the caller."""


def _bad_expression(shown: str, text: str, why: str) -> _ExpressionError:
    return _ExpressionError(
        f"{shown!r} is not a valid expression: {show(text)} {why}; allowed are numbers, "
        "declared parameter names, pi, + - * / ** and parentheses"
    )


class _ExpressionBuilder:
    """Turns a whitelisted Python AST into SymPy, remembering the names it meets."""

    def __init__(
        self, symbols: Mapping[str, sp.Symbol], fail: Callable[[str], _ExpressionError]
    ) -> None:
        self.symbols = symbols
        self.fail = fail
        self.names: set[str] = set()

    def build(self, node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Constant):
            return self._constant(node.value)
        if isinstance(node, ast.Name):
            return self._name(node.id)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
            operand = self.build(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return self._power(self.build(node.left), self.build(node.right))
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](self.build(node.left), self.build(node.right))
        raise self.fail(f"uses {_describe_node(node)}")

    def _constant(self, value: Any) -> sp.Expr:
        if not is_number(value):
            raise self.fail(f"contains the literal {value!r}")
        if isinstance(value, float) and not math.isfinite(value):
            raise self.fail("contains a number that is not finite")
        if abs(value) > MAX_MAGNITUDE:
            raise self.fail("contains a number larger than 1e300")
        if isinstance(value, int) and abs(value) > MAX_EXACT_INTEGER:
            raise self.fail(f"contains an integer beyond 2**53 ({_INEXACT_INTEGER})")
        return _sympy_number(value)

    def _name(self, name: str) -> sp.Expr:
        self.names.add(name)
        if name == "pi":
            return sp.pi
        if name in self.symbols:
            return self.symbols[name]
        declared = ", ".join(self.symbols) or "none"
        raise self.fail(
            f"uses the unknown name {name!r}{did_you_mean(name, [*self.symbols, 'pi'])} "
            f"(declared parameters: {declared})"
        )

    def _power(self, base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
        # Check numbers before SymPy evaluates them exactly: 9**9**9 would never finish.
        if not exponent.is_number:
            # L1**L1 and towers: no closed form symkin can simplify, print or bound.
            raise self.fail("has an exponent with parameters (exponents must be numbers)")
        size = finite_float(exponent)
        if size is None or abs(size) > MAX_EXPONENT:
            raise self.fail(f"has an exponent outside [-{MAX_EXPONENT}, {MAX_EXPONENT}]")
        if base.is_number:
            self._check_numeric_power(base, size)
        elif abs(size) > MAX_SYMBOLIC_EXPONENT:
            raise self.fail(
                f"raises parameters to a power outside [-{MAX_SYMBOLIC_EXPONENT}, "
                f"{MAX_SYMBOLIC_EXPONENT}]"
            )
        return base**exponent

    def _check_numeric_power(self, base: sp.Expr, exponent: float) -> None:
        value = finite_float(base)
        try:
            result = math.pow(value, exponent) if value is not None else math.nan
        except (OverflowError, ValueError, ZeroDivisionError):
            result = math.nan
        if not math.isfinite(result) or abs(result) > MAX_MAGNITUDE:
            raise self.fail("has a power that is not a finite real number")


def _describe_node(node: ast.AST) -> str:
    descriptions = {
        ast.Call: "a function call",
        ast.Attribute: "an attribute",
        ast.Subscript: "indexing",
        ast.Compare: "a comparison",
        ast.BoolOp: "a boolean operator",
        ast.Tuple: "a tuple (a comma?)",
    }
    for kind, text in descriptions.items():
        if isinstance(node, kind):
            return text
    if isinstance(node, ast.BinOp | ast.UnaryOp):
        return f"the operator {type(node.op).__name__}"
    return f"a {type(node).__name__} construct"

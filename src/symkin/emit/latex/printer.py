"""The LaTeX printer of symkin, and a width measure for deciding how a formula is laid out.

:class:`KinematicsLatexPrinter` prints the code-safe symbol names the way a lecture writes them
(``q1`` -> ``q_{1}``, ``dq1`` -> ``\\dot{q}_{1}``, ``ddq1`` -> ``\\ddot{q}_{1}``, ``L1`` ->
``L_{1}``, ``alpha`` -> ``\\alpha``) and, in shorthand mode, sines and cosines of joint variables
and of their unit sums as ``s_{1}``, ``c_{12}``; it records which abbreviations it used so the
legend can state exactly those, once.

:func:`latex_width` estimates how wide a piece of printed math is, in units of roughly one
italic letter, so Python (not a template) can decide whether a matrix fits the page.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.printing.latex import LatexPrinter

from symkin.emit.formula_text import shortest_float

# ---------------------------------------------------------------- printer


@dataclass(frozen=True, order=True)
class Abbreviation:
    """``c_{12}`` for ``cos(q1 + q2)``: the joint indices and the function letter."""

    indices: tuple[int, ...]
    letter: str  # "c" or "s"

    @property
    def subscript(self) -> str:
        separator = "," if any(i >= 10 for i in self.indices) else ""
        return separator.join(str(i) for i in self.indices)

    @property
    def latex(self) -> str:
        return f"{self.letter}_{{{self.subscript}}}"

    def sort_key(self) -> tuple:
        return (len(self.indices), self.indices, self.letter)


class KinematicsLatexPrinter(LatexPrinter):
    """SymPy's LaTeX printer with joint-variable decoration and optional shorthand.

    ``q``, ``dq``, ``ddq`` are the model's joint symbols (positions, velocities, accelerations).
    With ``shorthand=True``, ``cos(q1)`` prints as ``c_{1}`` and ``sin(q1 + q2)`` as
    ``s_{12}`` (only for sums of distinct joint variables with unit coefficients); every
    abbreviation printed is collected in :attr:`used`.  ``symbol_names`` prints further
    symbols as given (the inertial parameters: ``cx1`` -> ``c_{x,1}``).
    """

    def __init__(
        self,
        q: Sequence[sp.Symbol],
        dq: Sequence[sp.Symbol] = (),
        ddq: Sequence[sp.Symbol] = (),
        *,
        shorthand: bool = False,
        decimal_separator: str = "period",
        fold_func_brackets: bool = False,
        symbol_names: Mapping[sp.Symbol, str] | None = None,
    ) -> None:
        names: dict[sp.Symbol, str] = dict(symbol_names or {})
        for i, (qi, dqi, ddqi) in enumerate(zip(q, _padded(dq, q), _padded(ddq, q), strict=True)):
            names[qi] = f"q_{{{i + 1}}}"
            if dqi is not None:
                names[dqi] = rf"\dot{{q}}_{{{i + 1}}}"
            if ddqi is not None:
                names[ddqi] = rf"\ddot{{q}}_{{{i + 1}}}"
        super().__init__(
            {
                "symbol_names": names,
                "decimal_separator": decimal_separator,
                "fold_func_brackets": fold_func_brackets,
            }
        )
        self.joint_index = {qi: i + 1 for i, qi in enumerate(q)}
        self.shorthand = shorthand
        self.used: set[Abbreviation] = set()

    # -- shorthand ------------------------------------------------------------------------

    def abbreviation(self, expr: sp.Expr, letter: str) -> Abbreviation | None:
        """The abbreviation of ``sin``/``cos`` of ``expr`` if it is a unit sum of joints."""
        terms = sp.Add.make_args(expr)
        indices = []
        for term in terms:
            if term not in self.joint_index:
                return None
            indices.append(self.joint_index[term])
        if len(set(indices)) != len(indices):
            return None
        return Abbreviation(tuple(sorted(indices)), letter)

    def _print_trig(self, expr: sp.Function, letter: str, exp: str | None) -> str:
        abbreviation = self.abbreviation(expr.args[0], letter) if self.shorthand else None
        if abbreviation is None:
            return _plain_trig(self, expr, exp)
        self.used.add(abbreviation)
        return abbreviation.latex if exp is None else f"{abbreviation.latex}^{{{exp}}}"

    def _print_sin(self, expr: sp.Function, exp: str | None = None) -> str:
        return self._print_trig(expr, "s", exp)

    def _print_cos(self, expr: sp.Function, exp: str | None = None) -> str:
        return self._print_trig(expr, "c", exp)

    def _print_Float(self, expr: sp.Float) -> str:
        """The fewest digits that give the Float back (``0.3256``, not ``0.325600000000000``;
        :func:`symkin.emit.formula_text.shortest_float`), ``1.5 \\cdot 10^{-17}`` for powers."""
        text = shortest_float(expr)
        if text is None:
            return super()._print_Float(expr)
        mantissa, _, exponent = text.partition("e")
        if self._settings["decimal_separator"] == "comma":
            mantissa = mantissa.replace(".", "{,}")
        return f"{mantissa} \\cdot 10^{{{int(exponent)}}}" if exponent else mantissa

    def _print_atan2(self, expr: sp.Function, exp: str | None = None) -> str:
        y, x = (self._print(a) for a in expr.args)
        name = r"\operatorname{atan2}"
        if exp is not None:
            name = rf"{name}^{{{exp}}}"
        return rf"{name}\left({y}, {x}\right)"

    # -- legend ---------------------------------------------------------------------------

    def legend(self) -> list[tuple[str, str]]:
        """``[(abbreviation, definition)]`` of every abbreviation used so far, sorted."""
        plain = KinematicsLatexPrinter(list(self.joint_index))
        q = {i: s for s, i in self.joint_index.items()}
        rows = []
        for abbreviation in sorted(self.used, key=Abbreviation.sort_key):
            function = sp.cos if abbreviation.letter == "c" else sp.sin
            angle = sp.Add(*(q[i] for i in abbreviation.indices), evaluate=False)
            rows.append((abbreviation.latex, plain.doprint(function(angle, evaluate=False))))
        return rows


def _padded(values: Sequence[sp.Symbol], like: Sequence[sp.Symbol]) -> list[sp.Symbol | None]:
    return list(values) if len(values) == len(like) else [None] * len(like)


def _plain_trig(printer: LatexPrinter, expr: sp.Function, exp: str | None) -> str:
    """SymPy's own rendering of ``sin``/``cos`` (``\\sin{\\left(q_{1} \\right)}``).

    With ``fold_func_brackets`` a lone symbol goes without parentheses (``\\cos{\\theta_{i}}``).
    """
    name = rf"\{type(expr).__name__}"
    argument = printer._print(expr.args[0])
    if exp is not None:
        name = rf"{name}^{{{exp}}}"
    if printer._settings["fold_func_brackets"] and expr.args[0].is_Symbol:
        return rf"{name}{{{argument}}}"
    return rf"{name}{{\left({argument} \right)}}"


# ---------------------------------------------------------------- width measure

# Widths in units of about one italic letter (11 pt Computer Modern math, ~5.5 pt).
_COMMAND_WIDTHS = {
    "sin": 2.3,
    "cos": 2.5,
    "tan": 2.4,
    "sqrt": 1.6,
    "cdot": 1.5,
    "times": 2.4,
    "quad": 2.0,
    "qquad": 4.0,
    "pi": 1.1,
    "circ": 0.5,
}
_ZERO_WIDTH = {"left", "right", "bigl", "bigr", "Bigl", "Bigr", "displaystyle", "mathrm"}
_OPERATORS = {"+": 2.4, "-": 2.4, "=": 2.6, ",": 0.6, "(": 0.7, ")": 0.7, "[": 0.6, "]": 0.6}
_SPACES = {",": 0.3, ";": 0.5, "!": -0.3, " ": 0.6, "{": 0.0, "}": 0.0}
_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|[{}^_&]|\s+|.")


def latex_width(text: str) -> float:
    """Approximate printed width of inline math ``text`` (units of one italic letter).

    ``\\frac`` counts its wider part (scaled as in display style), super- and subscripts 70 %,
    ``\\sin``, ``\\cos`` their letters, binary operators with their spacing.
    """
    tokens = [t for t in _TOKEN.findall(text) if not t.isspace()]
    width, _ = _width_of(tokens, 0, until=None)
    return width


def _group(tokens: list[str], i: int) -> tuple[float, int]:
    """Width of the group or single token starting at ``tokens[i]``."""
    if i >= len(tokens):
        return 0.0, i
    if tokens[i] == "{":
        return _width_of(tokens, i + 1, until="}")
    return _width_of(tokens[i : i + 1], 0, until=None)[0], i + 1


def _width_of(tokens: list[str], i: int, until: str | None) -> tuple[float, int]:
    """Width of ``tokens[i:]`` up to the token ``until`` and the index just past it."""
    width = 0.0
    while i < len(tokens):
        token = tokens[i]
        if token == until:
            return width, i + 1
        if token == "{":
            inner, i = _width_of(tokens, i + 1, until="}")
            width += inner
            continue
        i += 1
        if token in ("^", "_"):
            inner, i = _group(tokens, i)
            width += 0.7 * inner
        elif token == "&":
            continue
        elif token.startswith("\\"):
            inner, i = _command_width(token[1:], tokens, i)
            width += inner
        elif token in _OPERATORS:
            width += _OPERATORS[token]
        elif token.isdigit() or token == ".":
            width += 0.9 if token.isdigit() else 0.5
        else:
            width += 1.0
    return width, i


def _command_width(name: str, tokens: list[str], i: int) -> tuple[float, int]:
    """Width of the command ``\\name`` with its arguments from ``tokens[i]`` on, and the
    index past them."""
    if name == "frac":
        numerator, i = _group(tokens, i)
        denominator, i = _group(tokens, i)
        return max(numerator, denominator) + 0.4, i
    if name in ("dot", "ddot", "hat", "bar", "boldsymbol", "text", "mathrm"):
        return _group(tokens, i)
    if name == "operatorname":
        inner, i = _group(tokens, i)
        return 0.85 * inner + 0.3, i
    if name in ("begin", "end"):
        return 0.0, _group(tokens, i)[1]
    if name in _ZERO_WIDTH:
        return 0.0, i
    if name in _COMMAND_WIDTHS:
        return _COMMAND_WIDTHS[name], i
    if name in _SPACES:
        return _SPACES[name], i
    if len(name) > 1:
        return 1.0, i  # a Greek letter or another single symbol
    return 0.5, i

"""Line breaking and matrix layout of the LaTeX derivation.

:class:`Layout` prints with one :class:`~symkin.emit.latex.printer.KinematicsLatexPrinter`
(so the legend sees every abbreviation) and decides, by
:func:`~symkin.emit.latex.printer.latex_width`, whether a matrix fits the line, which entries
get names (``T_{11}``) and are listed in an ``align*`` block, and where a long entry is broken
across lines. Widths are in the printer's units: :data:`UNITS_PER_CM` of them per centimetre.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp
from sympy.core.function import _coeff_isneg

from symkin.emit.latex.printer import KinematicsLatexPrinter, latex_width

# Page geometry of the standalone document: A4 with 2 cm margins, 11 pt, a 17 cm line.
# One width unit (see latex_width) is at most 6.7 pt in 11 pt type, measured against pdflatex
# on the catalogue's formulas: 72 units fill 17 cm; 70 leave a little room.
TEXT_WIDTH_CM = 17.0
UNITS_PER_CM = 70.0 / TEXT_WIDTH_CM


@dataclass
class Layout:
    """Printing and line-breaking with one printer (so the legend sees every abbreviation)."""

    printer: KinematicsLatexPrinter
    decimal_comma: bool
    width: float = TEXT_WIDTH_CM * UNITS_PER_CM

    def tex(self, expr: sp.Expr) -> str:
        return self.printer.doprint(expr)

    def measure(self, expr: sp.Expr) -> float:
        """Width of ``expr`` as printed, without recording abbreviations (a trial print)."""
        saved = set(self.printer.used)
        try:
            return latex_width(self.tex(expr))
        finally:
            self.printer.used = saved

    def number(self, value: float) -> str:
        """``0.5403``, ``-1``, ``1.2 \\cdot 10^{-5}`` (``{,}`` as decimal comma in German)."""
        value = float(value)
        if abs(value) < 5e-5:
            text = "0"
        elif 1e-3 <= abs(value) < 1e5:
            text = f"{value:.4f}".rstrip("0").rstrip(".")
        else:
            mantissa, exponent = f"{value:.3e}".split("e")
            text = f"{mantissa.rstrip('0').rstrip('.')} \\cdot 10^{{{int(exponent)}}}"
        return text.replace(".", "{,}") if self.decimal_comma else text

    def given_number(self, value: float) -> str:
        """A number from the robot file (a parameter value) with all its digits, as typed:
        ``d_3 = 0.15005``, never rounded like :meth:`number` rounds computed values."""
        return self.tex(sp.Float(float(value)))

    # -- breaking long expressions --------------------------------------------------------

    def pieces(self, expr: sp.Expr, budget: float) -> list[str]:
        """``expr`` printed as a list of pieces, each at most ``budget`` wide if possible.

        Sums break between terms; long products between factors, with a long sum factor
        in ``\\bigl( ... \\bigr)`` (``\\left``/``\\right`` cannot span lines); fractions as
        ``\\frac{1}{den}`` times the numerator.
        """
        text = self.tex(expr)
        if latex_width(text) <= budget:
            return [text]
        if expr.is_Add:
            out: list[str] = []
            for k, term in enumerate(self.printer._as_ordered_terms(expr)):
                sign = ""
                if k > 0:
                    sign = "{} - " if _coeff_isneg(term) else "{} + "
                    term = -term if _coeff_isneg(term) else term
                parts = self.pieces(term, budget - 3)
                out.append(sign + parts[0])
                out.extend(parts[1:])
            return out
        if expr.is_Mul:
            sign = ""
            if _coeff_isneg(expr):
                sign, expr = "- ", -expr
            numerator, denominator = sp.fraction(expr)
            out = []
            if denominator != 1:
                out.append(rf"\frac{{1}}{{{self.tex(denominator)}}}")
                factors = sp.Mul.make_args(numerator)
            else:
                factors = expr.as_ordered_factors()
            for factor in factors:
                if factor.is_Add:
                    inner = self.pieces(factor, budget - 2)
                    if len(inner) == 1:
                        out.append(rf"\left({inner[0]}\right)")
                    else:
                        out.append(r"\bigl(" + inner[0])
                        out.extend(inner[1:-1])
                        out.append(inner[-1] + r"\bigr)")
                else:
                    out.append(self.tex(factor))
            out[0] = sign + out[0]
            return out
        return [text]

    def lines(self, expr: sp.Expr, first: float, rest: float) -> list[str]:
        """Pieces of ``expr`` packed greedily into lines (``first`` wide, then ``rest``)."""
        lines: list[str] = []
        current = ""
        for piece in self.pieces(expr, min(first, rest)):
            candidate = f"{current} {piece}" if current else piece
            budget = first if not lines else rest
            if current and latex_width(candidate) > budget:
                lines.append(current)
                current = piece
            else:
                current = candidate
        lines.append(current)
        return lines

    def equation_rows(self, lhs: str, expr: sp.Expr, value: float | None = None) -> list[str]:
        """``lhs &= ...`` rows of an ``align*``, continuation lines indented by ``\\quad``."""
        lhs_width = latex_width(lhs) + 3
        lines = self.lines(expr, self.width - lhs_width, self.width - lhs_width - 2)
        rows = [f"{lhs} &= {lines[0]}"] + [rf"&\quad {line}" for line in lines[1:]]
        if value is not None:
            tail = f" = {self.number(value)}"
            last_width = latex_width(lines[-1]) + (0 if len(lines) == 1 else 2)
            if last_width + latex_width(tail) <= self.width - lhs_width:
                rows[-1] += tail
            else:
                rows.append(f"&= {self.number(value)}")
        return rows

    # -- matrices -------------------------------------------------------------------------

    @staticmethod
    def bmatrix(rows: Sequence[Sequence[str]]) -> str:
        body = r" \\ ".join(" & ".join(row) for row in rows)
        return rf"\begin{{bmatrix}} {body} \end{{bmatrix}}"

    @staticmethod
    def bmatrix_width(rows: Sequence[Sequence[str]]) -> float:
        columns = list(zip(*rows, strict=True))
        widths = [max(latex_width(entry) for entry in column) for column in columns]
        return sum(widths) + 1.8 * (len(widths) - 1) + 2.0

    def numeric_rows(self, values: np.ndarray) -> list[list[str]]:
        return [[self.number(v) for v in row] for row in np.atleast_2d(values)]

    def numeric_matrix(self, values: np.ndarray) -> str:
        return self.bmatrix(self.numeric_rows(values))

    def matrix_layout(
        self, matrix: sp.MatrixBase, name: Callable[[int, int], str], room: float
    ) -> tuple[list[list[str]], list[tuple[int, int]]]:
        """Entries as printed, long ones replaced by their names until the matrix fits.

        Returns the rows to typeset and the ``(j, k)`` of the named entries (row-major).
        Entries wider than a threshold are named; the threshold is the largest that makes
        the matrix fit ``room`` (so the same rule holds for every entry).
        """
        saved = set(self.printer.used)
        printed = [[self.tex(matrix[j, k]) for k in range(matrix.cols)] for j in range(matrix.rows)]
        if self.bmatrix_width(printed) <= room:
            return printed, []
        self.printer.used = saved  # the long entries are printed again, line by line
        widths = sorted({latex_width(e) for row in printed for e in row}, reverse=True)
        thresholds = [*widths[1:], -1.0]
        for threshold in thresholds:
            rows = [
                [
                    name(j, k) if latex_width(entry) > threshold else entry
                    for k, entry in enumerate(row)
                ]
                for j, row in enumerate(printed)
            ]
            if self.bmatrix_width(rows) <= room or threshold < 0:
                break
        named = [
            (j, k)
            for j in range(matrix.rows)
            for k in range(matrix.cols)
            if latex_width(printed[j][k]) > threshold
        ]
        for j, k in ((j, k) for j in range(matrix.rows) for k in range(matrix.cols)):
            if (j, k) not in named:
                self.tex(matrix[j, k])  # record the abbreviations of entries shown inline
        return rows, named

    def fits(self, lhs: str, matrix: sp.MatrixBase) -> bool:
        """Whether ``lhs = [matrix]`` fits the line with every entry written out."""
        saved = set(self.printer.used)
        rows = [[self.tex(matrix[j, k]) for k in range(matrix.cols)] for j in range(matrix.rows)]
        self.printer.used = saved
        return latex_width(lhs) + 2.6 + self.bmatrix_width(rows) <= self.width

    def displays(self, items: Sequence[MatrixItem], *, where: str, list_named: bool = True) -> str:
        """Matrices ``lhs = [..]`` (and ``lhs(q*) = [numbers]``) side by side where they fit.

        Each item is ``(lhs, matrix, entry names, numbers or None)``.  A matrix too wide for
        the line gets named entries (see :meth:`matrix_layout`), listed after it in an
        ``align*`` unless ``list_named`` is false (when they are defined elsewhere).
        """
        blocks: list[str] = []
        line: list[tuple[str, float]] = []
        for lhs, matrix, name, numbers in items:
            lhs_width = latex_width(lhs) + 2.6
            rows, named = self.matrix_layout(matrix, name, self.width - lhs_width)
            line.append((f"{lhs} = {self.bmatrix(rows)}", lhs_width + self.bmatrix_width(rows)))
            if numbers is not None:
                at, rows = at_configuration(lhs), self.numeric_rows(numbers)
                line.append(
                    (
                        f"{at} = {self.bmatrix(rows)}",
                        latex_width(at) + 2.6 + self.bmatrix_width(rows),
                    )
                )
            if named and list_named:
                blocks.append(gather(pack_items(line, self.width)))
                line = []
                listing = []
                for j, k in named:
                    listing += self.equation_rows(name(j, k), matrix[j, k])
                blocks.append(f"{where}\n{align(listing)}")
        if line:
            blocks.append(gather(pack_items(line, self.width)))
        return "\n".join(blocks)

    def matrix_display(
        self,
        lhs: str,
        matrix: sp.MatrixBase,
        name: Callable[[int, int], str],
        numbers: np.ndarray | None = None,
        *,
        where: str,
        list_named: bool = True,
    ) -> str:
        """``lhs = [matrix]`` (and ``lhs(q*) = [numbers]``), long entries listed after it."""
        return self.displays([(lhs, matrix, name, numbers)], where=where, list_named=list_named)


MatrixItem = tuple[str, sp.MatrixBase, Callable[[int, int], str], "np.ndarray | None"]


def pack_items(items: Sequence[tuple[str, float]], width: float) -> list[str]:
    """Displays joined by ``,\\qquad`` into lines of at most ``width``."""
    lines: list[str] = []
    current, used = "", 0.0
    for text, item_width in items:
        if current and used + 5.0 + item_width > width:
            lines.append(current)
            current, used = "", 0.0
        current = f"{current},\\qquad {text}" if current else text
        used += item_width + (5.0 if used else 0.0)
    lines.append(current)
    return lines


def align(rows: Sequence[str]) -> str:
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def at_configuration(lhs: str) -> str:
    """``T(q^{*})`` for ``T = {}^{0}T_{6} = ...`` (the first name of a chain)."""
    return f"{lhs.split(' = ')[0]}(q^{{*}})"


def entry_name(symbol: str, superscript: str = "") -> Callable[[int, int], str]:
    def name(j: int, k: int) -> str:
        separator = "," if max(j, k) >= 9 else ""
        return f"{symbol}{superscript}_{{{j + 1}{separator}{k + 1}}}"

    return name


def vector_name(symbol: str, labels: Sequence[str], index: str = "") -> Callable[[int, int], str]:
    """Names ``p_{x}`` or, with an index, ``o_{3,x}``."""

    def name(j: int, _: int) -> str:
        return f"{symbol}_{{{index},{labels[j]}}}" if index else f"{symbol}_{{{labels[j]}}}"

    return name


def pack(items: Sequence[str], separator: str, width: float) -> list[str]:
    lines: list[str] = []
    current = ""
    for item in items:
        candidate = f"{current}{separator}{item}" if current else item
        if current and latex_width(candidate) > width:
            lines.append(current + separator.rstrip().rstrip("\\quad").rstrip())
            current = item
        else:
            current = candidate
    lines.append(current)
    return lines


def gather(lines: Sequence[str]) -> str:
    return "\\begin{gather*}\n" + " \\\\\n".join(lines) + "\n\\end{gather*}"

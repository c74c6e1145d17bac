"""LaTeX backend: the derivation of a robot's kinematics as a lecture would write it.

:func:`latex_files` returns ``{relative path: text}`` and writes nothing:

* ``<robot>.tex``: a standalone A4 document (DH table, link transforms, the product built up
  step by step, tool position, Z-Y-X Euler angles, Jacobian column by column, determinant,
  singular configurations, inverse Jacobian as adjugate over determinant; on request the
  equations of motion by Lagrange);
* ``snippets/<quantity>.tex``: the same displays, one file per quantity, for ``\\input``;
* ``<robot>-macros.tex``: one ``\\newcommand`` per quantity.

Layout decisions are made here, not in the templates: whether a matrix fits the line (by
:func:`~symkin.emit.latex_printer.latex_width`), which entries get names (``T_{11}``) and are
listed in an ``align*`` block, and where a long entry is broken across lines.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from sympy.core.function import _coeff_isneg

from symkin.derive import Model
from symkin.derive.dynamics import link_inertial_data
from symkin.derive.kinematics import joint_dh_values, modified_dh_matrix, standard_dh_matrix
from symkin.derive.lagrange import READABLE_DOF
from symkin.derive.numeric import numeric_function
from symkin.emit.latex_printer import KinematicsLatexPrinter, latex_width
from symkin.emit.render import comment_text, render
from symkin.errors import SymkinError
from symkin.robot import Robot
from symkin.text import printable

SECTIONS = ("dh", "transforms", "fk", "euler", "jacobian", "det", "inverse", "dynamics")
# The equations of motion are asked for by name: they need inertial data and, by Lagrange,
# take seconds for three joints.
DEFAULT_SECTIONS = tuple(s for s in SECTIONS if s != "dynamics")
LANGUAGES = ("en", "de")

# Page geometry of the standalone document: A4 with 2 cm margins, 11 pt, a 17 cm line.
# One width unit (see latex_width) is at most 6.7 pt in 11 pt type, measured against pdflatex
# on the catalogue's formulas: 72 units fill 17 cm; 70 leave a little room.
TEXT_WIDTH_CM = 17.0
UNITS_PER_CM = 70.0 / TEXT_WIDTH_CM
MIN_TEXT_WIDTH_CM, MAX_TEXT_WIDTH_CM = 8.0, 40.0
# Symbolic inverse Jacobians are printed up to this many joints; beyond, the adjugate's
# entries (cofactors of (n-1) x (n-1) minors) run to pages and take minutes to form.
INVERSE_MAX_DOF = 4
INVERSE_MAX_LINES = 40
# Euler angles of this robot are printed in terms of q only when each fits on a line.
EULER_MARGIN_UNITS = 8.0

TEXT: dict[str, dict[str, str]] = {
    "en": {
        "title": "Kinematics of the {title}",
        "intro": (
            "Derived by symkin from the Denavit--Hartenberg table of the robot "
            "\\texttt{{{name}}} ({convention} DH, {dof} joints). Joint variables are "
            "$q_{{i}}$ (angles for revolute, lengths for prismatic joints), velocities "
            "$\\dot{{q}}_{{i}}$, accelerations $\\ddot{{q}}_{{i}}$."
        ),
        "standard": "standard (distal)",
        "modified": "modified (proximal, Craig)",
        "legend": "Abbreviations used throughout:",
        "configuration": (
            "Numbers are given next to the formulas for the configuration $q^{{*}}$ with"
        ),
        "parameters_values": "and the parameter values",
        "dh": "Denavit--Hartenberg parameters",
        "dh_intro_standard": (
            "Standard DH: frame $i$ follows from frame $i-1$ by a rotation $\\theta_{i}$ "
            "about $z_{i-1}$, a translation $d_{i}$ along $z_{i-1}$, a translation $a_{i}$ "
            "along $x_{i}$ and a rotation $\\alpha_{i}$ about $x_{i}$:"
        ),
        "dh_intro_modified": (
            "Modified DH: frame $i$ follows from frame $i-1$ by a rotation "
            "$\\alpha_{i-1}$ about $x_{i-1}$, a translation $a_{i-1}$ along $x_{i-1}$, a "
            "rotation $\\theta_{i}$ about $z_{i}$ and a translation $d_{i}$ along $z_{i}$:"
        ),
        "table_intro": "The table of this robot, joint variables inserted:",
        "revolute": "revolute",
        "prismatic": "prismatic",
        "joint": "type",
        "parameters": "Parameters:",
        "no_value": "no value",
        "no_parameters": "The table has no named parameters.",
        "base": "Base transform:",
        "tool": "Tool transform:",
        "transforms": "Link transforms",
        "transforms_intro": (
            "Each row of the table, inserted into the matrix above, gives the pose of frame "
            "$i$ in frame $i-1$."
        ),
        "fk": "Forward kinematics",
        "fk_intro": "The product is built up one link at a time:",
        "tool_position": "The tool position is the last column of $T$:",
        "euler": "Z-Y-X Euler angles",
        "euler_intro": (
            "The orientation $R = R_{z}(\\psi)\\, R_{y}(\\theta)\\, R_{x}(\\varphi)$ (yaw "
            "$\\psi$ about $z$, pitch $\\theta$ about the new $y$, roll $\\varphi$ about the "
            "newest $x$) follows from the entries $r_{jk} = T_{jk}$ of the rotation part of "
            "$T$:"
        ),
        "euler_singular": (
            "The formulas fail where $\\cos\\theta = 0$ ($\\theta = \\pm 90^{\\circ}$, "
            "$r_{11} = r_{21} = 0$): there only $\\psi \\pm \\varphi$ is determined."
        ),
        "euler_robot": "For this robot:",
        "euler_long": (
            "Inserted into these formulas, the entries of $T$ give expressions too long to "
            "be useful here; evaluate $r_{jk}$ first."
        ),
        "jacobian": "Geometric Jacobian",
        "jacobian_intro": (
            "The geometric Jacobian $J = \\bigl[J_{{1}} \\; \\cdots \\; J_{{{dof}}}\\bigr]$ "
            "maps $\\dot{{q}}$ to the linear and angular velocity of the tool, "
            "$\\left[\\begin{{smallmatrix}} v \\\\ \\omega \\end{{smallmatrix}}\\right] "
            "= J \\dot{{q}}$, "
            "all in base coordinates. Column $i$ depends on the type of joint $i$, "
            "with $z_{{{k}}}$ the joint axis, $o_{{{k}}}$ the origin of frame ${k}$ and "
            "$p$ the tool position:"
        ),
        "column": "Joint {i} ({kind}):",
        "jacobian_full": "Together:",
        "jacobian_names": "where $J_{jk}$ is entry $j$ of the column $J_{k}$ above.",
        "task": (
            "The task Jacobian keeps the rows {rows} of $J$ (the rows along which this robot "
            "can move):"
        ),
        "det": "Determinant and singular configurations",
        "det_intro": "The determinant of the task Jacobian, factored:",
        "det_none": (
            "The task Jacobian is not square, so it has no determinant; the manipulability "
            "$\\sqrt{\\det(J J^{T})}$ takes its place."
        ),
        "singular": "The Jacobian is singular (loses rank) when",
        "singular_none": "The determinant has no zeros in the joint variables.",
        "inverse": "Inverse Jacobian",
        "inverse_intro": (
            "Where $\\det J \\ne 0$, the inverse is the adjugate over the determinant:"
        ),
        "inverse_long": (
            "For {dof} joints the adjugate's entries (cofactors of ${m} \\times {m}$ minors) "
            "are too long to print; evaluate $J$ numerically and solve instead."
        ),
        "inverse_numbers": "At $q^{{*}}$:",
        "inverse_singular": "At $q^{*}$ the Jacobian is singular and has no inverse.",
        "where": "with",
        "or": "or",
        "dynamics": "Equations of motion",
        "dynamics_intro": (
            "Lagrange's equations give the joint forces and torques $\\tau$ as "
            "$\\tau = M(q)\\, \\ddot{q} + C(q, \\dot{q})\\, \\dot{q} + G(q) + F(\\dot{q})$. "
            "With link $i$ of mass $m_{i}$, centre of mass $r_{c,i}$, inertia tensor $I_{i}$ "
            "about it (frame-$i$ axes), the Jacobians $J_{v,i}$, $J_{\\omega,i}$ of its centre "
            "of mass and angular velocity and its rotation $R_{i}$ (all in base coordinates), "
            "gravity $g$ and, where given, rotor inertias $I_{a,i}$ reflected to the joints:"
        ),
        "dynamics_christoffel": (
            "$C$ comes from the Christoffel symbols of $M$, so that $\\dot{M} - 2C$ is "
            "skew-symmetric:"
        ),
        "mass_matrix": "The mass matrix:",
        "coriolis_matrix": "The Coriolis and centrifugal matrix:",
        "gravity_vector": "The gravity torques:",
        "friction_vector": "Friction (Coulomb, viscous and Stribeck, as the robot file gives it):",
        "dynamics_long": (
            "For {dof} joints the entries of $M$, $C$ and $G$ run to pages. The generated code "
            "computes them by recursive Newton--Euler, which names every intermediate "
            "quantity as the recursion goes (\\texttt{{symkin derive}})."
        ),
    },
    "de": {
        "title": "Kinematik: {title}",
        "intro": (
            "Von symkin aus der Denavit-Hartenberg-Tabelle des Roboters "
            "\\texttt{{{name}}} abgeleitet ({convention} DH, {dof} Gelenke). "
            'Gelenkvariablen sind $q_{{i}}$ (Winkel bei Dreh-, L\\"angen bei '
            "Schubgelenken), Geschwindigkeiten $\\dot{{q}}_{{i}}$, Beschleunigungen "
            "$\\ddot{{q}}_{{i}}$."
        ),
        "standard": "klassische",
        "modified": "modifizierte (nach Craig)",
        "legend": 'Abk\\"urzungen im ganzen Text:',
        "configuration": 'Zahlenwerte stehen neben den Formeln, f\\"ur die Stellung $q^{{*}}$ mit',
        "parameters_values": "und den Parameterwerten",
        "dh": "Denavit-Hartenberg-Parameter",
        "dh_intro_standard": (
            "Klassische DH-Konvention: Koordinatensystem $i$ entsteht aus $i-1$ durch "
            'Drehung um $\\theta_{i}$ um $z_{i-1}$, Verschiebung um $d_{i}$ l\\"angs '
            '$z_{i-1}$, Verschiebung um $a_{i}$ l\\"angs $x_{i}$ und Drehung um '
            "$\\alpha_{i}$ um $x_{i}$:"
        ),
        "dh_intro_modified": (
            "Modifizierte DH-Konvention: Koordinatensystem $i$ entsteht aus $i-1$ durch "
            'Drehung um $\\alpha_{i-1}$ um $x_{i-1}$, Verschiebung um $a_{i-1}$ l\\"angs '
            "$x_{i-1}$, Drehung um $\\theta_{i}$ um $z_{i}$ und Verschiebung um $d_{i}$ "
            'l\\"angs $z_{i}$:'
        ),
        "table_intro": "Die Tabelle dieses Roboters, mit eingesetzten Gelenkvariablen:",
        "revolute": "Drehgelenk",
        "prismatic": "Schubgelenk",
        "joint": "Typ",
        "parameters": "Parameter:",
        "no_value": "ohne Wert",
        "no_parameters": "Die Tabelle hat keine benannten Parameter.",
        "base": "Basistransformation:",
        "tool": "Werkzeugtransformation:",
        "transforms": "Transformationsmatrizen der Glieder",
        "transforms_intro": (
            "Jede Zeile der Tabelle, in die Matrix oben eingesetzt, ergibt die Lage von "
            "Koordinatensystem $i$ in $i-1$."
        ),
        "fk": 'Vorw\\"artskinematik',
        "fk_intro": 'Das Produkt entsteht Glied f\\"ur Glied:',
        "tool_position": "Die Werkzeugposition ist die letzte Spalte von $T$:",
        "euler": "Euler-Winkel (Z-Y-X)",
        "euler_intro": (
            "Die Orientierung $R = R_{z}(\\psi)\\, R_{y}(\\theta)\\, R_{x}(\\varphi)$ (Gieren "
            "$\\psi$ um $z$, Nicken $\\theta$ um das neue $y$, Rollen $\\varphi$ um das "
            "neueste $x$) folgt aus den Elementen $r_{jk} = T_{jk}$ des Rotationsteils von "
            "$T$:"
        ),
        "euler_singular": (
            "Die Formeln versagen bei $\\cos\\theta = 0$ ($\\theta = \\pm 90^{\\circ}$, "
            "$r_{11} = r_{21} = 0$): dort ist nur $\\psi \\pm \\varphi$ bestimmt."
        ),
        "euler_robot": 'F\\"ur diesen Roboter:',
        "euler_long": (
            'Mit den Elementen von $T$ eingesetzt werden diese Ausdr\\"ucke zu lang; '
            "man berechnet zuerst $r_{jk}$."
        ),
        "jacobian": "Geometrische Jacobi-Matrix",
        "jacobian_intro": (
            "Die geometrische Jacobi-Matrix $J = \\bigl[J_{{1}} \\; \\cdots \\; "
            "J_{{{dof}}}\\bigr]$ bildet $\\dot{{q}}$ auf die Geschwindigkeit und "
            "Winkelgeschwindigkeit des Werkzeugs ab, $\\left[\\begin{{smallmatrix}} v "
            "\\\\ \\omega \\end{{smallmatrix}}\\right] = J \\dot{{q}}$, "
            "alles in Basiskoordinaten. Spalte $i$ "
            'h\\"angt von der Art des Gelenks $i$ ab; $z_{{{k}}}$ ist die Gelenkachse, '
            "$o_{{{k}}}$ der Ursprung von System ${k}$ und $p$ die Werkzeugposition:"
        ),
        "column": "Gelenk {i} ({kind}):",
        "jacobian_full": "Zusammen:",
        "jacobian_names": "wobei $J_{jk}$ das Element $j$ der Spalte $J_{k}$ oben ist.",
        "task": (
            "Die Aufgaben-Jacobi-Matrix besteht aus den Zeilen {rows} von $J$ (den "
            "Richtungen, in denen sich dieser Roboter bewegen kann):"
        ),
        "det": 'Determinante und Singularit\\"aten',
        "det_intro": "Die Determinante der Aufgaben-Jacobi-Matrix, faktorisiert:",
        "det_none": (
            "Die Aufgaben-Jacobi-Matrix ist nicht quadratisch und hat keine Determinante; "
            "an ihre Stelle tritt die Manipulierbarkeit $\\sqrt{\\det(J J^{T})}$."
        ),
        "singular": 'Die Jacobi-Matrix ist singul\\"ar (verliert Rang) f\\"ur',
        "singular_none": "Die Determinante hat keine Nullstellen in den Gelenkvariablen.",
        "inverse": "Inverse Jacobi-Matrix",
        "inverse_intro": (
            'F\\"ur $\\det J \\ne 0$ ist die Inverse die Adjunkte geteilt durch die Determinante:'
        ),
        "inverse_long": (
            "Bei {dof} Gelenken sind die Elemente der Adjunkte (Kofaktoren von "
            "${m} \\times {m}$-Minoren) zu lang zum Abdrucken; man wertet $J$ numerisch aus "
            'und l\\"ost das Gleichungssystem.'
        ),
        "inverse_numbers": "Bei $q^{{*}}$:",
        "inverse_singular": 'Bei $q^{*}$ ist die Jacobi-Matrix singul\\"ar und nicht invertierbar.',
        "where": "mit",
        "or": "oder",
        "dynamics": "Bewegungsgleichungen",
        "dynamics_intro": (
            'Die Lagrange-Gleichungen ergeben die Gelenkkr\\"afte und -momente $\\tau$ als '
            "$\\tau = M(q)\\, \\ddot{q} + C(q, \\dot{q})\\, \\dot{q} + G(q) + F(\\dot{q})$. "
            'Mit Masse $m_{i}$, Schwerpunkt $r_{c,i}$ und Tr\\"agheitstensor $I_{i}$ (um den '
            "Schwerpunkt, Achsen von System $i$) von Glied $i$, den Jacobi-Matrizen "
            "$J_{v,i}$, $J_{\\omega,i}$ seines Schwerpunkts und seiner Winkelgeschwindigkeit, "
            "seiner Drehung $R_{i}$ (alles in Basiskoordinaten), der Schwerkraft $g$ und, "
            'falls angegeben, den auf die Gelenke reduzierten Rotortr\\"agheiten $I_{a,i}$:'
        ),
        "dynamics_christoffel": (
            "$C$ folgt aus den Christoffel-Symbolen von $M$, sodass $\\dot{M} - 2C$ "
            "schiefsymmetrisch ist:"
        ),
        "mass_matrix": "Die Massenmatrix:",
        "coriolis_matrix": "Die Matrix der Coriolis- und Zentrifugalterme:",
        "gravity_vector": "Die Gravitationsmomente:",
        "friction_vector": "Reibung (Coulomb, viskos und Stribeck, wie in der Roboterdatei):",
        "dynamics_long": (
            "Bei {dof} Gelenken werden die Elemente von $M$, $C$ und $G$ seitenlang. Der "
            "erzeugte Code berechnet sie rekursiv nach Newton--Euler und benennt dabei jede "
            'Zwischengr\\"o\\ss{{}}e (\\texttt{{symkin derive}}).'
        ),
    },
}
ROW_LATEX = {"x": "x", "y": "y", "z": "z", "wx": "\\omega_{x}", "wy": "\\omega_{y}"}
ROW_LATEX["wz"] = "\\omega_{z}"
DIGIT_WORDS = ("Zero", "One", "Two", "Three", "Four", "Five", "Six", "Seven", "Eight", "Nine")


def check_sections(names: Iterable[str]) -> tuple[str, ...]:
    """Validate section names (``--sections``); order follows :data:`SECTIONS`."""
    chosen = {n.strip() for n in names if n.strip()}
    unknown = sorted(chosen - set(SECTIONS))
    if unknown:
        raise SymkinError(
            f"--sections: unknown section(s) {', '.join(unknown)}; "
            f"choose from {', '.join(SECTIONS)}"
        )
    if not chosen:
        raise SymkinError(f"--sections: name at least one of {', '.join(SECTIONS)}")
    return tuple(s for s in SECTIONS if s in chosen)


def macro_prefix(name: str) -> str:
    """A robot name as letters only (``puma560`` -> ``pumaFiveSixZero``) for macro names."""
    out, upper = [], False
    for char in name:
        if char.isdigit():
            out.append(DIGIT_WORDS[int(char)])
        elif char.isalpha():
            out.append(char.upper() if upper else char)
            upper = False
        else:
            upper = True
    return "".join(out)


def number_words(i: int) -> str:
    return "".join(DIGIT_WORDS[int(c)] for c in str(i))


# ---------------------------------------------------------------- layout helpers


@dataclass(frozen=True)
class Quantity:
    """One displayed quantity: a snippet file, a macro and a part of a section."""

    key: str
    macro: str
    description: str
    body: str
    text: str = ""


@dataclass(frozen=True)
class Section:
    key: str
    heading: str
    intro: str
    quantities: tuple[Quantity, ...]


@dataclass
class _Layout:
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
                at, rows = _at_configuration(lhs), self.numeric_rows(numbers)
                line.append(
                    (
                        f"{at} = {self.bmatrix(rows)}",
                        latex_width(at) + 2.6 + self.bmatrix_width(rows),
                    )
                )
            if named and list_named:
                blocks.append(_gather(_pack_items(line, self.width)))
                line = []
                listing = []
                for j, k in named:
                    listing += self.equation_rows(name(j, k), matrix[j, k])
                blocks.append(f"{where}\n{_align(listing)}")
        if line:
            blocks.append(_gather(_pack_items(line, self.width)))
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


def _pack_items(items: Sequence[tuple[str, float]], width: float) -> list[str]:
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


def _align(rows: Sequence[str]) -> str:
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def _at_configuration(lhs: str) -> str:
    """``T(q^{*})`` for ``T = {}^{0}T_{6} = ...`` (the first name of a chain)."""
    return f"{lhs.split(' = ')[0]}(q^{{*}})"


def _entry_name(symbol: str, superscript: str = "") -> Callable[[int, int], str]:
    def name(j: int, k: int) -> str:
        separator = "," if max(j, k) >= 9 else ""
        return f"{symbol}{superscript}_{{{j + 1}{separator}{k + 1}}}"

    return name


def inertial_symbol_names(robot: Robot) -> dict[sp.Symbol, str]:
    """How the inertial symbols of links without data print: ``m_{1}``, ``c_{x,1}``,
    ``I_{xx,1}`` (``link_inertial_data`` names them ``m1``, ``cx1``, ``ixx1``)."""
    names: dict[sp.Symbol, str] = {}
    for index, joint in enumerate(robot.joints):
        if joint.link is not None:
            continue
        link, i = link_inertial_data(robot, index), index + 1
        names[link.mass] = f"m_{{{i}}}"
        for axis, c in zip("xyz", link.com, strict=True):
            names[c] = f"c_{{{axis},{i}}}"
        for axes, entry in zip(("xx", "yy", "zz", "xy", "xz", "yz"), link.inertia, strict=True):
            names[entry] = f"I_{{{axes},{i}}}"
    return names


def _vector_name(symbol: str, labels: Sequence[str], index: str = "") -> Callable[[int, int], str]:
    """Names ``p_{x}`` or, with an index, ``o_{3,x}``."""

    def name(j: int, _: int) -> str:
        return f"{symbol}_{{{index},{labels[j]}}}" if index else f"{symbol}_{{{labels[j]}}}"

    return name


def _distribute_sign(expr: sp.Expr) -> sp.Expr:
    """``-(a + b)`` as ``-a - b``; other factors stay factored (``L_3 (a + b)``)."""
    expr = sp.factor_terms(expr)
    coefficient, rest = expr.as_coeff_Mul()
    if coefficient == -1 and rest.is_Add:
        return sp.Add(*(-term for term in rest.args))
    return expr


def _is_identity(matrix: sp.MatrixBase) -> bool:
    return sp.ImmutableMatrix(matrix) == sp.ImmutableMatrix(sp.eye(matrix.rows))


# ---------------------------------------------------------------- the document


@dataclass
class _Writer:
    model: Model
    sections: tuple[str, ...]
    shorthand: bool
    lang: str
    q: tuple[float, ...] | None
    overrides: Mapping[str, float] | None
    text_width_cm: float = TEXT_WIDTH_CM
    layout: _Layout = field(init=False)

    def __post_init__(self) -> None:
        model = self.model
        if self.shorthand:
            _check_shorthand_names(model)
        printer = KinematicsLatexPrinter(
            model.q,
            model.dq,
            model.ddq,
            shorthand=self.shorthand,
            decimal_separator="comma" if self.lang == "de" else "period",
            symbol_names=inertial_symbol_names(model.robot),
        )
        self.layout = _Layout(
            printer, decimal_comma=self.lang == "de", width=self.text_width_cm * UNITS_PER_CM
        )
        self.t = TEXT[self.lang]

    # -- helpers --------------------------------------------------------------------------

    def numbers(self, expr: sp.MatrixBase | sp.Expr) -> np.ndarray | None:
        if self.q is None:
            return None
        return numeric_function(self.model, expr, self.overrides)(np.asarray(self.q, dtype=float))

    def scalar(self, expr: sp.Expr) -> float | None:
        values = self.numbers(expr)
        return None if values is None else float(values)

    @property
    def axis_index(self) -> Callable[[int], int]:
        """Frame index of joint i's axis (1-based i): i-1 in standard, i in modified DH."""
        offset = 1 if self.model.robot.convention == "standard" else 0
        return lambda i: i - offset

    def math(self, expr: sp.Expr) -> str:
        return f"${self.layout.tex(expr)}$"

    # -- sections -------------------------------------------------------------------------

    def section_dh(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        robot = model.robot
        standard = robot.convention == "standard"
        theta, d = sp.Symbol("theta_i", real=True), sp.Symbol("d_i", real=True)
        if standard:
            a, alpha = sp.Symbol("a_i", real=True), sp.Symbol("alpha_i", real=True)
            general = standard_dh_matrix(theta, d, a, alpha)
            product = (
                r"\mathrm{Rot}_{z}(\theta_{i})\, \mathrm{Trans}_{z}(d_{i})\, "
                r"\mathrm{Trans}_{x}(a_{i})\, \mathrm{Rot}_{x}(\alpha_{i})"
            )
            columns = [r"\theta_{i}", "d_{i}", "a_{i}", r"\alpha_{i}"]
        else:
            a, alpha = sp.Symbol("a_{i-1}", real=True), sp.Symbol("alpha_{i-1}", real=True)
            general = modified_dh_matrix(theta, d, a, alpha)
            product = (
                r"\mathrm{Rot}_{x}(\alpha_{i-1})\, \mathrm{Trans}_{x}(a_{i-1})\, "
                r"\mathrm{Rot}_{z}(\theta_{i})\, \mathrm{Trans}_{z}(d_{i})"
            )
            columns = [r"\alpha_{i-1}", "a_{i-1}", r"\theta_{i}", "d_{i}"]
        # The general matrix is printed without shorthand: its angles are theta_i, alpha_i.
        general_printer = KinematicsLatexPrinter((), fold_func_brackets=True)
        general_rows = [
            [general_printer.doprint(general[j, k]) for k in range(4)] for j in range(4)
        ]
        formula = _align(
            [
                rf"A_{{i}} = {{}}^{{i-1}}T_{{i}} &= {product} \\"
                rf"&= {layout.bmatrix(general_rows)}"
            ]
        )
        header = " & ".join([r"$i$", t["joint"]] + [f"${c}$" for c in columns])
        lines = [
            r"\begin{center}",
            r"\begin{tabular}{cl" + "c" * 4 + "}",
            r"\toprule",
            header + r" \\",
            r"\midrule",
        ]
        for index, (joint, qi) in enumerate(zip(robot.joints, model.q, strict=True), start=1):
            th, dd, aa, al = joint_dh_values(joint, qi)
            values = [th, dd, aa, al] if standard else [al, aa, th, dd]
            cells = [f"${index}$", t[joint.type]] + [self.math(v) for v in values]
            lines.append(" & ".join(cells) + r" \\")
        lines += [r"\bottomrule", r"\end{tabular}", r"\end{center}"]
        table = "\n".join(lines)
        quantities = [
            Quantity("dh-matrix", "DHMatrix", "the general DH link transform", formula),
            Quantity(
                "dh-table",
                "DHTable",
                "the DH table",
                table,
                text=t["table_intro"],
            ),
        ]
        parameters = self.parameter_text()
        quantities.append(Quantity("parameters", "Parameters", "parameter values", parameters))
        for key, matrix in (("base", robot.base), ("tool", robot.tool)):
            if not _is_identity(matrix):
                symbol = r"T_{\mathrm{" + key + "}}"
                body = layout.matrix_display(
                    symbol, matrix, _entry_name("b" if key == "base" else "e"), where=t["where"]
                )
                quantities.append(
                    Quantity(
                        f"{key}-transform", key.capitalize(), f"the {key} transform", body, t[key]
                    )
                )
        intro = t["dh_intro_standard" if standard else "dh_intro_modified"]
        return Section("dh", t["dh"], intro, tuple(quantities))

    def parameter_text(self) -> str:
        robot, t = self.model.robot, self.t
        if not robot.parameters:
            return t["no_parameters"]
        overrides = dict(self.overrides or {})
        items = []
        for symbol, (name, value) in zip(robot.parameter_symbols, robot.parameters, strict=True):
            value = overrides.get(name, value)
            name_tex = self.layout.tex(symbol)
            if value is None:
                items.append(f"${name_tex}$ ({t['no_value']})")
            else:
                items.append(f"${name_tex} = {self.layout.number(value)}$")
        separator = "; " if self.lang == "de" else ", "
        return t["parameters"] + " " + separator.join(items) + "."

    def section_transforms(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        quantities = []
        for i, matrix in enumerate(model.link_transforms, start=1):
            lhs = rf"A_{{{i}}} = {{}}^{{{i - 1}}}T_{{{i}}}"
            body = layout.matrix_display(
                lhs, matrix, _entry_name("a", f"^{{({i})}}"), self.numbers(matrix), where=t["where"]
            )
            quantities.append(
                Quantity(
                    f"link-transform-{i}",
                    f"LinkTransform{number_words(i)}",
                    f"A_{i}, the pose of frame {i} in frame {i - 1}",
                    body,
                )
            )
        return Section("transforms", t["transforms"], t["transforms_intro"], tuple(quantities))

    def section_fk(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        robot = model.robot
        n = robot.dof
        has_base, has_tool = not _is_identity(robot.base), not _is_identity(robot.tool)
        quantities = []
        frames = model.frame_transforms
        for i in range(1, n + 1):
            last = i == n and not has_tool
            if i == 1:
                product = r"T_{\mathrm{base}}\, A_{1}" if has_base else "A_{1}"
            else:
                product = rf"{{}}^{{0}}T_{{{i - 1}}}\, A_{{{i}}}"
            if i == 1 and not has_base and not last:
                body = _align([r"{}^{0}T_{1} &= A_{1}"])
            else:
                lhs = (
                    rf"T = {{}}^{{0}}T_{{{i}}} = {product}"
                    if last
                    else rf"{{}}^{{0}}T_{{{i}}} = {product}"
                )
                name = _entry_name("T") if last else _entry_name("t", f"^{{({i})}}")
                body = layout.matrix_display(
                    lhs, frames[i], name, self.numbers(frames[i]), where=t["where"]
                )
            quantities.append(
                Quantity(
                    "forward-kinematics" if last else f"frame-transform-{i}",
                    "ForwardKinematics" if last else f"FrameTransform{number_words(i)}",
                    "T, the pose of the tool in the base frame"
                    if last
                    else f"T_0_{i}, the pose of frame {i} in the base frame",
                    body,
                )
            )
        if has_tool:
            lhs = rf"T = {{}}^{{0}}T_{{{n}}}\, T_{{\mathrm{{tool}}}}"
            body = layout.matrix_display(
                lhs,
                model.forward_kinematics,
                _entry_name("T"),
                self.numbers(model.forward_kinematics),
                where=t["where"],
            )
            quantities.append(
                Quantity(
                    "forward-kinematics",
                    "ForwardKinematics",
                    "T, the pose of the tool in the base frame",
                    body,
                )
            )
        position = model.tool_position
        body = layout.matrix_display(
            r"p = \begin{bmatrix} x \\ y \\ z \end{bmatrix}",
            position,
            _vector_name("p", "xyz"),
            self.numbers(position),
            where=t["where"],
        )
        quantities.append(
            Quantity(
                "tool-position", "ToolPosition", "p, the tool position", body, t["tool_position"]
            )
        )
        return Section("fk", t["fk"], t["fk_intro"], tuple(quantities))

    def section_euler(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        general = _align(
            [
                r"\psi &= \operatorname{atan2}\left(r_{21}, r_{11}\right)",
                r"\theta &= \operatorname{atan2}\left(-r_{31}, "
                r"\sqrt{r_{11}^{2} + r_{21}^{2}}\right)",
                r"\varphi &= \operatorname{atan2}\left(r_{32}, r_{33}\right)",
            ]
        )
        angles = model.euler_zyx
        names = (r"\psi", r"\theta", r"\varphi")
        values = [self.scalar(a) for a in angles]
        if all(layout.measure(a) <= layout.width - EULER_MARGIN_UNITS for a in angles):
            rows = []
            for symbol, angle, value in zip(names, angles, values, strict=True):
                rows += layout.equation_rows(symbol, angle, None if angle.is_number else value)
            body, text = _align(rows), t["euler_singular"] + " " + t["euler_robot"]
        else:
            body, text = "", t["euler_singular"] + " " + t["euler_long"]
            if self.q is not None:
                rows = [
                    f"{s}(q^{{*}}) &= {layout.number(v)}"
                    for s, v in zip(names, values, strict=True)
                ]
                body = _align(rows)
        quantities = [
            Quantity("euler-zyx-formulas", "EulerFormulas", "the Z-Y-X Euler formulas", general),
            Quantity("euler-zyx", "EulerZYX", "the Z-Y-X Euler angles of this robot", body, text),
        ]
        return Section("euler", t["euler"], t["euler_intro"], tuple(quantities))

    def section_jacobian(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        robot = model.robot
        standard = robot.convention == "standard"
        k = "i-1" if standard else "i"
        quantities = []
        formula = _align(
            [
                rf"J_{{i}} &= \begin{{bmatrix}} z_{{{k}}} \times (p - o_{{{k}}}) \\ z_{{{k}}}"
                rf"\end{{bmatrix}} \qquad \text{{({t['revolute']})}}",
                rf"J_{{i}} &= \begin{{bmatrix}} z_{{{k}}} \\ 0 \end{{bmatrix}} "
                rf"\qquad \text{{({t['prismatic']})}}",
            ]
        )
        quantities.append(
            Quantity("jacobian-formula", "JacobianFormula", "Jacobian columns", formula)
        )
        jacobian = model.geometric_jacobian
        frames = model.kinematics.joint_frames
        for i, joint in enumerate(robot.joints, start=1):
            f = self.axis_index(i)
            frame = frames[i - 1]
            axis, origin = frame[:3, 2], frame[:3, 3]
            column = jacobian[:, i - 1]
            items: list[MatrixItem] = [(f"z_{{{f}}}", axis, _vector_name("z", "xyz", str(f)), None)]
            if joint.type == "revolute":
                items.append((f"o_{{{f}}}", origin, _vector_name("o", "xyz", str(f)), None))
            items.append(
                (f"J_{{{i}}}", column, lambda j, _, i=i: f"J_{{{j + 1}{i}}}", self.numbers(column))
            )
            body = layout.displays(items, where=t["where"])
            quantities.append(
                Quantity(
                    f"jacobian-column-{i}",
                    f"JacobianColumn{number_words(i)}",
                    f"column {i} of the geometric Jacobian",
                    body,
                    t["column"].format(i=i, kind=t[joint.type]),
                )
            )
        body = layout.matrix_display(
            "J",
            jacobian,
            _entry_name("J"),
            self.numbers(jacobian),
            where=t["where"],
            list_named=False,
        )
        if not layout.fits("J", jacobian):
            body += "\n" + t["jacobian_names"]
        quantities.append(
            Quantity("jacobian", "Jacobian", "the geometric Jacobian", body, t["jacobian_full"])
        )
        rows = model.task_rows
        if tuple(rows) != ("x", "y", "z", "wx", "wy", "wz"):
            task = model.task_jacobian(rows)
            names = ", ".join(f"${ROW_LATEX[r]}$" for r in rows)
            body = layout.matrix_display(
                r"J_{\mathrm{task}}",
                task,
                _entry_name("J"),
                self.numbers(task),
                where=t["where"],
                list_named=False,
            )
            quantities.append(
                Quantity(
                    "task-jacobian",
                    "TaskJacobian",
                    "the task Jacobian",
                    body,
                    t["task"].format(rows=names),
                )
            )
        intro = t["jacobian_intro"].format(dof=robot.dof, k=k)
        return Section("jacobian", t["jacobian"], intro, tuple(quantities))

    @property
    def task_symbol(self) -> str:
        if tuple(self.model.task_rows) == ("x", "y", "z", "wx", "wy", "wz"):
            return "J"
        return r"J_{\mathrm{task}}"

    def section_det(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        determinant = model.determinant()
        if determinant is None:
            return Section("det", t["det"], t["det_none"], ())
        symbol = self.task_symbol
        body = _align(
            layout.equation_rows(rf"\det {symbol}", determinant, self.scalar(determinant))
        )
        quantities = [Quantity("determinant", "Determinant", "the factored determinant", body)]
        conditions = model.singular_configurations()
        if conditions:
            rows = [layout.equation_rows(layout.tex(c.lhs), c.rhs)[0] for c in conditions]
            rows = [
                row + (rf" \qquad \text{{{t['or']}}}" if n < len(rows) - 1 else "")
                for n, row in enumerate(rows)
            ]
            body = _align(rows)
            text = t["singular"]
        else:
            body, text = t["singular_none"], ""
        quantities.append(
            Quantity("singularities", "Singularities", "the singular configurations", body, text)
        )
        return Section("det", t["det"], t["det_intro"], tuple(quantities))

    def section_inverse(self) -> Section | None:
        model, layout, t = self.model, self.layout, self.t
        determinant = model.determinant()
        if determinant is None:
            return None
        n = model.robot.dof
        symbol = self.task_symbol
        numbers = None
        if self.q is not None:
            task = self.numbers(model.task_jacobian())
            numbers = None if abs(np.linalg.det(task)) < 1e-12 else np.linalg.inv(task)
        body = ""
        if n <= INVERSE_MAX_DOF:
            inverse = model.inverse_task_jacobian()
            adjugate = inverse.applyfunc(lambda e: _distribute_sign(sp.cancel(e * determinant)))
            if sum(layout.measure(e) for e in adjugate) <= INVERSE_MAX_LINES * layout.width:
                formula = (
                    rf"{symbol}^{{-1}} &= \frac{{\operatorname{{adj}} {symbol}}}{{\det {symbol}}}"
                )
                body = (
                    _align([formula])
                    + "\n"
                    + layout.matrix_display(
                        rf"\operatorname{{adj}} {symbol}",
                        adjugate,
                        _entry_name(r"\tilde{J}"),
                        where=t["where"],
                    )
                )
        if not body:
            body = t["inverse_long"].format(dof=n, m=n - 1)
        if self.q is not None:
            if numbers is None:
                body += "\n" + t["inverse_singular"]
            else:
                body += "\n" + _align(
                    [rf"{symbol}^{{-1}}(q^{{*}}) &= {layout.numeric_matrix(numbers)}"]
                )
        quantity = Quantity("inverse-jacobian", "InverseJacobian", "the inverse Jacobian", body)
        return Section("inverse", t["inverse"], t["inverse_intro"], (quantity,))

    def section_dynamics(self) -> Section:
        model, layout, t = self.model, self.layout, self.t
        n = model.robot.dof
        # Reflected rotor inertias, where the file gives them, sit on M's diagonal.
        rotors = any(j.link and j.link.motor_inertia != 0 for j in model.robot.joints)
        lagrange = _align(
            [
                r"M(q) &= \sum_{i=1}^{n} \left( m_{i}\, J_{v,i}^{T} J_{v,i} + J_{\omega,i}^{T} "
                r"R_{i} I_{i} R_{i}^{T} J_{\omega,i} \right)"
                + (r" + \operatorname{diag}(I_{a,i})" if rotors else ""),
                r"G(q) &= \frac{\partial P}{\partial q}, \qquad "
                r"P = -\sum_{i=1}^{n} m_{i}\, g^{T} r_{c,i}",
            ]
        )
        christoffel = _align(
            [
                r"C_{kj} &= \sum_{i=1}^{n} \frac{1}{2} \left( "
                r"\frac{\partial M_{kj}}{\partial q_{i}} + \frac{\partial M_{ki}}{\partial q_{j}}"
                r" - \frac{\partial M_{ij}}{\partial q_{k}} \right) \dot{q}_{i}"
            ]
        )
        quantities = [
            Quantity("lagrange", "Lagrange", "M and G by Lagrange", lagrange),
            Quantity(
                "christoffel", "Christoffel", "C from M", christoffel, t["dynamics_christoffel"]
            ),
        ]
        # M, C and G are printed where Lagrange gives them readable (contracted); beyond, their
        # entries run to pages and the section says how the generated code computes them.
        if n > READABLE_DOF:
            quantities.append(
                Quantity(
                    "dynamics-long",
                    "DynamicsLong",
                    "where the equations of motion are",
                    t["dynamics_long"].format(dof=n),
                )
            )
            return Section("dynamics", t["dynamics"], t["dynamics_intro"], tuple(quantities))
        dynamics = model.lagrange
        # Numbers at q* need every inertial value; a file without them leaves symbols.
        numeric = self.q is not None and all(j.link is not None for j in model.robot.joints)
        shown = [
            ("mass-matrix", "MassMatrix", "the mass matrix", "M", dynamics.mass_matrix, True),
            (
                "coriolis-matrix",
                "CoriolisMatrix",
                "the Coriolis matrix",
                "C",
                dynamics.coriolis_matrix,
                False,
            ),
            (
                "gravity-vector",
                "GravityVector",
                "the gravity torques",
                "G",
                dynamics.gravity_vector,
                True,
            ),
        ]
        if any(e != 0 for e in dynamics.friction):
            shown.append(
                (
                    "friction-vector",
                    "FrictionVector",
                    "the friction torques",
                    "F",
                    dynamics.friction,
                    False,
                )
            )
        for key, macro, description, symbol, matrix, with_numbers in shown:
            rows = [str(i) for i in range(1, n + 1)]
            name = _entry_name(symbol) if matrix.cols > 1 else _vector_name(symbol, rows)
            numbers = self.numbers(matrix) if numeric and with_numbers else None
            body = layout.matrix_display(symbol, matrix, name, numbers, where=t["where"])
            text = t[key.replace("-", "_")]
            quantities.append(Quantity(key, macro, description, body, text))
        return Section("dynamics", t["dynamics"], t["dynamics_intro"], tuple(quantities))

    # -- whole document -------------------------------------------------------------------

    def build(self) -> list[Section]:
        builders: dict[str, Callable[[], Section | None]] = {
            "dh": self.section_dh,
            "transforms": self.section_transforms,
            "fk": self.section_fk,
            "euler": self.section_euler,
            "jacobian": self.section_jacobian,
            "det": self.section_det,
            "inverse": self.section_inverse,
            "dynamics": self.section_dynamics,
        }
        sections = []
        for key in self.sections:
            if key in builders:
                section = builders[key]()
                if section is not None:
                    sections.append(section)
        return sections

    def configuration_text(self) -> str:
        if self.q is None:
            return ""
        layout = self.layout
        items = []
        for i, (joint, value) in enumerate(zip(self.model.robot.joints, self.q, strict=True), 1):
            text = f"q_{{{i}}}^{{*}} = {layout.number(value)}"
            if joint.type == "revolute":
                text += rf" = {layout.number(math.degrees(value))}^{{\circ}}"
            items.append(text)
        lines = _pack(items, r",\quad ", self.layout.width)
        return self.t["configuration"] + "\n" + _gather(lines) + "\n" + self.parameter_line()

    def parameter_line(self) -> str:
        robot = self.model.robot
        if not robot.parameters:
            return ""
        values = robot.parameter_values(self.overrides)
        items = [
            f"{self.layout.tex(s)} = {self.layout.number(values[s.name])}"
            for s in robot.parameter_symbols
        ]
        return (
            self.t["parameters_values"]
            + "\n"
            + _gather(_pack(items, r",\quad ", self.layout.width))
        )

    def legend_text(self) -> str:
        legend = self.layout.printer.legend()
        if not legend:
            return ""
        items = [f"{abbreviation} = {definition}" for abbreviation, definition in legend]
        return self.t["legend"] + "\n" + _gather(_pack(items, r",\quad ", self.layout.width))


def _pack(items: Sequence[str], separator: str, width: float) -> list[str]:
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


def _gather(lines: Sequence[str]) -> str:
    return "\\begin{gather*}\n" + " \\\\\n".join(lines) + "\n\\end{gather*}"


def _check_shorthand_names(model: Model) -> None:
    clash = [s.name for s in model.robot.parameter_symbols if re.fullmatch(r"[cs]_?\d+", s.name)]
    if clash:
        raise SymkinError(
            f"--shorthand: parameter(s) {', '.join(clash)} would read like the abbreviations "
            "c_i, s_i of cosines and sines; rename them or leave out --shorthand"
        )


def header_lines(model: Model, what: str, command: str) -> list[str]:
    """The comment lines heading each file (made safe by :func:`comment_text`: a newline in a
    title would otherwise leave the ``%`` comment and run as TeX)."""
    robot = model.robot
    source = comment_text(robot.file or f"robot '{robot.name}' built in Python")
    return [
        f"{what} for robot '{robot.name}' ({comment_text(robot.title) or 'no title'}).",
        f"Generated by symkin from {source}; do not edit.",
        f"Regenerate with: {comment_text(command)}",
    ]


def regenerate_command(
    model: Model,
    sections: Sequence[str],
    shorthand: bool,
    lang: str,
    q: Sequence[float] | None,
    overrides: Mapping[str, float] | None,
) -> str:
    parts = ["symkin latex", model.robot.name]
    if shorthand:
        parts.append("--shorthand")
    if lang != "en":
        parts.append(f"--lang {lang}")
    if q is not None:
        parts.append("--q " + ",".join(repr(float(v)) for v in q))
    for name, value in sorted((overrides or {}).items()):
        parts.append(f"--set {name}={float(value)!r}")
    if tuple(sections) != SECTIONS:
        parts.append("--sections " + ",".join(sections))
    return " ".join(parts)


def latex_files(
    model: Model,
    *,
    sections: Sequence[str] = DEFAULT_SECTIONS,
    shorthand: bool = False,
    lang: str = "en",
    q: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
    text_width_cm: float = TEXT_WIDTH_CM,
) -> dict[str, str]:
    """The LaTeX derivation of ``model``: standalone document, snippets and macros.

    ``sections`` are names from :data:`SECTIONS` (``dynamics``: the equations of motion by
    Lagrange, printed up to three joints); ``shorthand`` prints ``c_{1}``, ``s_{12}`` with a
    legend; ``lang`` is ``"en"`` or ``"de"``; ``q`` (radians / metres) adds numbers at that
    configuration, with parameter values from the robot file updated by ``overrides``.
    Formulas are laid out for a line of ``text_width_cm`` (17 cm: A4 with 2 cm margins; give
    the host document's ``\\textwidth`` when the snippets go into narrower notes).
    Returns ``{"<robot>.tex", "<robot>-macros.tex", "snippets/<quantity>.tex": text}``.
    """
    if lang not in LANGUAGES:
        raise SymkinError(f"--lang must be one of {', '.join(LANGUAGES)}, got {lang!r}")
    chosen = check_sections(sections)
    robot = model.robot
    if q is not None:
        if len(q) != robot.dof:
            raise SymkinError(f"--q needs {robot.dof} values (one per joint), got {len(q)}")
        robot.parameter_values(overrides)  # unknown names or missing values: say so now
        q = tuple(float(v) for v in q)
    if not MIN_TEXT_WIDTH_CM <= text_width_cm <= MAX_TEXT_WIDTH_CM:
        raise SymkinError(
            f"text width must be from {MIN_TEXT_WIDTH_CM:g} to {MAX_TEXT_WIDTH_CM:g} cm, "
            f"got {text_width_cm:g}"
        )
    writer = _Writer(model, chosen, shorthand, lang, q, overrides, text_width_cm)
    sections_built = writer.build()
    configuration = writer.configuration_text()
    legend = writer.legend_text()  # last: every abbreviation has been printed by now
    t = TEXT[lang]
    command = regenerate_command(model, chosen, shorthand, lang, q, overrides)
    intro = t["intro"].format(
        name=robot.name.replace("_", r"\_"),
        convention=t[robot.convention],
        dof=robot.dof,
    )
    geometry = (
        "a4paper,margin=2cm"
        if text_width_cm == TEXT_WIDTH_CM
        else f"a4paper,textwidth={text_width_cm:g}cm,vmargin=2cm"
    )
    document = render(
        "latex/document.tex.j2",
        geometry=geometry,
        header=header_lines(model, "LaTeX derivation", command),
        title=_escape_text(robot.title or robot.name),
        intro=intro,
        configuration=configuration,
        legend=legend,
        sections=sections_built,
    )
    quantities = [quantity for section in sections_built for quantity in section.quantities]
    if legend:
        quantities.insert(0, Quantity("legend", "Legend", "the abbreviations", legend))
    if configuration:
        quantities.insert(
            0,
            Quantity(
                "configuration", "Configuration", "q* and the parameter values", configuration
            ),
        )
    files = {f"{robot.name}.tex": document}
    for quantity in quantities:
        files[f"snippets/{quantity.key}.tex"] = render(
            "latex/snippet.tex.j2",
            header=header_lines(model, f"LaTeX snippet '{quantity.key}'", command),
            body=quantity.body,
        )
    prefix = macro_prefix(robot.name)
    files[f"{robot.name}-macros.tex"] = render(
        "latex/macros.tex.j2",
        header=header_lines(model, "LaTeX macros", command),
        macros=[
            {"name": prefix + q.macro, "description": q.description, "body": q.body}
            for q in quantities
        ],
    )
    return dict(sorted(files.items()))


def _escape_text(text: str) -> str:
    """Plain text for LaTeX (robot titles): unprintable characters as visible escapes, then
    TeX's special characters as text."""
    text = printable(text)
    replacements = {
        "\\": r"\textbackslash{}",
        "&": r"\&",
        "%": r"\%",
        "$": r"\$",
        "#": r"\#",
        "_": r"\_",
        "{": r"\{",
        "}": r"\}",
        "~": r"\textasciitilde{}",
        "^": r"\textasciicircum{}",
    }
    return "".join(replacements.get(c, c) for c in text)

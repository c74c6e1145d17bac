"""Numbers in shown formulas: the fewest digits that give the number back (issue 21).

Expected texts are the numbers as typed into the robot file below (``0.3256``, ``-0.0629``,
``0.15005``), and products worked out by hand (0.3256 * 0.15005 = 0.04885628).
"""

from __future__ import annotations

import json

import pytest
import sympy as sp

from symkin.cli import main
from symkin.emit.formula_text import formula_text, shortest_float
from symkin.emit.latex.printer import KinematicsLatexPrinter

ARM = """
name = "decimals"
convention = "standard"
[[joints]]
type = "revolute"
a = 0.3256
d = -0.0629
[[joints]]
type = "revolute"
a = 0.15005
"""


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (0.3256, "0.3256"),
        (-0.0629, "-0.0629"),
        (0.3256 * 0.15005, "0.04885628"),
        (1e-17, "1e-17"),
        (2.0, "2.0"),
        (1 / 3, "0.333333333333333"),
        (1.5e20, "1.5e20"),
    ],
)
def test_shortest_float(value: float, text: str) -> None:
    assert shortest_float(sp.Float(value)) == text
    assert float(text) == pytest.approx(value, rel=1e-14)


def test_unit_coefficients_are_not_shown() -> None:
    x, y = sp.symbols("x y")
    expr = sp.Float(1.0) * x * y - sp.Float(1.0) * y**2 + sp.Float(0.5) * x
    assert formula_text(expr) == "x*y + 0.5*x - y**2"
    assert sp.simplify(sp.sympify(formula_text(expr)) - expr) == 0


def test_show_prints_numbers_as_typed(tmp_path, capsys) -> None:
    path = tmp_path / "decimals.toml"
    path.write_text(ARM, encoding="utf-8")
    assert main(["show", str(path)]) == 0
    out = capsys.readouterr().out
    assert "0.325600000" not in out and "0.0629000" not in out
    assert "-0.0629" in out and "0.15005" in out
    assert "det J = 0.04885628*sin(q2)" in out
    assert main(["show", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["T"][2][3] == "-0.0629"
    assert sp.sympify(data["det"]) == sp.sympify("0.04885628*sin(q2)")


def test_latex_numbers() -> None:
    q1, q2 = sp.symbols("q1 q2")
    expr = sp.Float(0.3256) * sp.cos(q1) + sp.Float(-0.0629) + sp.Float(1e-17) * q2
    english = KinematicsLatexPrinter([q1, q2]).doprint(expr)
    german = KinematicsLatexPrinter([q1, q2], decimal_separator="comma").doprint(expr)
    assert "0.3256" in english and "- 0.0629" in english and r"1 \cdot 10^{-17}" in english
    assert "0{,}3256" in german and "0{,}0629" in german
    assert "0.3256000" not in english


def test_german_document_keeps_parameter_digits(tmp_path) -> None:
    """The PUMA's d3 = 0.15005 m (Corke's table) must not show as 0.15."""
    out = tmp_path / "puma.tex"
    assert main(["latex", "puma560", "--lang", "de", "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    assert "d_{3} = 0{,}15005" in text


def test_lower_precision_floats_keep_their_own_digits() -> None:
    """``sympy.N(pi/3, 6)`` (the placement table's numbers) is 1.04720, shown as 1.0472."""
    assert shortest_float(sp.N(sp.pi / 3, 6)) == "1.0472"
    assert shortest_float(sp.Float(0.1, 10)) == "0.1"

"""The lecture's Newton path table as text and LaTeX (``symkin ik --table [--latex]``).

The columns "for Gl. (14.15)" hold the increment fed into the next step: row 0 holds
``x_1 - x_0`` (here one fifth of the path, from the inputs alone), row ``i`` holds
``x_{i+1} - x_{i,real}`` (the next row's target minus this row's reached point, both printed in
the table), the end rows ``x_5 - x_{5,real}``.  Reached points are checked against the
independent numeric DH product of ``tests/numeric_dh.py``.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from numeric_dh import reference
from symkin.cli import main
from symkin.emit.latex.number_table import table_number
from symkin.runtime.latex_build import compile_pdf, log_problems

Q0 = np.radians([30.0, 60.0])
END = np.array([1.0, 1.2])


def table_argv(*extra: str) -> list[str]:
    x0 = reference("planar_2r").fk(Q0)[:2, 3]
    return [
        "ik",
        "planar_2r",
        "--path-from",
        f"{float(x0[0])!r},{float(x0[1])!r}",
        "--q0",
        "30deg,60deg",
        "--to",
        "1,1.2",
        "--steps",
        "5",
        "--table",
        *extra,
    ]


def test_text_columns_hold_the_increment_for_the_next_step(capsys) -> None:
    assert main(table_argv()) == 0
    lines = capsys.readouterr().out.splitlines()[2:]
    rows = [[float(v) for v in line.split()[1:]] for line in lines]
    labels = [line.split()[0] for line in lines]
    x0 = reference("planar_2r").fk(Q0)[:2, 3]
    # Row 0: x_1 - x_0, a fifth of the path.
    np.testing.assert_allclose(rows[0][6:8], (END - x0) / 5, rtol=1e-2)
    for i in range(1, 5):
        q = np.array(rows[i][2:4])
        real = reference("planar_2r").fk(q)[:2, 3]
        np.testing.assert_allclose(rows[i][4:6], real, atol=2e-6)
        np.testing.assert_allclose(
            rows[i][6:8], np.array(rows[i + 1][0:2]) - real, rtol=1e-3, atol=2e-6
        )
    for i, label in enumerate(labels[5:], start=5):
        assert label == "5" or label.startswith("5")
        real = reference("planar_2r").fk(np.array(rows[i][2:4]))[:2, 3]
        # q is printed to 1e-6 rad: the recomputed point is good to about 2e-6 m.
        np.testing.assert_allclose(rows[i][6:8], END - real, atol=5e-6)


def test_latex_table_layout(capsys) -> None:
    assert main(table_argv("--latex", "--lang", "de")) == 0
    tex = capsys.readouterr().out
    heading = next(line for line in tex.splitlines() if line.startswith("$i$"))
    cells = [c.strip() for c in heading.rstrip("\\ ").split("&")]
    assert cells == [
        "$i$",
        "$x_{i}$",
        "$y_{i}$",
        "$q_{1}$",
        "$q_{2}$",
        r"$x_{i,\mathrm{real}}$",
        r"$y_{i,\mathrm{real}}$",
        r"$\Delta x$",
        r"$\Delta y$",
    ]
    assert r"\multicolumn{2}{c}{für Gl. (14.15)}" in tex
    labels = re.findall(r"^(\w+) & ", tex, flags=re.M)
    assert labels[:7] == ["0", "1", "2", "3", "4", "5", "5a"]
    assert "{,}" in tex and "." not in tex.split(r"\midrule")[1].split(r"\bottomrule")[0]


def test_table_number() -> None:
    assert table_number(0.15005) == "0.15005"
    assert table_number(-1.5707963) == "-1.5708"
    assert table_number(3.2e-5) == r"3.2 \cdot 10^{-5}"
    assert table_number(-0.0) == "0"
    assert table_number(0.25, decimal_comma=True) == "0{,}25"


def test_latex_flag_needs_the_table(capsys) -> None:
    argv = [a for a in table_argv("--latex") if a != "--table"]
    assert main(argv) == 2
    assert "--latex" in capsys.readouterr().err


@pytest.mark.needs_latex
@pytest.mark.slow
def test_latex_table_compiles(capsys, tmp_path) -> None:
    assert main(table_argv("--latex")) == 0
    tex = tmp_path / "path_table.tex"
    tex.write_text(capsys.readouterr().out, encoding="utf-8")
    log = compile_pdf(tex).with_suffix(".log").read_text(encoding="utf-8", errors="replace")
    assert not log_problems(log).errors

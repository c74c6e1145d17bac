"""``symkin check``: worked examples recomputed entry by entry (issue 21).

The examples in ``examples/worked`` carry values worked out by hand or by an independent
NumPy implementation (their comments say how); ``tests/data/worked/mistyped.toml`` has two
entries typed wrong on purpose, whose right values are worked out in its comments.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from symkin.cli import main
from symkin.errors import SymkinError
from symkin.solve.check import check_example, printed_number
from symkin.solve.check.printed import with_neighbours

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted((ROOT / "examples" / "worked").glob("*.toml"))
MISTYPED = ROOT / "tests" / "data" / "worked" / "mistyped.toml"
SCARA = 'robot = "scara"\n[[check]]\n'


@pytest.mark.parametrize(
    ("item", "value", "tolerance"),
    [
        ("0.8660", 0.866, 5e-5),
        ("-1.5", -1.5, 0.05),
        (0.25, 0.25, 5e-3),
        ("1.2e-3", 1.2e-3, 5e-5),
        ("0,0633", 0.0633, 5e-5),  # German decimal comma
        (3, 3.0, 0.5),
    ],
)
def test_printed_tolerance_is_half_the_last_digit(item, value, tolerance) -> None:
    number = printed_number(item, "x")
    assert number.value == pytest.approx(value)
    assert number.tolerance == pytest.approx(tolerance)


def test_integers_among_decimals_are_exact_to_their_neighbours() -> None:
    numbers = with_neighbours([printed_number(v, "x") for v in (0, "0.8660", 1)])
    assert [n.tolerance for n in numbers] == pytest.approx([5e-5, 5e-5, 5e-5])
    alone = with_neighbours([printed_number(v, "x") for v in (0, 1)])
    assert [n.tolerance for n in alone] == pytest.approx([5e-5, 5e-5])


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_worked_examples_match(path: Path, capsys) -> None:
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("match")
    assert "do not match" not in out


def test_mismatches_are_named_entry_by_entry_with_corrected_latex(capsys) -> None:
    assert main(["check", str(MISTYPED)]) == 1
    out = capsys.readouterr().out
    assert "(1, 4): printed 0.2851, symkin 0.281458" in out
    assert "printed 0.0731, symkin 0.0633281" in out
    assert "2 of 3 checks do not match" in out
    # German decimal commas; the corrected matrix keeps the printed layout (3 x 4).
    assert r"\begin{bmatrix} 0 & -1 & 0 & 0{,}2815 \\ 1 & 0 & 0 & 0{,}3875" in out
    assert "      0{,}0633" in out
    assert main(["check", str(MISTYPED), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["matches"] is False
    assert [c["matches"] for c in data["checks"]] == [False, False, True]
    wrong = [e for e in data["checks"][0]["entries"] if not e["matches"]]
    assert [(e["row"], e["column"]) for e in wrong] == [(1, 4)]


def test_a_value_just_outside_half_a_digit_fails(tmp_path) -> None:
    """det = 0.0633281: "0.06333" (diff 1.9e-6 < 5e-6) passes, "0.06334" (7e-6) fails."""
    for printed, matches in (("0.06333", True), ("0.06334", False)):
        path = tmp_path / "det.toml"
        path.write_text(
            f'robot = "scara"\n[[check]]\nquantity = "det"\nq = [30, 60, 0.1]\n'
            f'printed = "{printed}"\n',
            encoding="utf-8",
        )
        assert check_example(str(path)).matches is matches


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('robot = "scara"\n', "no \\[\\[check"),
        (SCARA + 'quantity = "torque"\nq = [0, 0, 0]\nprinted = 1\n', "quantity"),
        ('robot = "scara"\n[[check]]\nquantity = "det"\nprinted = 1\n', "needs 'q'"),
        (SCARA + 'quantity = "det"\nq = [0, 0, 0]\nprinted = "x"\n', "not a number"),
        ('[[check]]\nquantity = "det"\nq = [0, 0, 0]\nprinted = 1\n', "give 'robot'"),
        ('robot = "scara"\n[[check]]\nquantity = "T"\nq = [0, 0]\nprinted = 1\n', "3 joints"),
        ('robot = "scara"\nbogus = 1\n', "unknown key"),
        ("robot = [", "not valid TOML"),
    ],
)
def test_bad_files_are_one_clear_error(tmp_path, capsys, text: str, message: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SymkinError, match=message):
        check_example(str(path))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("symkin: error:") and "Traceback" not in err

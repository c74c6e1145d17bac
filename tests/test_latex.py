"""The LaTeX backend: real pdflatex runs, and the formulas read back equal the model.

* Every standalone document (SCARA and PUMA 560; plain and shorthand; English and German)
  compiles with pdflatex; its log has no errors and at most ``MAX_OVERFULL_HBOXES`` overfull
  hboxes, none wider than ``MAX_OVERFULL_PT`` (today there are none), and no overfull vboxes.
* Content: entries of ``T``, every Jacobian column and the determinant are parsed back with
  SymPy's own LaTeX parser (``sympy.parsing.latex.parse_latex``, independent of our printer)
  and compared with the model numerically at random configurations; in shorthand documents
  the abbreviations are replaced by the legend's own definitions, parsed the same way, so the
  legend is checked too.
* The legend lists exactly the abbreviations the document uses.
* Snippets and macros compile when ``\\input`` into a minimal host document.
* With ``q``, the numbers printed equal :func:`symkin.derive.numeric.numeric_function`.
* The dynamics section: ``M``, ``C`` and ``G`` of Spong's two-link arm parsed back equal the
  textbook's closed form; those of the planar 2R arm with symbolic inertia equal the
  Newton–Euler equations (another method); both documents compile, in English and German.

pdflatex comes from TeX Live (Debian: texlive-latex-base, texlive-latex-recommended);
``scripts/install-latex.sh`` installs it when missing, as ``make test`` does.
"""

from __future__ import annotations

import dataclasses
import re
import subprocess
from pathlib import Path

# SymPy's LaTeX parser needs the ANTLR runtime, a test extra (antlr4-python3-runtime==4.11.*):
# without it these tests fail at import, they are not skipped.
import antlr4  # noqa: F401
import numpy as np
import pytest
import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.parsing.latex import parse_latex

from numeric_dh import model, without_inertials
from symkin.derive import Model, derive
from symkin.derive.numeric import numeric_function
from symkin.emit.latex import (
    SECTIONS,
    check_sections,
    inertial_symbol_names,
    latex_files,
    macro_prefix,
)
from symkin.emit.latex.printer import Abbreviation, KinematicsLatexPrinter, latex_width
from symkin.errors import RobotError, SymkinError
from symkin.io import load_robot, robot_from_toml
from symkin.runtime.latex_build import compile_pdf, log_problems

pytestmark = pytest.mark.needs_latex

MAX_OVERFULL_HBOXES = 1
MAX_OVERFULL_PT = 3.0
ROBOTS = ("scara", "puma560")
Q_STAR = {"scara": (0.5, -0.7, 0.12), "puma560": (0.3, -0.4, 0.9, 0.2, -1.1, 0.5)}
SEED = 20240607
CONTINUATION = r"&\quad"


@pytest.fixture(scope="module")
def models() -> dict[str, Model]:
    return {name: model(name) for name in ROBOTS}


def write(root: Path, files: dict[str, str]) -> None:
    for relative, text in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


@pytest.fixture(scope="module")
def built(models, tmp_path_factory):
    """``built(robot, shorthand, lang, with_q)`` -> (files, folder, pdf), compiled once each."""
    cache: dict[tuple, tuple[dict[str, str], Path, Path]] = {}

    def build(robot: str, shorthand: bool, lang: str, with_q: bool = False):
        key = (robot, shorthand, lang, with_q)
        if key not in cache:
            files = latex_files(
                models[robot],
                shorthand=shorthand,
                lang=lang,
                q=Q_STAR[robot] if with_q else None,
            )
            folder = tmp_path_factory.mktemp(f"{robot}-{'sh' if shorthand else 'plain'}-{lang}")
            write(folder, files)
            pdf = compile_pdf(folder / f"{robot}.tex")
            cache[key] = (files, folder, pdf)
        return cache[key]

    return build


VARIANTS = [
    (robot, shorthand, lang)
    for robot in ROBOTS
    for shorthand in (False, True)
    for lang in ("en", "de")
]


def assert_clean_log(log_path: Path) -> None:
    problems = log_problems(log_path.read_text(errors="replace"))
    assert not problems.errors, problems.errors
    assert len(problems.overfull_hboxes) <= MAX_OVERFULL_HBOXES, problems.overfull_hboxes
    assert all(pt <= MAX_OVERFULL_PT for pt in problems.overfull_hboxes), problems
    assert not problems.overfull_vboxes, problems.overfull_vboxes


# ---------------------------------------------------------------- reading the LaTeX back


def parameter_and_joint_symbols(model: Model) -> dict[str, sp.Symbol]:
    """``"q_{1}" -> q1``, ``"L_{1}" -> L1``: how parse_latex names a printed symbol."""
    names = {}
    for symbol in (*model.q, *model.robot.parameter_symbols):
        match = re.fullmatch(r"([A-Za-z]+)(\d+)", symbol.name)
        printed = f"{match.group(1)}_{{{match.group(2)}}}" if match else symbol.name
        names[printed] = symbol
    names.update({f"Z_{{{900 + k}}}": s for k, s in enumerate(swapped_symbols(model))})
    return names


def swapped_symbols(model: Model) -> dict[sp.Symbol, str]:
    """Printed names parse_latex cannot read (``\\dot{q}_{1}``, ``c_{x,1}``), by symbol."""
    names = {s: rf"\dot{{q}}_{{{i}}}" for i, s in enumerate(model.dq, 1)}
    return names | inertial_symbol_names(model.robot)


def read_expression(text: str, model: Model, legend: dict[str, sp.Expr]) -> sp.Expr:
    """A printed formula parsed by SymPy and expressed in the model's symbols."""
    # parse_latex misreads \dot{q}_{1} and subscripts with commas (c_{x,1}): each such name
    # is swapped for a plain Z_{900 + k} first (parameter_and_joint_symbols maps it back).
    for k, printed in enumerate(swapped_symbols(model).values()):
        text = text.replace(printed, f"Z_{{{900 + k}}}")
    cleaned = (
        text.replace("{,}", ".")  # the German decimal comma
        .replace(r"&\quad", " ")
        .replace("&", " ")
        .replace("{} ", " ")
        .replace(r"\bigl(", r"\left(")
        .replace(r"\bigr)", r"\right)")
    )
    expr = parse_latex(cleaned)
    # parse_latex reads "a_{2} \left(x\right)" as a function a_{2} applied to x.
    expr = expr.replace(
        lambda e: isinstance(e, AppliedUndef) and len(e.args) == 1,
        lambda e: sp.Symbol(e.func.__name__) * e.args[0],
    )
    symbols = parameter_and_joint_symbols(model)
    replacements: dict[sp.Symbol, sp.Expr] = {}
    for symbol in expr.free_symbols:
        if symbol.name == "pi":
            replacements[symbol] = sp.pi
        elif symbol.name in legend:
            replacements[symbol] = legend[symbol.name]
        elif symbol.name in symbols:
            replacements[symbol] = symbols[symbol.name]
        else:
            raise AssertionError(f"unexpected symbol {symbol.name!r} in {text!r}")
    return expr.xreplace(replacements)


def legend_of(files: dict[str, str], model: Model) -> dict[str, sp.Expr]:
    """``{"c_{12}": cos(q1 + q2), ...}`` from the legend snippet, both sides parsed."""
    if "snippets/legend.tex" not in files:
        return {}
    body = gather_body(files["snippets/legend.tex"])
    legend = {}
    for item in re.split(r",\\quad |\\\\", body):
        if item.strip():
            name, definition = item.split(" = ")
            legend[name.strip()] = read_expression(definition, model, {})
    return legend


def gather_body(text: str) -> str:
    return text.split("\\begin{gather*}", 1)[1].split("\\end{gather*}", 1)[0]


def align_rows(text: str) -> list[tuple[str, str]]:
    """``(name, formula)`` of every ``name &= formula`` row, continuation lines joined."""
    rows: list[tuple[str, str]] = []
    for block in re.findall(r"\\begin\{align\*\}\n(.*?)\n\\end\{align\*\}", text, re.S):
        for row in block.split(" \\\\\n"):
            if row.startswith(CONTINUATION) and rows:
                name, formula = rows[-1]
                rows[-1] = (name, formula + " " + row.removeprefix(CONTINUATION))
            elif " &= " in row:
                name, formula = row.split(" &= ", 1)
                rows.append((name, formula))
    return rows


def matrix_entries(text: str, lhs: str) -> list[list[str]]:
    """Entries of the matrix displayed as ``lhs = \\begin{bmatrix} ... \\end{bmatrix}``."""
    start = text.index(f"{lhs} = \\begin{{bmatrix}}") + len(f"{lhs} = \\begin{{bmatrix}}")
    body = text[start : text.index("\\end{bmatrix}", start)]
    return [[cell.strip() for cell in row.split(" & ")] for row in body.split(" \\\\ ")]


def matrix_formulas(text: str, lhs: str) -> list[list[str]]:
    """Like :func:`matrix_entries`, with named entries replaced by their listed formulas."""
    listed = dict(align_rows(text))
    return [[listed.get(cell, cell) for cell in row] for row in matrix_entries(text, lhs)]


def forward_kinematics_lhs(text: str) -> str:
    """``T = {}^{0}T_{n} = {}^{0}T_{n-1}\\, A_{n}``, the left-hand side of the T display."""
    match = re.search(r"^(T = \{\}\^\{0\}T_\{\d+\} = [^=]*?) = \\begin\{bmatrix\}", text, re.M)
    assert match, text[:500]
    return match.group(1)


def numbers_in(cell: str) -> float:
    text = cell.replace("{,}", ".")
    match = re.fullmatch(r"(-?[\d.]+) \\cdot 10\^\{(-?\d+)\}", text)
    return float(match.group(1)) * 10 ** int(match.group(2)) if match else float(text)


def random_states(model: Model, count: int = 3) -> list[np.ndarray]:
    rng = np.random.default_rng(SEED)
    return [rng.uniform(-np.pi, np.pi, model.robot.dof) for _ in range(count)]


def assert_same_function(model: Model, printed: sp.Expr, expected: sp.Expr, what: str) -> None:
    for q in random_states(model):
        got = numeric_function(model, printed)(q)
        want = numeric_function(model, expected)(q)
        assert np.allclose(got, want, atol=1e-9), f"{what} at q={q}: {got} != {want}"


# ---------------------------------------------------------------- compiling


@pytest.mark.parametrize(("robot", "shorthand", "lang"), VARIANTS)
def test_standalone_document_compiles_cleanly(built, robot, shorthand, lang):
    files, folder, pdf = built(robot, shorthand, lang)
    assert pdf.stat().st_size > 10_000
    assert_clean_log(folder / f"{robot}.log")
    document = files[f"{robot}.tex"]
    assert "\\begin{document}" in document and document.rstrip().endswith("\\end{document}")
    assert ("Abbreviations" in document or "Abk" in document) == shorthand
    assert ("Vorw" in document) == (lang == "de")


@pytest.mark.parametrize("robot", ROBOTS)
def test_document_with_numbers_compiles_and_renders(built, robot, tmp_path):
    _, folder, pdf = built(robot, True, "en", True)
    assert_clean_log(folder / f"{robot}.log")
    subprocess.run(
        ["pdftoppm", "-png", "-r", "40", "-f", "1", "-l", "1", str(pdf), str(tmp_path / "p")],
        check=True,
    )
    assert any(p.stat().st_size > 1000 for p in tmp_path.glob("p*.png"))


def test_snippets_and_macros_compile_in_a_host_document(built):
    files, folder, _ = built("puma560", True, "de")
    prefix = macro_prefix("puma560")
    macros = re.findall(r"\\newcommand\{\\(\w+)\}", files["puma560-macros.tex"])
    assert macros and all(m.startswith(prefix) for m in macros)
    snippets = sorted(p for p in files if p.startswith("snippets/"))
    host = "\n".join(
        [
            r"\documentclass[11pt,a4paper]{article}",
            r"\usepackage[a4paper,margin=2cm]{geometry}",
            r"\usepackage{amsmath,booktabs}",
            r"\allowdisplaybreaks",
            r"\input{puma560-macros}",
            r"\begin{document}",
            r"\section{Snippets}",
            *(rf"\input{{{p.removesuffix('.tex')}}}" for p in snippets),
            r"\section{Macros}",
            *(rf"\{m}" for m in macros),
            r"\end{document}",
        ]
    )
    (folder / "host.tex").write_text(host, encoding="utf-8")
    compile_pdf(folder / "host.tex")
    assert_clean_log(folder / "host.log")


def test_compile_pdf_reports_latex_errors(tmp_path):
    broken = tmp_path / "broken.tex"
    broken.write_text("\\documentclass{article}\\begin{document}\\undefinedmacro\\end{document}\n")
    with pytest.raises(SymkinError, match=r"Undefined control sequence"):
        compile_pdf(broken)


def test_compile_pdf_says_how_to_install_pdflatex(tmp_path, monkeypatch):
    import symkin.runtime.latex_build as latex_build

    monkeypatch.setattr(latex_build, "pdflatex_path", lambda: None)
    (tmp_path / "x.tex").write_text("\\documentclass{article}\n")
    with pytest.raises(SymkinError, match="texlive-latex-base"):
        compile_pdf(tmp_path / "x.tex")


def test_log_problems_reads_errors_and_overfull_boxes():
    log = (
        "Overfull \\hbox (12.5pt too wide) in paragraph at lines 3--4\n"
        "Overfull \\vbox (1.0pt too high) has occurred while \\output is active\n"
        "! Undefined control sequence.\n"
    )
    problems = log_problems(log)
    assert problems.errors == ("! Undefined control sequence.",)
    assert problems.overfull_hboxes == (12.5,)
    assert problems.overfull_vboxes == (1.0,)


# ---------------------------------------------------------------- content


@pytest.mark.parametrize(("robot", "shorthand"), [(r, s) for r in ROBOTS for s in (False, True)])
def test_formulas_parse_back_to_the_model(built, models, robot, shorthand):
    model = models[robot]
    files, _, _ = built(robot, shorthand, "en")
    legend = legend_of(files, model)
    assert bool(legend) == shorthand

    fk = files["snippets/forward-kinematics.tex"]
    cells = matrix_formulas(fk, forward_kinematics_lhs(fk))
    for j in range(3):
        for k in range(4):
            printed = read_expression(cells[j][k], model, legend)
            expected = model.forward_kinematics[j, k]
            assert_same_function(model, printed, expected, f"T[{j},{k}]")

    for i in range(1, model.robot.dof + 1):
        column = files[f"snippets/jacobian-column-{i}.tex"]
        cells = matrix_formulas(column, f"J_{{{i}}}")
        printed = sp.Matrix([read_expression(c[0], model, legend) for c in cells])
        assert_same_function(model, printed, model.geometric_jacobian[:, i - 1], f"J_{i}")

    ((_, formula),) = align_rows(files["snippets/determinant.tex"])
    printed = read_expression(formula, model, legend)
    assert_same_function(model, printed, model.determinant(), "det J")
    assert printed.is_Mul or robot == "scara"  # the factored form survives printing


ARM_2R = Path(__file__).resolve().parents[1] / "examples" / "arm_2r.toml"


def spong_two_link(q, dq, length=0.5, mass=1.0, g=9.81):
    """M, C, G of the planar elbow arm (Spong, Hutchinson, Vidyasagar, *Robot Modeling and
    Control*, 2006, Sec. 7.4.2) with uniform rods: centres of mass at l/2, I = m l^2 / 12."""
    l1 = l2 = length
    lc1, lc2 = l1 / 2, l2 / 2
    i1 = i2 = mass * length**2 / 12
    c2, s2 = np.cos(q[1]), np.sin(q[1])
    d11 = mass * lc1**2 + mass * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + i1 + i2
    d12 = mass * (lc2**2 + l1 * lc2 * c2) + i2
    d22 = mass * lc2**2 + i2
    h = -mass * l1 * lc2 * s2
    coriolis = np.array([[h * dq[1], h * dq[1] + h * dq[0]], [-h * dq[0], 0.0]])
    g1 = (mass * lc1 + mass * l1) * g * np.cos(q[0]) + mass * lc2 * g * np.cos(q[0] + q[1])
    g2 = mass * lc2 * g * np.cos(q[0] + q[1])
    return np.array([[d11, d12], [d12, d22]]), coriolis, np.array([g1, g2])


def printed_dynamics(files: dict[str, str], model: Model):
    """M, C, G of the dynamics snippets, parsed back (named entries replaced by theirs)."""
    matrices = []
    for key, lhs in (("mass-matrix", "M"), ("coriolis-matrix", "C"), ("gravity-vector", "G")):
        cells = matrix_formulas(files[f"snippets/{key}.tex"], lhs)
        matrices.append(sp.Matrix([[read_expression(c, model, {}) for c in row] for row in cells]))
    return matrices


@pytest.mark.parametrize("lang", ["en", "de"])
def test_dynamics_of_spongs_two_link_arm_read_back_as_the_textbook(tmp_path, lang):
    model = derive(load_robot(ARM_2R))
    q_star = (0.4, -1.1)
    files = latex_files(model, sections=["dynamics"], lang=lang, q=q_star)
    write(tmp_path, files)
    assert_clean_log(compile_pdf(tmp_path / "arm_2r.tex").with_suffix(".log"))
    mass, coriolis, gravity = printed_dynamics(files, model)
    rng = np.random.default_rng(SEED)
    for _ in range(4):
        q, dq = rng.uniform(-np.pi, np.pi, (2, 2))
        expected = spong_two_link(q, dq)
        for printed, want, what in zip((mass, coriolis, gravity), expected, "MCG", strict=True):
            got = numeric_function(model, printed)(q, dq)
            np.testing.assert_allclose(got.reshape(want.shape), want, atol=1e-12, err_msg=what)
    # The numbers at q* are the textbook's too.
    expected_mass, _, expected_gravity = spong_two_link(np.array(q_star), np.zeros(2))
    for key, lhs, want in (
        ("mass-matrix", "M", expected_mass),
        ("gravity-vector", "G", expected_gravity),
    ):
        start = files[f"snippets/{key}.tex"].index(f"{lhs}(q^{{*}}) = ")
        cells = matrix_entries(files[f"snippets/{key}.tex"][start:], f"{lhs}(q^{{*}})")
        got = np.array([[numbers_in(c) for c in row] for row in cells]).reshape(want.shape)
        np.testing.assert_allclose(got, want, atol=1e-4)


def test_dynamics_with_symbolic_inertia_read_back_as_newton_euler(tmp_path):
    # The planar 2R file without its inertial data: M, C, G print in m_{i}, c_{x,i}, I_{zz,i}.
    # Its gravity is along -z, normal to the plane of motion (G = 0); along -y here, so the
    # printed G has something to be compared.
    bare = robot_from_toml(without_inertials("planar_2r"), "planar_2r.toml")
    robot = dataclasses.replace(bare, gravity=(0, -9.81, 0))
    model = derive(robot)
    files = latex_files(model, sections=["dynamics"])
    write(tmp_path, files)
    assert_clean_log(compile_pdf(tmp_path / "planar_2r.tex").with_suffix(".log"))
    assert "c_{x,1}" in files["snippets/mass-matrix.tex"]
    printed = printed_dynamics(files, model)
    newton_euler = model.newton_euler
    expected = [
        newton_euler.expanded(m)
        for m in (
            newton_euler.mass_matrix,
            newton_euler.coriolis_matrix,
            newton_euler.gravity_vector,
        )
    ]
    assert any(g != 0 for g in expected[2])
    rng = np.random.default_rng(SEED)
    inertial = {s: rng.uniform(0.5, 2.0) for s in inertial_symbol_names(model.robot)}
    for got, want, what in zip(printed, expected, "MCG", strict=True):
        got = got.xreplace(inertial).reshape(*want.shape)
        want = want.xreplace(inertial)
        for q in random_states(model):
            dq = -0.5 * q
            np.testing.assert_allclose(
                numeric_function(model, got)(q, dq),
                numeric_function(model, want)(q, dq),
                atol=1e-10,
                err_msg=what,
            )


def test_scara_inverse_is_adjugate_over_determinant(built, models):
    model = models["scara"]
    files, _, _ = built("scara", False, "en")
    text = files["snippets/inverse-jacobian.tex"]
    cells = matrix_formulas(text, r"\operatorname{adj} J_{\mathrm{task}}")
    adjugate = sp.Matrix([[read_expression(c, model, {}) for c in row] for row in cells])
    assert_same_function(
        model, adjugate / model.determinant(), model.inverse_task_jacobian(), "adj J / det J"
    )


def test_singular_configurations_are_those_of_the_model(built, models):
    model = models["puma560"]
    files, _, _ = built("puma560", False, "en")
    rows = align_rows(files["snippets/singularities.tex"])
    printed = {
        (
            read_expression(lhs, model, {}),
            read_expression(rhs.split(r" \qquad")[0], model, {}),
        )
        for lhs, rhs in rows
    }
    expected = {(c.lhs, c.rhs) for c in model.singular_configurations()}
    assert len(printed) == len(expected)
    for lhs, rhs in expected:
        assert any(sp.simplify(lhs - a) == 0 and sp.simplify(rhs - b) == 0 for a, b in printed)


@pytest.mark.parametrize("robot", ROBOTS)
def test_legend_lists_exactly_the_abbreviations_used(built, robot):
    files, _, _ = built(robot, True, "en")
    document = files[f"{robot}.tex"]
    legend_text = files["snippets/legend.tex"]
    legend_body = gather_body(legend_text)
    listed = re.findall(r"([cs]_\{[\d,]+\}) = ", legend_body)
    assert len(listed) == len(set(listed))
    body = document.replace(legend_body, "")
    used = set(re.findall(r"(?<![A-Za-z\\])([cs]_\{[\d,]+\})", body))
    assert set(listed) == used
    assert document.count(legend_body) == 1  # stated once
    plain, _, _ = built(robot, False, "en")
    assert not re.search(r"(?<![A-Za-z\\])[cs]_\{\d", plain[f"{robot}.tex"])


@pytest.mark.parametrize(("robot", "lang"), [("scara", "en"), ("puma560", "de")])
def test_numbers_at_q_equal_the_reference_evaluator(built, models, robot, lang):
    model = models[robot]
    q = np.array(Q_STAR[robot])
    files = latex_files(model, shorthand=True, lang=lang, q=Q_STAR[robot])
    fk = files["snippets/forward-kinematics.tex"]
    cells = matrix_entries(fk, "T(q^{*})")
    printed = np.array([[numbers_in(c) for c in row] for row in cells])
    assert np.allclose(printed, numeric_function(model, model.forward_kinematics)(q), atol=6e-5)
    for i in range(1, model.robot.dof + 1):
        column = files[f"snippets/jacobian-column-{i}.tex"]
        cells = matrix_entries(column, f"J_{{{i}}}(q^{{*}})")
        printed = np.array([numbers_in(c[0]) for c in cells])
        expected = numeric_function(model, model.geometric_jacobian[:, i - 1])(q).ravel()
        assert np.allclose(printed, expected, atol=6e-5)
    ((_, formula),) = align_rows(files["snippets/determinant.tex"])
    value = numbers_in(formula.rsplit(" = ", 1)[1])
    expected = float(numeric_function(model, model.determinant())(q))
    assert value == pytest.approx(expected, abs=6e-5)
    assert (
        f"q_{{1}}^{{*}} = {Q_STAR[robot][0]}".replace(".", "{,}" if lang == "de" else ".")
        in (files[f"{robot}.tex"])
    )


def test_build_with_numbers(built):
    # The compiled variants with numbers are covered above; this checks their structure.
    files, _, _ = built("scara", True, "en", True)
    assert "snippets/configuration.tex" in files
    assert r"A_{1}(q^{*}) = \begin{bmatrix}" in files["snippets/link-transform-1.tex"]


# ---------------------------------------------------------------- layout decisions


def test_wide_matrices_get_named_entries_and_narrow_ones_do_not(models):
    files = latex_files(models["puma560"])
    fk = files["snippets/forward-kinematics.tex"]
    assert "T_{11} &= " in fk  # named and listed in an align* block
    assert matrix_entries(fk, forward_kinematics_lhs(fk))[0][0] == "T_{11}"
    link = files["snippets/link-transform-1.tex"]
    assert "a^{(1)}_{" not in link and "align*" not in link
    shorthand = latex_files(models["puma560"], shorthand=True)
    assert "T_{11} &=" in shorthand["snippets/forward-kinematics.tex"]


def test_long_entries_are_broken_into_lines_that_fit(models):
    files = latex_files(models["puma560"])
    fk = files["snippets/forward-kinematics.tex"]
    rows = [
        r
        for block in re.findall(r"\\begin\{align\*\}\n(.*?)\n\\end\{align\*\}", fk, re.S)
        for r in block.split(" \\\\\n")
    ]
    assert any(r.startswith(r"&\quad {} ") for r in rows)
    assert max(latex_width(r) for r in rows) <= 72


def test_inverse_of_a_six_joint_robot_is_described_not_printed(models):
    files = latex_files(models["puma560"], sections=["inverse"])
    text = files["snippets/inverse-jacobian.tex"]
    assert "too long to print" in text and "bmatrix" not in text


# ---------------------------------------------------------------- printer


@pytest.fixture(scope="module")
def symbols():
    q = sp.symbols("q1:4", real=True)
    dq = sp.symbols("dq1:4", real=True)
    ddq = sp.symbols("ddq1:4", real=True)
    return q, dq, ddq


def test_printer_decorates_joint_symbols_and_parameters(symbols):
    q, dq, ddq = symbols
    printer = KinematicsLatexPrinter(q, dq, ddq)
    assert printer.doprint(q[0]) == "q_{1}"
    assert printer.doprint(dq[1]) == r"\dot{q}_{2}"
    assert printer.doprint(ddq[2]) == r"\ddot{q}_{3}"
    assert printer.doprint(sp.Symbol("L1")) == "L_{1}"
    assert printer.doprint(sp.Symbol("d3")) == "d_{3}"
    assert printer.doprint(sp.Symbol("alpha")) == r"\alpha"
    assert printer.doprint(sp.Symbol("theta2")) == r"\theta_{2}"


def test_printer_without_shorthand_matches_sympy(symbols):
    q, _, _ = symbols
    names = {s: f"q_{{{i}}}" for i, s in enumerate(q, 1)}
    L1 = sp.Symbol("L1")
    for expr in (
        L1 * sp.cos(q[0]) + sp.sin(q[0] + q[1]) ** 2,
        sp.sin(2 * q[0]) / L1,
        -sp.cos(q[0] + q[1] + q[2]) * L1,
    ):
        assert KinematicsLatexPrinter(q).doprint(expr) == sp.latex(expr, symbol_names=names)


def test_shorthand_abbreviates_unit_sums_of_joint_variables_only(symbols):
    q, _, _ = symbols
    printer = KinematicsLatexPrinter(q, shorthand=True)
    assert printer.doprint(sp.cos(q[0])) == "c_{1}"
    assert printer.doprint(sp.sin(q[0] + q[1])) == "s_{12}"
    assert printer.doprint(sp.cos(q[0] + q[1] + q[2]) ** 2) == "c_{123}^{2}"
    assert printer.doprint(sp.sin(2 * q[0])) == r"\sin{\left(2 q_{1} \right)}"
    assert printer.doprint(sp.sin(q[0] - q[1])) == r"\sin{\left(q_{1} - q_{2} \right)}"
    assert printer.doprint(sp.cos(sp.Symbol("phi"))) == r"\cos{\left(\phi \right)}"
    assert printer.used == {
        Abbreviation((1,), "c"),
        Abbreviation((1, 2), "s"),
        Abbreviation((1, 2, 3), "c"),
    }
    legend = dict(printer.legend())
    assert list(legend) == ["c_{1}", "s_{12}", "c_{123}"]
    assert legend["s_{12}"] == sp.latex(sp.sin(sp.Symbol("q_{1}") + sp.Symbol("q_{2}")))


def test_shorthand_indices_of_ten_and_more_are_separated():
    q = sp.symbols("q1:12", real=True)
    printer = KinematicsLatexPrinter(q, shorthand=True)
    assert printer.doprint(sp.sin(q[0] + q[10])) == "s_{1,11}"


def test_atan2_prints_as_atan2(symbols):
    q, _, _ = symbols
    text = KinematicsLatexPrinter(q).doprint(sp.atan2(q[1], q[0]))
    assert text == r"\operatorname{atan2}\left(q_{2}, q_{1}\right)"


def test_width_measure_orders_formulas_sensibly():
    assert latex_width("q_{1}") < latex_width(r"\sin{\left(q_{1} \right)}")
    assert latex_width(r"\frac{a}{b + c + d}") == pytest.approx(latex_width("b + c + d") + 0.4)
    assert latex_width(r"L_{1} c_{1} + L_{2} c_{12}") < 20


# ---------------------------------------------------------------- options


def test_sections_are_validated_and_large_robots_get_no_dynamics_matrices(models):
    assert check_sections(["det", "dh"]) == ("dh", "det")
    assert check_sections(SECTIONS) == SECTIONS
    with pytest.raises(SymkinError, match="unknown section"):
        check_sections(["dh", "kinetics"])
    files = latex_files(models["scara"], sections=["det", "dynamics"])
    document = files["scara.tex"]
    assert document.count("\\section{") == 2 and "Equations of motion" in document
    assert "M = \\begin{bmatrix}" in document  # three joints: the matrices are printed
    files = latex_files(models["puma560"], sections=["dynamics"])
    document = files["puma560.tex"]
    # Six joints: the general formulas and a pointer to the generated code, no matrices.
    assert "run to pages" in document and "M = \\begin{bmatrix}" not in document
    assert sorted(p for p in files if p.startswith("snippets/")) == [
        "snippets/christoffel.tex",
        "snippets/dynamics-long.tex",
        "snippets/lagrange.tex",
        "snippets/wrench-energies.tex",
    ]
    # The wrench term and the energies: their general formulas, and the readable -J^T w and V
    # of a small robot.
    assert "J^{T} w" in document and "L = T - V" in document
    scara = latex_files(models["scara"], sections=["dynamics"])["scara.tex"]
    assert "\\tau_{w} = \\begin{bmatrix}" in scara and "V &= " in scara


def test_bad_options_are_user_errors(models):
    with pytest.raises(SymkinError, match="lang must be one of"):
        latex_files(models["scara"], lang="fr")
    with pytest.raises(SymkinError, match="3 values"):
        latex_files(models["scara"], q=[0.1, 0.2])
    with pytest.raises(SymkinError, match="text_width_cm must be from 8 to 40 cm"):
        latex_files(models["scara"], text_width_cm=3)


def test_output_is_deterministic_and_names_its_source(models):
    first = latex_files(models["scara"], shorthand=True, q=Q_STAR["scara"])
    second = latex_files(models["scara"], shorthand=True, q=Q_STAR["scara"])
    assert first == second
    assert set(first) >= {"scara.tex", "scara-macros.tex", "snippets/legend.tex"}
    for text in first.values():
        assert text.startswith("% LaTeX ")
        assert "Regenerate with: symkin latex scara --shorthand --q 0.5,-0.7,0.12" in text


def test_macro_names_are_letters_only():
    assert macro_prefix("puma560") == "pumaFiveSixZero"
    assert macro_prefix("planar_2r") == "planarTwoR"
    assert macro_prefix("scara") == "scara"


# ---------------------------------------------------------------- pdflatex locked down
# A robot file from someone else ends up in the document; even a document that tries to read
# or write files, or to run a command, must not manage to (docs/security.md).


def _hostile_document(folder: Path, body: str) -> Path:
    tex = folder / "hostile.tex"
    tex.write_text(
        "\\documentclass{article}\n\\begin{document}\nx\n" + body + "\n\\end{document}\n",
        encoding="utf-8",
    )
    return tex


def test_pdflatex_cannot_read_files_outside_the_document_folder(tmp_path):
    secret = tmp_path / "secret.tex"
    secret.write_text("SECRET-CONTENT\n", encoding="utf-8")
    folder = tmp_path / "doc"
    folder.mkdir()
    tex = _hostile_document(folder, f"\\input{{{secret}}}")
    with pytest.raises(SymkinError, match="not found"):
        compile_pdf(tex)
    relative = _hostile_document(folder, "\\input{../secret}")
    with pytest.raises(SymkinError, match="not found"):
        compile_pdf(relative)


def test_pdflatex_cannot_write_files_or_run_commands(tmp_path):
    target = tmp_path / "written.txt"
    ran = tmp_path / "ran"
    folder = tmp_path / "doc"
    folder.mkdir()
    tex = _hostile_document(
        folder,
        f"\\immediate\\write18{{touch {ran}}}\n"
        f"\\immediate\\openout1={target}\n\\immediate\\write1{{x}}\n\\immediate\\closeout1\n",
    )
    with pytest.raises(SymkinError, match="can't write"):
        compile_pdf(tex)
    assert not target.exists() and not ran.exists()
    # Only the log is left beside the document: pdflatex wrote into a temporary folder.
    assert sorted(p.name for p in folder.iterdir()) == ["hostile.log", "hostile.tex"]


def test_a_title_cannot_leave_its_tex_comment():
    robot = load_robot("planar_2r")
    hostile = "x\n\\AtBeginDocument{\\input{/etc/hostname}}\n% "
    with pytest.raises(RobotError, match="printable"):
        dataclasses.replace(robot, title=hostile)
    # A robot that bypassed the check (object.__setattr__) is still written safely.
    sneaky = dataclasses.replace(robot, title="ok")
    object.__setattr__(sneaky, "title", hostile)
    document = latex_files(derive(sneaky))["planar_2r.tex"]
    for line in document.splitlines():
        assert not line.startswith("\\AtBeginDocument"), line
    assert "\\input{/etc/hostname}" not in document.replace("\\textbackslash{}", "/")

"""The examples in the documentation run and show what symkin really prints.

Rules for the Markdown files checked here (README.md, docs/tutorial.md, docs/cli.md,
docs/backends.md, docs/dynamics.md, docs/latex.md, docs/ik.md, docs/ik-generated.md,
docs/trajopt.md, docs/workspace.md, docs/identification.md):

* Each file runs in a fresh temporary directory, its fenced blocks in document order.
* A ```toml block whose first line is a comment naming a file (``# two_link.toml: ...``) is
  written to that file, so later examples can load it.
* ```python blocks of one file run in one shared namespace, in order, exactly as written.
  Blocks that state a value assert it, so a wrong statement fails here.
* ```console blocks: each ``$ symkin ...`` line runs through :func:`symkin.cli.main`.  The
  lines shown after it must appear in the real output (stdout and stderr), in that order; a line
  ``...`` stands for omitted output, and numbers are compared to a relative 1e-6.  The exit
  status must be 0, or 2 when the shown output contains ``error:``.
* ```bash blocks: each line starting with ``symkin `` runs and must exit with status 0 (other
  lines, such as ``make run``, are set-up commands and are not run here).
* Other blocks (```text, ```sh, ```c, ...) are shown, not run: ``symkin generate`` needs the
  repository checkout and takes long, and ``--pdf`` needs pdflatex.

A failing Python block is reported as ``<file>:<line of its fence>``, line N of the block.
"""

from __future__ import annotations

import math
import re
import shlex
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from symkin.cli import main

ROOT = Path(__file__).resolve().parent.parent
BLOCK = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)
TOML_FILE_COMMENT = re.compile(r"^#\s*([\w.-]+\.toml)\b")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
OMITTED = "..."


@dataclass(frozen=True)
class Block:
    language: str
    text: str
    line: int  # 1-based line of the opening fence


@dataclass
class Command:
    line: int
    argv: list[str]
    shown: list[str] = field(default_factory=list)


def blocks(path: Path) -> list[Block]:
    source = path.read_text(encoding="utf-8")
    return [
        Block(m.group(1), m.group(2), source.count("\n", 0, m.start()) + 1)
        for m in BLOCK.finditer(source)
    ]


def console_commands(block: Block) -> list[Command]:
    """``$ symkin ...`` lines of a console block, each with the output lines shown after it."""
    commands: list[Command] = []
    current: Command | None = None
    for offset, line in enumerate(block.text.splitlines(), start=1):
        if line.startswith("$ "):
            words = shlex.split(line[2:])
            current = None
            if words and words[0] == "symkin":
                current = Command(block.line + offset, words[1:])
                commands.append(current)
        elif current is not None:
            current.shown.append(line)
    return commands


def bash_commands(block: Block) -> list[Command]:
    return [
        Command(block.line + offset, shlex.split(line, comments=True)[1:])
        for offset, line in enumerate(block.text.splitlines(), start=1)
        if line.startswith("symkin ")
    ]


def same_line(shown: str, actual: str) -> bool:
    """Equal text, with numbers compared to a relative 1e-6 (and -0.0 equal to 0.0)."""
    shown, actual = shown.strip(), actual.strip()
    if NUMBER.split(shown) != NUMBER.split(actual):
        return False
    return all(
        math.isclose(float(a), float(b), rel_tol=1e-6, abs_tol=1e-9)
        for a, b in zip(NUMBER.findall(shown), NUMBER.findall(actual), strict=True)
    )


def missing_lines(shown: list[str], actual: list[str]) -> list[str]:
    """Shown lines not found in ``actual`` in order (``...`` lines skip freely)."""
    position = 0
    missing = []
    for line in shown:
        if line.strip() in ("", OMITTED):
            continue
        for index in range(position, len(actual)):
            if same_line(line, actual[index]):
                position = index + 1
                break
        else:
            missing.append(line)
    return missing


def run_symkin(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    capsys.readouterr()
    try:
        status = main(argv)
    except SystemExit as exit_:  # argparse usage errors
        status = exit_.code if isinstance(exit_.code, int) else 1
    captured = capsys.readouterr()
    return status, captured.out + captured.err


def run_document(path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    namespace: dict[str, object] = {"__name__": f"docs:{path.name}"}
    ran = 0
    for block in blocks(path):
        where = f"{path.relative_to(ROOT)}:{block.line}"
        if block.language == "toml":
            match = TOML_FILE_COMMENT.match(block.text)
            if match:
                Path(match.group(1)).write_text(block.text, encoding="utf-8")
        elif block.language == "python":
            exec(compile(block.text, where, "exec"), namespace)
            ran += 1
        elif block.language in ("console", "bash"):
            commands = console_commands(block) if block.language == "console" else []
            commands += bash_commands(block) if block.language == "bash" else []
            for command in commands:
                status, output = run_symkin(command.argv, capsys)
                expected = 2 if any("error:" in line for line in command.shown) else 0
                text = " ".join(command.argv)
                assert status == expected, (
                    f"{path.name}:{command.line}: symkin {text} exited with {status}:\n{output}"
                )
                missing = missing_lines(command.shown, output.splitlines())
                assert not missing, (
                    f"{path.name}:{command.line}: symkin {text} did not print, in this order:\n"
                    + "\n".join(missing)
                    + f"\n--- real output ---\n{output}"
                )
                ran += 1
    assert ran, f"{path.name}: no runnable examples found"


@pytest.fixture
def in_tmp_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_readme_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "README.md", capsys)


def test_readme_opens_with_the_two_setup_commands() -> None:
    first = blocks(ROOT / "README.md")[0]
    commands = [line.split("#")[0].strip() for line in first.text.splitlines()]
    assert first.language == "bash"
    assert commands == ["make run", "make test"]


@pytest.mark.slow
def test_tutorial_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "tutorial.md", capsys)


@pytest.mark.slow
def test_cli_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "cli.md", capsys)


@pytest.mark.slow
def test_backends_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "backends.md", capsys)


@pytest.mark.slow
def test_dynamics_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "dynamics.md", capsys)


@pytest.mark.needs_latex
@pytest.mark.slow
def test_latex_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The Python example compiles a PDF: it needs pdflatex (``scripts/install-latex.sh``)."""
    run_document(ROOT / "docs" / "latex.md", capsys)


@pytest.mark.slow
@pytest.mark.parametrize("page", ["ik.md", "ik-generated.md"])
def test_ik_examples_run(page: str, in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / page, capsys)


@pytest.mark.slow
def test_workspace_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "workspace.md", capsys)


@pytest.mark.slow
def test_trajopt_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Run from the repository's point of view: the examples load ``examples/arm_2r.toml``."""
    shutil.copytree(ROOT / "examples", in_tmp_dir / "examples")
    run_document(ROOT / "docs" / "trajopt.md", capsys)


@pytest.mark.slow
def test_identification_examples_run(in_tmp_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run_document(ROOT / "docs" / "identification.md", capsys)


def test_doc_links_resolve() -> None:
    """Relative links between the documents point at files that exist."""
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    broken = []
    for page in pages:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text("utf-8")):
            if "://" not in target and not (page.parent / target).exists():
                broken.append(f"{page.relative_to(ROOT)} -> {target}")
    assert not broken


@pytest.mark.parametrize(
    ("shown", "actual", "same"),
    [
        ("det = 0.15, manipulability = 0.15", "det = 0.15, manipulability = 0.15", True),
        ("(120.000, -0.000, 0.000 deg)", "(120.000, 0.000, 0.000 deg)", True),
        ("  0.10606601717798213,", "0.10606601717798217,", True),
        ("det J = L1*L2*sin(q2)", "det J = L1*L2*cos(q2)", False),
        ("position = [0.5 0.5]", "position = [0.5 0.6]", False),
    ],
)
def test_output_comparison(shown: str, actual: str, same: bool) -> None:
    assert same_line(shown, actual) is same


def test_missing_lines_respects_order() -> None:
    actual = ["a", "b 1.0", "c"]
    assert missing_lines(["a", "...", "c"], actual) == []
    assert missing_lines(["c", "a"], actual) == ["a"]

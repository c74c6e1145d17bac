"""Turning a LaTeX file into a PDF with ``pdflatex`` (the one place that runs it).

:func:`compile_pdf` runs ``pdflatex -interaction=nonstopmode -halt-on-error`` twice and
returns the PDF's path; a failed run raises :class:`SymkinError` with the first error lines of
the log.  A document may come from a robot file someone else wrote, so pdflatex runs locked
down (docs/security.md): ``-no-shell-escape``; ``openin_any=p`` and ``openout_any=p`` (no
absolute paths, no ``..``, no dot files), reading only the document's folder and TeX's own
tree; writing only into a fresh temporary build folder (``-output-directory``), from which
the PDF and the log are copied beside the document; a time limit on each run.
:func:`log_problems` reads a log for errors and overfull boxes (the tests use it to hold the
documents to "no errors, no overfull boxes").
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from symkin.errors import SymkinError
from symkin.output_folder import replace_file

INSTALL_HINT = (
    "pdflatex is not installed; install texlive-latex-base and texlive-latex-recommended "
    "(Debian/Ubuntu: sudo apt-get install --no-install-recommends texlive-latex-base "
    "texlive-latex-recommended, or run scripts/install-latex.sh), or run make test, "
    "which installs them"
)
RUNS = 2
TIMEOUT_SECONDS = 120
# kpathsea's "paranoid" mode for \openin and \openout; the rest of the environment is kept
# (PATH, TEXMF* of a user's own TeX installation).
LOCKED_DOWN = {"openin_any": "p", "openout_any": "p", "shell_escape": "f"}
PLAIN_FILE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*\.tex")
_OVERFULL = re.compile(r"^Overfull \\([hv])box \((\d+(?:\.\d+)?)pt too (?:wide|high)\)", re.M)


@dataclass(frozen=True)
class LogProblems:
    """What a pdflatex log reports: error lines (``! ...``) and overfull boxes (pt)."""

    errors: tuple[str, ...]
    overfull_hboxes: tuple[float, ...]
    overfull_vboxes: tuple[float, ...]


def log_problems(log: str) -> LogProblems:
    """Errors and overfull boxes in the text of a pdflatex ``.log``."""
    errors = tuple(line for line in log.splitlines() if line.startswith("! "))
    boxes = _OVERFULL.findall(log)
    return LogProblems(
        errors=errors,
        overfull_hboxes=tuple(float(pt) for kind, pt in boxes if kind == "h"),
        overfull_vboxes=tuple(float(pt) for kind, pt in boxes if kind == "v"),
    )


def pdflatex_path() -> str | None:
    return shutil.which("pdflatex")


def _error_excerpt(log: str, lines: int = 12) -> str:
    """The first error of a log with the lines after it (where TeX says what and where)."""
    text = log.splitlines()
    for i, line in enumerate(text):
        if line.startswith("! "):
            return "\n".join(text[i : i + lines])
    return "\n".join(text[-lines:])


def compile_pdf(tex_path: str | Path) -> Path:
    """``pdflatex`` twice (cross references settle), locked down as the module says; the path
    of the PDF written beside the document.

    Raises :class:`SymkinError` when pdflatex is missing or reports an error.
    """
    tex_path = Path(tex_path).resolve()
    if not tex_path.is_file():
        raise SymkinError(f"no LaTeX file at {tex_path}")
    if not PLAIN_FILE_NAME.fullmatch(tex_path.name):
        # pdflatex reads its argument as TeX: a name with a backslash would be commands.
        raise SymkinError(
            f"{tex_path.name!r}: name the LaTeX file with letters, digits, '.', '_' and '-' only"
        )
    pdflatex = pdflatex_path()
    if pdflatex is None:
        raise SymkinError(INSTALL_HINT)
    with tempfile.TemporaryDirectory(prefix="symkin-latex-") as build:
        command = [
            pdflatex,
            "-no-shell-escape",
            "-interaction=nonstopmode",
            "-halt-on-error",
            f"-output-directory={build}",
            tex_path.name,
        ]
        outputs = [Path(build) / tex_path.with_suffix(suffix).name for suffix in (".pdf", ".log")]
        for _ in range(RUNS):
            result = _run_pdflatex(command, tex_path)
            log = outputs[1].read_text(errors="replace") if outputs[1].exists() else ""
            if result.returncode != 0:
                replace_file(tex_path.parent, outputs[1].name, log)
                raise SymkinError(
                    f"pdflatex failed on {tex_path} (log: {tex_path.with_suffix('.log')}):\n"
                    f"{_error_excerpt(log or result.stdout)}"
                )
        if not outputs[0].is_file():
            raise SymkinError(f"pdflatex produced no PDF for {tex_path}")
        replace_file(tex_path.parent, outputs[1].name, log)
        return replace_file(tex_path.parent, outputs[0].name, outputs[0].read_bytes())


def _run_pdflatex(command: list[str], tex_path: Path) -> subprocess.CompletedProcess[str]:
    try:
        return subprocess.run(
            command,
            cwd=tex_path.parent,
            env={**os.environ, **LOCKED_DOWN},
            stdin=subprocess.DEVNULL,
            capture_output=True,
            text=True,
            errors="replace",
            timeout=TIMEOUT_SECONDS,
            check=False,
        )
    except subprocess.TimeoutExpired:
        raise SymkinError(
            f"pdflatex did not finish {tex_path.name} within {TIMEOUT_SECONDS} s"
        ) from None

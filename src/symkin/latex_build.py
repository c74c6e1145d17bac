"""Turning a LaTeX file into a PDF with ``pdflatex`` (the one place that runs it).

:func:`compile_pdf` runs ``pdflatex -interaction=nonstopmode -halt-on-error`` twice in the
file's folder and returns the PDF's path; a failed run raises :class:`SymkinError` with the
first error lines of the log.  :func:`log_problems` reads a log for errors and overfull boxes
(the tests use it to hold the documents to "no errors, no overfull boxes").
"""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from symkin.errors import SymkinError

INSTALL_HINT = (
    "pdflatex is not installed; install texlive-latex-base and texlive-latex-recommended "
    "(Debian/Ubuntu: sudo apt-get install --no-install-recommends texlive-latex-base "
    "texlive-latex-recommended, or run scripts/install-latex.sh), or run make test, "
    "which installs them"
)
RUNS = 2
TIMEOUT_SECONDS = 300
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
    """``pdflatex`` twice in the file's folder (cross references settle); the PDF's path.

    Raises :class:`SymkinError` when pdflatex is missing or reports an error.
    """
    tex_path = Path(tex_path).resolve()
    if not tex_path.is_file():
        raise SymkinError(f"no LaTeX file at {tex_path}")
    pdflatex = pdflatex_path()
    if pdflatex is None:
        raise SymkinError(INSTALL_HINT)
    command = [pdflatex, "-interaction=nonstopmode", "-halt-on-error", tex_path.name]
    log_path = tex_path.with_suffix(".log")
    for _ in range(RUNS):
        try:
            result = subprocess.run(
                command,
                cwd=tex_path.parent,
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
        if result.returncode != 0:
            log = log_path.read_text(errors="replace") if log_path.exists() else result.stdout
            raise SymkinError(
                f"pdflatex failed on {tex_path} (log: {log_path}):\n{_error_excerpt(log)}"
            )
    pdf_path = tex_path.with_suffix(".pdf")
    if not pdf_path.is_file():
        raise SymkinError(f"pdflatex produced no PDF for {tex_path} (log: {log_path})")
    return pdf_path

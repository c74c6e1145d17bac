"""Hypothesis strategies and a subprocess case runner for fuzzing the ``symkin`` command.

A *case* is one run of the real command line in a fresh temporary folder: the arguments after
``symkin`` (``{tmp}`` stands for that folder) and the files written there first.
:func:`run_case` runs it under a time limit (and an address-space cap, so that reading
``/dev/zero`` cannot exhaust the machine) and sorts the result into one category:

``clean``
    exit 0 with well-formed output, or exit 2 with exactly one ``symkin: error:`` line on
    standard error (argparse's usage block before its own error line is allowed, and so are
    ``symkin: ...`` progress and warning lines); ``ik`` may also exit 1 (target not reached).
``traceback``
    ``Traceback`` on standard error, or any other exit status (a signal, a crash).
``hang``
    no exit within the time limit.
``wrong``
    the command ended normally but its output is malformed: invalid JSON or JSON with
    NaN/Infinity, raw control characters (C0/C1, DEL, bidi controls, Unicode line separators;
    ``\\n`` and ``\\t`` are fine) in standard output, standard error or a generated file, stray
    standard-error lines, an exit-2 message that is not one line, generated C that does not
    compile with ``-std=c99 -Wall -Wextra -Werror -pedantic``, a generated Python module that
    does not import, or LaTeX in which text from the robot's title or source escapes its
    comment or group as a command (``\\input{/etc/...}``, ``\\openout``, ...).

The strategies mutate small valid robots (1-3 joints, so honest cases take about two seconds)
with hostile numbers, expressions, names and texts, and fuzz the command-line arguments of
``show``, ``eval``, ``derive``, ``latex`` and ``ik``.  :func:`draw_cases` draws a fixed set of
cases per suite with Hypothesis (``derandomize=True``, no database, no shrinking), and
:func:`run_cases` runs them concurrently.

Stand-alone report (all suites, counts per category and every non-clean case)::

    .venv/bin/python -m tests.fuzz_cases --report [SUITE ...]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import sysconfig
import tempfile
import time
import tomllib
from collections import Counter
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from importlib.util import find_spec
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

CATEGORIES = ("clean", "wrong", "traceback", "hang")

# Per-case time limits in seconds: an honest case of these tiny robots takes 1-4 s.
QUICK_TIMEOUT = 20.0
DERIVE_TIMEOUT = 45.0
LATEX_TIMEOUT = 40.0
# Address-space cap of each run (bytes): generous for SymPy, small next to the machine.
MEMORY_LIMIT = 6 * 2**30
# Cases run concurrently; SYMKIN_FUZZ_JOBS overrides.
JOBS = int(os.environ.get("SYMKIN_FUZZ_JOBS", "0")) or max(1, min(4, os.cpu_count() or 1))

# Raw characters that must never reach a terminal or a generated file: C0 controls except
# \t and \n, DEL, C1 controls, bidi controls (Trojan Source) and Unicode line separators.
CONTROL_CHARACTERS = re.compile(
    "[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028\u2029\u202a-\u202e\u2066-\u2069]"
)
ERROR_LINE = re.compile(r"^symkin(?: [a-z]+)?: error: ")
# TeX that must not appear as live code when the title or source contained it.
TEX_MARKERS = (
    "\\input{/etc/",
    "\\openout",
    "\\AtBeginDocument",
    "\\write18",
    "\\immediate",
    "\\catcode",
    "\\end{document}",
    "^^5c",
)
BINARY_SUFFIXES = (".so", ".o", ".pdf", ".png", ".pyc", ".aux", ".log")


# ---------------------------------------------------------------------------------------------
# Running one case
# ---------------------------------------------------------------------------------------------


def symkin_command() -> list[str]:
    """``python -m symkin.cli`` when the package is importable, else the venv's script."""
    if find_spec("symkin.cli") is not None:
        return [sys.executable, "-m", "symkin.cli"]
    return [str(Path(sys.executable).with_name("symkin"))]


def _limit_prefix() -> list[str]:
    prlimit = shutil.which("prlimit")
    return [prlimit, f"--as={MEMORY_LIMIT}", "--"] if prlimit else []


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env.update(
        PYTHONIOENCODING="utf-8",
        PYTHONDONTWRITEBYTECODE="1",
        OMP_NUM_THREADS="1",
        OPENBLAS_NUM_THREADS="1",
        MKL_NUM_THREADS="1",
    )
    env.pop("PYTHONWARNINGS", None)
    return env


Files = Mapping[str, str | bytes] | Sequence[tuple[str, str | bytes]]


@dataclass(frozen=True)
class Case:
    """Arguments after ``symkin`` (``{tmp}`` = the case's folder) and the files put there."""

    argv: tuple[str, ...]
    files: tuple[tuple[str, str | bytes], ...] = ()
    timeout: float = QUICK_TIMEOUT
    suite: str = ""
    note: str = ""  # what was mutated, for the report


@dataclass
class Outcome:
    category: str
    detail: str
    argv: tuple[str, ...]
    files: tuple[tuple[str, str | bytes], ...] = ()
    returncode: int | None = None
    stdout: str = ""
    stderr: str = ""
    seconds: float = 0.0
    suite: str = ""
    extra: dict[str, Any] = field(default_factory=dict)
    note: str = ""

    @property
    def clean(self) -> bool:
        return self.category == "clean"

    @property
    def signature(self) -> str:
        """What groups equal findings: the category and the first line of the detail."""
        first = self.detail.splitlines()[0] if self.detail else ""
        return f"{self.category}: {re.sub(r':[0-9]+(:[0-9]+)?', '', first)}"

    def report(self, tail: int = 12) -> str:
        lines = [
            f"[{self.category}] {self.detail}",
            f"  argv: symkin {' '.join(_quote(a) for a in self.argv)}",
            f"  exit: {self.returncode}  time: {self.seconds:.1f} s",
        ]
        if self.note:
            lines.append(f"  mutations: {ascii(self.note)[1:-1][:300]}")
        for name, content in self.files:
            text = content if isinstance(content, str) else repr(content[:600])
            if len(text) > 1500:
                text = text[:1500] + f"... ({len(text)} characters)"
            lines.append(f"  file {name}:")
            lines.extend("    " + ascii(line)[1:-1] for line in text.split("\n"))
        err = self.stderr.splitlines()[-tail:]
        if err:
            lines.append("  stderr (tail):")
            lines.extend("    " + ascii(line)[1:-1] for line in err)
        return "\n".join(lines)


def _quote(argument: str) -> str:
    if argument and re.fullmatch(r"[\w./{}:,=+@%^-]+", argument):
        return argument
    return ascii(argument)


def run_case(
    argv: Sequence[str],
    files: Files = (),
    timeout: float = QUICK_TIMEOUT,
    *,
    suite: str = "",
    setup: Callable[[Path], object] | None = None,
    inspect: Callable[[Path], object] | None = None,
) -> Outcome:
    """Run ``symkin *argv`` in a fresh folder holding ``files`` and classify the result.

    ``setup(folder)`` runs after the files are written (e.g. to plant a symlink);
    ``inspect(folder)`` runs after the command, its result is ``outcome.extra["inspect"]``.
    """
    items = tuple(files.items()) if isinstance(files, Mapping) else tuple(files)
    argv = tuple(argv)
    with tempfile.TemporaryDirectory(prefix="symkin-fuzz-") as folder:
        tmp = Path(folder)
        for name, content in items:
            path = tmp / name
            path.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(content, bytes):
                path.write_bytes(content)
            else:
                path.write_text(content, encoding="utf-8")
        if setup is not None:
            setup(tmp)
        inputs = {p.relative_to(tmp).as_posix() for p in tmp.rglob("*")}
        args = [a.replace("{tmp}", folder) for a in argv]
        command = [*_limit_prefix(), *symkin_command(), *args]
        start = time.monotonic()
        process = subprocess.Popen(
            command,
            cwd=folder,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            start_new_session=True,
            env=_environment(),
        )
        try:
            raw_out, raw_err = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill(process)
            raw_out, raw_err = process.communicate()
            return Outcome(
                "hang",
                f"no exit within {timeout:g} s",
                argv,
                items,
                None,
                _text(raw_out, folder)[0],
                _text(raw_err, folder)[0],
                time.monotonic() - start,
                suite,
            )
        seconds = time.monotonic() - start
        out, out_ok = _text(raw_out, folder)
        err, err_ok = _text(raw_err, folder)
        outcome = Outcome("clean", "", argv, items, process.returncode, out, err, seconds, suite)
        category, detail = _classify(args, items, process.returncode, out, err, tmp, inputs)
        if category == "clean" and not (out_ok and err_ok):
            category, detail = "wrong", "output is not UTF-8"
        outcome.category, outcome.detail = category, detail
        if inspect is not None:
            outcome.extra["inspect"] = inspect(tmp)
        return outcome


def _kill(process: subprocess.Popen[bytes]) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGKILL)


def _text(data: bytes, folder: str) -> tuple[str, bool]:
    try:
        text, ok = data.decode("utf-8"), True
    except UnicodeDecodeError:
        text, ok = data.decode("utf-8", errors="replace"), False
    return text.replace(folder, "{tmp}"), ok


def _classify(
    args: list[str],
    files: tuple[tuple[str, str | bytes], ...],
    code: int,
    out: str,
    err: str,
    tmp: Path,
    inputs: set[str],
) -> tuple[str, str]:
    command = args[0] if args else ""
    if "Traceback" in err:
        return "traceback", _traceback_summary(err)
    allowed = {0, 2} | ({1} if command == "ik" else set())
    if code not in allowed:
        name = f" ({signal.Signals(-code).name})" if code < 0 and -code in _SIGNALS else ""
        tail = err.strip().splitlines()[-1:] or [""]
        return "traceback", f"exit status {code}{name}: {tail[0][:200]}"
    for stream, text in (("stdout", out), ("stderr", err)):
        bad = CONTROL_CHARACTERS.search(text)
        if bad:
            return "wrong", f"raw control character {bad.group()!r} on {stream}"
    if code == 2:
        return _check_error_lines(err)
    problem = _check_success_stderr(err)
    if problem:
        return "wrong", problem
    if "--json" in args:
        problem = _check_json(out)
        if problem:
            return "wrong", problem
    if code == 0 and command in ("derive", "latex"):
        problem = _check_written_files(tmp, inputs, files)
        if problem:
            return "wrong", problem
    return "clean", ""


_SIGNALS = {s.value for s in signal.Signals}


def _traceback_summary(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    frames = [line.strip() for line in lines if "/symkin/" in line and line.strip()[:5] == "File "]
    where = ""
    if frames:
        match = re.search(r"symkin/(\S+)\", line (\d+), in (\S+)", frames[-1])
        if match:
            where = f" at {match.group(1)}:{match.group(2)} ({match.group(3)})"
    last = lines[-1].strip() if lines else ""
    return f"{last[:200]}{where}"


def _check_error_lines(err: str) -> tuple[str, str]:
    lines = err.split("\n")
    if lines and lines[-1] == "":
        lines = lines[:-1]
    errors = [i for i, line in enumerate(lines) if ERROR_LINE.match(line)]
    if len(errors) != 1:
        return "wrong", f"exit 2 with {len(errors)} 'symkin: error:' lines on stderr"
    index = errors[0]
    if index != len(lines) - 1:
        return "wrong", "exit 2: the error message spans more than one line"
    argparse_error = not lines[index].startswith("symkin: error:")
    for line in lines[:index]:
        if line.startswith("symkin: ") and not ERROR_LINE.match(line):
            continue  # progress or warning line
        if argparse_error and (line.startswith("usage: ") or line.startswith(" ")):
            continue  # argparse's usage block
        return "wrong", f"exit 2 with a stray stderr line: {line[:120]!r}"
    return "clean", ""


def _check_success_stderr(err: str) -> str:
    for line in err.split("\n"):
        if line and not line.startswith("symkin: "):
            return f"stray stderr line: {line[:120]!r}"
        if ERROR_LINE.match(line):
            return "an error line on stderr although the command succeeded"
    return ""


def _reject_constant(text: str) -> float:
    raise ValueError(f"JSON contains {text}")


def _check_json(out: str) -> str:
    try:
        json.loads(out, parse_constant=_reject_constant)
    except ValueError as error:
        message = str(error)
        if "JSON contains" in message:
            return message
        return f"stdout is not valid JSON: {message[:120]}"
    return ""


# ---------------------------------------------------------------------------------------------
# Checks of written files: control characters, C, Python, LaTeX
# ---------------------------------------------------------------------------------------------


def _check_written_files(
    tmp: Path, inputs: set[str], files: tuple[tuple[str, str | bytes], ...]
) -> str:
    written = sorted(
        p for p in tmp.rglob("*") if p.is_file() and p.relative_to(tmp).as_posix() not in inputs
    )
    for path in written:
        if path.suffix in BINARY_SUFFIXES:
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            return f"{path.relative_to(tmp)} is not UTF-8"
        bad = CONTROL_CHARACTERS.search(text.replace("\f", ""))
        if bad:
            return f"raw control character {bad.group()!r} in {path.relative_to(tmp)}"
    problem = _check_tex(tmp, [p for p in written if p.suffix == ".tex"], files)
    if problem:
        return problem
    for folder in sorted({p.parent for p in written if p.parent.name == "c"}):
        problem = compile_c(folder)
        if problem:
            return problem
    python = [p for p in written if p.suffix == ".py"]
    if python:
        problem = import_modules(python)
        if problem:
            return problem
    return ""


def compile_c(folder: Path) -> str:
    """Compile every .c of a generated ``c/`` folder (and its sibling ``python/``) strictly."""
    sources = sorted(folder.glob("*.c"))
    extension = sorted((folder.parent / "python").glob("*.c"))
    flags = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c", f"-I{folder}"]
    jobs = [(sources, [])]
    if extension:
        import numpy

        includes = ["-isystem", sysconfig.get_paths()["include"], "-isystem", numpy.get_include()]
        jobs.append((extension, includes))
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        return ""
    with tempfile.TemporaryDirectory(prefix="symkin-fuzz-cc-") as objects:
        for group, includes in jobs:
            if not group:
                continue
            done = subprocess.run(
                [compiler, *flags, *includes, *map(str, group)],
                cwd=objects,
                capture_output=True,
                text=True,
                timeout=120,
                check=False,
            )
            if done.returncode != 0:
                first = [line for line in done.stderr.splitlines() if "error" in line][:3]
                shown = " | ".join(line.replace(str(folder.parent), "OUT") for line in first)
                return f"generated C does not compile: {shown[:400]}"
    return ""


_IMPORT_SCRIPT = """
import importlib.util, sys
for index, path in enumerate(sys.argv[1:]):
    spec = importlib.util.spec_from_file_location(f"fuzz_generated_{index}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
"""


def import_modules(paths: Sequence[Path]) -> str:
    """Import generated Python modules in a subprocess; their text must also compile."""
    done = subprocess.run(
        [sys.executable, "-c", _IMPORT_SCRIPT, *map(str, paths)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        env=_environment(),
    )
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines()
        return f"generated Python module does not import: {lines[-1][:200] if lines else ''}"
    return ""


def _input_texts(files: tuple[tuple[str, str | bytes], ...]) -> list[str]:
    """Title and source strings of the input robot files (where TeX could come from)."""
    texts = []
    for _, content in files:
        try:
            text = content if isinstance(content, str) else content.decode("utf-8")
            document = tomllib.loads(text)
        except (UnicodeDecodeError, tomllib.TOMLDecodeError, ValueError, RecursionError):
            continue
        texts.extend(
            document[key] for key in ("title", "source") if isinstance(document.get(key), str)
        )
    return texts


def live_tex(line: str) -> str:
    """The part of a TeX line before its first unescaped ``%`` (the rest is a comment)."""
    for match in re.finditer("%", line):
        backslashes = len(line[: match.start()]) - len(line[: match.start()].rstrip("\\"))
        if backslashes % 2 == 0:
            return line[: match.start()]
    return line


def _check_tex(
    tmp: Path, tex_files: Sequence[Path], files: tuple[tuple[str, str | bytes], ...]
) -> str:
    texts = _input_texts(files)
    markers = [m for m in TEX_MARKERS if any(m in t for t in texts)]
    if not markers:
        return ""
    for path in tex_files:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            code = live_tex(line)
            for marker in markers:
                # A line that is only "\end{document}" is the document's own end.
                if marker in code and code.strip() != marker:
                    where = f"{path.relative_to(tmp)}:{number}"
                    return f"title/source TeX {marker!r} is live code at {where}: {line[:100]!r}"
    return ""


# ---------------------------------------------------------------------------------------------
# Running many cases and counting
# ---------------------------------------------------------------------------------------------


def run_cases(cases: Sequence[Case], jobs: int = JOBS) -> list[Outcome]:
    """Run cases concurrently (``jobs`` at a time); outcomes in the order of ``cases``."""

    def one(case: Case) -> Outcome:
        outcome = run_case(case.argv, case.files, case.timeout, suite=case.suite)
        outcome.note = case.note
        return outcome

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(one, cases))


def tally(outcomes: Iterable[Outcome]) -> Counter[str]:
    """Counts per category plus ``tried``."""
    counts: Counter[str] = Counter({c: 0 for c in CATEGORIES})
    for outcome in outcomes:
        counts["tried"] += 1
        counts[outcome.category] += 1
    return counts


def format_tally(counts: Mapping[str, int], label: str = "") -> str:
    parts = [f"tried {counts.get('tried', 0)}"] + [f"{c} {counts.get(c, 0)}" for c in CATEGORIES]
    return f"{label + ': ' if label else ''}{', '.join(parts)}"


def failure_report(outcomes: Sequence[Outcome], limit: int = 12) -> str:
    """Non-clean outcomes grouped by signature, each group with its first reproduction."""
    bad = [o for o in outcomes if not o.clean]
    groups: dict[str, list[Outcome]] = {}
    for outcome in bad:
        groups.setdefault(outcome.signature, []).append(outcome)
    lines = [f"{len(bad)} of {len(outcomes)} cases are not clean ({len(groups)} kinds):"]
    for index, (signature, members) in enumerate(groups.items()):
        if index >= limit:
            lines.append(f"... and {len(groups) - limit} more kinds")
            break
        lines.append(f"\n=== {len(members)} x {signature}")
        lines.append(members[0].report())
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# TOML text of robot documents
# ---------------------------------------------------------------------------------------------


def toml_string(text: str) -> str:
    out = ['"']
    for ch in text:
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def toml_key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else toml_string(key)


def toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        items = ", ".join(f"{toml_key(k)} = {toml_value(v)}" for k, v in value.items())
        return "{ " + items + " }"
    raise TypeError(f"no TOML for {value!r}")


def render_robot(document: Mapping[str, Any], names: Mapping[str, str] | None = None) -> str:
    """TOML text of a robot document; ``{P}``/``{Q}`` in strings become parameter names."""
    names = {"{P}": "L1", "{Q}": "L2", **(names or {})}

    def sub(value: Any) -> Any:
        if isinstance(value, str):
            for placeholder, name in names.items():
                value = value.replace(placeholder, name)
            return value
        if isinstance(value, list):
            return [sub(v) for v in value]
        if isinstance(value, dict):
            return {sub(k): sub(v) for k, v in value.items()}
        return value

    document = sub(dict(document))
    lines = []
    tables = ("parameters", "joints", "tool", "base")
    for key, value in document.items():
        if key not in tables:
            lines.append(f"{toml_key(key)} = {toml_value(value)}")
    if isinstance(document.get("parameters"), dict):
        lines.append("\n[parameters]")
        lines.extend(f"{toml_key(k)} = {toml_value(v)}" for k, v in document["parameters"].items())
    elif "parameters" in document:
        lines.append(f"parameters = {toml_value(document['parameters'])}")
    for joint in document.get("joints", []):
        lines.append("\n[[joints]]")
        link = joint.get("link")
        for key, value in joint.items():
            if key != "link" or not isinstance(value, dict):
                lines.append(f"{toml_key(key)} = {toml_value(value)}")
        if isinstance(link, dict):
            lines.append("[joints.link]")
            lines.extend(f"{toml_key(k)} = {toml_value(v)}" for k, v in link.items())
    for key in ("tool", "base"):
        if isinstance(document.get(key), dict):
            lines.append(f"\n[{key}]")
            lines.extend(f"{toml_key(k)} = {toml_value(v)}" for k, v in document[key].items())
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# Small valid robots (templates: {P} = 0.5 and {Q} = 0.25 are parameters)
# ---------------------------------------------------------------------------------------------


def _link(mass: Any = 1.0, com: Any = None, izz: Any = 0.02) -> dict[str, Any]:
    return {
        "mass": mass,
        "com": com or ["-{P}/2", 0, 0],
        "inertia": {"ixx": 0.01, "iyy": 0.02, "izz": izz},
    }


BASE_ROBOTS: tuple[dict[str, Any], ...] = (
    {
        "name": "arm",
        "title": "One revolute joint",
        "parameters": {"{P}": 0.5, "{Q}": 0.25},
        "joints": [{"type": "revolute", "a": "{P}", "link": _link()}],
    },
    {
        "name": "planar",
        "title": "Planar 2R",
        "source": "fuzz test",
        "parameters": {"{P}": 0.5, "{Q}": 0.25},
        "joints": [
            {"type": "revolute", "a": "{P}", "link": _link()},
            {"type": "revolute", "a": "{Q}", "link": _link(0.5, ["-{Q}/2", 0, 0], 0.01)},
        ],
    },
    {
        "name": "rp",
        "title": "Revolute then prismatic",
        "angles": "deg",
        "parameters": {"{P}": 0.5, "{Q}": 0.25},
        "joints": [
            {"type": "revolute", "d": "{P}", "alpha": 90, "limits": [-170, 170], "link": _link()},
            {"type": "prismatic", "a": "{Q}", "limits": [0, 0.5], "link": _link(0.5, [0, 0, 0])},
        ],
    },
    {
        "name": "rpr",
        "title": "RPR arm",
        "convention": "standard",
        "parameters": {"{P}": 0.5, "{Q}": 0.25},
        "joints": [
            {"type": "revolute", "alpha": 90},
            {"type": "prismatic", "theta": 90, "alpha": 90},
            {"type": "revolute", "a": "{P}"},
        ],
        "tool": {"xyz": [0, 0, "{Q}"]},
    },
)
DYNAMIC_ROBOTS = BASE_ROBOTS[:3]  # every link has inertial data


# ---------------------------------------------------------------------------------------------
# Hostile values
# ---------------------------------------------------------------------------------------------

PARAMETER_NAMES = (
    "M", "mu", "NAN", "NaN", "INFINITY", "HUGE_VAL", "M_PI", "fabs", "pow", "x0", "x", "y", "t",
    "g", "e", "j", "L", "sin", "pi", "E", "I", "S", "beta", "gamma", "lam", "tau", "c", "C", "G",
    "J", "T", "R", "p", "q", "dq", "q1", "qd", "m1", "izz1", "cx2", "np", "sp", "sympy", "cmath",
    "ca", "SX", "MX", "DM", "Matrix", "Symbol", "Float", "Integer", "Abs", "Heaviside", "int",
    "double", "return", "main", "printf", "errno", "stdin", "NULL", "bool", "true", "_Bool",
    "complex", "len", "print", "list", "sum", "abs", "self", "None", "True", "_", "__import__",
    "__builtins__", "result", "out", "ret", "i", "k", "n", "count", "det", "mass_matrix", "fk",
    "jacobian", "position", "manipulability", "theta", "alpha", "a", "d", "m", "Ixx", "O", "oo",
    "zoo", "nan", "inf", "Inf", "lambda", "a b", "", "1x", "x-y", "\u03d5", "\xe9", "L" * 80,
)  # fmt: skip
ROBOT_NAMES = (
    "math", "stdio", "stdlib", "string", "numpy", "casadi", "sympy", "symkin", "sys", "os",
    "example", "main", "int", "return", "import", "class", "lambda", "none", "true", "test",
    "errno", "signal", "time", "complex", "assert", "float", "double", "static", "struct",
    "typing", "builtins", "io", "re", "python", "arm_ext", "arm_kinematics", "a", "x0", "a" * 90,
    "Math", "1a", "", "a-b", "\xe4", "a b", "_a", "arm\n",
)  # fmt: skip
JOINT_NAMES = ("q1", "elbow", "int", "main", "math", "a" * 70, "Elbow", "", "x y", "j\n")
HOSTILE_TEXTS = (
    "", "*/", "/* x */", "*/ int x = 1; /*", '"""', "'''", '"""; import os; """', "\\", "a\\",
    "\\n", "\\u0041", "\\x41", "line1\nline2", "\r", "\x00", "a\x00b", "\x1b[31mred\x1b[0m",
    "\u202eevil", "\u2066x\u2069", "\u200f", "\x7f", "\x85", "\u2028", "\x0c", "\t", "\x08",
    "%", "%\n\\input{/etc/hostname}", "\\input{/etc/hostname}", "\\immediate\\write18{id}",
    "\\openout1=x", "\\AtBeginDocument{\\input{/etc/hostname}}", "}\\input{/etc/hostname}{",
    "$\\input{/etc/hostname}$", "^^5cinput{/etc/hostname}", "\\end{document}", "#", "&", "_",
    "~", "{", "}", "$", "\xe9 \xfc \xdf \u6f22 \U0001f916", "\ufeff", "??/", "\\\n#include <x>",
    "\n#include </etc/passwd>\n", "\n// */\n", "{{ title }}", "{% raw %}", "${HOME}", "x" * 3000,
)  # fmt: skip
EXPRESSIONS = (
    "{P}", "-{P}/2", "2*{P} + 0.1", "{P}**{P}", "{P}**({P}**{P})", "({P}**{P})**{P}",
    "{P}**{P}**{P}**{P}", "1/(2*{P} - 1)", "1/({P} - 0.5)", "({P} - 0.5)**-1", "{P}/(1 - 2*{P})",
    "({P} + 1)**100", "({P} + {Q})**7", "({P} + {Q} + 1)**50", "(1 + {P})**-100", "{P}**100",
    "{P}**-100", "{P}**0.5", "(-{P})**0.5", "(-{P})**{P}", "0**{P}", "{P}**-{P}", "2**100",
    "10**100", "(-8)**(1/3)", "pi**pi**pi", "1e300*{P}", "1e300*1e300", "1e-300*1e-300",
    "{P}/0", "0/0", "0**0", "0**-1", "{P}*0", "1/3", "(" * 60 + "{P}" + ")" * 60,
    "-" * 300 + "{P}", "+".join(["{P}"] * 120), "9**9**9", "2**101", "(-1)**0.5", "{P}**1e-300",
    "1e309", "1e300", "sin(1)", "q1", "__import__('os')", "{P}.real", "{P}[0]", "{P} if 1 else 0",
    "lambda: 0", "{P} {P}", "", " ", "symbol", "pi", "-pi/2", "1_000", "0x10", "1j", "True",
    "{Q}**{P}", "({P}*{Q})**({P}*{Q})", "{P}**(1/{Q})", "(2*{P} - 1)**0.5", "(2*{P} - 1)**-2",
)  # fmt: skip
NUMBERS = (
    0, 1, -1, 2, 10**29 + 7, -(10**29) - 3, 123456789012345678901234567890, 2**63, 2**64 + 1,
    10**300, 10**301, 2**1000, 1e308, -1e308, 1e300, 1e-300, 5e-324, 1e-320, -0.0, 0.1, 1e16,
    math.nan, math.inf, -math.inf, 1.7976931348623157e308,
)  # fmt: skip
ODD_TYPES = (True, [1, 2], [], {"x": 1}, {}, "symbol", [[["deep"]]])

_atoms = st.sampled_from(["{P}", "{Q}", "pi", "0", "1", "2", "0.5", "1e300", "1e-300", "100", "3"])


def _combine(parts: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    binary = st.tuples(parts, st.sampled_from(["+", "-", "*", "/", "**"]), parts).map(
        lambda t: f"({t[0]}{t[1]}{t[2]})"
    )
    return st.one_of(binary, parts.map(lambda s: f"-{s}"))


random_expressions = st.recursive(_atoms, _combine, max_leaves=6)


# Categorical choices (which mutation, which hostile value, which command) come from a
# random.Random seeded by Hypothesis: with a few dozen examples per suite, Hypothesis's own
# choices repeat the first items of a list; a seeded generator spreads over the catalogues.
# Numbers, texts, bytes and expression trees are still Hypothesis strategies.
def _chooser(draw: st.DrawFn) -> random.Random:
    return random.Random(draw(st.integers(0, 2**32 - 1)))


def hostile_value(draw: st.DrawFn, rnd: random.Random) -> Any:
    """A DH entry, inertial value or parameter value: numbers, expressions, odd TOML types."""
    branch = rnd.randrange(8)
    if branch <= 2:
        return rnd.choice(EXPRESSIONS)
    if branch == 3:
        return rnd.choice(NUMBERS)
    if branch == 4:
        return draw(random_expressions)
    if branch == 5:
        return rnd.choice([1, -1]) * rnd.randrange(10**29, 10**30)  # 30 digits
    if branch == 6:
        return draw(st.floats(width=64))
    return rnd.choice([*ODD_TYPES, rnd.randint(-5, 5)])


def hostile_text(draw: st.DrawFn, rnd: random.Random) -> str:
    branch = rnd.randrange(4)
    if branch <= 1:
        return rnd.choice(HOSTILE_TEXTS)
    if branch == 2:
        return "x".join(rnd.sample(HOSTILE_TEXTS, 2))
    return draw(st.text(max_size=30))


def hostile_parameter_name(draw: st.DrawFn, rnd: random.Random) -> str:
    if rnd.randrange(5) == 0:
        return draw(st.from_regex(r"[A-Za-z_]\w{0,6}", fullmatch=True))
    return rnd.choice(PARAMETER_NAMES)


# ---------------------------------------------------------------------------------------------
# Mutations of the small robots
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Robot:
    """A mutated robot: the TOML text and its joint count (for --q and the like)."""

    text: str
    joints: int
    mutations: tuple[str, ...]

    @property
    def note(self) -> str:
        return "; ".join(self.mutations)


MUTATIONS = (
    "dh", "dh", "dh", "dh", "link", "link", "parameter_name", "parameter_value", "robot_name",
    "title", "source", "limits", "gravity", "tool", "joint_name", "convention", "odd_key",
)  # fmt: skip


def mutate(
    draw: st.DrawFn,
    rnd: random.Random,
    document: dict[str, Any],
    names: dict[str, str],
    kind: str | None = None,
) -> str:
    """Apply one mutation (of ``kind``, else a random one) and describe it."""
    joints = document["joints"]
    kind = kind or rnd.choice(MUTATIONS)
    index = rnd.randrange(len(joints))
    joint = joints[index]
    where = f"joint {index + 1}"
    if kind == "dh":
        key = rnd.choice(["theta", "d", "a", "alpha"])
        joint[key] = hostile_value(draw, rnd)
        return f"{where} {key} = {joint[key]!r}"
    if kind == "link":
        link = joint.setdefault("link", _link())
        key = rnd.choice(["mass", "com", "izz", "ixx", "ixy", "motor_inertia", "viscous"])
        value = hostile_value(draw, rnd)
        if key == "com":
            link["com"] = [value, 0, 0]
        elif key in ("izz", "ixx", "ixy"):
            link["inertia"] = {**link.get("inertia", {}), key: value}
        elif key == "viscous":
            link["friction"] = {"viscous": value}
        else:
            link[key] = value
        return f"{where} link {key} = {value!r}"
    if kind == "parameter_name":
        which = rnd.choice(["{P}", "{Q}"])
        names[which] = hostile_parameter_name(draw, rnd)
        return f"parameter {which} named {names[which]!r}"
    if kind == "parameter_value":
        which = rnd.choice(["{P}", "{Q}"])
        value = rnd.choice(NUMBERS) if rnd.randrange(2) else hostile_value(draw, rnd)
        document["parameters"][which] = value
        return f"parameter {which} = {value!r}"
    if kind == "robot_name":
        document["name"] = rnd.choice(ROBOT_NAMES)
        return f"name = {document['name']!r}"
    if kind in ("title", "source"):
        document[kind] = hostile_text(draw, rnd)
        return f"{kind} = {document[kind]!r}"
    if kind == "limits":
        joint["limits"] = [hostile_value(draw, rnd), hostile_value(draw, rnd)]
        return f"{where} limits = {joint['limits']!r}"
    if kind == "gravity":
        document["gravity"] = [0, hostile_value(draw, rnd), -9.81]
        return f"gravity = {document['gravity']!r}"
    if kind == "tool":
        key = rnd.choice(["xyz", "rpy"])
        document["tool"] = {key: [hostile_value(draw, rnd), 0, 0]}
        return f"tool = {document['tool']!r}"
    if kind == "joint_name":
        joint["name"] = rnd.choice(JOINT_NAMES)
        return f"{where} name = {joint['name']!r}"
    if kind == "convention":
        document["convention"] = rnd.choice(["modified", "standard", "Modified"])
        document["angles"] = rnd.choice(["rad", "deg", "grad"])
        return f"convention {document['convention']}, angles {document['angles']}"
    key = rnd.choice(["alhpa", "type", "link"])
    joint[key] = rnd.choice(ODD_TYPES)
    return f"{where} {key} = {joint[key]!r}"


@st.composite
def robots(
    draw: st.DrawFn,
    bases: Sequence[dict[str, Any]] = BASE_ROBOTS,
    mutations: tuple[int, int] = (1, 2),
    forced: Sequence[str] = (),
) -> Robot:
    """A small valid robot with 1-2 hostile mutations (the ``forced`` kinds first)."""
    rnd = _chooser(draw)
    document = json.loads(json.dumps(rnd.choice(list(bases))))
    names: dict[str, str] = {}
    done = [mutate(draw, rnd, document, names, kind) for kind in forced]
    for _ in range(rnd.randint(*mutations)):
        done.append(mutate(draw, rnd, document, names))
    return Robot(render_robot(document, names), len(document["joints"]), tuple(done))


def _q(count: int, value: str = "0.3") -> str:
    return ",".join([value] * count)


# ---------------------------------------------------------------------------------------------
# Suites: strategies of cases
# ---------------------------------------------------------------------------------------------

ROBOT = "{tmp}/robot.toml"


def _case(argv: Sequence[str], robot: Robot, timeout: float, suite: str) -> Case:
    return Case(tuple(argv), (("robot.toml", robot.text),), timeout, suite, robot.note)


@st.composite
def show_eval_cases(draw: st.DrawFn) -> tuple[Case, ...]:
    """One mutated robot through ``show`` and ``eval --json`` (with the dynamics when every
    link has inertial data)."""
    rnd = _chooser(draw)
    dynamic = rnd.randrange(2) == 0
    robot = draw(robots(DYNAMIC_ROBOTS if dynamic else BASE_ROBOTS))
    q, dq = _q(robot.joints), _q(robot.joints, "1")
    show = ("show", ROBOT, "--json") if rnd.randrange(2) else ("show", ROBOT)
    evaluate: tuple[str, ...] = ("eval", ROBOT, "--q", q, "--json")
    if dynamic:
        evaluate += ("--dq", dq, "--dynamics")
    return tuple(_case(argv, robot, QUICK_TIMEOUT, "show_eval") for argv in (show, evaluate))


@st.composite
def derive_cases(draw: st.DrawFn) -> Case:
    rnd = _chooser(draw)
    robot = draw(robots())
    emit = rnd.choice(["numpy,c"] * 4 + ["numpy,c,python", "numpy,c,casadi"])
    argv = ["derive", ROBOT, "--out", "{tmp}/out", "--emit", emit, "--no-build"]
    if rnd.randrange(6) == 0:
        argv += ["--precision", "float"]
    if rnd.randrange(6) == 0:
        argv += ["--numeric-parameters"]
    return _case(argv, robot, DERIVE_TIMEOUT, "derive")


@st.composite
def name_cases(draw: st.DrawFn) -> Case:
    """Parameter and robot names that collide with C, Python, SymPy or generated names."""
    rnd = _chooser(draw)
    forced = rnd.choice([("parameter_name",), ("robot_name",), ("parameter_name", "robot_name")])
    robot = draw(robots(DYNAMIC_ROBOTS, mutations=(0, 0), forced=forced))
    emit = rnd.choice(["numpy,c", "numpy,c,python", "numpy,c,casadi"])
    argv = ["derive", ROBOT, "--out", "{tmp}/out", "--emit", emit, "--no-build"]
    if rnd.randrange(4) == 0:
        argv += ["--numeric-parameters"]
    return _case(argv, robot, DERIVE_TIMEOUT, "names")


@st.composite
def latex_cases(draw: st.DrawFn) -> Case:
    rnd = _chooser(draw)
    forced = rnd.choice([("title",), ("source",), ("title", "source")])
    robot = draw(robots(mutations=(0, 1), forced=forced))
    argv = ["latex", ROBOT, "-o", "{tmp}/doc/x.tex"]
    argv += rnd.choice([[], ["--shorthand"], ["--lang", "de"], ["--sections", "dh,fk"]])
    return _case(argv, robot, LATEX_TIMEOUT, "latex")


@st.composite
def ik_cases(draw: st.DrawFn) -> Case:
    rnd = _chooser(draw)
    robot = draw(robots())
    target = rnd.choice(["0.3,0.2", "0.3,0.2,0.1", "0.5,0,0", "1e308,0,0", "0,0"])
    argv = ["ik", ROBOT, "--target", target, "--restarts", "2"]
    argv += rnd.choice([[], ["--json"], ["--all"], ["--method", "newton"]])
    return _case(argv, robot, QUICK_TIMEOUT, "ik")


NUMBER_TEXTS = (
    "0", "0.3", "-0.3", "1e308", "-1e308", "1e309", "nan", "NaN", "inf", "-inf", "", " ",
    "1deg", "1e308deg", "nandeg", "0x10", "1_0", "1e-320", "--1", "+1", "1,", "\u0661", "1e",
    "pi", "1/2", "9" * 400, "0.3rad",
)  # fmt: skip
HONEST_NUMBERS = ("0.3", "-0.2", "1", "0", "45deg", "0.1", "-1", "2.5", "1e-3")


def _vector(rnd: random.Random, honest: int = 2) -> str:
    """Comma-separated values, usually 2 (the argument robot's joints), 2 in 3 honest."""
    count = rnd.choice([2, 2, 2, 2, 2, 2, 1, 3, 0])
    pool = [HONEST_NUMBERS] * honest + [NUMBER_TEXTS]
    return ",".join(rnd.choice(rnd.choice(pool)) for _ in range(count))


@st.composite
def argument_cases(draw: st.DrawFn) -> Case:
    """Fuzzed options of every command on one honest 2-joint robot with inertial data."""
    rnd = _chooser(draw)
    robot = render_robot(DYNAMIC_ROBOTS[1])
    command = rnd.choice(["eval", "eval", "eval", "ik", "ik", "latex", "derive", "show"])
    argv: list[str] = [command, ROBOT]
    timeout = QUICK_TIMEOUT
    if command == "eval":
        argv += ["--q", _vector(rnd)]
        if rnd.randrange(2):
            argv += ["--dq", _vector(rnd)]
            if rnd.randrange(2):
                argv += ["--ddq", _vector(rnd)]
        for option, choices in (("--set", SET_VALUES), ("--point", POINTS), ("--task", TASKS)):
            if rnd.randrange(3) == 0:
                argv += [option, rnd.choice(choices)]
        argv += rnd.choice([["--json"], ["--json", "--dynamics"], ["--dynamics"], []])
    elif command == "ik":
        argv += ["--target", _vector(rnd).replace("45deg", "0.5")]
        argv += ["--restarts", rnd.choice(["2", "2", "2", "0", "-1", "1"])]
        for option, choices in IK_OPTIONS:
            if rnd.randrange(3) == 0:
                argv += [option, rnd.choice(choices)]
        argv += rnd.choice([[], ["--json"], ["--all"]])
    elif command == "latex":
        argv += ["-o", rnd.choice(OUTPUT_FILES)]
        if rnd.randrange(3) == 0:
            argv += ["--text-width", rnd.choice(["0", "-1", "nan", "1e308", "0.001", "12"])]
        if rnd.randrange(2):
            argv += ["--q", _vector(rnd)]
        if rnd.randrange(3) == 0:
            argv += ["--sections", rnd.choice(["dh,fk", "fk", "dh,dh", "dynamics", "", ",", "DH"])]
        timeout = LATEX_TIMEOUT
    elif command == "derive":
        argv += ["--out", rnd.choice(OUTPUT_FOLDERS)]
        argv += ["--emit", rnd.choice(["numpy", "c", "", ",", "numpy,numpy", "C", "c,latex"])]
        argv += rnd.choice([["--no-build"]] * 3 + [["--no-build", "--precision", "half"]])
        if rnd.randrange(2):
            argv += ["--numeric-parameters", "--set", rnd.choice(SET_VALUES)]
        timeout = DERIVE_TIMEOUT
    else:
        argv += ["--task", rnd.choice(TASKS)]
        argv += rnd.choice([[], ["--json"], ["--dynamics"]])
    files = [("robot.toml", robot), ("afile", "not a folder\n")]
    return Case(tuple(argv), tuple(files), timeout, "arguments")


SET_VALUES = (
    "L1=0.4", "L2=0.3", "L1=1e-300", "L1=1e300", "L1=-0.5", "L1=nan", "L1=inf", "L1=1e308",
    "L1=", "=1", "L1", "L1=1=2", "M=1", "q1=1", "L1=1deg", "L2=-1e308", "m1=1", "L1=0.5,L2=1",
)  # fmt: skip
POINTS = ("1:0,0,0", "2:0.1,0,0", "3:0,0,0", "0:0,0,0", "-1:0,0,0", "1:nan,0,0", "1:1e308,0,0", ":")
TASKS = ("x,y", "xy", "x,y,z,wx,wy,wz", "", ",", "x,x", "q", "X", "wz")
IK_OPTIONS = (
    ("--seed", ("-1", "0", "7", "4294967296", "18446744073709551616", "-9223372036854775809")),
    ("--tolerance", ("0", "-1", "nan", "inf", "1e-300", "1e308", "1e-6")),
    ("--q0", ("0,0", "0.5,0.5", "nan,0", "1e308,1e308", "0", "")),
    ("--method", ("newton", "lm")),
    ("--task", TASKS),
)
OUTPUT_FILES = (
    "{tmp}/x.tex", "{tmp}/sub/dir/x.tex", "{tmp}/", "{tmp}", "{tmp}/x", "{tmp}/\xfcn\xeff.tex",
    "{tmp}/-x.tex", "{tmp}/a b.tex", "{tmp}/afile/x.tex", "{tmp}/robot.toml", "", "{tmp}/%.tex",
    "{tmp}/a\nb.tex",
)  # fmt: skip
OUTPUT_FOLDERS = ("{tmp}/out", "{tmp}/afile", "{tmp}/robot.toml", "", "{tmp}/a b/c", "{tmp}/a\nb")


@st.composite
def raw_file_cases(draw: st.DrawFn) -> Case:
    """Bytes-level damage to a valid file, and odd whole files; loaded with ``show``."""
    rnd = _chooser(draw)
    text = render_robot(rnd.choice(BASE_ROBOTS)).encode()
    kind = rnd.choice(["truncate", "insert", "replace", "random", "special"])
    if kind == "truncate":
        data = text[: rnd.randrange(len(text))]
    elif kind in ("insert", "replace"):
        at = rnd.randrange(len(text))
        piece = draw(st.binary(min_size=1, max_size=4))
        data = text[:at] + piece + text[at + (len(piece) if kind == "replace" else 0) :]
    elif kind == "random":
        data = draw(st.binary(max_size=200))
    else:
        data = rnd.choice(SPECIAL_FILES)
    argv = rnd.choice([("show", ROBOT), ("show", ROBOT, "--json")])
    return Case(argv, (("robot.toml", data),), QUICK_TIMEOUT, "raw_files", kind)


SPECIAL_FILES = (
    b"",
    b"\xef\xbb\xbf" + render_robot(BASE_ROBOTS[0]).encode(),
    render_robot(BASE_ROBOTS[0]).encode("utf-16"),
    b"a = " + b"[" * 5000 + b"]" * 5000,
    b"a = " + b"{b = " * 3000 + b"1" + b"}" * 3000,
    b'name = "arm"\n[[joints]]\ntype = "revolute"\na = ' + b"9" * 5000 + b"\n",
    b'name = "arm"\n' + b'[[joints]]\ntype = "revolute"\n' * 3000,
    b"\x00" * 100,
    b'name = "arm"\n[[joints]]\ntype = "revolute"\na = 1979-05-27T07:32:00Z\n',
)


SUITES: dict[str, tuple[Callable[[], st.SearchStrategy[Any]], int]] = {
    "show_eval": (show_eval_cases, 16),  # two cases per example
    "derive": (derive_cases, 16),
    "names": (name_cases, 12),
    "latex": (latex_cases, 14),
    "ik": (ik_cases, 10),
    "arguments": (argument_cases, 26),
    "raw_files": (raw_file_cases, 12),
}


def draw_cases(
    strategy: st.SearchStrategy[Case | tuple[Case, ...]], max_examples: int
) -> list[Case]:
    """A fixed list of distinct cases drawn by Hypothesis (derandomized, no shrinking); an
    example may be one case or a tuple of cases."""
    cases: list[Case] = []

    @settings(
        max_examples=max_examples,
        derandomize=True,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def collect(example: Case | tuple[Case, ...]) -> None:
        for case in example if isinstance(example, tuple) else (example,):
            if case not in cases:
                cases.append(case)

    collect()
    return cases


def suite_cases(name: str) -> list[Case]:
    factory, count = SUITES[name]
    return draw_cases(factory(), count)


def run_suite(name: str, jobs: int = JOBS) -> list[Outcome]:
    return run_cases(suite_cases(name), jobs)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Run the symkin CLI fuzz suites and count.")
    parser.add_argument("--report", action="store_true", help="print every non-clean case too")
    parser.add_argument("suites", nargs="*", metavar="SUITE", help=", ".join(SUITES))
    args = parser.parse_args(argv)
    unknown = set(args.suites) - set(SUITES)
    if unknown:
        parser.error(f"unknown suite(s) {', '.join(sorted(unknown))}; choose from {list(SUITES)}")
    args.suites = args.suites or list(SUITES)
    total: list[Outcome] = []
    start = time.monotonic()
    for name in args.suites:
        outcomes = run_suite(name)
        total.extend(outcomes)
        print(format_tally(tally(outcomes), name), flush=True)
        if args.report and any(not o.clean for o in outcomes):
            print(failure_report(outcomes, limit=100), flush=True)
    print(format_tally(tally(total), "all suites"))
    print(f"{time.monotonic() - start:.0f} s with {JOBS} jobs")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The derivation cache on disk: a command's text products, keyed by what shapes them.

What is stored is *text*: the report of ``symkin show``, the ``{path: text}`` files of
``symkin derive`` and ``symkin latex``.  Those are the end of the costly chain (derivation,
simplification, CSE, printing), so a warm command skips all of it; and text comes back with
``json.loads`` alone: nothing read from the cache is parsed as an expression, imported or
executed (no pickle, no ``sympify``), so a tampered entry can at worst be wrong text.

The key (:func:`entry_key`) is a SHA-256 of the robot's content (every compared field of
:class:`~symkin.robot.Robot`, in ``srepr`` form; not its file path or time: a caller whose
text names the path puts it in ``options``), the command's options that shape the text, the
symkin, SymPy, SymEngine, NumPy and Jinja2 versions, and a digest of symkin's own source
files (a development checkout changes code without changing its version).

Safety (see docs/security.md): the directory is ``$XDG_CACHE_HOME/symkin`` (an absolute
``XDG_CACHE_HOME``), else ``~/.cache/symkin``, created with mode 0700; a directory or entry
not owned by the user or writable by group or others is ignored, as is an entry that is not
valid JSON of this format and key (truncated, garbage, another version): it is rebuilt.
Writes go to a temporary file in the same directory and ``os.replace`` it, so two processes
deriving the same robot at once both succeed and leave one valid entry.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import stat
import sys
import tempfile
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path

import sympy as sp

from symkin.errors import BudgetWarning, RobotWarning, SymkinError
from symkin.output_folder import check_relative
from symkin.progress import detail
from symkin.robot import Robot

__all__ = ["DISABLE_VARIABLE", "DiskCache", "entry_key", "remembered", "user_cache"]

# Bump when the entry layout or the key's recipe changes: older entries are then ignored.
FORMAT = 2
# Set (to anything but "" or "0") to turn the cache off, e.g. for a test suite.
DISABLE_VARIABLE = "SYMKIN_NO_CACHE"

Text = str | dict[str, str]

# The warning classes an entry may name (by name, looked up here: never imported from the
# entry); a templated one keeps its template, so the front end spells its parameters as on
# the cold run.  Any other class is given again as a UserWarning.
PLAIN_WARNINGS = {"RobotWarning": RobotWarning, "RuntimeWarning": RuntimeWarning}


def cache_directory(environ: Mapping[str, str] = os.environ) -> Path:
    """``$XDG_CACHE_HOME/symkin``, else ``~/.cache/symkin`` (the XDG Base Directory spec:
    a relative ``XDG_CACHE_HOME`` is invalid and ignored)."""
    base = environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if os.path.isabs(base) else Path.home() / ".cache"
    return root / "symkin"


def _canonical(value: object) -> str:
    """Deterministic text of a robot's content: dataclass fields that take part in equality
    (so not ``Robot.file``), SymPy objects by ``srepr``, the rest by ``repr``."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        parts = (
            f"{f.name}={_canonical(getattr(value, f.name))}"
            for f in dataclasses.fields(value)
            if f.compare
        )
        return f"{type(value).__name__}({', '.join(parts)})"
    if isinstance(value, sp.Basic):
        return sp.srepr(value)
    if isinstance(value, tuple | list):
        return "(" + ", ".join(_canonical(v) for v in value) + ")"
    return repr(value)


@cache
def _software() -> dict[str, str]:
    """Versions and the source digest that shape every result."""
    versions = {}
    # NumPy prints number literals, Jinja2 renders the templates: both shape the text.
    for package in ("symkin", "sympy", "symengine", "numpy", "jinja2"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = "none"
    digest = hashlib.sha256()
    package_root = Path(__file__).parent
    # followlinks: a development checkout links templates/ into the package.
    for folder, subfolders, names in os.walk(package_root, followlinks=True):
        subfolders[:] = sorted(s for s in subfolders if s != "__pycache__")
        for name in sorted(names):
            path = Path(folder, name)
            digest.update(path.relative_to(package_root).as_posix().encode() + b"\0")
            # A dangling link (a removed file in a checkout) is named, not read.
            digest.update(path.read_bytes() if path.is_file() else b"\0dangling\0")
    python = f"{sys.version_info.major}.{sys.version_info.minor}"
    return versions | {"python": python, "source": digest.hexdigest()}


def entry_key(kind: str, robot: Robot, options: Mapping[str, object]) -> str:
    """SHA-256 (hex) of everything that shapes the ``kind`` product of ``robot``."""
    recipe = {
        "format": FORMAT,
        "kind": kind,
        "robot": _canonical(robot),
        "options": dict(options),
        "software": _software(),
    }
    text = json.dumps(recipe, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def _unsafe(status: os.stat_result) -> str | None:
    """Why a file or directory must not be trusted, or None."""
    if status.st_uid != os.geteuid():
        return "is not owned by you"
    if status.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return "is writable by group or others"
    return None


def _is_text(value: object) -> bool:
    return isinstance(value, str) or (
        isinstance(value, dict) and all(isinstance(v, str) for v in value.values())
    )


def _is_file_map(value: object) -> bool:
    """Text, or ``{path: text}`` whose every path is a plain relative one (no ``..``, not
    absolute): an entry naming a file outside the output folder is not an entry of ours."""
    if isinstance(value, str):
        return True
    try:
        return _is_text(value) and all(check_relative(path) for path in value)
    except SymkinError:
        return False


def _warnings_of(entry: dict) -> list[dict[str, str]] | None:
    """The entry's ``[{"category": name, "text": message or template}]``, or None if malformed."""
    said = entry.get("warnings")
    ok = isinstance(said, list) and all(
        isinstance(w, dict) and set(w) == {"category", "text"} and _is_text(w) for w in said
    )
    return said if ok else None


def warning_record(message: Warning) -> dict[str, str]:
    """What an entry keeps of a warning: its class name and its text (a template if it has one)."""
    if isinstance(message, BudgetWarning):
        return {"category": "BudgetWarning", "text": message.template}
    return {"category": type(message).__name__, "text": str(message)}


def warning_from_record(record: Mapping[str, str]) -> Warning:
    """The warning :func:`warning_record` kept, rebuilt from the allow-listed classes only."""
    name, text = record["category"], record["text"]
    if name == "BudgetWarning":
        return BudgetWarning(text)
    return PLAIN_WARNINGS.get(name, UserWarning)(text)


@dataclass(frozen=True)
class DiskCache:
    """One cache directory, already checked (see :func:`user_cache`)."""

    directory: Path

    def path(self, kind: str, key: str) -> Path:
        return self.directory / f"{kind}-{key}.json"

    def load(self, kind: str, key: str) -> tuple[Text, list[dict[str, str]]] | None:
        """The stored text and the warnings its derivation gave, or None: missing, unsafe or
        not a valid entry of this format and key (never an exception)."""
        path = self.path(kind, key)
        try:
            descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
        except FileNotFoundError:
            return None
        except OSError as error:
            detail(f"cache: cannot read {path} ({error.strerror}); deriving")
            return None
        with os.fdopen(descriptor, "rb") as file:
            status = os.fstat(file.fileno())
            why = "is not a regular file" if not stat.S_ISREG(status.st_mode) else None
            why = why or _unsafe(status)
            if why:
                detail(f"cache: ignoring {path}: it {why}")
                return None
            raw = file.read()
        try:
            entry = json.loads(raw.decode("utf-8"))
        except ValueError:  # truncated or garbage (JSONDecodeError, UnicodeDecodeError)
            entry = None
        valid = isinstance(entry, dict) and (entry.get("format"), entry.get("key")) == (
            FORMAT,
            key,
        )
        if not valid or not _is_file_map(entry.get("value")) or _warnings_of(entry) is None:
            detail(f"cache: ignoring {path}: not a valid entry of this symkin; rebuilding it")
            return None
        return entry["value"], _warnings_of(entry)

    def store(self, kind: str, key: str, value: Text, said: list[dict[str, str]]) -> None:
        """Write atomically: a temporary file in the same directory, then ``os.replace``
        (readers see the old entry or the new one, never half of one; an interrupted write
        leaves neither an entry nor its temporary file)."""
        entry = {"format": FORMAT, "kind": kind, "key": key, "warnings": said, "value": value}
        try:
            descriptor, temporary = tempfile.mkstemp(
                prefix=f".{kind}-", suffix=".tmp", dir=self.directory
            )
        except OSError as error:
            detail(f"cache: cannot write to {self.directory} ({error.strerror})")
            return
        try:
            with os.fdopen(descriptor, "w", encoding="utf-8") as file:
                json.dump(entry, file)
            os.replace(temporary, self.path(kind, key))
            detail(f"cache: stored {self.path(kind, key)}")
        except BaseException as error:  # also Ctrl-C and the --time-limit alarm
            Path(temporary).unlink(missing_ok=True)
            if not isinstance(error, OSError):
                raise
            detail(f"cache: cannot write {self.path(kind, key)} ({error.strerror})")


def user_cache(environ: Mapping[str, str] = os.environ) -> DiskCache | None:
    """The user's cache directory (created 0700), or None when it is turned off by
    ``SYMKIN_NO_CACHE`` or must not be trusted (said once, as a verbose detail)."""
    if environ.get(DISABLE_VARIABLE, "") not in ("", "0"):
        return None
    directory = cache_directory(environ)
    try:
        directory.parent.mkdir(parents=True, exist_ok=True)
        directory.mkdir(mode=0o700, exist_ok=True)
        # lstat: a symbolic link is refused, not followed (its owner could repoint it after
        # this check); set XDG_CACHE_HOME to keep the cache elsewhere.
        status = directory.lstat()
    except OSError as error:
        detail(f"cache: not used: cannot create {directory} ({error.strerror})")
        return None
    why = "is not a directory" if not stat.S_ISDIR(status.st_mode) else _unsafe(status)
    why = "is a symbolic link" if stat.S_ISLNK(status.st_mode) else why
    if why:
        detail(f"cache: not used: {directory} {why}")
        return None
    return DiskCache(directory)


def remembered(
    cache: DiskCache | None,
    kind: str,
    robot: Robot,
    options: Mapping[str, object],
    compute: Callable[[], Text],
) -> Text:
    """``compute()``, or its stored text when ``cache`` holds an entry for this key.

    The warnings ``compute`` gave are stored with the text and given again on a hit, so a
    warm run says what the cold one said (see :func:`warning_record` for what is kept).
    """
    if cache is None:
        return compute()
    key = entry_key(kind, robot, options)
    found = cache.load(kind, key)
    if found is not None:
        detail(f"cache: {kind} of {robot.name} from {cache.path(kind, key)}")
        value, said = found
        for record in said:
            warnings.warn(warning_from_record(record), stacklevel=2)
        return value
    said: list[Warning] = []
    show = warnings.showwarning

    def keep_and_show(message: Warning, *where: object, **more: object) -> None:
        # Shown as it comes (a long derivation's early warning is not held back to its end).
        said.append(message)
        show(message, *where, **more)

    with warnings.catch_warnings():
        warnings.showwarning = keep_and_show
        value = compute()
    cache.store(kind, key, value, [warning_record(message) for message in said])
    return value

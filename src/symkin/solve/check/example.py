"""The worked-example file of ``symkin check`` (TOML; the format is in docs/worked-examples.md).

::

    title = "SCARA: Jacobian and determinant"
    source = "where the printed numbers come from"
    robot = "scara"            # catalogue name or a robot file, relative to this file
    angles = "deg"             # revolute q and printed angles in deg (default) or rad
    lang = "en"                # "de": the corrected LaTeX with decimal commas
    [set]                      # parameter values, as --set
    L1 = 0.325

    [[check]]
    quantity = "det"           # one of CHECKS
    q = [0, 90, 0.1]
    printed = "0.0731"         # a number, a list, or a list of rows, as printed

Numbers may be written as strings to keep the printed digits (``"0.8660"``): the tolerance is
half a unit of the last printed digit (:mod:`symkin.solve.check.printed`).
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symkin.errors import SymkinError
from symkin.io.robot_file import MAX_FILE_BYTES
from symkin.solve.check.printed import PrintedNumber, printed_number, with_neighbours

#: quantity -> extra keys it takes (besides quantity, name, q, printed)
CHECKS: Mapping[str, tuple[str, ...]] = {
    "T": (),
    "position": (),
    "euler_zyx": (),
    "jacobian": (),
    "task_jacobian": ("rows",),
    "det": ("rows",),
    "inverse": ("rows",),
    "point_position": ("link", "point"),
    "point_velocity": ("link", "point", "dq"),
    "point_acceleration": ("link", "point", "dq", "ddq"),
    "rotation_zyx": ("euler",),
    "rotation_zyz": ("euler",),
    "path_table": ("from", "to", "steps", "q0", "rows"),
}
NEEDS_Q = frozenset(CHECKS) - {"rotation_zyx", "rotation_zyz", "path_table"}
NEEDS_ROBOT = frozenset(CHECKS) - {"rotation_zyx", "rotation_zyz"}
TOP_KEYS = ("title", "source", "robot", "angles", "lang", "set", "check")


@dataclass(frozen=True)
class Check:
    """One printed result: ``printed`` keeps the table's shape (a list of rows, a list, or
    one number); ``options`` are the quantity's extra keys as written."""

    index: int
    quantity: str
    name: str
    q: tuple[float, ...] | None
    printed: tuple[tuple[PrintedNumber, ...], ...]
    shape: str  # "scalar", "vector" or "matrix"
    options: Mapping[str, Any] = field(default_factory=dict)
    labels: tuple[str, ...] = ()  # path_table: the row labels (0, 1, ..., 5a)


@dataclass(frozen=True)
class WorkedExample:
    """The example file, read and checked for form (not yet recomputed)."""

    path: Path
    title: str
    source: str
    robot: str | None
    degrees: bool
    lang: str
    overrides: Mapping[str, float]
    checks: tuple[Check, ...]


def read_example(path: str | Path) -> WorkedExample:
    """Read and validate an example file; :class:`SymkinError` names the file and the check."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise SymkinError(f"{path}: larger than {MAX_FILE_BYTES} bytes")
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SymkinError(f"{path}: cannot read it ({exc.strerror or exc})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SymkinError(f"{path}: not valid TOML ({exc})") from None
    unknown = sorted(set(document) - set(TOP_KEYS))
    if unknown:
        raise SymkinError(f"{path}: unknown key {unknown[0]!r}; expected {', '.join(TOP_KEYS)}")
    angles = document.get("angles", "deg")
    lang = document.get("lang", "en")
    if angles not in ("deg", "rad") or lang not in ("en", "de"):
        raise SymkinError(f"{path}: 'angles' must be deg or rad and 'lang' en or de")
    checks = document.get("check", [])
    if not isinstance(checks, list) or not checks:
        raise SymkinError(f"{path}: no [[check]] tables: nothing to check")
    robot = document.get("robot")
    if robot is not None and not isinstance(robot, str):
        raise SymkinError(f"{path}: 'robot' must be a catalogue name or a file path")
    if isinstance(robot, str) and (robot.endswith((".toml", ".urdf")) or "/" in robot):
        robot = str((path.parent / robot).resolve())
    parsed = tuple(_check(c, i, f"{path}: check {i}") for i, c in enumerate(checks, start=1))
    if robot is None and any(c.quantity in NEEDS_ROBOT for c in parsed):
        raise SymkinError(f"{path}: give 'robot' for the checks of a robot's quantities")
    return WorkedExample(
        path=path,
        title=str(document.get("title", "")),
        source=str(document.get("source", "")),
        robot=robot,
        degrees=angles == "deg",
        lang=lang,
        overrides=_overrides(document.get("set", {}), f"{path}: [set]"),
        checks=parsed,
    )


def _overrides(table: Any, where: str) -> dict[str, float]:
    if not isinstance(table, dict):
        raise SymkinError(f"{where} must be a table of NAME = value")
    return {str(k): printed_number(v, f"{where} {k}").value for k, v in table.items()}


def _check(table: Any, index: int, where: str) -> Check:
    if not isinstance(table, dict):
        raise SymkinError(f"{where}: expected a table")
    quantity = table.get("quantity")
    if quantity not in CHECKS:
        raise SymkinError(
            f"{where}: 'quantity' must be one of {', '.join(CHECKS)}, got {quantity!r}"
        )
    allowed = {"quantity", "name", "q", "printed", *CHECKS[quantity]}
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise SymkinError(f"{where}: {quantity} takes no key {unknown[0]!r}")
    q = None
    if quantity in NEEDS_Q:
        if "q" not in table:
            raise SymkinError(f"{where}: {quantity} needs 'q', the joint values")
        q = tuple(printed_number(v, f"{where} q").value for v in _list(table["q"], where, "q"))
    if "printed" not in table:
        raise SymkinError(f"{where}: 'printed' (the values as the book prints them) is missing")
    labels: tuple[str, ...] = ()
    printed = table["printed"]
    if quantity == "path_table":
        rows = [_list(row, where, "printed row") for row in _list(printed, where, "printed")]
        labels = tuple(str(row[0]) for row in rows)
        printed = [row[1:] for row in rows]
    shape, numbers = _numbers(printed, where)
    options = {k: table[k] for k in CHECKS[quantity] if k in table}
    name = str(table.get("name", quantity))
    return Check(index, quantity, name, q, numbers, shape, options, labels)


def _list(value: Any, where: str, key: str) -> list:
    if not isinstance(value, list) or not value:
        raise SymkinError(f"{where}: {key!r} must be a non-empty list")
    return value


def _numbers(printed: Any, where: str) -> tuple[str, tuple[tuple[PrintedNumber, ...], ...]]:
    """The printed values as rows of numbers; integers take their neighbours' precision."""
    if isinstance(printed, list) and printed and all(isinstance(r, list) for r in printed):
        shape, rows = "matrix", printed
        if len({len(r) for r in rows}) != 1:
            raise SymkinError(f"{where}: the printed rows have different lengths")
    elif isinstance(printed, list):
        shape, rows = "vector", [printed]
    else:
        shape, rows = "scalar", [[printed]]
    numbers = [printed_number(v, f"{where} printed") for row in rows for v in row]
    numbers = with_neighbours(numbers)
    width = len(rows[0])
    return shape, tuple(tuple(numbers[i : i + width]) for i in range(0, len(numbers), width))

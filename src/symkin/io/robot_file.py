"""Robot description files (TOML) -> :class:`symkin.robot.Robot`.

The format is described for users in ``docs/robot-files.md``.  Everything a file can get wrong
is reported as one :class:`~symkin.errors.RobotError` whose message names the file, the joint
(1-based) and the key, and says what was expected::

    robots/arm.toml: joint 2: 'type' must be "revolute" or "prismatic", got "rotary"

No other exception escapes for any file content; anything else would be a bug here.

Values and formula strings are read by :mod:`symkin.io.expressions`, the tables by
:mod:`symkin.io.robot_tables`; this module finds and reads the file and assembles the robot.
"""

from __future__ import annotations

import stat
import tomllib
from collections.abc import Mapping
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any

import sympy as sp

from symkin.errors import RobotError
from symkin.io.context import Context, check_keys, did_you_mean, read_choice, read_text, show
from symkin.io.inertia_tables import joints_with_payload
from symkin.io.placement import canonical_joints
from symkin.io.poses import read_poses
from symkin.io.robot_tables import (
    check_link_symbol_clash,
    read_frame,
    read_joints,
    read_parameters,
    read_payload,
    read_placed_joints,
    read_vector,
)
from symkin.io.urdf import robot_from_urdf
from symkin.names import robot_name_reason
from symkin.robot import MAX_NAME_LENGTH, NAME_PATTERN, Robot
from symkin.symbols import parameter_symbol

__all__ = ["catalogue_names", "load_robot", "robot_from_toml"]

# ---------------------------------------------------------------------------------------------
# Allowed top-level keys (the tables' keys are in robot_tables).  Anything else is an error
# with a "did you mean" hint.
# ---------------------------------------------------------------------------------------------

TOP_KEYS = (
    "name", "title", "source", "convention", "angles", "gravity",
    "parameters", "joints", "tool", "base", "poses", "payload",
)  # fmt: skip
CONVENTIONS = ("standard", "modified", "placement")
ANGLE_UNITS = ("deg", "rad")

CATALOGUE_DIR = "robots"
# A 100-joint robot with full inertial data is about 60 KiB.
MAX_FILE_BYTES = 1024 * 1024
# URDFs carry visuals, collisions and simulator tags besides the chain (a humanoid: ~1 MiB).
MAX_URDF_BYTES = 16 * 1024 * 1024
ROBOT_FILE_KIND = "a robot file is a short .toml or .urdf text"


# ---------------------------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------------------------


def catalogue_names() -> list[str]:
    """Names of the built-in robots (``src/symkin/robots/<name>.toml``), sorted."""
    directory = resources.files("symkin") / CATALOGUE_DIR
    if not directory.is_dir():
        return []
    return sorted(
        entry.name.removesuffix(".toml")
        for entry in directory.iterdir()
        if entry.name.endswith(".toml") and entry.is_file()
    )


def load_robot(
    name_or_path: str | Path, *, tip: str | None = None, base: str | None = None
) -> Robot:
    """Load a robot by catalogue name (``"scara"``), from a ``.toml`` robot file or from a
    ``.urdf`` file (:mod:`symkin.io.urdf`).

    A :class:`~pathlib.Path`, or a string ending in ``.toml`` or ``.urdf`` or containing a path
    separator, is a file; any other string is a catalogue name.  ``tip`` and ``base`` name the
    links a URDF's chain runs between (needed when its tree has several leaves).  Raises
    :class:`RobotError` for unknown names, unreadable files and invalid content.
    """
    is_urdf = _looks_like_path(name_or_path) and _is_urdf(Path(name_or_path))
    if (tip is not None or base is not None) and not is_urdf:
        raise RobotError(f"{name_or_path}: a tip or base link is chosen in URDF files only")
    if _looks_like_path(name_or_path):
        return _load_path(Path(name_or_path), str(name_or_path), tip, base)
    return _load_catalogue(str(name_or_path))


def robot_from_toml(text: str, file: str) -> Robot:
    """Build a robot from TOML ``text``; ``file`` names it in error messages and ``Robot.file``."""
    document = _parse_toml(text, file)
    return _robot_from_document(document, file)


# ---------------------------------------------------------------------------------------------
# Finding and reading files
# ---------------------------------------------------------------------------------------------


def _looks_like_path(name_or_path: str | Path) -> bool:
    if isinstance(name_or_path, Path):
        return True
    lower = name_or_path.lower()
    return lower.endswith((".toml", ".urdf")) or "/" in name_or_path or "\\" in name_or_path


def _is_urdf(path: Path) -> bool:
    return path.suffix.lower() == ".urdf"


def _load_path(path: Path, shown: str, tip: str | None = None, base: str | None = None) -> Robot:
    limit = MAX_URDF_BYTES if _is_urdf(path) else MAX_FILE_BYTES
    try:
        data = read_limited(path, shown, limit)
    except OSError as exc:
        hint = ""
        if path.stem in catalogue_names() and not path.exists():
            hint = f" (to load the built-in robot give just its name: {path.stem!r})"
        raise RobotError(f"{shown}: cannot read the file: {exc.strerror or exc}{hint}") from None
    if _is_urdf(path):
        return robot_from_urdf(data, shown, tip=tip, base=base)
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark some editors write is dropped
    except UnicodeDecodeError:
        raise RobotError(f"{shown}: the file is not UTF-8 text") from None
    return robot_from_toml(text, shown)


def read_limited(
    path: Path, shown: str, limit: int = MAX_FILE_BYTES, kind: str = ROBOT_FILE_KIND
) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (``/dev/zero``, a pipe or a
    folder would otherwise be read until memory runs out, or block).  ``kind`` says in the
    messages what the file should be.  Raises :class:`RobotError`; ``OSError`` passes."""
    info = path.stat()
    if not stat.S_ISREG(info.st_mode):
        raise RobotError(f"{shown}: not a regular file ({kind})")
    with path.open("rb") as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise RobotError(f"{shown}: the file is larger than {limit // 1024:,} KiB ({kind})")
    return data


def _load_catalogue(name: str) -> Robot:
    names = catalogue_names()
    if name not in names:
        raise RobotError(_unknown_robot_message(name, names))
    entry = resources.files("symkin") / CATALOGUE_DIR / f"{name}.toml"
    return robot_from_toml(entry.read_text(encoding="utf-8"), f"{CATALOGUE_DIR}/{name}.toml")


def _unknown_robot_message(name: str, names: list[str]) -> str:
    listing = ", ".join(names) if names else "(the catalogue is empty)"
    return (
        f"unknown robot {name!r}{did_you_mean(name, names)}; catalogue robots: {listing}; "
        "to load a file give a path ending in .toml or .urdf"
    )


def _parse_toml(text: str, file: str) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotError(f"{file}: not valid TOML: {exc}") from None
    except RecursionError:
        raise RobotError(f"{file}: not valid TOML: arrays or tables nested too deeply") from None
    except ValueError as exc:  # e.g. an integer literal longer than Python converts
        raise RobotError(f"{file}: not valid TOML: {exc}") from None


# ---------------------------------------------------------------------------------------------
# The whole document
# ---------------------------------------------------------------------------------------------


def _robot_from_document(document: dict[str, Any], file: str) -> Robot:
    ctx = Context(file)
    check_keys(document, TOP_KEYS, ctx)
    name = _robot_name(document, ctx)
    angles = read_choice(document, "angles", ANGLE_UNITS, ctx)
    convention = read_choice(document, "convention", CONVENTIONS, ctx)
    parameters = read_parameters(document.get("parameters", {}), ctx)
    ctx = replace(
        ctx,
        angles=angles,
        symbols={n: parameter_symbol(n) for n, _ in parameters},
        values=dict(parameters),
    )
    extra: dict[str, Any] = {}
    if "gravity" in document:
        extra["gravity"] = read_vector(document["gravity"], "gravity", 3, ctx)
    for key in ("base", "tool"):
        if key in document:
            extra[key] = read_frame(document[key], key, ctx)
    if convention == "placement":
        placed, axes = read_placed_joints(document, ctx)
        joints, extra["tool"] = canonical_joints(placed, axes, extra.get("tool", sp.eye(4)))
    else:
        joints = read_joints(document, ctx)
    check_link_symbol_clash(parameters, joints, ctx)
    if "payload" in document:
        payload = read_payload(document["payload"], ctx)
        joints = joints_with_payload(joints, payload, extra.get("tool", sp.eye(4)), ctx)
    if "poses" in document:
        extra["poses"] = read_poses(document["poses"], joints, ctx)
    extra["title"] = read_text(document, "title", ctx)
    extra["source"] = read_text(document, "source", ctx)
    try:
        return Robot(
            name=name,
            joints=joints,
            convention=convention,  # type: ignore[arg-type]
            parameters=parameters,
            file=file,
            **extra,
        )
    except RobotError as exc:  # the dataclass checks do not know the file name
        raise ctx.error(str(exc)) from None


def _robot_name(document: Mapping[str, Any], ctx: Context) -> str:
    if "name" not in document:
        raise ctx.error("'name' is missing; give the robot a name matching [a-z][a-z0-9_]*")
    name = document["name"]
    if not isinstance(name, str) or not NAME_PATTERN.match(name):
        raise ctx.error(f"'name' must match [a-z][a-z0-9_]*, got {show(name)}")
    if len(name) > MAX_NAME_LENGTH:
        raise ctx.error(
            f"'name' has {len(name)} characters; at most {MAX_NAME_LENGTH} (it starts the "
            "generated files' names and C symbols)"
        )
    reason = robot_name_reason(name)
    if reason:
        raise ctx.error(f"'name' {show(name)} is reserved ({reason}); rename the robot")
    return name

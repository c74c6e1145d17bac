"""Robot description files (TOML) -> :class:`symkin.robot.Robot`.

The format is described for users in ``docs/robot-files.md``.  Everything a file can get wrong
is reported as one :class:`~symkin.errors.RobotError` whose message names the file, the joint
(1-based) and the key, and says what was expected::

    robots/arm.toml: joint 2: 'type' must be "revolute" or "prismatic", got "rotary"

No other exception escapes for any file content; anything else would be a bug here.

Values become SymPy expressions.  Strings are parsed by walking Python's ``ast`` with a small
whitelist (numbers, declared parameter names, ``pi``, unary ``+``/``-``, binary ``+ - * / **``,
parentheses); user text is never passed to ``eval`` or ``sympify``.
"""

from __future__ import annotations

import ast
import difflib
import json
import keyword
import math
import re
import stat
import tomllib
import warnings
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from symkin.errors import RobotError, RobotWarning
from symkin.names import reserved_reason, robot_name_reason
from symkin.robot import NAME_PATTERN, Joint, Link, Robot
from symkin.symbols import parameter_symbol

__all__ = ["catalogue_names", "load_robot", "robot_from_toml"]

# ---------------------------------------------------------------------------------------------
# Allowed keys, per level of the file.  Anything else is an error with a "did you mean" hint.
# ---------------------------------------------------------------------------------------------

TOP_KEYS = (
    "name", "title", "source", "convention", "angles", "gravity",
    "parameters", "joints", "tool", "base",
)  # fmt: skip
JOINT_KEYS = ("type", "name", "theta", "d", "a", "alpha", "limits", "link")
FRAME_KEYS = ("xyz", "rpy")
LINK_KEYS = ("mass", "com", "inertia", "motor_inertia", "friction")
INERTIA_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
FRICTION_KEYS = ("coulomb", "viscous", "stribeck")
STRIBECK_KEYS = ("static", "velocity")

JOINT_TYPES = ("revolute", "prismatic")
CONVENTIONS = ("standard", "modified")
ANGLE_UNITS = ("deg", "rad")
SYMBOL_MARKER = "symbol"

PARAMETER_PATTERN = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# Joint variables are created by symkin; a parameter of the same name would silently merge.
JOINT_VARIABLE_PATTERN = re.compile(r"^(q|dq|ddq)[0-9]+$")
# Symbols symkin invents for a link without inertial data (see derive/); a parameter named like
# one of them would be the same SymPy symbol and silently couple two unrelated quantities.
LINK_SYMBOL_PATTERN = re.compile(r"^(m|cx|cy|cz|ixx|iyy|izz|ixy|ixz|iyz)([0-9]+)$")
# Expressions are short formulas; the caps keep pathological input (deep nesting, 9**9**9)
# from exhausting time or memory before it can be rejected.
MAX_EXPRESSION_LENGTH = 500
MAX_EXPONENT = 100
# A power of a parameter expression is expanded by the derivations: (L1 + L2)**100 would not
# finish.  Squares, cubes, square roots and the like are what robot geometry uses.
MAX_SYMBOLIC_EXPONENT = 4
# Integers beyond 2**53 are not exact in double precision and overflow C's integer literals.
MAX_EXACT_INTEGER = 2**53
MAX_MAGNITUDE = 1e300
# Constants closer to zero underflow in products and print as C constants truncated to zero.
MIN_MAGNITUDE = 1e-300

CATALOGUE_DIR = "robots"
# A 100-joint robot with full inertial data is about 60 KiB.
MAX_FILE_BYTES = 1024 * 1024


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


def load_robot(name_or_path: str | Path) -> Robot:
    """Load a robot by catalogue name (``"scara"``) or from a ``.toml`` file path.

    A :class:`~pathlib.Path`, or a string ending in ``.toml`` or containing a path separator,
    is a file; any other string is a catalogue name.  Raises :class:`RobotError` for unknown
    names, unreadable files and invalid content.
    """
    if _looks_like_path(name_or_path):
        return _load_path(Path(name_or_path), str(name_or_path))
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
    return name_or_path.lower().endswith(".toml") or "/" in name_or_path or "\\" in name_or_path


def _load_path(path: Path, shown: str) -> Robot:
    try:
        data = _read_limited(path, shown)
    except OSError as exc:
        hint = ""
        if path.stem in catalogue_names() and not path.exists():
            hint = f" (to load the built-in robot give just its name: {path.stem!r})"
        raise RobotError(f"{shown}: cannot read the file: {exc.strerror or exc}{hint}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise RobotError(f"{shown}: the file is not UTF-8 text") from None
    return robot_from_toml(text, shown)


def _read_limited(path: Path, shown: str) -> bytes:
    """The bytes of a regular file of at most :data:`MAX_FILE_BYTES` (``/dev/zero``, a pipe or
    a folder would otherwise be read until memory runs out, or block)."""
    info = path.stat()
    if not stat.S_ISREG(info.st_mode):
        raise RobotError(f"{shown}: not a regular file (a robot file is a .toml text file)")
    with path.open("rb") as handle:
        data = handle.read(MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES:
        raise RobotError(
            f"{shown}: the file is larger than {MAX_FILE_BYTES // 1024} KiB; "
            "a robot file is a short text"
        )
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
        f"unknown robot {name!r}{_hint(name, names)}; catalogue robots: {listing}; "
        "to load a file give a path ending in .toml"
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
# Where we are in the file (for messages) and what expressions may use
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Context:
    """Location for error messages plus what value conversion needs (units, parameters)."""

    file: str
    angles: str = "deg"
    symbols: Mapping[str, sp.Symbol] | None = None
    values: Mapping[str, float | None] | None = None
    joint: int | None = None
    prefix: str = ""

    def at_joint(self, index: int) -> _Context:
        return replace(self, joint=index, prefix="")

    def within(self, key: str) -> _Context:
        return replace(self, prefix=self.key(key) + ".")

    def key(self, key: str) -> str:
        """The dotted key as shown to the user, e.g. ``link.inertia.ixx``."""
        return f"{self.prefix}{key}"

    def error(self, message: str) -> RobotError:
        where = [self.file] if self.joint is None else [self.file, f"joint {self.joint}"]
        return RobotError(": ".join([*where, message]))


def _hint(word: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _show(value: Any, depth: int = 0) -> str:
    """A user's value as they wrote it in TOML (shortened), for 'got ...' in messages."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, str):
        text = json.dumps(value, ensure_ascii=False)
    elif isinstance(value, dict):
        return "a table"
    elif isinstance(value, int) and abs(value) > 10**30:
        return "a very large integer"
    elif isinstance(value, int | float):
        text = repr(value)
    elif isinstance(value, list) and depth >= 3:  # TOML arrays may nest arbitrarily deep
        return "[...]"
    elif isinstance(value, list):
        items = ", ".join(_show(v, depth + 1) for v in value[:4])
        text = "[" + items + (", ...]" if len(value) > 4 else "]")
    else:
        text = f"{value} (a {type(value).__name__})"  # TOML dates and times
    return text if len(text) <= 60 else text[:57] + "..."


def _check_keys(table: Mapping[str, Any], allowed: Iterable[str], ctx: _Context) -> None:
    allowed = tuple(allowed)
    for key in table:
        if key not in allowed:
            raise ctx.error(
                f"unknown key {ctx.key(key)!r}{_hint(key, allowed)}; "
                f"allowed here: {', '.join(allowed)}"
            )


def _table(value: Any, key: str, ctx: _Context) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise ctx.error(f"{ctx.key(key)!r} must be a table, got {_show(value)}")
    return value


def _choice(table: Mapping[str, Any], key: str, choices: tuple[str, ...], ctx: _Context) -> str:
    value = table.get(key, choices[0])
    if value not in choices:
        options = " or ".join(f'"{c}"' for c in choices)
        raise ctx.error(f"{ctx.key(key)!r} must be {options}, got {_show(value)}")
    return value


def _text(table: Mapping[str, Any], key: str, ctx: _Context) -> str:
    value = table.get(key, "")
    if not isinstance(value, str):
        raise ctx.error(f"{ctx.key(key)!r} must be a string, got {_show(value)}")
    return value


# ---------------------------------------------------------------------------------------------
# The whole document
# ---------------------------------------------------------------------------------------------


def _robot_from_document(document: dict[str, Any], file: str) -> Robot:
    ctx = _Context(file)
    _check_keys(document, TOP_KEYS, ctx)
    name = _robot_name(document, ctx)
    angles = _choice(document, "angles", ANGLE_UNITS, ctx)
    convention = _choice(document, "convention", CONVENTIONS, ctx)
    parameters = _parameters(document.get("parameters", {}), ctx)
    ctx = replace(
        ctx,
        angles=angles,
        symbols={n: parameter_symbol(n) for n, _ in parameters},
        values=dict(parameters),
    )
    joints = _joints(document, ctx)
    _check_link_symbol_clash(parameters, joints, ctx)
    extra: dict[str, Any] = {}
    if "gravity" in document:
        extra["gravity"] = _vector(document["gravity"], "gravity", 3, ctx)
    for key in ("base", "tool"):
        if key in document:
            extra[key] = _frame(document[key], key, ctx)
    extra["title"] = _text(document, "title", ctx)
    extra["source"] = _text(document, "source", ctx)
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


def _robot_name(document: Mapping[str, Any], ctx: _Context) -> str:
    if "name" not in document:
        raise ctx.error("'name' is missing; give the robot a name matching [a-z][a-z0-9_]*")
    name = document["name"]
    if not isinstance(name, str) or not NAME_PATTERN.match(name):
        raise ctx.error(f"'name' must match [a-z][a-z0-9_]*, got {_show(name)}")
    reason = robot_name_reason(name)
    if reason:
        raise ctx.error(f"'name' {_show(name)} is reserved ({reason}); rename the robot")
    return name


# ---------------------------------------------------------------------------------------------
# [parameters]
# ---------------------------------------------------------------------------------------------


def _parameters(value: Any, ctx: _Context) -> tuple[tuple[str, float | None], ...]:
    table = _table(value, "parameters", ctx)
    return tuple((name, _parameter(name, v, ctx)) for name, v in table.items())


def _parameter(name: str, value: Any, ctx: _Context) -> float | None:
    key = f"parameters.{name}"
    _check_parameter_name(name, key, ctx)
    if isinstance(value, str) and value == SYMBOL_MARKER:
        return None
    if _is_number(value):
        number = _finite_number(value, key, ctx)
        return float(number)
    raise ctx.error(f'{key!r} must be a number or "symbol", got {_show(value)}')


def _check_parameter_name(name: str, key: str, ctx: _Context) -> None:
    if not PARAMETER_PATTERN.match(name) or keyword.iskeyword(name):
        raise ctx.error(f"{key!r}: a parameter name must be an identifier, got {_show(name)}")
    reason = reserved_reason(name)
    if reason:
        raise ctx.error(f"{key!r}: {name!r} is reserved ({reason}); rename the parameter")
    if JOINT_VARIABLE_PATTERN.match(name):
        raise ctx.error(f"{key!r}: {name!r} is reserved for a joint variable (q<i>, dq<i>, ddq<i>)")


def _check_link_symbol_clash(
    parameters: tuple[tuple[str, float | None], ...], joints: tuple[Joint, ...], ctx: _Context
) -> None:
    for name, _ in parameters:
        match = LINK_SYMBOL_PATTERN.match(name)
        if not match:
            continue
        index = int(match.group(2))
        if 1 <= index <= len(joints) and joints[index - 1].link is None:
            raise ctx.error(
                f"'parameters.{name}': {name!r} is the symbol symkin uses for link {index}, "
                f"which has no [joints.link] data; rename the parameter or give the link data"
            )


# ---------------------------------------------------------------------------------------------
# [[joints]]
# ---------------------------------------------------------------------------------------------


def _joints(document: Mapping[str, Any], ctx: _Context) -> tuple[Joint, ...]:
    tables = document.get("joints")
    if tables is None or tables == []:
        raise ctx.error("the joint list is empty; add at least one [[joints]] table")
    if not isinstance(tables, list):
        raise ctx.error(f"'joints' must be an array of tables ([[joints]]), got {_show(tables)}")
    joints = tuple(_joint(t, ctx.at_joint(i)) for i, t in enumerate(tables, start=1))
    _check_unique_joint_names(joints, ctx)
    return joints


def _check_unique_joint_names(joints: tuple[Joint, ...], ctx: _Context) -> None:
    first_use: dict[str, int] = {}
    for index, joint in enumerate(joints, start=1):
        if joint.name is None:
            continue
        if joint.name in first_use:
            raise ctx.at_joint(index).error(
                f"'name' {_show(joint.name)} is already used by joint {first_use[joint.name]}"
            )
        first_use[joint.name] = index


def _joint(table: Any, ctx: _Context) -> Joint:
    if not isinstance(table, dict):
        raise ctx.error(f"each entry of 'joints' must be a table, got {_show(table)}")
    _check_keys(table, JOINT_KEYS, ctx)
    kind = _joint_type(table, ctx)
    fields = {
        "name": _joint_name(table, ctx),
        "theta": _value(table.get("theta", 0), "theta", ctx, angle=True),
        "d": _value(table.get("d", 0), "d", ctx),
        "a": _value(table.get("a", 0), "a", ctx),
        "alpha": _value(table.get("alpha", 0), "alpha", ctx, angle=True),
        "limits": _limits(table, kind, ctx),
        "link": _link(table["link"], ctx.within("link")) if "link" in table else None,
    }
    try:
        return Joint(type=kind, **fields)  # type: ignore[arg-type]
    except RobotError as exc:  # the dataclass checks do not know the file or joint
        raise ctx.error(str(exc)) from None


def _joint_type(table: Mapping[str, Any], ctx: _Context) -> str:
    if "type" not in table:
        raise ctx.error('\'type\' is missing; it must be "revolute" or "prismatic"')
    return _choice(table, "type", JOINT_TYPES, ctx)


def _joint_name(table: Mapping[str, Any], ctx: _Context) -> str | None:
    if "name" not in table:
        return None
    name = table["name"]
    # Same pattern as the robot name: joint names may end up in generated symbol names.
    if not isinstance(name, str) or not NAME_PATTERN.match(name):
        raise ctx.error(f"'name' must match [a-z][a-z0-9_]*, got {_show(name)}")
    return name


def _limits(table: Mapping[str, Any], kind: str, ctx: _Context) -> tuple[float, float] | None:
    """Joint limits as floats in radians (revolute) or length units (prismatic)."""
    if "limits" not in table:
        return None
    raw = table["limits"]
    if not isinstance(raw, list) or len(raw) != 2:
        raise ctx.error(f"'limits' must be a list [low, high] of 2 values, got {_show(raw)}")
    low, high = (
        _constant(v, f"limits[{i}]", ctx, angle=kind == "revolute") for i, v in enumerate(raw)
    )
    if not low < high:
        raise ctx.error(f"'limits' must be [low, high] with low < high, got {_show(raw)}")
    return low, high


def _constant(value: Any, key: str, ctx: _Context, *, angle: bool) -> float:
    expr = _value(value, key, ctx, angle=angle)
    if expr.free_symbols:
        # Limits are stored as plain floats, so they cannot follow a parameter's overrides.
        raise ctx.error(
            f"{ctx.key(key)!r} must be a number or an expression of pi only, "
            f"not of parameters, got {_show(value)}"
        )
    number = _finite_float(expr)
    if number is None:
        raise ctx.error(f"{ctx.key(key)!r} must be a finite real number, got {_show(value)}")
    return number


# ---------------------------------------------------------------------------------------------
# [base], [tool], vectors
# ---------------------------------------------------------------------------------------------


def _frame(value: Any, key: str, ctx: _Context) -> sp.ImmutableMatrix:
    """A fixed 4x4 transform from ``xyz`` and fixed-axis ``rpy`` (R = Rz(y) Ry(p) Rx(r))."""
    # Imported here because spatial.py is a sibling module that may import from io in future.
    from symkin.spatial import rotation_from_rpy, transform_from_rotation_translation

    table = _table(value, key, ctx)
    inner = ctx.within(key)
    _check_keys(table, FRAME_KEYS, inner)
    xyz = _vector(table.get("xyz", [0, 0, 0]), "xyz", 3, inner)
    roll, pitch, yaw = _vector(table.get("rpy", [0, 0, 0]), "rpy", 3, inner, angle=True)
    rotation = rotation_from_rpy(roll, pitch, yaw)
    return sp.ImmutableMatrix(transform_from_rotation_translation(rotation, sp.Matrix(xyz)))


def _vector(
    value: Any, key: str, length: int, ctx: _Context, *, angle: bool = False
) -> tuple[sp.Expr, ...]:
    if not isinstance(value, list) or len(value) != length:
        raise ctx.error(f"{ctx.key(key)!r} must be a list of {length} values, got {_show(value)}")
    return tuple(_value(v, f"{key}[{i}]", ctx, angle=angle) for i, v in enumerate(value))


# ---------------------------------------------------------------------------------------------
# [joints.link]: inertial data
# ---------------------------------------------------------------------------------------------


def _link(value: Any, ctx: _Context) -> Link:
    """Inertial data of one link; ``ctx`` is already inside ``link.``."""
    if not isinstance(value, dict):
        raise ctx.error(f"'link' must be a table, got {_show(value)}")
    _check_keys(value, LINK_KEYS, ctx)
    if "mass" not in value:
        raise ctx.error(f"{ctx.key('mass')!r} is missing; a [joints.link] table needs a mass")
    mass = _value(value["mass"], "mass", ctx)
    _check_not_negative(mass, "mass", ctx)
    inertia = _inertia(value.get("inertia", {}), ctx)
    motor_inertia = _value(value.get("motor_inertia", 0), "motor_inertia", ctx)
    _check_not_negative(motor_inertia, "motor_inertia", ctx)
    return Link(
        mass=mass,
        com=_vector(value.get("com", [0, 0, 0]), "com", 3, ctx),  # type: ignore[arg-type]
        inertia=inertia,
        motor_inertia=motor_inertia,
        **_friction(value.get("friction", {}), ctx),
    )


def _inertia(value: Any, ctx: _Context) -> tuple[sp.Expr, ...]:
    """The six tensor elements about the COM; missing ones are 0."""
    table = _table(value, "inertia", ctx)
    inner = ctx.within("inertia")
    _check_keys(table, INERTIA_KEYS, inner)
    elements = tuple(_value(table.get(k, 0), k, inner) for k in INERTIA_KEYS)
    numbers = [_numeric(e, ctx) for e in elements]
    if all(n is not None for n in numbers):
        _check_inertia_physical(np.array(numbers, dtype=float), inner)
    return elements


def _check_inertia_physical(elements: np.ndarray, ctx: _Context) -> None:
    """Reject tensors no rigid body can have (negative moments, not PSD) with an error; warn
    (:class:`RobotWarning`) about a violated triangle inequality, which published models with
    lumped inertias do have (e.g. Corke's PUMA 560) and which the dynamics can still use."""
    ixx, iyy, izz, ixy, ixz, iyz = elements
    tolerance = 1e-9 * float(np.max(np.abs(elements)))
    where = ctx.prefix.rstrip(".")
    for key, moment in zip(INERTIA_KEYS[:3], elements[:3], strict=True):
        if moment < -tolerance:
            raise ctx.error(f"{ctx.key(key)!r} must be >= 0 (a moment of inertia), got {moment:g}")
    tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    moments = np.linalg.eigvalsh(tensor)  # ascending
    if moments[0] < -tolerance:
        raise ctx.error(
            f"{where!r} is not positive semi-definite: principal moments "
            f"{', '.join(f'{m:g}' for m in moments)}"
        )
    for first, second, third, names in (
        (ixx, iyy, izz, ("ixx", "iyy", "izz")),
        (iyy, izz, ixx, ("iyy", "izz", "ixx")),
        (izz, ixx, iyy, ("izz", "ixx", "iyy")),
    ):
        if first + second < third - tolerance:
            _warn(
                ctx,
                f"{where!r} violates the triangle inequality: {names[0]} + {names[1]} >= "
                f"{names[2]} is required, got {first:g} + {second:g} < {third:g} "
                "(no rigid body has this tensor; loaded as given)",
            )
            return
    if moments[0] + moments[1] < moments[2] - tolerance:
        _warn(
            ctx,
            f"{where!r}: the principal moments {', '.join(f'{m:g}' for m in moments)} violate "
            "the triangle inequality (the two smaller must add up to at least the largest; "
            "loaded as given)",
        )


def _warn(ctx: _Context, message: str) -> None:
    """A :class:`RobotWarning` located like an error (file, joint, key)."""
    warnings.warn(str(ctx.error(message)), RobotWarning, stacklevel=2)


def _friction(value: Any, ctx: _Context) -> dict[str, sp.Expr | None]:
    table = _table(value, "friction", ctx)
    inner = ctx.within("friction")
    _check_keys(table, FRICTION_KEYS, inner)
    result: dict[str, sp.Expr | None] = {}
    for key in ("coulomb", "viscous"):
        result[key] = _value(table.get(key, 0), key, inner)
        _check_not_negative(result[key], key, inner)
    if "stribeck" in table:
        result["stribeck_static"], result["stribeck_velocity"] = _stribeck(table["stribeck"], inner)
    return result


def _stribeck(value: Any, ctx: _Context) -> tuple[sp.Expr, sp.Expr]:
    table = _table(value, "stribeck", ctx)
    inner = ctx.within("stribeck")
    _check_keys(table, STRIBECK_KEYS, inner)
    for key in STRIBECK_KEYS:
        if key not in table:
            raise inner.error(f"{inner.key(key)!r} is missing; stribeck needs static and velocity")
    static = _value(table["static"], "static", inner)
    _check_not_negative(static, "static", inner)
    velocity = _value(table["velocity"], "velocity", inner)
    number = _numeric(velocity, inner)
    if number is not None and number <= 0:  # it divides the joint speed
        raise inner.error(f"{inner.key('velocity')!r} must be > 0, got {number:g}")
    return static, velocity


def _check_not_negative(expr: sp.Expr | None, key: str, ctx: _Context) -> None:
    number = None if expr is None else _numeric(expr, ctx)
    if number is not None and number < 0:
        raise ctx.error(f"{ctx.key(key)!r} must be >= 0, got {number:g}")


def _numeric(expr: sp.Expr, ctx: _Context) -> float | None:
    """The value with parameter defaults substituted, or None when a parameter has none."""
    values = ctx.values or {}
    substitutions = {}
    for symbol in expr.free_symbols:
        value = values.get(symbol.name)
        if value is None:
            return None
        substitutions[symbol] = sp.Float(value)
    return _finite_float(expr.xreplace(substitutions))


def _finite_float(expr: sp.Expr) -> float | None:
    """``float(expr)`` when expr is a finite real number, else None."""
    try:
        number = complex(expr.evalf())
    except (TypeError, ValueError, OverflowError, ZeroDivisionError):
        return None
    if number.imag != 0 or not math.isfinite(number.real):
        return None
    return number.real


# ---------------------------------------------------------------------------------------------
# Values: numbers and expression strings
# ---------------------------------------------------------------------------------------------


def _is_number(value: Any) -> bool:
    # bool is an int subclass in Python, but `true` is never a number in a robot file
    return isinstance(value, int | float) and not isinstance(value, bool)


def _finite_number(value: int | float, key: str, ctx: _Context) -> int | float:
    if isinstance(value, float) and not math.isfinite(value):
        raise ctx.error(f"{ctx.key(key)!r} must be a finite number, got {_show(value)}")
    if abs(value) > MAX_MAGNITUDE:
        raise ctx.error(f"{ctx.key(key)!r} is too large ({_show(value)}); the limit is 1e300")
    if isinstance(value, int) and abs(value) > MAX_EXACT_INTEGER:
        raise ctx.error(f"{ctx.key(key)!r}: {_INEXACT_INTEGER}, got {_show(value)}")
    if 0 < abs(value) < MIN_MAGNITUDE:
        raise ctx.error(f"{ctx.key(key)!r} is too small ({_show(value)}); write 0 or >= 1e-300")
    return value


def _value(value: Any, key: str, ctx: _Context, *, angle: bool = False) -> sp.Expr:
    """A number or expression string as SymPy; angle constants follow the file's unit."""
    if _is_number(value):
        number = _finite_number(value, key, ctx)
        if angle and ctx.angles == "deg":
            return _degrees(sp.Rational(str(number)))
        return _sympy_number(number)
    if isinstance(value, str):
        expr, names = _parse_expression(value, key, ctx)
        # A string naming pi or a parameter is radians; a plain numeric string is a constant.
        if angle and ctx.angles == "deg" and not names:
            return _degrees(expr)
        return expr
    raise ctx.error(
        f"{ctx.key(key)!r} must be a number or an expression string, got {_show(value)}"
    )


def _sympy_number(value: int | float) -> sp.Expr:
    """Integers (also 2.0) exactly; other floats as SymPy Floats of their shortest decimal text."""
    if isinstance(value, int):
        return sp.Integer(value)
    if value.is_integer() and abs(value) <= MAX_EXACT_INTEGER:
        return sp.Integer(int(value))
    return sp.Float(repr(value))


def _degrees(number: sp.Expr) -> sp.Expr:
    """Degrees to radians exactly: 90 -> pi/2, 0.5 -> pi/360 (a Float via its decimal text)."""
    exact = number if number.is_Rational else sp.Rational(repr(float(number)))
    return exact * sp.pi / 180


def _parse_expression(text: str, key: str, ctx: _Context) -> tuple[sp.Expr, frozenset[str]]:
    """Parse a whitelisted arithmetic expression; returns it and the names it uses."""
    shown = ctx.key(key)
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise ctx.error(f"{shown!r} is longer than {MAX_EXPRESSION_LENGTH} characters")
    if not text.strip():
        raise ctx.error(f"{shown!r} must be a number or an expression, got an empty string")
    try:
        with warnings.catch_warnings():
            # "invalid decimal literal" and the like: we report our own error instead
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise ctx.error(f"{shown!r} is not a valid expression: {_show(text)}") from None
    builder = _ExpressionBuilder(ctx.symbols or {}, lambda why: _bad_expression(shown, text, why))
    try:
        expr = builder.build(tree.body)
    except RecursionError:
        raise ctx.error(f"{shown!r} is nested too deeply: {_show(text)}") from None
    except _ExpressionError as exc:
        raise ctx.error(str(exc)) from None
    _check_nested_powers(expr, shown, text, ctx)
    _check_expression_value(expr, shown, text, ctx)
    return expr, frozenset(builder.names)


def _check_nested_powers(expr: sp.Expr, shown: str, text: str, ctx: _Context) -> None:
    """SymPy merges nested powers ((x**4)**4 -> x**16): the cap holds for the result too."""
    for power in expr.atoms(sp.Pow):
        if power.base.free_symbols and abs(float(power.exp)) > MAX_SYMBOLIC_EXPONENT:
            raise ctx.error(
                f"{shown!r} is not a valid expression: {_show(text)} raises parameters to the "
                f"power {sp.sstr(power.exp)}, outside [-{MAX_SYMBOLIC_EXPONENT}, "
                f"{MAX_SYMBOLIC_EXPONENT}]"
            )


def _check_expression_value(expr: sp.Expr, shown: str, text: str, ctx: _Context) -> None:
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise ctx.error(f"{shown!r} is not finite (division by zero?): {_show(text)}")
    # SymPy folds the numbers of a product (L1*1e-300*1e-300 -> 1e-600*L1): every constant
    # left in the formula must be a double, or the C compiler truncates or overflows it.
    for number in expr.atoms(sp.Number):
        magnitude = abs(number)  # compared exactly: float() would flush 1e-600 to 0
        if magnitude > MAX_MAGNITUDE or (magnitude != 0 and magnitude < MIN_MAGNITUDE):
            raise ctx.error(
                f"{shown!r} holds the constant {sp.sstr(number.evalf(3))}, outside "
                f"1e-300..1e300 in magnitude: {_show(text)}"
            )
    if not expr.is_number:
        _check_value_at_defaults(expr, shown, text, ctx)
        return
    number = _finite_float(expr)
    if number is None or abs(number) > MAX_MAGNITUDE:
        raise ctx.error(
            f"{shown!r} is not a finite real number of magnitude <= 1e300: {_show(text)}"
        )


def _check_value_at_defaults(expr: sp.Expr, shown: str, text: str, ctx: _Context) -> None:
    """A formula with a pole (or a complex value) at the parameters' own values gives NaN or
    inf in every backend: reject it when all its parameters have values."""
    values = ctx.values or {}
    if any(values.get(s.name) is None for s in expr.free_symbols):
        return
    number = _numeric(expr, ctx)
    if number is None or abs(number) > MAX_MAGNITUDE:
        given = ", ".join(
            f"{s.name} = {values[s.name]:g}" for s in sorted(expr.free_symbols, key=str)
        )
        raise ctx.error(
            f"{shown!r} is not a finite real number at the parameters' values ({given}): "
            f"{_show(text)}"
        )


_BINARY: Mapping[type[ast.operator], Callable[[sp.Expr, sp.Expr], sp.Expr]] = {
    ast.Add: lambda x, y: x + y,
    ast.Sub: lambda x, y: x - y,
    ast.Mult: lambda x, y: x * y,
    ast.Div: lambda x, y: x / y,
}


_INEXACT_INTEGER = (
    "integers beyond 2**53 are not exact in double precision; write the number as a float, "
    "such as 1e30"
)


class _ExpressionError(Exception):
    """Internal: an expression broke the whitelist; turned into a RobotError by the caller."""


def _bad_expression(shown: str, text: str, why: str) -> _ExpressionError:
    return _ExpressionError(
        f"{shown!r} is not a valid expression: {_show(text)} {why}; allowed are numbers, "
        "declared parameter names, pi, + - * / ** and parentheses"
    )


class _ExpressionBuilder:
    """Turns a whitelisted Python AST into SymPy, remembering the names it meets."""

    def __init__(
        self, symbols: Mapping[str, sp.Symbol], fail: Callable[[str], _ExpressionError]
    ) -> None:
        self.symbols = symbols
        self.fail = fail
        self.names: set[str] = set()

    def build(self, node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Constant):
            return self._constant(node.value)
        if isinstance(node, ast.Name):
            return self._name(node.id)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
            operand = self.build(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return self._power(self.build(node.left), self.build(node.right))
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](self.build(node.left), self.build(node.right))
        raise self.fail(f"uses {_describe_node(node)}")

    def _constant(self, value: Any) -> sp.Expr:
        if not _is_number(value):
            raise self.fail(f"contains the literal {value!r}")
        if isinstance(value, float) and not math.isfinite(value):
            raise self.fail("contains a number that is not finite")
        if abs(value) > MAX_MAGNITUDE:
            raise self.fail("contains a number larger than 1e300")
        if isinstance(value, int) and abs(value) > MAX_EXACT_INTEGER:
            raise self.fail(f"contains an integer beyond 2**53 ({_INEXACT_INTEGER})")
        return _sympy_number(value)

    def _name(self, name: str) -> sp.Expr:
        self.names.add(name)
        if name == "pi":
            return sp.pi
        if name in self.symbols:
            return self.symbols[name]
        declared = ", ".join(self.symbols) or "none"
        raise self.fail(
            f"uses the unknown name {name!r}{_hint(name, [*self.symbols, 'pi'])} "
            f"(declared parameters: {declared})"
        )

    def _power(self, base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
        # Check numbers before SymPy evaluates them exactly: 9**9**9 would never finish.
        if not exponent.is_number:
            # L1**L1 and towers: no closed form symkin can simplify, print or bound.
            raise self.fail("has an exponent with parameters (exponents must be numbers)")
        size = _finite_float(exponent)
        if size is None or abs(size) > MAX_EXPONENT:
            raise self.fail(f"has an exponent outside [-{MAX_EXPONENT}, {MAX_EXPONENT}]")
        if base.is_number:
            self._check_numeric_power(base, size)
        elif abs(size) > MAX_SYMBOLIC_EXPONENT:
            raise self.fail(
                f"raises parameters to a power outside [-{MAX_SYMBOLIC_EXPONENT}, "
                f"{MAX_SYMBOLIC_EXPONENT}]"
            )
        return base**exponent

    def _check_numeric_power(self, base: sp.Expr, exponent: float) -> None:
        value = _finite_float(base)
        try:
            result = math.pow(value, exponent) if value is not None else math.nan
        except (OverflowError, ValueError, ZeroDivisionError):
            result = math.nan
        if not math.isfinite(result) or abs(result) > MAX_MAGNITUDE:
            raise self.fail("has a power that is not a finite real number")


def _describe_node(node: ast.AST) -> str:
    descriptions = {
        ast.Call: "a function call",
        ast.Attribute: "an attribute",
        ast.Subscript: "indexing",
        ast.Compare: "a comparison",
        ast.BoolOp: "a boolean operator",
        ast.Tuple: "a tuple (a comma?)",
    }
    for kind, text in descriptions.items():
        if isinstance(node, kind):
            return text
    if isinstance(node, ast.BinOp | ast.UnaryOp):
        return f"the operator {type(node.op).__name__}"
    return f"a {type(node).__name__} construct"

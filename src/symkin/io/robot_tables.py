"""The tables of a robot file: ``[parameters]``, ``[[joints]]`` with ``[joints.link]``
(inertial data, friction) and the fixed ``[base]``/``[tool]`` frames.

Each reader checks one table's keys and values and returns what :class:`~symkin.robot.Robot`
stores; errors are :class:`~symkin.errors.RobotError` located by the
:class:`~symkin.io.context.Context`, and physically doubtful inertias are
:class:`~symkin.errors.RobotWarning`.
"""

from __future__ import annotations

import keyword
import re
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
import sympy as sp

from symkin.errors import RobotError, RobotWarning
from symkin.io.context import Context, as_table, check_keys, read_choice, read_text, show
from symkin.io.drive_tables import check_positive, read_drive, read_stiffness
from symkin.io.expressions import (
    finite_float,
    finite_number,
    is_number,
    numeric_value,
    sympy_value,
)
from symkin.io.inertia_tables import mass_and_inertia_from_shape
from symkin.io.placement import unit_axis, warn_normalised
from symkin.names import reserved_reason
from symkin.robot import NAME_PATTERN, Joint, Link
from symkin.spatial import rotation_from_rpy, transform_from_rotation_translation
from symkin.symbols import WRENCH_NAMES
from symkin.text import unprintable_characters

# Allowed keys per table.  Anything else is an error with a "did you mean" hint.
JOINT_KEYS = (
    "type", "name", "theta", "d", "a", "alpha", "flip", "limits",
    "max_velocity", "max_effort", "link",
)  # fmt: skip
# A joint of the placement form (convention = "placement"): URDF's origin and axis.
PLACED_JOINT_KEYS = (
    "type", "name", "origin", "axis", "limits", "max_velocity", "max_effort", "link",
)  # fmt: skip
FRAME_KEYS = ("xyz", "rpy")
LINK_KEYS = (
    "mass", "com", "inertia", "shape", "density", "motor_inertia", "friction", "stiffness",
    "drive", "inertia_note",
)  # fmt: skip
PAYLOAD_KEYS = ("mass", "com", "inertia", "shape", "density")
INERTIA_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
FRICTION_KEYS = (
    "coulomb", "coulomb_positive", "coulomb_negative", "viscous", "stribeck", "smoothing",
    "stiction",
)  # fmt: skip
DIRECTIONAL_KEYS = ("coulomb_positive", "coulomb_negative")
STRIBECK_KEYS = ("static", "velocity")

JOINT_TYPES = ("revolute", "prismatic")
SYMBOL_MARKER = "symbol"

PARAMETER_PATTERN = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# Joint variables are created by symkin; a parameter of the same name would silently merge.
JOINT_VARIABLE_PATTERN = re.compile(r"^(q|dq|ddq|d3q|d4q)[0-9]+$")
# Symbols symkin invents for a link without inertial data (see derive/); a parameter named like
# one of them would be the same SymPy symbol and silently couple two unrelated quantities.
LINK_SYMBOL_PATTERN = re.compile(r"^(m|cx|cy|cz|ixx|iyy|izz|ixy|ixz|iyz)([0-9]+)$")


# ---------------------------------------------------------------------------------------------
# [parameters]
# ---------------------------------------------------------------------------------------------


def read_parameters(value: Any, ctx: Context) -> tuple[tuple[str, float | None], ...]:
    """``[parameters]`` as ``(name, default)`` pairs in file order; ``"symbol"`` gives None."""
    table = as_table(value, "parameters", ctx)
    return tuple((name, _parameter(name, v, ctx)) for name, v in table.items())


def _parameter(name: str, value: Any, ctx: Context) -> float | None:
    key = f"parameters.{name}"
    _check_parameter_name(name, key, ctx)
    if isinstance(value, str) and value == SYMBOL_MARKER:
        return None
    if is_number(value):
        number = finite_number(value, key, ctx)
        return float(number)
    raise ctx.error(f'{key!r} must be a number or "symbol", got {show(value)}')


def _check_parameter_name(name: str, key: str, ctx: Context) -> None:
    if not PARAMETER_PATTERN.match(name) or keyword.iskeyword(name):
        raise ctx.error(f"{key!r}: a parameter name must be an identifier, got {show(name)}")
    reason = reserved_reason(name)
    if reason:
        raise ctx.error(f"{key!r}: {name!r} is reserved ({reason}); rename the parameter")
    if JOINT_VARIABLE_PATTERN.match(name):
        raise ctx.error(f"{key!r}: {name!r} is reserved for a joint variable (q<i>, dq<i>, ddq<i>)")
    if name in WRENCH_NAMES:
        raise ctx.error(f"{key!r}: {name!r} is reserved for the external wrench on the tool")


def check_link_symbol_clash(
    parameters: tuple[tuple[str, float | None], ...], joints: tuple[Joint, ...], ctx: Context
) -> None:
    """Reject a parameter named like the symbol symkin mints for a link without data."""
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


def read_joints(document: Mapping[str, Any], ctx: Context) -> tuple[Joint, ...]:
    """``[[joints]]`` in file order, each checked, with unique names."""
    tables = _joint_tables(document, ctx)
    joints = tuple(_joint(t, ctx.at_joint(i)) for i, t in enumerate(tables, start=1))
    _check_unique_joint_names(joints, ctx)
    return joints


def read_placed_joints(
    document: Mapping[str, Any], ctx: Context
) -> tuple[tuple[Joint, ...], tuple[tuple[sp.Expr, ...], ...]]:
    """``[[joints]]`` of the placement form: joints whose ``placement`` is the URDF ``origin``
    (from the parent link frame) and links in the child link frame, and their unit axes
    (:func:`symkin.io.placement.canonical_joints` makes them canonical)."""
    tables = _joint_tables(document, ctx)
    placed = [_placed_joint(t, ctx.at_joint(i)) for i, t in enumerate(tables, start=1)]
    joints = tuple(joint for joint, _ in placed)
    _check_unique_joint_names(joints, ctx)
    return joints, tuple(axis for _, axis in placed)


def _joint_tables(document: Mapping[str, Any], ctx: Context) -> list[Any]:
    tables = document.get("joints")
    if tables is None or tables == []:
        raise ctx.error("the joint list is empty; add at least one [[joints]] table")
    if not isinstance(tables, list):
        raise ctx.error(f"'joints' must be an array of tables ([[joints]]), got {show(tables)}")
    for index, table in enumerate(tables, start=1):
        if not isinstance(table, dict):
            raise ctx.at_joint(index).error(
                f"each entry of 'joints' must be a table, got {show(table)}"
            )
    return tables


def _placed_joint(table: dict[str, Any], ctx: Context) -> tuple[Joint, tuple[sp.Expr, ...]]:
    check_keys(table, PLACED_JOINT_KEYS, ctx)
    kind = _joint_type(table, ctx)
    if "axis" not in table:
        raise ctx.error("'axis' is missing; give the joint's direction, e.g. axis = [0, 0, 1]")
    values = _list_of(table["axis"], "axis", 3, ctx)
    raw = [_constant(v, f"axis[{i}]", ctx, angle=False) for i, v in enumerate(values)]
    axis, normalised = unit_axis(raw, ctx.where)
    if normalised:
        warn_normalised(ctx.where, raw)
    joint = Joint(
        type=kind,  # type: ignore[arg-type]
        name=_joint_name(table, ctx),
        limits=_limits(table, kind, ctx),
        link=_link(table["link"], ctx.within("link")) if "link" in table else None,
        placement=read_frame(table.get("origin", {}), "origin", ctx),
        **_rate_limits(table, ctx),
    )
    return joint, axis


def _list_of(value: Any, key: str, length: int, ctx: Context) -> list[Any]:
    if not isinstance(value, list) or len(value) != length:
        raise ctx.error(f"{ctx.key(key)!r} must be a list of {length} values, got {show(value)}")
    return value


def _check_unique_joint_names(joints: tuple[Joint, ...], ctx: Context) -> None:
    first_use: dict[str, int] = {}
    for index, joint in enumerate(joints, start=1):
        if joint.name is None:
            continue
        if joint.name in first_use:
            raise ctx.at_joint(index).error(
                f"'name' {show(joint.name)} is already used by joint {first_use[joint.name]}"
            )
        first_use[joint.name] = index


def _joint(table: dict[str, Any], ctx: Context) -> Joint:
    check_keys(table, JOINT_KEYS, ctx)
    kind = _joint_type(table, ctx)
    fields = {
        "name": _joint_name(table, ctx),
        "theta": sympy_value(table.get("theta", 0), "theta", ctx, angle=True),
        "d": sympy_value(table.get("d", 0), "d", ctx),
        "a": sympy_value(table.get("a", 0), "a", ctx),
        "alpha": sympy_value(table.get("alpha", 0), "alpha", ctx, angle=True),
        "flip": _flip(table, ctx),
        "limits": _limits(table, kind, ctx),
        "link": _link(table["link"], ctx.within("link")) if "link" in table else None,
        **_rate_limits(table, ctx),
    }
    try:
        return Joint(type=kind, **fields)  # type: ignore[arg-type]
    except RobotError as exc:  # the dataclass checks do not know the file or joint
        raise ctx.error(str(exc)) from None


def _joint_type(table: Mapping[str, Any], ctx: Context) -> str:
    if "type" not in table:
        raise ctx.error('\'type\' is missing; it must be "revolute" or "prismatic"')
    return read_choice(table, "type", JOINT_TYPES, ctx)


def _joint_name(table: Mapping[str, Any], ctx: Context) -> str | None:
    if "name" not in table:
        return None
    name = table["name"]
    # Same pattern as the robot name: joint names may end up in generated symbol names.
    if not isinstance(name, str) or not NAME_PATTERN.match(name):
        raise ctx.error(f"'name' must match [a-z][a-z0-9_]*, got {show(name)}")
    return name


def _flip(table: Mapping[str, Any], ctx: Context) -> bool:
    """``flip``: true when the joint variable enters the DH table as ``-q`` (default false)."""
    value = table.get("flip", False)
    if not isinstance(value, bool):
        raise ctx.error(f"'flip' must be true or false, got {show(value)}")
    return value


def _limits(table: Mapping[str, Any], kind: str, ctx: Context) -> tuple[float, float] | None:
    """Joint limits as floats in radians (revolute) or length units (prismatic)."""
    if "limits" not in table:
        return None
    raw = table["limits"]
    if not isinstance(raw, list) or len(raw) != 2:
        raise ctx.error(f"'limits' must be a list [low, high] of 2 values, got {show(raw)}")
    low, high = (
        _constant(v, f"limits[{i}]", ctx, angle=kind == "revolute") for i, v in enumerate(raw)
    )
    if not low < high:
        raise ctx.error(f"'limits' must be [low, high] with low < high, got {show(raw)}")
    return low, high


def _rate_limits(table: Mapping[str, Any], ctx: Context) -> dict[str, float | None]:
    """``max_velocity`` and ``max_effort`` (URDF's ``<limit velocity effort>``): > 0 or absent.
    Plain SI numbers (rad/s or m/s, N m or N): the file's angle unit does not apply."""
    result: dict[str, float | None] = {}
    for key in ("max_velocity", "max_effort"):
        value = _constant(table[key], key, ctx, angle=False) if key in table else None
        if value is not None and value <= 0:
            raise ctx.error(f"{ctx.key(key)!r} must be > 0, got {value:g}")
        result[key] = value
    return result


def _constant(value: Any, key: str, ctx: Context, *, angle: bool) -> float:
    expr = sympy_value(value, key, ctx, angle=angle)
    if expr.free_symbols:
        # Limits are stored as plain floats, so they cannot follow a parameter's overrides.
        raise ctx.error(
            f"{ctx.key(key)!r} must be a number or an expression of pi only, "
            f"not of parameters, got {show(value)}"
        )
    number = finite_float(expr)
    if number is None:
        raise ctx.error(f"{ctx.key(key)!r} must be a finite real number, got {show(value)}")
    return number


# ---------------------------------------------------------------------------------------------
# [base], [tool], vectors
# ---------------------------------------------------------------------------------------------


def read_frame(value: Any, key: str, ctx: Context) -> sp.ImmutableMatrix:
    """A fixed 4x4 transform from ``xyz`` and fixed-axis ``rpy`` (R = Rz(y) Ry(p) Rx(r))."""
    table = as_table(value, key, ctx)
    inner = ctx.within(key)
    check_keys(table, FRAME_KEYS, inner)
    xyz = read_vector(table.get("xyz", [0, 0, 0]), "xyz", 3, inner)
    roll, pitch, yaw = read_vector(table.get("rpy", [0, 0, 0]), "rpy", 3, inner, angle=True)
    rotation = rotation_from_rpy(roll, pitch, yaw)
    return sp.ImmutableMatrix(transform_from_rotation_translation(rotation, sp.Matrix(xyz)))


def read_vector(
    value: Any, key: str, length: int, ctx: Context, *, angle: bool = False
) -> tuple[sp.Expr, ...]:
    """``value`` as a list of ``length`` SymPy values (``key[i]`` in messages)."""
    if not isinstance(value, list) or len(value) != length:
        raise ctx.error(f"{ctx.key(key)!r} must be a list of {length} values, got {show(value)}")
    return tuple(sympy_value(v, f"{key}[{i}]", ctx, angle=angle) for i, v in enumerate(value))


# ---------------------------------------------------------------------------------------------
# [joints.link]: inertial data
# ---------------------------------------------------------------------------------------------


def _link(value: Any, ctx: Context) -> Link:
    """Inertial data of one link; ``ctx`` is already inside ``link.``."""
    if not isinstance(value, dict):
        raise ctx.error(f"'link' must be a table, got {show(value)}")
    check_keys(value, LINK_KEYS, ctx)
    note = read_text(value, "inertia_note", ctx)
    if unprintable_characters(note):
        # Shown by `symkin show`: one line of printable text, like a title.
        raise ctx.error(f"{ctx.key('inertia_note')!r} must be one line of printable text")
    mass, inertia = _mass_and_inertia(value, ctx, documented=bool(note))
    drive, reflected = read_drive(value, ctx)
    motor_inertia = sympy_value(value.get("motor_inertia", 0), "motor_inertia", ctx)
    _check_not_negative(motor_inertia, "motor_inertia", ctx)
    return Link(
        stiffness=read_stiffness(value, ctx),
        drive=drive,
        mass=mass,
        com=read_vector(value.get("com", [0, 0, 0]), "com", 3, ctx),  # type: ignore[arg-type]
        inertia=inertia,
        motor_inertia=motor_inertia if reflected is None else reflected,
        **_friction(value.get("friction", {}), ctx),
        inertia_note=note,
    )


def read_payload(value: Any, ctx: Context) -> Link:
    """``[payload]``: mass, centre and inertia (or shape) of a body the tool holds, tool frame
    (composed into the last link by :func:`symkin.io.inertia_tables.joints_with_payload`)."""
    table = as_table(value, "payload", ctx)
    inner = ctx.within("payload")
    check_keys(table, PAYLOAD_KEYS, inner)
    mass, inertia = _mass_and_inertia(table, inner)
    com = read_vector(table.get("com", [0, 0, 0]), "com", 3, inner)
    return Link(mass=mass, com=com, inertia=inertia)  # type: ignore[arg-type]


def _mass_and_inertia(
    table: dict[str, Any], ctx: Context, documented: bool = False
) -> tuple[sp.Expr, tuple[sp.Expr, ...]]:
    """The mass and the six tensor elements: given, or from ``shape`` and density or mass
    (``documented``: see :func:`_inertia`)."""
    if "shape" in table:
        return mass_and_inertia_from_shape(table, ctx)
    if "density" in table:
        raise ctx.error(f"{ctx.key('density')!r} needs a 'shape' (the volume it fills)")
    if "mass" not in table:
        raise ctx.error(f"{ctx.key('mass')!r} is missing; a [joints.link] table needs a mass")
    mass = sympy_value(table["mass"], "mass", ctx)
    _check_not_negative(mass, "mass", ctx)
    return mass, _inertia(table.get("inertia", {}), ctx, documented)


def _inertia(value: Any, ctx: Context, documented: bool = False) -> tuple[sp.Expr, ...]:
    """The six tensor elements about the COM; missing ones are 0.  ``documented``: the file
    explains the tensor (``inertia_note``), so a violated triangle inequality is not warned
    about."""
    table = as_table(value, "inertia", ctx)
    inner = ctx.within("inertia")
    check_keys(table, INERTIA_KEYS, inner)
    elements = tuple(sympy_value(table.get(k, 0), k, inner) for k in INERTIA_KEYS)
    numbers = [numeric_value(e, ctx) for e in elements]
    if all(n is not None for n in numbers):
        _check_inertia_physical(np.array(numbers, dtype=float), inner, documented)
    return elements


def _check_inertia_physical(elements: np.ndarray, ctx: Context, documented: bool) -> None:
    """Reject tensors no rigid body can have (negative moments, not PSD) with an error; warn
    (:class:`RobotWarning`) about a violated triangle inequality, which published models with
    lumped inertias do have (e.g. Corke's PUMA 560) and which the dynamics can still use,
    unless the file documents the tensor (``documented``)."""
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
    if documented:
        return
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


def _warn(ctx: Context, message: str) -> None:
    """A :class:`RobotWarning` located like an error (file, joint, key)."""
    warnings.warn(str(ctx.error(message)), RobotWarning, stacklevel=2)


def _friction(value: Any, ctx: Context) -> dict[str, sp.Expr | None]:
    """``coulomb``/``viscous``/``stribeck`` as :class:`Link` fields; ``coulomb_positive`` and
    ``coulomb_negative`` (both, instead of ``coulomb``) give ``coulomb`` and
    ``coulomb_negative``."""
    table = as_table(value, "friction", ctx)
    inner = ctx.within("friction")
    check_keys(table, FRICTION_KEYS, inner)
    result: dict[str, sp.Expr | None] = {}
    for key in ("coulomb", "viscous", *DIRECTIONAL_KEYS):
        result[key] = sympy_value(table.get(key, 0), key, inner)
        _check_not_negative(result[key], key, inner)
    directional = [key for key in DIRECTIONAL_KEYS if key in table]
    if directional:
        _check_directional(table, directional, inner)
        result["coulomb"] = result["coulomb_positive"]
    else:
        result["coulomb_negative"] = None
    del result["coulomb_positive"]
    if "stribeck" in table:
        result["stribeck_static"], result["stribeck_velocity"] = _stribeck(table["stribeck"], inner)
    # smoothing: the width w of tanh(dq / w) in place of sign(dq); stiction: gamma_s.
    if "smoothing" in table:
        result["coulomb_width"] = sympy_value(table["smoothing"], "smoothing", inner)
        check_positive(result["coulomb_width"], "smoothing", inner)
    if "stiction" in table:
        result["stiction"] = sympy_value(table["stiction"], "stiction", inner)
        _check_not_negative(result["stiction"], "stiction", inner)
    return result


def _check_directional(table: Mapping[str, Any], given: list[str], ctx: Context) -> None:
    """Both directional Coulomb keys, and neither ``coulomb`` nor ``stribeck`` beside them."""
    if len(given) == 1:
        missing = next(key for key in DIRECTIONAL_KEYS if key not in given)
        raise ctx.error(
            f"{ctx.key(given[0])!r} needs {ctx.key(missing)!r} as well "
            "(or one symmetric 'coulomb' value)"
        )
    if "coulomb" in table:
        raise ctx.error(
            f"{ctx.key('coulomb')!r} cannot be combined with 'coulomb_positive' and "
            "'coulomb_negative': give one symmetric value or the two directional ones"
        )
    if "stribeck" in table:
        raise ctx.error(
            f"{ctx.key('stribeck')!r} needs the symmetric 'coulomb'; it is not defined with "
            "'coulomb_positive' and 'coulomb_negative'"
        )


def _stribeck(value: Any, ctx: Context) -> tuple[sp.Expr, sp.Expr]:
    table = as_table(value, "stribeck", ctx)
    inner = ctx.within("stribeck")
    check_keys(table, STRIBECK_KEYS, inner)
    for key in STRIBECK_KEYS:
        if key not in table:
            raise inner.error(f"{inner.key(key)!r} is missing; stribeck needs static and velocity")
    static = sympy_value(table["static"], "static", inner)
    _check_not_negative(static, "static", inner)
    velocity = sympy_value(table["velocity"], "velocity", inner)
    number = numeric_value(velocity, inner)
    if number is not None and number <= 0:  # it divides the joint speed
        raise inner.error(f"{inner.key('velocity')!r} must be > 0, got {number:g}")
    return static, velocity


def _check_not_negative(expr: sp.Expr | None, key: str, ctx: Context) -> None:
    number = None if expr is None else numeric_value(expr, ctx)
    if number is not None and number < 0:
        raise ctx.error(f"{ctx.key(key)!r} must be >= 0, got {number:g}")

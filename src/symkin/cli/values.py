"""Argument values of the ``symkin`` command: numbers (``0.5``, ``-30deg``), per-joint lists,
``--set NAME=VALUE``, points, task rows, targets, limits and time limits.

Angles are radians unless a value ends in ``deg``; lengths are metres.  A bad value is a
:class:`~symkin.errors.SymkinError` naming the option it came from.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Sequence

import sympy as sp

from symkin.derive.kinematics import link_transform
from symkin.errors import SymkinError
from symkin.io import load_robot
from symkin.robot import Robot
from symkin.symbols import joint_symbols

# Every command stops with an error past this (no hang); the largest catalogue derivation
# takes well under a minute, a generic 6R arm about five.
DEFAULT_TIME_LIMIT = 900.0
MAX_TIME_LIMIT = 1e7
# Rows of a sampled table (identify --excite, trajopt --rate): held in memory as numbers and
# as CSV text, about 1 KiB a row for a 7-joint arm; a million rows is 2.8 hours at 100 Hz.
MAX_ROWS = 1_000_000
# Options whose values may start with a minus sign ("--q -30deg,45deg").
VALUE_OPTIONS = frozenset(
    {
        "--q",
        "--dq",
        "--ddq",
        "--d3q",
        "--d4q",
        "--set",
        "--point",
        "--task",
        "--target",
        "--q0",
        "--path-from",
        "--to",
        "--from",
        "--cartesian-goal",
    }
)
# Task rows written without commas: "xy", "xyz", "xywz".
COMPACT_ROWS = re.compile(r"(?:w?[xyz])+")


def number_from_text(text: str, what: str) -> float:
    """A float from ``"0.5"``, ``"-30deg"`` or ``"pi/2"``-free plain numbers."""
    raw = text.strip()
    scale = 1.0
    if raw.endswith("deg"):
        raw, scale = raw[: -len("deg")], math.pi / 180
    try:
        value = float(raw)
    except ValueError:
        raise SymkinError(f"{what}: expected a number such as 0.5 or 30deg, got {text!r}") from None
    if not math.isfinite(value):
        raise SymkinError(f"{what}: expected a finite number, got {text!r}")
    return value * scale


def time_limit_from_text(text: str) -> float:
    """Seconds for ``--time-limit``: a finite number from 0 (no limit) to about four months."""
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not 0 <= seconds <= MAX_TIME_LIMIT:
        raise argparse.ArgumentTypeError(
            f"expected seconds from 0 (no limit) to {MAX_TIME_LIMIT:g}, got {text!r}"
        )
    return seconds


SKIPPABLE = ("determinant", "dynamics")


def budget_from_text(text: str) -> float:
    """Seconds for ``--budget``: a finite number from 0 (no limit) to about four months."""
    return time_limit_from_text(text)


def skip_from_text(text: str) -> tuple[str, ...]:
    """``--skip determinant,dynamics``: the parts not to derive, each named once."""
    items = tuple(dict.fromkeys(item.strip() for item in text.split(",") if item.strip()))
    unknown = [item for item in items if item not in SKIPPABLE]
    if unknown or not items:
        raise argparse.ArgumentTypeError(
            f"expected a comma-separated list of {', '.join(SKIPPABLE)}, got {text!r}"
        )
    return items


def seed_from_text(text: str) -> int:
    """A random seed: a whole number >= 0 (what NumPy's generators accept)."""
    try:
        seed = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}") from None
    if seed < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}")
    return seed


def joint_values(text: str, option: str, robot: Robot) -> list[float]:
    """One value per joint from ``"v1,v2,..."``; ``deg`` only for revolute joints."""
    parts = text.split(",")
    if len(parts) != robot.dof:
        raise SymkinError(
            f"{option}: {robot.name} has {robot.dof} joints, got {len(parts)} value(s) in {text!r}"
        )
    values = []
    for i, (part, joint) in enumerate(zip(parts, robot.joints, strict=True), start=1):
        if part.strip().endswith("deg") and joint.type == "prismatic":
            raise SymkinError(f"{option}: joint {i} is prismatic; give a length, not {part!r}")
        values.append(number_from_text(part, f"{option} joint {i}"))
    return values


def parameter_overrides(items: Sequence[str], robot: Robot) -> dict[str, float]:
    """``["L1=0.3", ...]`` as a dict; ``deg`` only for a parameter that is an angle of the
    robot (inside a sine or cosine of its transforms: an ``alpha``, a ``theta``, an ``rpy``),
    so ``--set L1=30deg`` is not silently 0.52 m."""
    overrides = {}
    angles: frozenset[str] | None = None
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise SymkinError(f"--set: expected NAME=VALUE, got {item!r}")
        if value.strip().endswith("deg"):
            angles = angle_parameters(robot) if angles is None else angles
            known = any(name == parameter for parameter, _ in robot.parameters)
            if known and name not in angles:  # an unknown name is said where all are checked
                raise SymkinError(
                    f"--set {name}: 'deg' is for a parameter that is an angle of the robot "
                    f"(alpha, theta, rpy); {name} is not one: give its value in SI units"
                )
        overrides[name] = number_from_text(value, f"--set {name}")
    return overrides


def angle_parameters(robot: Robot) -> frozenset[str]:
    """The parameters that appear in the argument of a sine or cosine of a joint's transform
    or of the base or tool transform."""
    matrices = [robot.base, robot.tool]
    q = joint_symbols(robot.dof)
    matrices += [
        link_transform(joint, qi, robot.convention)
        for joint, qi in zip(robot.joints, q, strict=True)
    ]
    inside = {
        symbol.name
        for matrix in matrices
        for trig in sp.Matrix(matrix).atoms(sp.sin, sp.cos)
        for symbol in trig.free_symbols
    }
    return frozenset(name for name, _ in robot.parameters if name in inside)


def wrench_from_text(text: str) -> list[float]:
    """``"fx,fy,fz,nx,ny,nz"`` (N and N m) for ``--wrench``."""
    parts = text.split(",")
    if len(parts) != 6:
        raise SymkinError(
            f"--wrench: expected six values FX,FY,FZ,MX,MY,MZ (N, N m), got {len(parts)} "
            f"in {text!r}"
        )
    names = ("FX", "FY", "FZ", "MX", "MY", "MZ")
    for name, part in zip(names, parts, strict=True):
        if part.strip().endswith("deg"):
            raise SymkinError(f"--wrench {name}: a force or moment, not an angle: {part!r}")
    return [number_from_text(p, f"--wrench {n}") for n, p in zip(names, parts, strict=True)]


def point_from_text(text: str, robot: Robot) -> tuple[int, list[float]]:
    """``"LINK:X,Y,Z"`` as ``(link, [x, y, z])``."""
    link_text, sep, coordinates = text.partition(":")
    try:
        link = int(link_text)
    except ValueError:
        link = -1
    if not sep or not 0 <= link <= robot.dof:
        raise SymkinError(
            f"--point: expected LINK:X,Y,Z with LINK from 0 to {robot.dof}, got {text!r}"
        )
    values = coordinates.split(",")
    if len(values) != 3:
        raise SymkinError(f"--point: expected three coordinates X,Y,Z, got {coordinates!r}")
    if any(v.strip().endswith("deg") for v in values):
        raise SymkinError(f"--point: coordinates are lengths in metres, got {coordinates!r}")
    return link, [number_from_text(v, "--point") for v in values]


def task_rows_from_text(text: str | None) -> tuple[str, ...] | None:
    """``"x,y,wz"`` (or ``"xywz"``) as a tuple of row names (validated by the model)."""
    if text is None:
        return None
    rows = tuple(part.strip() for part in text.split(",") if part.strip())
    if len(rows) == 1 and COMPACT_ROWS.fullmatch(rows[0]):
        rows = tuple(re.findall(r"w?[xyz]", rows[0]))
    if not rows:
        raise SymkinError(f"--task: name at least one row of x, y, z, wx, wy, wz, got {text!r}")
    return rows


def target_from_text(text: str, option: str) -> list[float]:
    """``x,y``, ``x,y,z`` or ``x,y,z,rx,ry,rz``: metres, then Z-Y-X Euler angles (rad or deg)."""
    parts = text.split(",")
    if len(parts) not in (2, 3, 6):
        raise SymkinError(
            f"{option}: expected x,y or x,y,z or x,y,z,rx,ry,rz (Z-Y-X Euler angles), "
            f"got {len(parts)} value(s) in {text!r}"
        )
    for part in parts[:3]:
        if part.strip().endswith("deg"):
            raise SymkinError(f"{option}: x, y, z are lengths in metres, got {part.strip()!r}")
    return [number_from_text(part, option) for part in parts]


def limit_values(text: str | None, option: str, robot: Robot, rates: bool) -> list[float] | None:
    """Per-joint limits from ``"v"`` (the same for every joint) or ``"v1,v2,..."``.

    Velocities (``rates``) take ``deg`` (deg/s) for revolute joints; torques and forces do not.
    """
    if text is None:
        return None
    if not rates and "deg" in text:
        raise SymkinError(f"{option}: torques and forces are plain numbers (N m, N), got {text!r}")
    return joint_values(text if "," in text else ",".join([text] * robot.dof), option, robot)


def seconds_from_text(text: str, option: str) -> float:
    """A duration in seconds: a plain number, no ``deg``."""
    if text.strip().endswith("deg"):
        raise SymkinError(f"{option}: a time in seconds, got {text!r}")
    return number_from_text(text, option)


def sampled_rows(rate: float, seconds: float, rate_option: str, time_option: str) -> int:
    """The rows of a table sampled at ``rate`` Hz over ``seconds`` (both ends: ``seconds *
    rate + 1``); a :class:`SymkinError` naming the options when either is not a positive
    finite number or ``rate * seconds`` exceeds :data:`MAX_ROWS`."""
    for value, option in ((rate, rate_option), (seconds, time_option)):
        if not (math.isfinite(value) and value > 0):
            raise SymkinError(f"{option}: expected a positive finite number, got {value:g}")
    if seconds * rate > MAX_ROWS:  # the docs' "rate x time at most 10^6 samples"
        raise SymkinError(
            f"{rate_option} {rate:g} over {time_option} {seconds:g} s is {seconds * rate:,.0f} "
            f"samples; at most {MAX_ROWS:,} (lower {rate_option} or {time_option})"
        )
    return math.floor(seconds * rate) + 1


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``["--q", "-30deg"]`` -> ``["--q=-30deg"]`` so argparse does not see an option."""
    joined: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in VALUE_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            joined.append(f"{arg}={argv[i + 1]}")
            i += 2
        else:
            joined.append(arg)
            i += 1
    return joined


def robot_from_args(args: argparse.Namespace) -> Robot:
    """The robot named by ``ROBOT`` (``--tip``/``--base`` choose a URDF's chain)."""
    return load_robot(args.robot, tip=getattr(args, "tip", None), base=getattr(args, "base", None))

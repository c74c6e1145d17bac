"""The drive keys of ``[joints.link]``: ``stiffness`` (an elastic joint) and the ``drive``
table (gear ratio, rotor inertia, DC motor), read into :class:`~symkin.robot.Drive`.

``drive.rotor_inertia`` ``Jm`` is reflected to the joint as ``G^2 Jm`` (the motor turns ``G``
times as fast, so its kinetic energy is ``1/2 Jm (G dq)^2``) and becomes the link's
``motor_inertia``; giving both is an error, so no inertia is counted twice.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import sympy as sp

from symkin.io.context import Context, as_table, check_keys
from symkin.io.expressions import numeric_value, sympy_value
from symkin.robot import Drive

DRIVE_KEYS = (
    "gear_ratio", "rotor_inertia", "torque_constant", "back_emf_constant", "resistance",
    "inductance",
)  # fmt: skip
MOTOR_KEYS = ("torque_constant", "back_emf_constant", "resistance")


def read_stiffness(link: Mapping[str, Any], ctx: Context) -> sp.Expr | None:
    """``stiffness`` K (N m/rad or N/m), > 0 when numeric; None for a rigid joint."""
    if "stiffness" not in link:
        return None
    stiffness = sympy_value(link["stiffness"], "stiffness", ctx)
    check_positive(stiffness, "stiffness", ctx)
    if "motor_inertia" not in link and "drive" not in link:
        raise ctx.error(
            f"{ctx.key('stiffness')!r} makes the joint elastic, which needs the motor-side "
            "inertia: give 'motor_inertia' (B) or 'drive.rotor_inertia'"
        )
    return stiffness


def read_drive(link: Mapping[str, Any], ctx: Context) -> tuple[Drive | None, sp.Expr | None]:
    """The ``drive`` table and the reflected rotor inertia ``G^2 Jm`` (None without one)."""
    if "drive" not in link:
        return None, None
    table = as_table(link["drive"], "drive", ctx)
    inner = ctx.within("drive")
    check_keys(table, DRIVE_KEYS, inner)
    values = {key: sympy_value(table[key], key, inner) for key in DRIVE_KEYS if key in table}
    for key, value in values.items():
        check_positive(value, key, inner)
    given = [key for key in MOTOR_KEYS if key in values]
    if (given and len(given) != len(MOTOR_KEYS)) or ("inductance" in values and not given):
        missing = ", ".join(repr(inner.key(k)) for k in MOTOR_KEYS if k not in values)
        raise inner.error(f"a DC motor needs {', '.join(MOTOR_KEYS)}; missing {missing}")
    if "rotor_inertia" in values and "motor_inertia" in link:
        raise inner.error(
            f"{inner.key('rotor_inertia')!r} and 'motor_inertia' both give the rotor's inertia; "
            "keep one (motor_inertia is the reflected G^2 Jm)"
        )
    drive = Drive(**values)
    reflected = None
    if drive.rotor_inertia is not None:
        reflected = drive.gear_ratio**2 * drive.rotor_inertia
    return drive, reflected


def check_positive(expr: sp.Expr, key: str, ctx: Context) -> None:
    """A numeric ``expr`` must be > 0 (a stiffness, a width, a motor constant)."""
    number = numeric_value(expr, ctx)
    if number is not None and number <= 0:
        raise ctx.error(f"{ctx.key(key)!r} must be > 0, got {number:g}")

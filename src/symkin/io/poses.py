"""``[poses]``: named configurations in a robot file (``home = [0, 30, -60]``).

Each pose lists one value per joint, revolute joints in the file's ``angles`` unit (degrees
unless ``angles = "rad"``), prismatic joints in metres; the robot keeps them in radians and
metres.  They are names for configurations the commands accept (``--pose home``) and the one
Jupyter shows a model in.
"""

from __future__ import annotations

import math
from typing import Any

from symkin.io.context import Context, as_table, show
from symkin.io.expressions import finite_number, is_number
from symkin.robot import NAME_PATTERN, Joint


def read_poses(
    value: Any, joints: tuple[Joint, ...], ctx: Context
) -> tuple[tuple[str, tuple[float, ...]], ...]:
    """The ``[poses]`` table as ``(name, values)`` pairs in file order, values in SI units."""
    table = as_table(value, "poses", ctx)
    return tuple((name, _pose(name, values, joints, ctx)) for name, values in table.items())


def _pose(name: str, values: Any, joints: tuple[Joint, ...], ctx: Context) -> tuple[float, ...]:
    key = f"poses.{name}"
    if not NAME_PATTERN.match(name):
        raise ctx.error(f"{key!r}: a pose name must match [a-z][a-z0-9_]*, got {show(name)}")
    if not isinstance(values, list) or len(values) != len(joints):
        raise ctx.error(
            f"{key!r} must list {len(joints)} numbers (one per joint), got {show(values)}"
        )
    scale = math.pi / 180 if ctx.angles == "deg" else 1.0
    pose = []
    for joint, v in zip(joints, values, strict=True):
        if not is_number(v):
            raise ctx.error(f"{key!r} must hold numbers, got {show(v)}")
        number = float(finite_number(v, key, ctx))
        pose.append(number * scale if joint.type == "revolute" else number)
    return tuple(pose)

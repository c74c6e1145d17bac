"""IK targets: a tool pose in the base frame from ``x, y, z[, rx, ry, rz]``.

Convention (docs/conventions.md, docs/ik.md): the position is in metres, base frame; the
rotation is given by Z-Y-X Euler angles in radians, ``R = Rz(rz) Ry(ry) Rx(rx)`` (yaw ``rz``
about z, then pitch ``ry`` about the new y', then roll ``rx`` about x''; the same matrix as
roll ``rx``, pitch ``ry``, yaw ``rz`` about the fixed axes X, Y, Z).  The values are listed in
the order x, y, z, rx, ry, rz, i.e. the rotation angles in the order they act on fixed axes.

``orientation`` names another way to read the three rotation values: any of the twelve
intrinsic Euler orders (``"xyz"`` ... ``"zyz"``: ``R = Ra(v4) Rb(v5) Rc(v6)`` for order
``"abc"``) or ``"rotvec"`` (the rotation vector ``(v4, v5, v6) = axis * angle``); see
:func:`symkin.spatial.rotation_from_orientation`.

Three values give a position-only target: its rotation is the identity and means nothing; the
solver is told separately (``position_only=True``) to ignore it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from symkin.derive import Model
from symkin.derive.jacobians import rows_from_names
from symkin.errors import SymkinError
from symkin.spatial import rotation_from_euler_zyx, rotation_from_orientation


def pose_from_target(values: Sequence[float], orientation: str | None = None) -> np.ndarray:
    """The 4x4 pose of ``x, y, z`` or ``x, y, z, rx, ry, rz`` (``R = Rz(rz) Ry(ry) Rx(rx)``),
    or of ``x, y, z`` and three values of ``orientation`` (see the module docstring)."""
    values = [float(v) for v in values]
    if len(values) not in (3, 6):
        raise SymkinError(
            f"a target is x,y,z or x,y,z,rx,ry,rz (Z-Y-X Euler angles), got {len(values)} values"
        )
    if not all(np.isfinite(values)):
        raise SymkinError(f"a target needs finite numbers, got {values}")
    pose = np.eye(4)
    pose[:3, 3] = values[:3]
    if len(values) == 6 and orientation is not None:
        pose[:3, :3] = rotation_from_orientation(orientation, values[3:])
    elif len(values) == 6:
        rx, ry, rz = values[3:]
        pose[:3, :3] = rotation_from_euler_zyx(rz, ry, rx)
    return pose


def task_rows_for(
    model: Model, task: Sequence[str] | None = None, position_only: bool = False
) -> tuple[str, ...]:
    """The rows an IK problem matches: ``task``, else ``x y z`` for a position-only target,
    else the robot's default task rows (``model.task_rows``: planar 2R ``x y``, 6 DOF all)."""
    if task is not None:
        rows = tuple(task)
    elif position_only:
        rows = ("x", "y", "z")
    else:
        rows = model.task_rows
    rows_from_names(rows)
    if not rows:
        raise SymkinError("the task needs at least one row of x, y, z, wx, wy, wz")
    return rows

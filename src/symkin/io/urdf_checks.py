"""Checks of a parsed URDF's numbers and names, before any of them is used.

The parser (``urdf_parser_py``) accepts what XML Schema's ``double`` accepts, so ``inf`` and
``NaN`` pass, and it keeps repeated names.  The same rules as a robot file's apply
(docs/robot-files.md): every number finite, a mass and the principal moments of an inertia
tensor not negative (the tensor positive semi-definite), position limits with
``lower <= upper``; link and joint names unique (URDF specification, ``<robot>``).  Each
problem is one :class:`~symkin.errors.RobotError` naming the file and the link or joint.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from symkin.errors import RobotError

__all__ = ["check_inertial", "check_urdf_model"]

INERTIA_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")


def check_urdf_model(model: Any, file: str) -> None:
    """Raise :class:`RobotError` for the first repeated name or invalid joint number of
    ``model`` (inertials are checked by :func:`check_inertial` on the links the chain uses:
    real files have broken ones on links off the chain, e.g. TIAGo's antennas)."""
    _check_unique(file, "link", (link.name for link in model.links))
    _check_unique(file, "joint", (joint.name for joint in model.joints))
    for joint in model.joints:
        where = f"{file}: joint {joint.name!r}"
        _check_pose(where, joint.origin)
        _check_finite(where, "axis", joint.axis or ())
        _check_limits(where, joint.limit)


def _check_unique(file: str, kind: str, names: Iterable[str]) -> None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise RobotError(f"{file}: two {kind}s are named {name!r}; URDF names are unique")
        seen.add(name)


def _check_finite(where: str, key: str, values: Iterable[Any]) -> None:
    numbers = [float(v) for v in values]
    if not all(math.isfinite(v) for v in numbers):
        raise RobotError(f"{where}: {key} must be finite numbers, got {numbers}")


def _check_pose(where: str, pose: Any) -> None:
    if pose is not None:
        _check_finite(where, "origin xyz", pose.xyz or ())
        _check_finite(where, "origin rpy", pose.rpy or ())


def _check_limits(where: str, limit: Any) -> None:
    if limit is None:
        return
    values = [getattr(limit, key) for key in ("lower", "upper", "velocity", "effort")]
    _check_finite(where, "limit lower, upper, velocity and effort", (v or 0 for v in values))
    lower, upper = values[0], values[1]
    if lower is not None and upper is not None and float(lower) > float(upper):
        raise RobotError(f"{where}: limit lower={lower} is above upper={upper}")


def check_inertial(where: str, inertial: Any) -> None:
    """Mass >= 0 and a positive semi-definite tensor: relative tolerance 1e-9, as for a robot
    file's ``[joints.link]``, and absolute 1e-12 kg m^2 (iCub's head holds +-2e-35)."""
    _check_pose(where, inertial.origin)
    mass = float(inertial.mass or 0.0)
    tensor = inertial.inertia
    elements = [float(getattr(tensor, k) or 0.0) for k in INERTIA_KEYS] if tensor else [0.0] * 6
    _check_finite(where, "inertial mass and inertia", [mass, *elements])
    if mass < 0:
        raise RobotError(f"{where}: inertial mass must be >= 0, got {mass:g}")
    ixx, iyy, izz, ixy, ixz, iyz = elements
    matrix = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    moments = np.linalg.eigvalsh(matrix)
    if moments[0] < -max(1e-9 * float(np.max(np.abs(matrix))), 1e-12):
        raise RobotError(
            f"{where}: the inertia tensor is not positive semi-definite: principal moments "
            f"{', '.join(f'{m:g}' for m in moments)}"
        )

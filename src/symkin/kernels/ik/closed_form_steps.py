"""The per-pose steps the closed-form families share, on floats: the two-link elbow, the
waist angle with a shoulder offset, square roots clamped at the edge of the workspace, the
branch flags.  ``templates/c/lib/symkin_closed_form.h`` holds the same steps in C.
"""

from __future__ import annotations

import math

import numpy as np

#: ``|cos delta|`` up to this much above 1 is rounding at full stretch, clamped to 1; the FK
#: check then decides whether the pose is reached.
REACH_TOL = 1e-9
#: ``sin th5`` below this is the wrist singularity (one joint set to its offset, flag "singular").
WRIST_SINGULAR = 1e-12

#: A raw solution: joint values (not yet wrapped) and branch flags as (name, value) pairs.
Candidate = tuple[tuple[float, ...], tuple[tuple[str, str], ...]]


def rot_z(angle: float) -> np.ndarray:
    """``Rz(angle)`` as a 3x3 float array."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def twist_rotations(cosines: tuple[float, ...], sines: tuple[float, ...]) -> list[np.ndarray]:
    """``Rx(alpha_i)`` as 3x3 float arrays, from the cosines and sines of the twists."""
    return [
        np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
        for c, s in zip(cosines, sines, strict=True)
    ]


def transform(entries: tuple[float, ...] | None) -> np.ndarray:
    """A row-major 4x4 transform from its 16 entries; the identity for ``None``."""
    return np.eye(4) if entries is None else np.array(entries, dtype=float).reshape(4, 4)


def clamped_sqrt(value: float, scale: float) -> float | None:
    """``sqrt(value)``; a negative ``value`` within rounding of 0 (relative to ``scale``) gives
    0, a clearly negative one ``None`` (no real solution)."""
    if value >= 0.0:
        return math.sqrt(value)
    return 0.0 if value >= -REACH_TOL * scale else None


def two_link(x: float, y: float, l1: float, l2: float) -> tuple[tuple[float, float, int], ...]:
    """Both solutions ``(beta_1, delta, sign of sin delta)`` of
    ``l1 (cos beta_1, sin beta_1) + l2 (cos(beta_1 + delta), sin(beta_1 + delta)) = (x, y)``.

    Empty when the point is out of reach.  ``l1, l2 > 0``.  The textbook two-link solution
    (Spong, Hutchinson, Vidyasagar, *Robot Modeling and Control*, Sec. 5.3; Craig,
    *Introduction to Robotics*, Sec. 4.4) without ``acos``: ``cos delta = (|p|^2 - l1^2 -
    l2^2) / (2 l1 l2)``, ``delta = atan2(+-sqrt(1 - cos^2), cos)``, ``beta_1 = atan2(y, x) -
    atan2(l2 sin delta, l1 + l2 cos delta)``.
    """
    cos_delta = (x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    if abs(cos_delta) > 1.0 + REACH_TOL:
        return ()
    cos_delta = min(1.0, max(-1.0, cos_delta))
    sin_delta = math.sqrt((1.0 - cos_delta) * (1.0 + cos_delta))
    direction = math.atan2(y, x)
    return tuple(
        (direction - math.atan2(l2 * s, l1 + l2 * cos_delta), math.atan2(s, cos_delta), sign)
        for s, sign in ((sin_delta, 1), (-sin_delta, -1))
    )


def shoulder(x: float, y: float, offset: float, scale: float) -> tuple[tuple[float, float], ...]:
    """Both ``(X, th1)`` with ``Rz(th1) (X, offset) = (x, y)``: the waist angle that puts a
    point at horizontal offset ``offset`` from the arm's plane (Paul and Zhang 1986, eq. 40).
    Empty when the point is closer to the waist axis than ``|offset|``."""
    reach = clamped_sqrt(x * x + y * y - offset * offset, scale * scale)
    if reach is None:
        return ()
    direction = math.atan2(y, x)
    return tuple((X, direction - math.atan2(offset, X)) for X in (reach, -reach))


def shoulder_flag(X: float, offset: float) -> tuple[str, str]:
    """Shoulder "right" when the shoulder offset lies to the right of the reach direction seen from
    above (``X * offset < 0``; with no offset: reaching forward, ``X >= 0``).  For the PUMA 560
    this is Robotics Toolbox's 'r' (righty)."""
    right = X * offset < 0 if offset != 0.0 else X >= 0
    return ("shoulder", "right" if right else "left")


def elbow_flag(sign: int, X: float, twist: int) -> tuple[str, str]:
    """Elbow "up" when the elbow lies above the line from the shoulder to the wrist, looking at the
    arm's plane with the reach pointing forward: ``-sign(sin delta) sign(X) sin(alpha_1) > 0``
    (for the PUMA 560 Robotics Toolbox's 'u')."""
    forward = 1 if X >= 0 else -1
    return ("elbow", "up" if -sign * forward * twist > 0 else "down")


def extension_flag(root: float) -> tuple[str, str]:
    """Extension "forward" for the positive square root of the reach equation (for the Stanford arm:
    the prismatic reach ``lambda`` is positive), "backward" for the negative one."""
    return ("extension", "forward" if root >= 0 else "backward")

"""The geometry under DH extraction: joint axes as lines, and the common normal of two lines.

Plain NumPy on the axes of a robot at ``q = 0`` (base frame of the base's parent, numbers).
The cases follow the lecture's frame-assignment procedure (Spong, Hutchinson and Vidyasagar,
*Robot Modeling and Control*, sec. 3.3): skew axes have one common normal; parallel axes
have infinitely many, and the one through the previous origin is taken (``d_i = 0``);
intersecting axes have a normal of length zero along ``z_{i-1} x z_i``; coincident axes leave
the normal's direction free.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

# Two directions are parallel, or two lines meet, when they do so to this tolerance
# (radians for directions, metres for distances): far below any machined offset, far above
# the rounding of a product of a few transforms.
SNAP_TOLERANCE = 1e-9

Case = Literal["skew", "parallel", "intersecting", "coincident"]


@dataclass(frozen=True)
class Line:
    """A directed line: a point on it and a unit direction (a joint axis, or the tool's z)."""

    point: np.ndarray
    direction: np.ndarray

    def foot_of(self, point: np.ndarray) -> np.ndarray:
        """The point of this line nearest ``point`` (orthogonal projection)."""
        return self.point + np.dot(point - self.point, self.direction) * self.direction


@dataclass(frozen=True)
class Normal:
    """The common normal chosen between line k (start) and line k+1 (end).

    ``direction`` is the unit x axis of the DH frame it defines; ``length`` the signed
    distance from start to end along it (the ``a`` of the DH row).
    """

    case: Case
    start: np.ndarray
    end: np.ndarray
    direction: np.ndarray
    length: float


def unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def perpendicular_part(vector: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """``vector`` with its component along the unit ``axis`` removed."""
    return vector - np.dot(vector, axis) * axis


def oriented(direction: np.ndarray, previous_x: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """``+direction`` or ``-direction``, whichever makes the joint offset smallest.

    Both signs give a valid x axis; the one within 90 degrees of the previous x axis keeps
    ``|theta offset| < 90 deg`` (so a published table whose offsets are zero comes back
    unchanged, negative ``a`` included).  At exactly 90 degrees, the one that turns
    positively about ``axis`` (offset ``+90 deg``).
    """
    cosine = float(np.dot(direction, previous_x))
    if abs(cosine) > SNAP_TOLERANCE:
        return direction if cosine > 0 else -direction
    turn = float(np.dot(np.cross(previous_x, direction), axis))
    return direction if turn > 0 else -direction


def common_normal(
    first: Line, second: Line, start: np.ndarray, previous_x: np.ndarray, scale: float
) -> Normal:
    """The common normal from ``first`` to ``second`` by the lecture's cases.

    ``start`` is where the previous normal ended on ``first`` (or frame 0's origin): the
    normal of parallel and coincident lines starts there (``d = 0``).  ``previous_x`` orients
    the result (:func:`oriented`) and is its direction when the lines coincide.
    """
    tolerance = SNAP_TOLERANCE * max(1.0, scale)
    cross = np.cross(first.direction, second.direction)
    sine = float(np.linalg.norm(cross))
    if sine < SNAP_TOLERANCE:
        end = second.foot_of(start)
        offset = end - start
        if np.linalg.norm(offset) < tolerance:
            end = first.foot_of(second.point)
            return Normal("coincident", start, end, previous_x, 0.0)
        return _normal("parallel", start, end, unit(offset), previous_x, first.direction)
    between = second.point - first.point
    t_first = float(np.dot(np.cross(between, second.direction), cross)) / sine**2
    t_second = float(np.dot(np.cross(between, first.direction), cross)) / sine**2
    foot_first = first.point + t_first * first.direction
    foot_second = second.point + t_second * second.direction
    offset = foot_second - foot_first
    if np.linalg.norm(offset) < tolerance:
        middle = (foot_first + foot_second) / 2
        return _normal("intersecting", middle, middle, cross / sine, previous_x, first.direction)
    return _normal("skew", foot_first, foot_second, unit(offset), previous_x, first.direction)


def _normal(
    case: Case,
    start: np.ndarray,
    end: np.ndarray,
    direction: np.ndarray,
    previous_x: np.ndarray,
    axis: np.ndarray,
) -> Normal:
    x = oriented(direction, previous_x, axis)
    return Normal(case, start, end, x, float(np.dot(end - start, x)))


def frame_from_axes(origin: np.ndarray, x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The 4x4 pose with the given origin, x and z axes (``y = z x x``)."""
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2], frame[:3, 3] = x, np.cross(z, x), z, origin
    return frame


def base_x_axis(base: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Frame 0's x axis: the base's x axis made perpendicular to ``z`` (its y axis when the
    base's x axis lies along ``z``), so frame 0 is the base frame whenever it can be."""
    for column in (0, 1):
        candidate = perpendicular_part(base[:3, column], z)
        if np.linalg.norm(candidate) > 1e-6:
            return unit(candidate)
    raise AssertionError("a rotation has two columns perpendicular to any unit vector")

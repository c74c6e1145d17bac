"""Three orientation numbers by name: any of the twelve Euler orders or the rotation vector.

One switch for the places where a user picks how an orientation is written (``symkin eval
--euler``, ``symkin ik --euler``): ``"zyx"`` ... ``"zyz"`` are intrinsic Euler/Tait-Bryan
angles (:mod:`symkin.spatial.euler`), ``"rotvec"`` is the rotation vector ``w = axis * angle``
(:func:`~symkin.spatial.lie.rotation_vector_from_rotation`, ``|w|`` in ``[0, pi]``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from symkin.errors import SymkinError
from symkin.spatial.backend import Matrix, MatrixLike, Scalar
from symkin.spatial.euler import EULER_ORDERS, euler_from_rotation, rotation_from_euler
from symkin.spatial.lie import rotation_from_rotation_vector, rotation_vector_from_rotation

#: Every name :func:`orientation_from_rotation` accepts.
ORIENTATIONS = (*EULER_ORDERS, "rotvec")


class Orientation(NamedTuple):
    """Three numbers of representation ``kind`` and its singular flag.

    For Euler orders ``singular`` is gimbal lock; for ``rotvec`` it is ``angle = pi``, where
    ``w`` and ``-w`` are the same rotation.
    """

    kind: str
    values: tuple[Scalar, Scalar, Scalar]
    singular: bool | None


def _check(kind: str) -> str:
    if not isinstance(kind, str) or kind.lower() not in ORIENTATIONS:
        raise SymkinError(f"orientation must be one of {', '.join(ORIENTATIONS)}, got {kind!r}")
    return kind.lower()


def orientation_from_rotation(R: MatrixLike, kind: str) -> Orientation:
    """``R`` as intrinsic Euler angles of order ``kind`` or as the rotation vector."""
    kind = _check(kind)
    if kind == "rotvec":
        w, _, singular = rotation_vector_from_rotation(R)
        return Orientation(kind, tuple(w[i] for i in range(3)), singular)
    angles, _, _, singular = euler_from_rotation(R, kind)
    return Orientation(kind, tuple(angles), singular)


def rotation_from_orientation(kind: str, values: Sequence[Scalar]) -> Matrix:
    """The rotation matrix of three numbers of representation ``kind``."""
    kind = _check(kind)
    if kind == "rotvec":
        return rotation_from_rotation_vector(values)
    return rotation_from_euler(kind, values)

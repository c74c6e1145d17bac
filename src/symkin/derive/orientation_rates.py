"""Orientation coordinates and the matrices ``E`` that map their rates to angular velocity.

For orientation coordinates ``phi`` of the tool, the base-frame angular velocity is
``w = E(phi) dphi/dt``, so the analytic Jacobian is ``J_a = blockdiag(I, E(phi)^-1) J_g``.
``E`` is singular where the coordinates are (the representation's own singular set, not the
robot's).  Representations (``R`` the tool rotation, rotations active, column vectors):

* ``"zyx"``: ``(psi, theta, phi)`` with ``R = Rz(psi) Ry(theta) Rx(phi)``;
  ``det E = -cos(theta)``: singular at ``theta = +-pi/2`` (gimbal lock).
* ``"rpy"``: ``(roll, pitch, yaw)`` about fixed X, Y, Z, ``R = Rz(yaw) Ry(pitch) Rx(roll)``: the
  same matrix as Z-Y-X (``roll = phi``, ``pitch = theta``, ``yaw = psi``), coordinates in the
  reverse order (``E``'s columns reversed, so ``det E = +cos(pitch)``); singular at
  ``pitch = +-pi/2``.
* ``"zyz"``: ``(alpha, beta, gamma)`` with ``R = Rz(alpha) Ry(beta) Rz(gamma)``;
  ``det E = -sin(beta)``: singular at ``beta = 0`` and ``pi`` (every planar arm is there).
* ``"rotation_vector"``: ``r = theta u`` (axis-angle, ``R = exp([r]x)``, ``theta = |r|``);
  ``E = I + (1 - cos theta)/theta^2 [r]x + (theta - sin theta)/theta^3 [r]x^2`` (the left
  Jacobian of SO(3)), ``det E = 2 (1 - cos theta)/theta^2``: singular at ``theta = 2 pi k``,
  ``k = 1, 2, ...``.  The closed form
  ``E^-1 = I - [r]x / 2 + (1/theta^2 - (1 + cos theta)/(2 theta sin theta)) [r]x^2``
  is 0/0 at ``theta = 0`` (removable: ``E = I`` there, the coefficient tends to 1/12); the
  principal rotation vector (``theta`` in ``[0, pi]``) never reaches ``2 pi`` but jumps from
  ``r`` to ``-r`` where ``theta`` passes ``pi``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from symkin.errors import SymkinError

REPRESENTATIONS = ("zyx", "rpy", "zyz", "rotation_vector")


@dataclass(frozen=True)
class OrientationRates:
    """``w = E dphi/dt`` for one representation, in its coordinate symbols.

    ``inverse`` is ``E^-1`` in closed form; ``singular`` the conditions on the coordinates
    under which ``det E = 0``.
    """

    representation: str
    coordinates: tuple[sp.Symbol, ...]
    rate_matrix: sp.ImmutableMatrix
    inverse: sp.ImmutableMatrix
    determinant: sp.Expr
    singular: tuple[sp.Eq, ...]


def _symbols(names: str) -> tuple[sp.Symbol, ...]:
    return tuple(sp.symbols(names, real=True))


def _zyx() -> OrientationRates:
    psi, theta, phi = _symbols("psi theta phi")
    cps, sps, cth, sth = sp.cos(psi), sp.sin(psi), sp.cos(theta), sp.sin(theta)
    # Columns: z, Rz(psi) y, Rz(psi) Ry(theta) x.
    E = sp.ImmutableMatrix([[0, -sps, cps * cth], [0, cps, sps * cth], [1, 0, -sth]])
    inverse = sp.ImmutableMatrix(
        [[cps * sth / cth, sps * sth / cth, 1], [-sps, cps, 0], [cps / cth, sps / cth, 0]]
    )
    return OrientationRates("zyx", (psi, theta, phi), E, inverse, -cth, (sp.Eq(cth, 0),))


def _rpy() -> OrientationRates:
    zyx = _zyx()
    roll, pitch, yaw = _symbols("roll pitch yaw")
    rename = dict(zip(zyx.coordinates, (yaw, pitch, roll), strict=True))
    E = zyx.rate_matrix.xreplace(rename)[:, ::-1]
    inverse = zyx.inverse.xreplace(rename)[::-1, :]
    return OrientationRates(
        "rpy", (roll, pitch, yaw), E, inverse, sp.cos(pitch), (sp.Eq(sp.cos(pitch), 0),)
    )


def _zyz() -> OrientationRates:
    alpha, beta, gamma = _symbols("alpha beta gamma")
    ca, sa, cb, sb = sp.cos(alpha), sp.sin(alpha), sp.cos(beta), sp.sin(beta)
    # Columns: z, Rz(alpha) y, Rz(alpha) Ry(beta) z.
    E = sp.ImmutableMatrix([[0, -sa, ca * sb], [0, ca, sa * sb], [1, 0, cb]])
    inverse = sp.ImmutableMatrix(
        [[-ca * cb / sb, -sa * cb / sb, 1], [-sa, ca, 0], [ca / sb, sa / sb, 0]]
    )
    return OrientationRates("zyz", (alpha, beta, gamma), E, inverse, -sb, (sp.Eq(sb, 0),))


def _rotation_vector() -> OrientationRates:
    r = _symbols("rx ry rz")
    theta = sp.sqrt(sum(c**2 for c in r))
    skew = sp.Matrix([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    E = (
        sp.eye(3)
        + (1 - sp.cos(theta)) / theta**2 * skew
        + (theta - sp.sin(theta)) / theta**3 * skew**2
    )
    coefficient = 1 / theta**2 - (1 + sp.cos(theta)) / (2 * theta * sp.sin(theta))
    inverse = sp.eye(3) - skew / 2 + coefficient * skew**2
    k = sp.Symbol("k", integer=True, positive=True)
    determinant = 2 * (1 - sp.cos(theta)) / theta**2
    return OrientationRates(
        "rotation_vector",
        r,
        sp.ImmutableMatrix(E),
        sp.ImmutableMatrix(inverse),
        determinant,
        (sp.Eq(theta, 2 * sp.pi * k),),
    )


_BUILDERS = {"zyx": _zyx, "rpy": _rpy, "zyz": _zyz, "rotation_vector": _rotation_vector}


def orientation_rates(representation: str) -> OrientationRates:
    """``E``, ``E^-1`` and the singular set of one representation (see the module docstring)."""
    if representation not in _BUILDERS:
        raise SymkinError(
            f"unknown orientation representation {representation!r}; expected one of "
            f"{', '.join(REPRESENTATIONS)}"
        )
    return _BUILDERS[representation]()

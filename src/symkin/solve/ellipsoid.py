"""Velocity and force manipulability ellipsoids at one configuration (Yoshikawa 1985).

With ``Jv`` the translational rows of the geometric Jacobian (those of x, y, z that are not
identically zero) and its singular value decomposition ``Jv = U S V^T``:

* the **velocity ellipsoid** ``{Jv dq : |dq| <= 1}`` has its axes along the columns of ``U``
  with semi-axes the singular values ``s_i`` (m/s per rad/s): the tool moves fastest along
  ``u_1``;
* the **force ellipsoid** ``{f : |Jv^T f| <= 1}`` (the tool forces that unit joint torques
  balance, ``tau = Jv^T f``) has the same axes with semi-axes ``1 / s_i``: the arm resists
  best where it moves slowest.  A zero singular value (a singular configuration) gives an
  infinite force semi-axis along that direction.

The manipulability ``w = s_1 s_2 ... `` is the velocity ellipsoid's volume up to a constant.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.ik.joints import parameter_vector
from symkin.solve.workspace import translational_rows

ROW_NAMES = ("x", "y", "z")


@dataclass(frozen=True)
class Ellipsoids:
    """The two ellipsoids at ``q``, centred at the tool ``position`` (base frame).

    ``axes[:, i]`` is the unit direction of semi-axes ``velocity_radii[i]`` and
    ``force_radii[i]`` in the space of the ``rows`` (e.g. ``("x", "y")`` for a planar arm).
    """

    q: tuple[float, ...]
    position: np.ndarray
    rows: tuple[str, ...]
    axes: np.ndarray
    velocity_radii: np.ndarray
    force_radii: np.ndarray
    manipulability: float


def ellipsoids_at(
    model: Model, q: Sequence[float], overrides: Mapping[str, float] | None = None
) -> Ellipsoids:
    """Velocity and force ellipsoids of the translational Jacobian at ``q`` (see the module)."""
    if len(q) != model.robot.dof:
        raise ParameterError(f"q needs {model.robot.dof} values (one per joint), got {len(q)}")
    kernel = generated_numpy_module(model, "kinematics").fk_jacobian
    with np.errstate(all="ignore"):
        transform, jacobian = kernel(np.asarray(q, dtype=float), parameter_vector(model, overrides))
    rows = translational_rows(model)
    Jv = jacobian[list(rows), :]
    if not np.all(np.isfinite(Jv)):
        raise ParameterError(f"the Jacobian at q = {list(q)} is not finite (a parameter pole?)")
    U, s, _ = np.linalg.svd(Jv)
    radii = np.zeros(len(rows))
    radii[: len(s)] = s  # more rows than joints: the missing directions have s = 0
    tiny = max(Jv.shape) * np.finfo(float).eps * max(float(radii.max()), 1.0)
    with np.errstate(divide="ignore"):
        force = np.where(radii > tiny, 1.0 / radii, np.inf)
    return Ellipsoids(
        q=tuple(float(v) for v in q),
        position=transform[:3, 3].copy(),
        rows=tuple(ROW_NAMES[r] for r in rows),
        axes=U,
        velocity_radii=radii,
        force_radii=force,
        manipulability=float(np.prod(radii)),
    )

"""The rigid body a URDF joint moves: its child link's ``<inertial>`` with those of every link
rigidly attached to it, lumped into one :class:`~symkin.robot.Link` in the child link frame.

A link's ``<inertial>`` gives the mass, the centre of mass at ``origin.xyz`` and the tensor
about it in axes turned by ``origin.rpy``.  Lumping (Featherstone, *Rigid Body Dynamics
Algorithms*, 2008, eq. 2.63, in 3-vector form): ``m = sum m_k``, ``c = sum m_k c_k / m``,
``I_c = sum R_k I_k R_k^T + m_k (|d_k|^2 E - d_k d_k^T)`` with ``d_k = c_k - c``, all in the
child link frame.  Computed in floats; a body of one link whose inertial axes are the link's
keeps the file's numbers unchanged.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from symkin.io.placement import exact_angle, exact_number
from symkin.io.urdf_checks import check_inertial
from symkin.robot import Link
from symkin.spatial import rotation_from_rpy

if TYPE_CHECKING:
    from symkin.io.urdf import Tree


def _pose(xyz: Any, rpy: Any) -> np.ndarray:
    """4x4 float transform; right angles exact first (cos(pi/2) is 0, not 6e-17)."""
    matrix = np.eye(4)
    angles = [exact_angle(float(a)) for a in (rpy or (0.0, 0.0, 0.0))]
    matrix[:3, :3] = np.array(sp.Matrix(rotation_from_rpy(*angles)), dtype=float)
    matrix[:3, 3] = [float(v) for v in (xyz or (0.0, 0.0, 0.0))]
    return matrix


def _origin(element: Any) -> np.ndarray:
    pose = element.origin
    return np.eye(4) if pose is None else _pose(pose.xyz, pose.rpy)


def _body(
    tree: Tree, link: str, stop: Any, pose: np.ndarray
) -> Iterator[tuple[str, np.ndarray, Any]]:
    """``(link, pose in the body's frame, joint above it)`` of every link of the body."""
    for joint in tree.child_joints.get(link, []):
        if joint is stop:
            continue
        child_pose = pose @ _origin(joint)
        yield joint.child, child_pose, joint
        yield from _body(tree, joint.child, stop, child_pose)


def body_link(tree: Tree, link: str, stop: Any) -> tuple[Link | None, list[str]]:
    """The lumped inertial data of ``link``'s body (None if no link of it has any) and the
    names of the moving joints inside it (side branches held at zero), ``stop`` being the
    chain's next moving joint (None for the last)."""
    members = [(link, np.eye(4), None), *_body(tree, link, stop, np.eye(4))]
    side = [j.name for _, _, j in members if j is not None and j.type != "fixed"]
    parts = []
    for name, pose, _ in members:
        inertial = tree.links[name].inertial
        if inertial is None:
            continue
        check_inertial(f"{tree.file}: link {name!r}", inertial)
        frame = pose @ _origin(inertial)
        tensor = inertial.inertia
        elements = (
            [float(getattr(tensor, k) or 0.0) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
            if tensor
            else [0.0] * 6
        )
        parts.append((float(inertial.mass or 0.0), frame, elements))
    if not parts:
        return None, side
    return _lumped(parts), side


def _lumped(parts: list[tuple[float, np.ndarray, list[float]]]) -> Link:
    mass = sum(m for m, _, _ in parts)
    centres = [frame[:3, 3] for _, frame, _ in parts]
    if mass > 0:
        com = sum(m * c for (m, _, _), c in zip(parts, centres, strict=True)) / mass
    else:
        com = np.zeros(3)
    tensor = np.zeros((3, 3))
    for (m, frame, (ixx, iyy, izz, ixy, ixz, iyz)), centre in zip(parts, centres, strict=True):
        own = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        rotation, d = frame[:3, :3], centre - com
        tensor += rotation @ own @ rotation.T + m * (d @ d * np.eye(3) - np.outer(d, d))
    upper = (tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2])
    return Link(
        mass=exact_number(mass),
        com=tuple(exact_number(c) for c in com),  # type: ignore[arg-type]
        inertia=tuple(exact_number(v) for v in upper),  # type: ignore[arg-type]
    )

"""The robot picture: the arm drawn at one configuration, as a PNG or a Jupyter image.

In 3-D (in the x-y plane for a planar arm): the links as a polyline through the frame origins
``T_0_0 (base), T_0_1, ..., T_0_n`` and the tool point; each joint's axis as an arrow along the
z axis of its axis frame (frame i-1 in standard DH, frame i in modified DH, pointing where
``q_i`` grows; a planar arm's axes point out of the picture and show as markers only); revolute
joints as circles, prismatic ones as squares; with ``frames`` the x (red), y (green), z (blue)
axes of every frame and of the tool; with ``labels`` each joint's DH row
``theta, d, a, alpha`` at its axis.  The numbers come from the model's product form
(:func:`symkin.derive.numeric.numeric_function`) at the parameters' file values or
``overrides``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.display import register_display
from symkin.derive.numeric import numeric_function
from symkin.errors import ParameterError
from symkin.solve.ik.plot import is_planar
from symkin.solve.plotting import new_figure, png_bytes, save_figure

AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")


@dataclass(frozen=True)
class ArmFrames:
    """Numeric frames at one configuration: ``frames[i] = T_0_i`` (``i = 0..n``), the joint
    axis frames ``joint_frames[i]`` (z along joint i+1) and the tool pose ``tool``."""

    frames: np.ndarray
    joint_frames: np.ndarray
    tool: np.ndarray

    @property
    def points(self) -> np.ndarray:
        """The stick figure: frame origins, then the tool point, shape (n + 2, 3)."""
        return np.vstack([self.frames[:, :3, 3], self.tool[None, :3, 3]])


@lru_cache(maxsize=16)
def _frames_function(model: Model, overrides: tuple[tuple[str, float], ...]):
    product = model.product_form
    matrices = [*product.frame_transforms, *product.kinematics.joint_frames]
    matrices.append(product.forward_kinematics)
    return numeric_function(product, sp.Matrix.hstack(*matrices), dict(overrides))


def arm_frames(
    model: Model, q: Sequence[float], overrides: Mapping[str, float] | None = None
) -> ArmFrames:
    """The frames of ``model`` at ``q`` (see :class:`ArmFrames`)."""
    n = model.robot.dof
    if len(q) != n:
        raise ParameterError(f"q needs {n} values (one per joint), got {len(q)}")
    function = _frames_function(model, tuple(sorted((overrides or {}).items())))
    stacked = function(np.asarray(q, dtype=float))
    matrices = np.stack([stacked[:, 4 * k : 4 * k + 4] for k in range(stacked.shape[1] // 4)])
    return ArmFrames(
        frames=matrices[: n + 1], joint_frames=matrices[n + 1 : 2 * n + 1], tool=matrices[-1]
    )


def dh_label(model: Model, index: int) -> str:
    """Joint ``index + 1``'s DH row as text, the joint variable added to theta or d."""
    joint = model.robot.joints[index]
    variable = sp.Symbol(f"q{index + 1}")
    theta = joint.theta + variable if joint.type == "revolute" else joint.theta
    d = joint.d + variable if joint.type == "prismatic" else joint.d
    name = joint.name or f"joint {index + 1}"
    return f"{name}: θ={theta}, d={d}, a={joint.a}, α={joint.alpha}"


def arm_figure(
    model: Model,
    q: Sequence[float],
    *,
    frames: bool = False,
    labels: bool = False,
    overrides: Mapping[str, float] | None = None,
    title: str | None = None,
) -> Any:
    """A matplotlib figure of the arm at ``q`` (see the module docstring)."""
    arm = arm_frames(model, q, overrides)
    points = arm.points
    planar = is_planar(model)
    figure = new_figure(figsize=(6.5, 6))
    axes = figure.add_subplot(111) if planar else figure.add_subplot(111, projection="3d")
    reach = max(float(np.ptp(points, axis=0).max()), 1e-3)
    size = 0.15 * reach
    columns = slice(0, 2) if planar else slice(0, 3)
    axes.plot(*points[:, columns].T, color="dimgray", linewidth=3, zorder=1, label="links")
    for i, (joint, frame) in enumerate(zip(model.robot.joints, arm.joint_frames, strict=True)):
        marker = "o" if joint.type == "revolute" else "s"
        origin = frame[:3, 3]
        axes.plot(*origin[columns, None], marker=marker, markersize=9, color="tab:orange")
        if not planar:
            axes.quiver(*origin, *(size * frame[:3, 2]), color="tab:orange", linewidth=1.5)
        if labels:
            # Staggered: several frames often share an origin (a wrist, a shoulder).
            offset = np.full(3, 0.03 * reach)
            offset[1 if planar else 2] -= 0.07 * reach * (i % 4)
            axes.text(*(origin + offset)[columns], dh_label(model, i), fontsize=7)
    axes.plot(*points[-1, columns, None], marker="*", markersize=12, color="black", label="tool")
    if frames:
        for pose in [*arm.frames, arm.tool]:
            _triad(axes, pose, 0.6 * size, planar)
    _finish_axes(axes, points, planar)
    axes.set_title(title or f"{model.robot.name} at q = [{', '.join(f'{v:.3g}' for v in q)}]")
    return figure


def _triad(axes: Any, pose: np.ndarray, size: float, planar: bool) -> None:
    origin = pose[:3, 3]
    for k, colour in enumerate(AXIS_COLOURS):
        direction = size * pose[:3, k]
        if planar:
            if k < 2:
                axes.annotate(
                    "",
                    xy=tuple(origin[:2] + direction[:2]),
                    xytext=tuple(origin[:2]),
                    arrowprops={"arrowstyle": "->", "color": colour},
                )
        else:
            axes.quiver(*origin, *direction, color=colour, linewidth=1)


def _finish_axes(axes: Any, points: np.ndarray, planar: bool) -> None:
    axes.set_xlabel("x [m]")
    axes.set_ylabel("y [m]")
    if planar:
        axes.set_aspect("equal", adjustable="datalim")
    else:
        axes.set_zlabel("z [m]")
        centre = (points.max(axis=0) + points.min(axis=0)) / 2
        half = max(float(np.ptp(points, axis=0).max()) / 2 * 1.2, 0.05)
        for setter, c in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), centre, strict=True):
            setter(c - half, c + half)
    axes.grid(True, alpha=0.3)


def draw_arm(
    model: Model,
    q: Sequence[float],
    path: str | Path,
    *,
    frames: bool = False,
    labels: bool = False,
    overrides: Mapping[str, float] | None = None,
) -> Path:
    """Write the picture of the arm at ``q`` as a PNG at ``path``."""
    figure = arm_figure(model, q, frames=frames, labels=labels, overrides=overrides)
    return save_figure(figure, path)


def display_configuration(model: Model) -> tuple[float, ...]:
    """The configuration a model shows in Jupyter: its pose ``home`` if the file names one,
    else its first named pose, else ``q = 0``."""
    poses = dict(model.robot.poses)
    if poses:
        return poses.get("home", next(iter(poses.values())))
    return (0.0,) * model.robot.dof


def model_png(model: Model) -> bytes | None:
    """Jupyter's ``_repr_png_`` of a model: the arm at :func:`display_configuration`; None
    (no image) when a parameter has no value."""
    try:
        return png_bytes(arm_figure(model, display_configuration(model), frames=True))
    except ParameterError:
        return None


register_display("png", model_png)

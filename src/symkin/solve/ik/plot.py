"""PNG plots of IK results: the arm in its solution configurations, and Cartesian paths.

The arm is drawn as a stick figure through the origins of the frames ``T_0_0 (base), T_0_1,
..., T_0_n`` and the tool point, in 2D (x-y plane) for a planar arm (its Jacobian has no
``z``, ``wx``, ``wy`` rows) and in 3D otherwise.  A path plot shows the targets against the
points reached and, beside it, the joint values over the waypoints: the lecture's figure of
the Newton path.  Needs matplotlib (:func:`symkin.solve.plotting.new_figure`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.numeric import numeric_function
from symkin.solve.plotting import colormap, new_figure, save_figure

PLANAR_ZERO_ROWS = (2, 3, 4)  # z, wx, wy


def is_planar(model: Model) -> bool:
    """True when the tool moves in the x-y plane only (z, wx, wy Jacobian rows all zero).

    Read off the product form, where such rows are zero entry by entry (no contraction)."""
    jacobian = model.product_form.geometric_jacobian
    return all(e == 0 for row in PLANAR_ZERO_ROWS for e in jacobian.row(row))


@lru_cache(maxsize=16)
def _origins_function(model: Model, overrides: tuple[tuple[str, float], ...]):
    product = model.product_form
    points = [T[:3, 3] for T in product.frame_transforms] + [product.tool_position]
    return numeric_function(product, sp.Matrix.hstack(*points), dict(overrides))


def joint_points(
    model: Model, q: Sequence[float], overrides: Mapping[str, float] | None = None
) -> np.ndarray:
    """Base-frame points of the stick figure, shape (n + 2, 3): frame origins, then the tool."""
    function = _origins_function(model, tuple(sorted((overrides or {}).items())))
    return np.asarray(function(np.asarray(q, dtype=float)), dtype=float).T


def _axes(figure, planar: bool, position: int = 111):
    if planar:
        axes = figure.add_subplot(position)
        axes.set_aspect("equal", adjustable="datalim")
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
    else:
        axes = figure.add_subplot(position, projection="3d")
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
        axes.set_zlabel("z [m]")
    axes.grid(True, alpha=0.3)
    return axes


def _draw(axes, points: np.ndarray, planar: bool, **style) -> None:
    columns = points[:, :2].T if planar else points.T
    axes.plot(*columns, **style)


def _equal_3d(axes, points: np.ndarray) -> None:
    """Equal scales on the three axes (matplotlib's 3D axes do not keep them)."""
    centre = (points.max(axis=0) + points.min(axis=0)) / 2
    half = max(float(np.ptp(points, axis=0).max()) / 2, 1e-3)
    for setter, c in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), centre, strict=True):
        setter(c - half, c + half)


def plot_solutions(
    model: Model,
    solutions: Sequence[Sequence[float]],
    path: str | Path,
    *,
    target: np.ndarray | None = None,
    labels: Sequence[str] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> Path:
    """The arm in each configuration of ``solutions``, overlaid, with the target position."""
    planar = is_planar(model)
    figure = new_figure(figsize=(6, 6))
    axes = _axes(figure, planar)
    colours = colormap("tab10")
    every = []
    for k, q in enumerate(solutions):
        points = joint_points(model, q, overrides)
        every.append(points)
        label = labels[k] if labels is not None else f"solution {k + 1}"
        _draw(axes, points, planar, marker="o", linewidth=2, color=colours(k % 10), label=label)
    if target is not None:
        point = np.asarray(target, dtype=float)[:3, 3]
        every.append(point[None, :])
        _draw(
            axes,
            point[None, :],
            planar,
            marker="x",
            markersize=12,
            color="black",
            linestyle="none",
            label="target",
        )
    if not planar and every:
        _equal_3d(axes, np.vstack(every))
    axes.set_title(f"{model.robot.name}: inverse kinematics")
    # Beside the axes: in 3D a legend inside would hide the arms.
    axes.legend(loc="upper left", bbox_to_anchor=(1.05, 1.0), fontsize="small")
    return save_figure(figure, path)


def _joint_values_panel(joints, qs: np.ndarray, labels: Sequence[str] | None) -> None:
    """Each joint's value over the waypoints."""
    steps = np.arange(len(qs))
    for j in range(qs.shape[1]):
        joints.plot(steps, qs[:, j], marker="o", label=f"q{j + 1}")
    if labels is not None:
        joints.set_xticks(steps, labels)
    joints.set_xlabel("waypoint i")
    joints.set_ylabel("joint value [rad or m]")
    joints.set_title("joint trajectories")
    joints.grid(True, alpha=0.3)
    joints.legend(loc="best", fontsize="small")


def plot_path(
    model: Model,
    targets: np.ndarray,
    reached: np.ndarray,
    qs: np.ndarray,
    path: str | Path,
    *,
    task: Sequence[str] = ("x", "y", "z"),
    labels: Sequence[str] | None = None,
    overrides: Mapping[str, float] | None = None,
) -> Path:
    """Targets against points reached (task coordinates ``task``, one row per waypoint), the
    arm at the first and last waypoint, and the joint values over the waypoints."""
    targets, reached, qs = (
        np.atleast_2d(np.asarray(a, dtype=float)) for a in (targets, reached, qs)
    )
    planar = len(task) < 3 or is_planar(model)
    figure = new_figure(figsize=(12, 5.5))
    axes = _axes(figure, planar, 121)
    index = {name: k for k, name in enumerate(task)}

    def xyz(values: np.ndarray) -> np.ndarray:
        """Task coordinates as x, y, z points (a coordinate not in the task is 0)."""
        points = np.zeros((len(values), 3))
        for k, name in enumerate(("x", "y", "z")):
            if name in index:
                points[:, k] = values[:, index[name]]
        return points

    target_points, reached_points = xyz(targets), xyz(reached)
    arms = [joint_points(model, qs[0], overrides), joint_points(model, qs[-1], overrides)]
    for arm, style, label in zip(
        arms, ("--", "-"), ("arm at the start", "arm at the end"), strict=True
    ):
        _draw(axes, arm, planar, marker="o", linestyle=style, color="grey", alpha=0.7, label=label)
    _draw_path(axes, target_points, reached_points, planar)
    if not planar:
        _equal_3d(axes, np.vstack([target_points, reached_points, *arms]))
    axes.set_title(f"{model.robot.name}: Cartesian path")
    axes.legend(loc="best", fontsize="small")

    _joint_values_panel(figure.add_subplot(122), qs, labels)
    figure.tight_layout()
    return save_figure(figure, path)


def _draw_path(axes, target_points: np.ndarray, reached_points: np.ndarray, planar: bool) -> None:
    """Bild 14-10 of the lecture: the straight line, the targets on it, the points reached."""
    _draw(
        axes,
        target_points[[0, -1]],
        planar,
        linestyle="-",
        linewidth=0.8,
        color="tab:blue",
        label="straight line X_0 to X_end",
    )
    _draw(
        axes,
        target_points,
        planar,
        marker="x",
        linestyle="none",
        color="tab:blue",
        label="targets X_i",
    )
    _draw(
        axes,
        reached_points,
        planar,
        marker=".",
        linestyle=":",
        color="tab:red",
        label="reached FK(q_i)",
    )

"""Figures of a sampled workspace and of the manipulability ellipsoids (matplotlib, PNG).

The workspace figure has three panels: the occupancy of the plane (samples per cell, log
scale) with the outer and inner boundary curves, the dexterity map (largest translational
manipulability per cell), and the 3-D preview cloud with the outer surface points (the
radial maximum per direction bin).  The ellipsoid figure draws the arm at the configuration
with both ellipsoids at the tool, each scaled so that its largest finite semi-axis is 40 % of
the arm's extent (their shapes and directions are what a picture shows; the true semi-axes are
in the legend and in the data); an infinite force semi-axis (a singular direction) is drawn
flat.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from symkin.derive import Model
from symkin.solve.draw import arm_frames
from symkin.solve.ellipsoid import Ellipsoids
from symkin.solve.ik.plot import is_planar
from symkin.solve.plotting import new_figure, save_figure
from symkin.solve.workspace import PLANES, Workspace, boundary_polygon

AXIS_NAMES = "xyz"


def workspace_figure(workspace: Workspace) -> Any:
    """The three-panel figure of ``workspace`` (see the module docstring)."""
    figure = new_figure(figsize=(18, 5.5))
    u_name, v_name = (AXIS_NAMES[i] for i in PLANES[workspace.plane][:2])
    extent = (*workspace.u_edges[[0, -1]], *workspace.v_edges[[0, -1]])
    occupancy, dexterity = figure.add_subplot(131), figure.add_subplot(132)
    with np.errstate(divide="ignore"):
        counts = np.where(workspace.counts > 0, np.log10(workspace.counts), np.nan)
    for axes, grid, label in (
        (occupancy, counts, "log10(samples per cell)"),
        (dexterity, workspace.manipulability_max, "largest manipulability w"),
    ):
        image = axes.imshow(grid.T, origin="lower", extent=extent, cmap="viridis", aspect="equal")
        figure.colorbar(image, ax=axes, label=label, shrink=0.8)
        axes.set_xlabel(f"{u_name} [m]")
        axes.set_ylabel(f"{v_name} [m]")
    for which, style in (("outer", "-"), ("inner", "--")):
        polygon = boundary_polygon(workspace, which)
        if len(polygon):
            closed = np.vstack([polygon, polygon[:1]])
            occupancy.plot(
                *closed.T, style, color="tab:red", linewidth=1, label=f"{which} boundary"
            )
    occupancy.legend(loc="upper right", fontsize="small")
    occupancy.set_title(f"{workspace.robot}: {workspace.samples:,} samples", fontsize="medium")
    dexterity.set_title("dexterity: best w = sqrt(det(Jv Jv^T))", fontsize="medium")
    cloud = figure.add_subplot(133, projection="3d")
    cloud.scatter(*workspace.preview.T, s=1, alpha=0.3, color="tab:blue", label="samples")
    surface = _surface_points(workspace)
    cloud.scatter(*surface.T, s=3, color="tab:red", label="outer surface")
    cloud.set_xlabel("x [m]")
    cloud.set_ylabel("y [m]")
    cloud.set_zlabel("z [m]")
    cloud.legend(loc="upper left", fontsize="small")
    cloud.set_title("3-D cloud and radial boundary", fontsize="medium")
    return figure


def _surface_points(workspace: Workspace) -> np.ndarray:
    """The outer surface: per direction bin, the farthest point reached (x, y, z)."""
    azimuth, elevation = np.meshgrid(workspace.azimuths, workspace.elevations, indexing="ij")
    radius = workspace.surface_radius
    keep = np.isfinite(radius)
    a, e, r = azimuth[keep], elevation[keep], radius[keep]
    return np.column_stack([r * np.cos(e) * np.cos(a), r * np.cos(e) * np.sin(a), r * np.sin(e)])


def plot_workspace(workspace: Workspace, path: str | Path) -> Path:
    """Write :func:`workspace_figure` as a PNG at ``path``."""
    return save_figure(workspace_figure(workspace), path)


def _ellipsoid_surface(axes: np.ndarray, radii: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Points of the ellipse/ellipsoid ``centre + axes @ diag(radii) @ unit sphere``."""
    if len(radii) == 2:
        t = np.linspace(0, 2 * np.pi, 100)
        unit = np.vstack([np.cos(t), np.sin(t)])
        return (centre[:, None] + axes @ (radii[:, None] * unit)).T
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 30), np.linspace(0, np.pi, 15))
    unit = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)])
    return centre[:, None, None] + np.einsum("ij,jkl->ikl", axes @ np.diag(radii), unit)


def ellipsoid_figure(model: Model, ellipsoids: Ellipsoids, overrides=None) -> Any:
    """The arm at ``ellipsoids.q`` with its velocity and force ellipsoids at the tool."""
    points = arm_frames(model, ellipsoids.q, overrides).points
    rows = [AXIS_NAMES.index(r) for r in ellipsoids.rows]
    planar = is_planar(model) and len(rows) == 2
    figure = new_figure(figsize=(6.5, 6))
    axes = figure.add_subplot(111) if planar else figure.add_subplot(111, projection="3d")
    columns = rows if planar else [0, 1, 2]
    axes.plot(*points[:, columns].T, "o-", color="dimgray", linewidth=3, label="arm")
    centre = ellipsoids.position[rows]
    extent = 0.4 * max(float(np.ptp(points, axis=0).max()), 1e-3)
    for radii, colour, name in (
        (ellipsoids.velocity_radii, "tab:blue", "velocity"),
        (ellipsoids.force_radii, "tab:red", "force"),
    ):
        label = f"{name} (scaled): semi-axes {', '.join(f'{r:.3g}' for r in radii)}"
        _draw_ellipsoid(
            axes, ellipsoids, _scaled(radii, extent), centre, rows, planar, colour, label
        )
    axes.set_xlabel(f"{AXIS_NAMES[columns[0]]} [m]")
    axes.set_ylabel(f"{AXIS_NAMES[columns[1]]} [m]")
    axes.set_aspect("equal", adjustable="datalim") if planar else None
    axes.set_title(
        f"{model.robot.name}: manipulability ellipsoids, w = {ellipsoids.manipulability:.4g}"
    )
    axes.legend(loc="upper left", fontsize="small")
    return figure


def _scaled(radii: np.ndarray, extent: float) -> np.ndarray:
    """``radii`` scaled to a largest finite value of ``extent``; infinite ones drawn as 0."""
    finite = radii[np.isfinite(radii)]
    largest = finite.max() if finite.size else 0.0
    scale = extent / largest if largest > 0 else 1.0
    return np.where(np.isfinite(radii), radii * scale, 0.0)


def _draw_ellipsoid(axes, ellipsoids, radii, centre, rows, planar, colour, label) -> None:
    if planar or len(rows) == 3:
        surface = _ellipsoid_surface(ellipsoids.axes, radii, centre)
        if planar:
            axes.plot(*surface.T, color=colour, label=label)
        else:
            axes.plot_wireframe(*surface, color=colour, linewidth=0.5, alpha=0.6, label=label)
        return
    # Two translational rows of a spatial arm: the ellipse in their plane, at the tool.
    full = np.zeros((3, 100))
    flat = _ellipsoid_surface(ellipsoids.axes, radii, centre).T
    full[rows] = flat
    other = [k for k in range(3) if k not in rows]
    full[other] = ellipsoids.position[other][:, None]
    axes.plot(*full, color=colour, label=label)


def plot_ellipsoids(model: Model, ellipsoids: Ellipsoids, path: str | Path, overrides=None) -> Path:
    """Write :func:`ellipsoid_figure` as a PNG at ``path``."""
    return save_figure(ellipsoid_figure(model, ellipsoids, overrides), path)

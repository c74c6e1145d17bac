"""``symkin workspace``, ``symkin ellipsoid`` and ``symkin draw``: the pictures of an arm.

Thin: parse the values, call :mod:`symkin.solve.workspace` (or its Dask twin),
:mod:`symkin.solve.ellipsoid` and :mod:`symkin.solve.draw`, and lay the results out as text,
JSON or CSV.  Files written are announced on stderr, so ``--json`` output stays clean.
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
from pathlib import Path

import numpy as np

from symkin.cli.report import json_text
from symkin.cli.values import joint_values, parameter_overrides, robot_from_args
from symkin.derive import derive
from symkin.errors import SymkinError
from symkin.output_folder import replace_file
from symkin.robot import Robot
from symkin.solve.draw import draw_arm
from symkin.solve.ellipsoid import Ellipsoids, ellipsoids_at
from symkin.solve.workspace import Workspace, sample_workspace


def _finite_or_none(values: np.ndarray) -> list:
    """A nested list with NaN (an empty bin) as None (JSON null)."""
    array = np.asarray(values, dtype=float)
    return np.where(np.isfinite(array), array, None).tolist()


def configuration_from_args(args: argparse.Namespace, robot: Robot) -> list[float]:
    """``--q V1,...`` or ``--pose NAME`` (a pose of the robot file's ``[poses]``)."""
    if args.q is not None and args.pose is not None:
        raise SymkinError("give --q or --pose, not both")
    if args.pose is not None:
        poses = dict(robot.poses)
        if args.pose not in poses:
            known = ", ".join(poses) or "none (add a [poses] table to the robot file)"
            raise SymkinError(f"--pose: {robot.name} has no pose {args.pose!r}; poses: {known}")
        return list(poses[args.pose])
    if args.q is None:
        raise SymkinError("give the configuration: --q V1,V2,... or --pose NAME")
    return joint_values(args.q, "--q", robot)


def workspace_json(workspace: Workspace) -> dict:
    """The summaries of a sampling run; empty bins are null."""
    return {
        "robot": workspace.robot,
        "samples": workspace.samples,
        "seed": workspace.seed,
        "plane": workspace.plane,
        "bounding_box": {"lower": workspace.lower.tolist(), "upper": workspace.upper.tolist()},
        "boundary": {
            "method": "radial extremes per polar-angle bin of the projection onto the plane",
            "angles": workspace.angles.tolist(),
            "outer_radius": _finite_or_none(workspace.outer_radius),
            "inner_radius": _finite_or_none(workspace.inner_radius),
        },
        "surface": {
            "method": "largest distance per azimuth x elevation bin",
            "azimuths": workspace.azimuths.tolist(),
            "elevations": workspace.elevations.tolist(),
            "radius": _finite_or_none(workspace.surface_radius),
        },
        "grid": {
            "u_edges": workspace.u_edges.tolist(),
            "v_edges": workspace.v_edges.tolist(),
            "counts": workspace.counts.astype(int).tolist(),
            "manipulability_max": _finite_or_none(workspace.manipulability_max),
            "manipulability_mean": _finite_or_none(workspace.manipulability_mean),
        },
    }


def workspace_csv(workspace: Workspace) -> str:
    """The boundary, one row per polar-angle bin: angle, radii and the outer point (u, v)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    u, v = (f"{'xyz'[k]}" for k in _plane_axes(workspace.plane))
    writer.writerow(["angle", "outer_radius", "inner_radius", f"outer_{u}", f"outer_{v}"])
    for angle, outer, inner in zip(
        workspace.angles, workspace.outer_radius, workspace.inner_radius, strict=True
    ):
        cells = [angle, outer, inner, outer * np.cos(angle), outer * np.sin(angle)]
        writer.writerow(["" if not np.isfinite(c) else repr(float(c)) for c in cells])
    return out.getvalue()


def _plane_axes(plane: str) -> tuple[int, int]:
    return "xyz".index(plane[0]), "xyz".index(plane[1])


def workspace_text(workspace: Workspace) -> str:
    outer, inner = workspace.outer_radius, workspace.inner_radius
    reached = int(np.isfinite(outer).sum())
    lines = [
        f"{workspace.robot}: {workspace.samples:,} samples (seed {workspace.seed}), "
        f"plane {workspace.plane}",
        f"bounding box lower = {np.round(workspace.lower, 6).tolist()} m",
        f"bounding box upper = {np.round(workspace.upper, 6).tolist()} m",
        f"outer boundary radius: {np.nanmin(outer):.6g} .. {np.nanmax(outer):.6g} m "
        f"({reached} of {len(outer)} angle bins reached)",
        f"inner boundary radius: {np.nanmin(inner):.6g} .. {np.nanmax(inner):.6g} m",
        f"largest manipulability: {np.nanmax(workspace.manipulability_max):.6g}",
    ]
    return "\n".join(lines)


def _write(path: str, data: bytes | str) -> None:
    target = Path(path)
    text = data.encode() if isinstance(data, str) else data
    replace_file(target.parent, target.name, text)
    print(f"wrote {target}", file=sys.stderr)


def command_workspace(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    model = derive(robot, closed_forms=False)
    overrides = parameter_overrides(args.set, robot)
    robot.parameter_values(overrides)  # unknown names and missing values first
    options = {"samples": args.samples, "plane": args.plane, "seed": args.seed}
    options |= {"chunk": args.chunk, "overrides": overrides}
    if args.dask or args.dask_address:
        from symkin.solve.workspace_dask import dask_client, sample_workspace_dask

        with dask_client(args.dask_address, args.dask_workers) as client:
            workspace = sample_workspace_dask(model, client=client, **options)
    else:
        workspace = sample_workspace(model, **options)
    if args.plot:
        from symkin.solve.workspace_plot import plot_workspace

        plot_workspace(workspace, args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.csv:
        _write(args.csv, workspace_csv(workspace))
    print(json_text(workspace_json(workspace)) if args.json else workspace_text(workspace))


def ellipsoid_json(ellipsoids: Ellipsoids) -> dict:
    force = ellipsoids.force_radii
    return {
        "q": list(ellipsoids.q),
        "position": ellipsoids.position.tolist(),
        "rows": list(ellipsoids.rows),
        "axes": ellipsoids.axes.T.tolist(),
        "velocity_semi_axes": ellipsoids.velocity_radii.tolist(),
        "force_semi_axes": [float(f) if np.isfinite(f) else None for f in force],
        "manipulability": ellipsoids.manipulability,
    }


def ellipsoid_text(ellipsoids: Ellipsoids) -> str:
    lines = [
        f"tool position = {np.round(ellipsoids.position, 6).tolist()} m",
        f"rows {','.join(ellipsoids.rows)}; manipulability w = {ellipsoids.manipulability:.6g}",
    ]
    for k, (v, f) in enumerate(zip(ellipsoids.velocity_radii, ellipsoids.force_radii, strict=True)):
        direction = np.round(ellipsoids.axes[:, k], 6).tolist()
        force = f"{f:.6g}" if np.isfinite(f) else "inf (singular direction)"
        lines.append(f"axis {k + 1} {direction}: velocity {v:.6g}, force {force}")
    return "\n".join(lines)


def command_ellipsoid(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    model = derive(robot, closed_forms=False)
    overrides = parameter_overrides(args.set, robot)
    q = configuration_from_args(args, robot)
    ellipsoids = ellipsoids_at(model, q, overrides)
    if args.plot:
        from symkin.solve.workspace_plot import plot_ellipsoids

        plot_ellipsoids(model, ellipsoids, args.plot, overrides)
        print(f"wrote {args.plot}", file=sys.stderr)
    print(json_text(ellipsoid_json(ellipsoids)) if args.json else ellipsoid_text(ellipsoids))


def command_draw(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    model = derive(robot, closed_forms=False)
    overrides = parameter_overrides(args.set, robot)
    q = configuration_from_args(args, robot)
    path = draw_arm(model, q, args.out, frames=args.frames, labels=args.labels, overrides=overrides)
    print(f"wrote {path}", file=sys.stderr)

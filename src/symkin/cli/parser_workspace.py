"""Sub-parsers of ``symkin workspace``, ``symkin ellipsoid`` and ``symkin draw``."""

from __future__ import annotations

import argparse

from symkin.cli.commands_workspace import command_draw, command_ellipsoid, command_workspace
from symkin.cli.values import seed_from_text
from symkin.solve.workspace import DEFAULT_CHUNK, DEFAULT_SAMPLES, MAX_CHUNK, MAX_CHUNKS, PLANES
from symkin.spatial import ORIENTATIONS

# argparse's (private) type of the object that add_subparsers returns
Commands = argparse._SubParsersAction


def positive_count(text: str) -> int:
    """A whole number >= 1 (``1e8`` accepted for large sample counts)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}") from None
    if not value.is_integer() or value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}")
    return int(value)


def add_euler_option(parser: argparse.ArgumentParser, text: str) -> None:
    """``--euler ORDER``: one of the twelve Euler/Tait-Bryan orders or ``rotvec``."""
    parser.add_argument(
        "--euler", choices=ORIENTATIONS, metavar="ORDER", help=f"{text}; ORDER is one of "
        f"{', '.join(ORIENTATIONS)}",
    )  # fmt: skip


def _add_configuration(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--q", metavar="V1,V2,...", help="joint values (rad or m; 'deg' ok)")
    parser.add_argument("--pose", metavar="NAME", help="a pose of the robot file's [poses]")
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="override a parameter"
    )


def add_workspace_commands(commands: Commands, add_robot_argument) -> None:
    """``workspace``, ``ellipsoid`` and ``draw``."""
    workspace = commands.add_parser(
        "workspace",
        help="reachable workspace, boundary and dexterity map by sampling the joint limits",
        description="Sample configurations uniformly within the joint limits, evaluate the "
        "generated kernels in chunks and report the bounding box, the boundary in a plane "
        "(radial extremes per angle bin), the 3-D outer surface and the manipulability per "
        "grid cell. --dask runs the same chunks on a Dask cluster.",
    )
    add_robot_argument(workspace)
    workspace.add_argument(
        "--samples", type=positive_count, default=DEFAULT_SAMPLES, metavar="N",
        help=f"configurations to sample (default {DEFAULT_SAMPLES:,}; 1e8 ok; at most "
        f"{MAX_CHUNKS:,} chunks, so at most {MAX_CHUNKS * MAX_CHUNK:.0e})",
    )  # fmt: skip
    workspace.add_argument("--plane", choices=tuple(PLANES), default="xy", help="default xy")
    workspace.add_argument("--seed", type=seed_from_text, default=0, metavar="N")
    workspace.add_argument(
        "--chunk", type=positive_count, default=DEFAULT_CHUNK, metavar="N",
        help=f"configurations per chunk (memory; default {DEFAULT_CHUNK:,}, at most {MAX_CHUNK:,})",
    )  # fmt: skip
    workspace.add_argument("--plot", metavar="FILE.png", help="write the three-panel figure")
    workspace.add_argument("--csv", metavar="FILE", help="write the boundary table as CSV")
    workspace.add_argument("--json", action="store_true", help="print a JSON object")
    workspace.add_argument(
        "--dask", action="store_true", help="run on Dask (a local cluster unless --dask-address)"
    )
    workspace.add_argument("--dask-address", metavar="ADDRESS", help="an existing scheduler")
    workspace.add_argument(
        "--dask-workers", type=positive_count, default=2, metavar="N",
        help="workers of the local cluster (default 2)",
    )  # fmt: skip
    workspace.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="override a parameter"
    )
    workspace.set_defaults(run=command_workspace)

    ellipsoid = commands.add_parser(
        "ellipsoid",
        help="velocity and force manipulability ellipsoids at one configuration",
        description="Semi-axes and directions of the velocity ellipsoid (singular values of "
        "the translational Jacobian) and of the force ellipsoid (their reciprocals).",
    )
    add_robot_argument(ellipsoid)
    _add_configuration(ellipsoid)
    ellipsoid.add_argument("--plot", metavar="FILE.png", help="draw the arm and the ellipsoids")
    ellipsoid.add_argument("--json", action="store_true", help="print a JSON object")
    ellipsoid.set_defaults(run=command_ellipsoid)

    draw = commands.add_parser("draw", help="the arm drawn at one configuration, as a PNG")
    add_robot_argument(draw)
    _add_configuration(draw)
    draw.add_argument("--out", required=True, metavar="FILE.png", help="the picture")
    draw.add_argument("--frames", action="store_true", help="draw every frame's x, y, z axes")
    draw.add_argument("--labels", action="store_true", help="label each joint with its DH row")
    draw.set_defaults(run=command_draw)

"""``symkin dh`` (the DH table by the frame-assignment procedure) and ``symkin urdf``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import sympy as sp

from symkin.cli.report import json_text, text_matrix
from symkin.cli.values import parameter_overrides, robot_from_args
from symkin.derive.dh_extraction import DhExtraction, extract_dh
from symkin.derive.dh_lines import SNAP_TOLERANCE
from symkin.derive.dh_proof import FkProof, prove_forward_kinematics
from symkin.emit.latex.dh_derivation import dh_derivation_tex
from symkin.emit.robot_toml import robot_toml
from symkin.emit.urdf import urdf_text
from symkin.errors import SymkinError
from symkin.output_folder import replace_file
from symkin.robot import Robot


def write_text_file(path_text: str, text: str) -> Path:
    """Write one file the user named (replaced whole, through a temporary name)."""
    path = Path(path_text)
    if path.is_dir():
        raise SymkinError(f"{path} is a folder; give a file name")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise SymkinError(f"cannot write {path}: {error.strerror or error}") from None
    return replace_file(path.parent, path.name, text)


def check_output_paths(source: Robot, paths: list[str]) -> None:
    """Refuse, before anything is written, an output file that is the robot's own file (``symkin
    urdf arm.urdf -o arm.urdf`` would replace the user's URDF by the export, without its meshes;
    ``dh arm.toml --toml arm.toml`` the robot file by its DH model) or that two outputs share."""
    taken = [(Path(source.file), "the robot file")] if source.file else []
    for text in paths:
        path = Path(text)
        for other, what in taken:
            if _same_file(path, other):
                raise SymkinError(f"{path} is {what}; give another file name")
        taken.append((path, "also another output"))


def _same_file(path: Path, other: Path) -> bool:
    """One file under two names (links and ``..`` included), existing or not yet."""
    if path.exists() and other.exists():
        return path.samefile(other)
    return path.resolve() == other.resolve()


def source_label(robot: Robot) -> str:
    """The robot's file name (no machine path) or catalogue name, for headers."""
    return Path(robot.file).name if robot.file else robot.name


def _value_text(value: sp.Expr, angle: bool) -> str:
    if angle:
        degrees = value * 180 / sp.pi
        return (
            str(sp.nsimplify(degrees))
            if value.has(sp.pi) or value == 0
            else f"{float(degrees):.10g}"
        )
    return f"{float(value):.12g}"


def _with_variable(variable: str, moves: bool, offset: str) -> str:
    if not moves:
        return offset
    if offset == "0":
        return variable
    return f"{variable} - {offset[1:]}" if offset.startswith("-") else f"{variable} + {offset}"


def dh_text(extraction: DhExtraction, proof: FkProof) -> str:
    """The table, the transforms that make it exact, the steps and the proof."""
    robot = extraction.robot
    lines = [
        f"{robot.name}: {robot.convention} DH table by the frame-assignment procedure "
        "(z along each joint axis, in the direction its variable grows)",
        f"{'i':>2}  {'joint':<14} {'type':<9} {'theta [deg]':>12} {'d [m]':>12} "
        f"{'a [m]':>12} {'alpha [deg]':>12}  case",
    ]
    for k, (joint, step) in enumerate(zip(robot.joints, extraction.steps, strict=True)):
        theta, d, a, alpha = step.row
        variable = f"q{k + 1}"
        theta_text = _with_variable(variable, joint.type == "revolute", _value_text(theta, True))
        d_text = _with_variable(variable, joint.type == "prismatic", _value_text(d, False))
        lines.append(
            f"{k + 1:>2}  {joint.name or '-':<14} {joint.type:<9} {theta_text:>12} {d_text:>12} "
            f"{_value_text(a, False):>12} {_value_text(alpha, True):>12}  {step.case}"
        )
    if robot.convention == "modified":
        lines.append(
            "(modified: row i holds alpha_{i-1} and a_{i-1}; the case of axes i and i+1 fixes "
            "x_i, so a_i and alpha_i appear in row i+1, or in the tool transform after the last)"
        )
    lines += ["", "T = base * A_1 ... A_n * tool, with", "base =", text_matrix(robot.base)]
    lines += ["tool =", text_matrix(robot.tool), "", "Steps:"]
    lines += [f"  {step.index}. {step.note}" for step in extraction.steps]
    lines += [
        "",
        f"Snapping: angles within {SNAP_TOLERANCE:g} rad of a multiple of 15 deg are exact, "
        "lengths below it are 0, others kept to 15 significant digits.",
        f"Proof: {proof.summary()}",
    ]
    return "\n".join(lines)


def dh_json(extraction: DhExtraction, proof: FkProof) -> dict:
    """The same as JSON: values in SymPy syntax (radians, metres)."""
    robot = extraction.robot
    rows = [
        {
            "joint": joint.name,
            "type": joint.type,
            **{
                key: str(value)
                for key, value in zip(("theta", "d", "a", "alpha"), step.row, strict=True)
            },
            "case": step.case,
            "note": step.note,
        }
        for joint, step in zip(robot.joints, extraction.steps, strict=True)
    ]
    return {
        "robot": robot.name,
        "convention": robot.convention,
        "rows": rows,
        "base": [[str(v) for v in robot.base.row(i)] for i in range(4)],
        "tool": [[str(v) for v in robot.tool.row(i)] for i in range(4)],
        "snap_tolerance": SNAP_TOLERANCE,
        "proof": {
            "method": proof.method,
            "symbolic_error": proof.symbolic_error,
            "numeric_error": proof.numeric_error,
            "configurations": proof.configurations,
            "reason": proof.reason,
            "snapping": proof.snapping,
        },
    }


def numeric_source(args: argparse.Namespace) -> Robot:
    """The robot with its parameters replaced by their values (``--set`` first): extraction
    and export work on numbers."""
    robot = robot_from_args(args)
    if not robot.parameters:
        return robot
    return robot.with_parameter_values(parameter_overrides(args.set, robot))


def command_dh(args: argparse.Namespace) -> None:
    source = numeric_source(args)
    extraction = extract_dh(source, args.convention)
    proof = prove_forward_kinematics(extraction)
    check_output_paths(source, [path for path in (args.toml, args.latex) if path])
    print(json_text(dh_json(extraction, proof)) if args.json else dh_text(extraction, proof))
    command = f"symkin dh {source_label(source)} --convention {args.convention}"
    if args.toml:
        header = f"DH model of {source_label(source)}, written by: {command} --toml FILE"
        path = write_text_file(args.toml, robot_toml(extraction.robot, header))
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    if args.latex:
        path = write_text_file(args.latex, dh_derivation_tex(extraction, proof))
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)


def command_urdf(args: argparse.Namespace) -> None:
    robot = numeric_source(args)
    check_output_paths(robot, [args.output])
    header = f"URDF of {source_label(robot)}, written by: symkin urdf {source_label(robot)} -o FILE"
    print(f"wrote {write_text_file(args.output, urdf_text(robot, header))}")

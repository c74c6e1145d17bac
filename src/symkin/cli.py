"""The ``symkin`` command: a thin layer over the public API.

User mistakes (bad files, bad values) print one ``symkin: error: ...`` line and exit with
status 2; they never show a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import sympy as sp

from symkin.build import build_extension
from symkin.derive import Model, derive
from symkin.derive.kinematics import joint_dh_values
from symkin.derive.lagrange import READABLE_DOF
from symkin.emit.c import PRECISIONS
from symkin.emit.latex import (
    LANGUAGES,
    SECTIONS,
    TEXT_WIDTH_CM,
    check_sections,
    latex_files,
    section_notes,
)
from symkin.emit.python_ext import extension_name
from symkin.errors import SymkinError
from symkin.evaluate import DynamicState, KinematicState, dynamic_state, kinematic_state
from symkin.generate import (
    BACKENDS,
    check_backends,
    files_for_robot,
    generate_catalogue,
    write_files,
)
from symkin.io import catalogue_names, load_robot
from symkin.latex_build import compile_pdf
from symkin.robot import Robot

DEFAULT_ROBOT = "scara"
# Options whose values may start with a minus sign ("--q -30deg,45deg").
VALUE_OPTIONS = frozenset({"--q", "--dq", "--ddq", "--set", "--point", "--task"})


# ---------------------------------------------------------------- value parsing


def number_from_text(text: str, what: str) -> float:
    """A float from ``"0.5"``, ``"-30deg"`` or ``"pi/2"``-free plain numbers."""
    raw = text.strip()
    scale = 1.0
    if raw.endswith("deg"):
        raw, scale = raw[: -len("deg")], math.pi / 180
    try:
        value = float(raw)
    except ValueError:
        raise SymkinError(f"{what}: expected a number such as 0.5 or 30deg, got {text!r}") from None
    if not math.isfinite(value):
        raise SymkinError(f"{what}: expected a finite number, got {text!r}")
    return value * scale


def joint_values(text: str, option: str, robot: Robot) -> list[float]:
    """One value per joint from ``"v1,v2,..."``; ``deg`` only for revolute joints."""
    parts = text.split(",")
    if len(parts) != robot.dof:
        raise SymkinError(
            f"{option}: {robot.name} has {robot.dof} joints, got {len(parts)} value(s) in {text!r}"
        )
    values = []
    for i, (part, joint) in enumerate(zip(parts, robot.joints, strict=True), start=1):
        if part.strip().endswith("deg") and joint.type == "prismatic":
            raise SymkinError(f"{option}: joint {i} is prismatic; give a length, not {part!r}")
        values.append(number_from_text(part, f"{option} joint {i}"))
    return values


def parameter_overrides(items: Sequence[str]) -> dict[str, float]:
    """``["L1=0.3", ...]`` as a dict."""
    overrides = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise SymkinError(f"--set: expected NAME=VALUE, got {item!r}")
        overrides[name.strip()] = number_from_text(value, f"--set {name.strip()}")
    return overrides


def point_from_text(text: str, robot: Robot) -> tuple[int, list[float]]:
    """``"LINK:X,Y,Z"`` as ``(link, [x, y, z])``."""
    link_text, sep, coordinates = text.partition(":")
    try:
        link = int(link_text)
    except ValueError:
        link = -1
    if not sep or not 0 <= link <= robot.dof:
        raise SymkinError(
            f"--point: expected LINK:X,Y,Z with LINK from 0 to {robot.dof}, got {text!r}"
        )
    values = coordinates.split(",")
    if len(values) != 3:
        raise SymkinError(f"--point: expected three coordinates X,Y,Z, got {coordinates!r}")
    if any(v.strip().endswith("deg") for v in values):
        raise SymkinError(f"--point: coordinates are lengths in metres, got {coordinates!r}")
    return link, [number_from_text(v, "--point") for v in values]


def task_rows_from_text(text: str | None) -> tuple[str, ...] | None:
    """``"x,y,wz"`` as a tuple of row names (validated by the model)."""
    if text is None:
        return None
    rows = tuple(part.strip() for part in text.split(",") if part.strip())
    if not rows:
        raise SymkinError(f"--task: name at least one row of x, y, z, wx, wy, wz, got {text!r}")
    return rows


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``["--q", "-30deg"]`` -> ``["--q=-30deg"]`` so argparse does not see an option."""
    joined: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in VALUE_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            joined.append(f"{arg}={argv[i + 1]}")
            i += 2
        else:
            joined.append(arg)
            i += 1
    return joined


# ---------------------------------------------------------------- output


def text_matrix(matrix: sp.MatrixBase) -> str:
    """One line per row, entries in SymPy syntax."""
    return "\n".join(
        "  [" + ", ".join(sp.sstr(e) for e in matrix.row(i)) + "]" for i in range(matrix.rows)
    )


def condition_text(condition: sp.Eq) -> str:
    return f"{sp.sstr(condition.lhs)} = {sp.sstr(condition.rhs)}"


def dh_table_text(model: Model) -> str:
    """The DH table with each joint's variable inserted (radians)."""
    columns = ("theta", "d", "a", "alpha")
    lines = [f"  {'i':>2}  {'type':<9}" + "".join(f"  {c:<14}" for c in columns)]
    for i, (joint, q) in enumerate(zip(model.robot.joints, model.q, strict=True), start=1):
        values = joint_dh_values(joint, q)
        lines.append(f"  {i:>2}  {joint.type:<9}" + "".join(f"  {sp.sstr(v):<14}" for v in values))
    return "\n".join(lines)


def show_text(model: Model, rows: tuple[str, ...] | None) -> str:
    robot = model.robot
    parameters = ", ".join(f"{n} = {'(symbol)' if v is None else v}" for n, v in robot.parameters)
    out = [
        f"{robot.name}: {robot.title}",
        f"source: {robot.source or '(not given)'}",
        f"{robot.dof} joints, {robot.convention} DH; parameters: {parameters or 'none'}",
        "",
        "DH table (angles in rad):",
        dh_table_text(model),
    ]
    for i, link in enumerate(model.link_transforms, start=1):
        out += ["", f"A_{i} (frame {i} in frame {i - 1}):", text_matrix(link)]
    out += ["", "T (tool in base):", text_matrix(model.forward_kinematics)]
    out += [
        "",
        "Geometric Jacobian (rows x y z wx wy wz, base frame):",
        text_matrix(model.geometric_jacobian),
    ]
    task = rows or model.task_rows
    out += ["", f"Task Jacobian rows: {', '.join(task)}"]
    determinant = model.determinant(task)
    if determinant is None:
        out.append("  not square: no determinant (manipulability sqrt(det(J J^T)) applies)")
    else:
        out.append(f"  det J = {sp.sstr(determinant)}")
        if determinant == 0:
            out.append("  singular in every configuration: these rows are linearly dependent")
        else:
            conditions = model.singular_configurations(task)
            out.append("  singular when:" if conditions else "  no singular configurations")
            out += [f"    {condition_text(c)}" for c in conditions]
    return "\n".join(out)


def dynamics_show_text(model: Model) -> str:
    """The equations of motion: Lagrange's readable M, C, G for small robots, else a summary."""
    n = model.robot.dof
    out = ["", "Equations of motion: tau = M(q) ddq + C(q, dq) dq + G(q) + F(dq)"]
    if n <= READABLE_DOF:
        dynamics = model.lagrange
        out += ["", "M (Lagrange):", text_matrix(dynamics.mass_matrix)]
        out += ["", "C (Christoffel symbols):", text_matrix(dynamics.coriolis_matrix)]
        out += ["", "G:", text_matrix(dynamics.gravity_vector)]
    else:
        dynamics = model.newton_euler
        out.append(
            f"  {n} joints: derived by recursive Newton-Euler with {len(dynamics.assignments)} "
            "named intermediates; too long to print readably. Use 'symkin derive' for code "
            "or 'symkin eval --dynamics' for numbers."
        )
    if any(e != 0 for e in dynamics.friction):
        out += ["", "F (friction):", text_matrix(dynamics.friction)]
    return "\n".join(out)


def dynamics_show_json(model: Model, args: argparse.Namespace) -> dict:
    """``M``, ``C``, ``G`` (Lagrange, SymPy syntax) for small robots; null for larger ones."""
    if not args.dynamics:
        return {}
    if model.robot.dof > READABLE_DOF:
        return {"M": None, "C": None, "G": None}
    dynamics = model.lagrange

    def strings(matrix: sp.MatrixBase) -> list:
        return [[sp.sstr(e) for e in matrix.row(i)] for i in range(matrix.rows)]

    return {
        "M": strings(dynamics.mass_matrix),
        "C": strings(dynamics.coriolis_matrix),
        "G": [sp.sstr(e) for e in dynamics.gravity_vector],
    }


def show_json(model: Model, rows: tuple[str, ...] | None) -> dict:
    determinant = model.determinant(rows)
    return {
        "robot": model.robot.name,
        "q": [s.name for s in model.q],
        "task_rows": list(rows or model.task_rows),
        "T": [[sp.sstr(e) for e in model.forward_kinematics.row(i)] for i in range(4)],
        "jacobian": [[sp.sstr(e) for e in model.geometric_jacobian.row(i)] for i in range(6)],
        "det": None if determinant is None else sp.sstr(determinant),
        "singular": [sp.sstr(c) for c in model.singular_configurations(rows)],
    }


def _array(values: np.ndarray | None) -> list | None:
    return None if values is None else np.asarray(values).tolist()


def eval_json(state: KinematicState) -> dict:
    result = {
        "T": _array(state.transform),
        "position": _array(state.position),
        "euler_zyx": _array(state.euler_zyx),
        "euler_zyx_singular": state.euler_zyx_singular,
        "jacobian": _array(state.jacobian),
        "task_rows": list(state.task_rows),
        "det": state.determinant,
        "manipulability": state.manipulability,
    }
    if state.points:
        result["points"] = [
            {
                "link": p.link,
                "point": list(p.point),
                "position": _array(p.position),
                "velocity": _array(p.velocity),
                "acceleration": _array(p.acceleration),
            }
            for p in state.points
        ]
    return result


def dynamics_json(state: DynamicState | None) -> dict:
    if state is None:
        return {}
    return {
        "M": _array(state.mass_matrix),
        "c": _array(state.coriolis),
        "G": _array(state.gravity),
        "tau": _array(state.torque),
    }


def dynamics_text(state: DynamicState | None) -> str:
    if state is None:
        return ""
    lines = ["", "M =", _format(state.mass_matrix), f"G = {_format(state.gravity)}"]
    if state.coriolis is not None:
        lines.append(f"c = C dq = {_format(state.coriolis)}")
    if state.torque is not None:
        lines.append(f"tau = {_format(state.torque)}")
    return "\n".join(lines)


def _format(values: np.ndarray) -> str:
    # "+ 0.0" turns -0.0 into 0.0 so exact zeros print without a sign.
    return np.array2string(np.asarray(values) + 0.0, precision=6, suppress_small=True)


def eval_text(state: KinematicState) -> str:
    fmt = _format
    psi, theta, phi = state.euler_zyx
    out = [
        "T =",
        fmt(state.transform),
        f"position = {fmt(state.position)}",
        f"euler_zyx [psi, theta, phi] = {fmt(state.euler_zyx)} rad "
        f"({math.degrees(psi):.3f}, {math.degrees(theta):.3f}, {math.degrees(phi):.3f} deg)"
        + ("  (gimbal lock: phi set to 0)" if state.euler_zyx_singular else ""),
        "geometric Jacobian (rows x y z wx wy wz) =",
        fmt(state.jacobian),
        f"task rows {', '.join(state.task_rows)}: "
        + (f"det = {state.determinant:.6g}, " if state.determinant is not None else "")
        + f"manipulability = {state.manipulability:.6g}",
    ]
    for p in state.points:
        out.append(f"point {list(p.point)} on link {p.link}: position {fmt(p.position)}")
        if p.velocity is not None:
            out.append(f"  velocity {fmt(p.velocity)}")
        if p.acceleration is not None:
            out.append(f"  acceleration {fmt(p.acceleration)}")
    return "\n".join(out)


# ---------------------------------------------------------------- commands


def command_list(_: argparse.Namespace) -> None:
    for name in catalogue_names():
        with warnings.catch_warnings():
            # Listing is not the place for data-quality warnings (show and eval give them).
            warnings.simplefilter("ignore")
            robot = load_robot(name)
        print(f"{name:<24} {robot.dof} DOF  {robot.convention:<8}  {robot.title}")


def command_show(args: argparse.Namespace) -> None:
    model = derive(load_robot(args.robot))
    rows = task_rows_from_text(args.task)
    if args.json:
        print(json.dumps(show_json(model, rows) | dynamics_show_json(model, args), indent=2))
    else:
        print(show_text(model, rows) + (dynamics_show_text(model) if args.dynamics else ""))


def command_eval(args: argparse.Namespace) -> None:
    robot = load_robot(args.robot)
    model = derive(robot)
    overrides = parameter_overrides(args.set)
    if not args.dynamics:
        robot.parameter_values(overrides)  # reject unknown names and missing values first
    dq = joint_values(args.dq, "--dq", robot) if args.dq else None
    ddq = joint_values(args.ddq, "--ddq", robot) if args.ddq else None
    if ddq is not None and dq is None:
        raise SymkinError("--ddq needs --dq as well (acceleration depends on both)")
    q = joint_values(args.q, "--q", robot)
    dynamics = dynamic_state(model, q, dq, ddq, overrides) if args.dynamics else None
    kinematic_overrides = {k: v for k, v in overrides.items() if k in dict(robot.parameters)}
    state = kinematic_state(
        model,
        q,
        dq,
        ddq,
        kinematic_overrides,
        [point_from_text(p, robot) for p in args.point],
        task_rows_from_text(args.task),
    )
    if args.json:
        print(json.dumps(eval_json(state) | dynamics_json(dynamics), indent=2))
    else:
        print(eval_text(state) + dynamics_text(dynamics))


def progress(message: str) -> None:
    print(f"symkin: {message}", file=sys.stderr, flush=True)


def command_derive(args: argparse.Namespace) -> None:
    backends = check_backends(args.emit.split(","))
    robot = load_robot(args.robot)
    progress(f"deriving {robot.name} and emitting {', '.join(backends)} ...")
    points = [point_from_text(p, robot) for p in args.point]
    files = files_for_robot(robot, backends, args.precision, points)
    out = Path(args.out)
    write_files(out, files)
    print(f"wrote {len(files)} file{'s' if len(files) != 1 else ''} to {out}/:")
    for relative in files:
        print(f"  {out / relative}")
    if "python" in backends and not args.no_build:
        progress("compiling the Python extension ...")
        extension = build_extension(
            out / "python" / f"{extension_name(robot)}.c", out / "c" / f"{robot.name}.c"
        )
        print(f"built {extension} (import it with symkin.build.load_extension)")
    if "c" in backends or "python" in backends:
        print(f"compile and run the C example: make -C {out / 'c'} && {out / 'c' / 'example'}")


def command_generate(args: argparse.Namespace) -> None:
    root = Path(args.root)
    diff = generate_catalogue(root, args.check, lambda name: progress(f"rendering {name}"))
    if args.check:
        if diff:
            sys.stdout.write(diff)
            raise SymkinError(f"{root}/ is out of date; run 'symkin generate' and commit")
        print(f"{root}/ is up to date")
    else:
        print(f"wrote {root}/ for {len(catalogue_names())} robots")


def command_latex(args: argparse.Namespace) -> None:
    robot = load_robot(args.robot)
    sections = check_sections(args.sections.split(","))
    for note in section_notes(sections):
        progress(note)
    q = joint_values(args.q, "--q", robot) if args.q else None
    files = latex_files(
        derive(robot),
        sections=sections,
        shorthand=args.shorthand,
        lang=args.lang,
        q=q,
        overrides=parameter_overrides(args.set),
        text_width_cm=args.text_width,
    )
    out = Path(args.output or f"{robot.name}.tex")
    write_files(
        out.parent, {out.name: files.pop(f"{robot.name}.tex"), **files}
    )  # snippets/ and <robot>-macros.tex beside the document
    print(f"wrote {out} and {len(files)} snippet and macro files in {out.parent}/")
    if args.pdf:
        print(f"wrote {compile_pdf(out)}")


def add_set_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="override a parameter"
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="symkin",
        description="Closed-form kinematics from Denavit-Hartenberg tables.",
        epilog="ROBOT is a built-in name (see 'symkin list') or a path to a .toml robot file.",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    listing = commands.add_parser("list", help="list the built-in robots")
    listing.set_defaults(run=command_list)

    task_help = "task Jacobian rows, e.g. x,y,wz (default: the n non-zero rows of x y z wz wx wy)"
    show = commands.add_parser(
        "show", help="DH table, transforms, Jacobian determinant and singularities"
    )
    show.add_argument("robot", metavar="ROBOT")
    show.add_argument("--json", action="store_true", help="print a JSON object (SymPy syntax)")
    show.add_argument("--task", metavar="ROWS", help=task_help)
    show.add_argument(
        "--dynamics", action="store_true", help="also print the equations of motion (M, C, G)"
    )
    show.set_defaults(run=command_show)

    evaluate = commands.add_parser(
        "eval",
        help="numbers at one configuration",
        description="Evaluate pose, Jacobian, determinant and point motion at one state. "
        "Values are radians (or metres for prismatic joints); append 'deg' for degrees.",
    )
    evaluate.add_argument("robot", metavar="ROBOT")
    evaluate.add_argument("--q", required=True, metavar="V1,V2,...", help="joint positions")
    evaluate.add_argument("--dq", metavar="V1,V2,...", help="joint velocities")
    evaluate.add_argument("--ddq", metavar="V1,V2,...", help="joint accelerations")
    add_set_option(evaluate)
    evaluate.add_argument(
        "--point",
        action="append",
        default=[],
        metavar="LINK:X,Y,Z",
        help="a point fixed in link LINK (0 = base), coordinates in that link's frame",
    )
    evaluate.add_argument("--task", metavar="ROWS", help=task_help)
    evaluate.add_argument(
        "--dynamics",
        action="store_true",
        help="add M, c, G and tau (c needs --dq, tau --dq and --ddq); links without inertial "
        "data need --set m1=...,cx1=...",
    )
    evaluate.add_argument("--json", action="store_true", help="print a JSON object")
    evaluate.set_defaults(run=command_eval)

    derive_parser = commands.add_parser(
        "derive", help="write generated code (NumPy, C, CasADi) for one robot"
    )
    derive_parser.add_argument("robot", metavar="ROBOT")
    derive_parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    derive_parser.add_argument(
        "--emit",
        default=",".join(BACKENDS),
        metavar="LIST",
        help=f"backends, comma-separated (default: {','.join(BACKENDS)}; also: latex)",
    )
    derive_parser.add_argument(
        "--precision", choices=PRECISIONS, default="double", help="C floating-point type"
    )
    derive_parser.add_argument(
        "--no-build", action="store_true", help="do not compile the Python extension"
    )
    derive_parser.add_argument(
        "--point",
        action="append",
        default=[],
        metavar="LINK:X,Y,Z",
        help="also a kernel pointK for a point fixed in link LINK (position, velocity, "
        "acceleration)",
    )
    derive_parser.set_defaults(run=command_derive)

    latex = commands.add_parser(
        "latex",
        help="the derivation as a LaTeX document and snippets (optionally a PDF)",
        description="Write the DH table, transforms, Jacobian, determinant and singularities "
        "as LaTeX: a standalone document plus snippets and macros to \\input into notes.",
    )
    latex.add_argument("robot", metavar="ROBOT")
    latex.add_argument("-o", "--output", metavar="FILE", help="document path (default ROBOT.tex)")
    latex.add_argument("--pdf", action="store_true", help="compile with pdflatex as well")
    latex.add_argument("--shorthand", action="store_true", help="c_1, s_12, ... with a legend")
    latex.add_argument("--lang", choices=LANGUAGES, default="en", help="headings (default: en)")
    latex.add_argument("--q", metavar="V1,V2,...", help="also show numbers at this configuration")
    add_set_option(latex)
    latex.add_argument(
        "--sections",
        default=",".join(s for s in SECTIONS if s != "dynamics"),
        metavar="LIST",
        help=f"comma-separated, from {','.join(SECTIONS)} (default: all but dynamics)",
    )
    latex.add_argument(
        "--text-width",
        type=float,
        default=TEXT_WIDTH_CM,
        metavar="CM",
        help=f"text width that decides where matrices split (default {TEXT_WIDTH_CM})",
    )
    latex.set_defaults(run=command_latex)

    generate = commands.add_parser(
        "generate", help="regenerate generated/<robot>/ for every built-in robot"
    )
    generate.add_argument("--check", action="store_true", help="compare only; exit 2 on a diff")
    generate.add_argument("--root", default="generated", metavar="DIR", help="default: generated")
    generate.set_defaults(run=command_generate)
    return parser


def show_warning(message: Warning | str, *_: object, **__: object) -> None:
    """One ``symkin: warning: ...`` line instead of Python's file-and-line format."""
    print(f"symkin: warning: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else argv))
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            args.run(args)
    except SymkinError as error:
        print(f"symkin: error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # Output piped into `head` and closed early: not an error of ours.
        sys.stderr.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

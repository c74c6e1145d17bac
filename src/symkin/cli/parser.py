"""The ``symkin`` argument parser: global options, then one sub-parser per command, each
bound to its function in :mod:`symkin.cli.commands` or :mod:`symkin.cli.commands_ik`.

Joint values are strings here; the commands parse them (:mod:`symkin.cli.values`) once the
robot, and so the number and kind of its joints, is known.
"""

from __future__ import annotations

import argparse

from symkin.cli.commands import (
    command_derive,
    command_eval,
    command_generate,
    command_latex,
    command_list,
    command_show,
)
from symkin.cli.commands_check import add_check
from symkin.cli.commands_geometry import command_dh, command_urdf
from symkin.cli.commands_identify import command_identify
from symkin.cli.commands_ik import command_ik
from symkin.cli.commands_trajopt import add_trajopt_options, command_trajopt
from symkin.cli.parser_workspace import add_euler_option, add_workspace_commands
from symkin.cli.values import (
    DEFAULT_TIME_LIMIT,
    budget_from_text,
    seed_from_text,
    skip_from_text,
    time_limit_from_text,
)
from symkin.derive.budget import DEFAULT_BUDGET_SECONDS
from symkin.emit.c import PRECISIONS
from symkin.emit.latex import DEFAULT_SECTIONS, LANGUAGES, SECTIONS, TEXT_WIDTH_CM
from symkin.generate import BACKENDS
from symkin.solve.ik.backends import BACKENDS as IK_BACKENDS
from symkin.solve.ik.numeric import DEFAULT_RESTARTS, DEFAULT_TOLERANCE, METHODS
from symkin.solve.trajopt import OBJECTIVES

# argparse's (private) type of the object that add_subparsers returns
Commands = argparse._SubParsersAction
# Commands whose text products the derivation cache keeps (symkin.cache).
CACHED_COMMANDS = ("show", "derive", "latex")
IK_EULER_HELP = (
    "how the three rotation values of a target read: an intrinsic Euler order (angles in that "
    "order) or rotvec (axis * angle); default: rx,ry,rz of R = Rz(rz) Ry(ry) Rx(rx)"
)
TASK_HELP = "task Jacobian rows, e.g. x,y,wz (default: the n non-zero rows of x y z wz wx wy)"


def add_set_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="override a parameter"
    )


def add_derivation_options(parser: argparse.ArgumentParser) -> None:
    """``--budget``, ``--skip`` and ``--kinematics-only``: what to derive and for how long."""
    parser.add_argument(
        "--budget",
        type=budget_from_text,
        default=DEFAULT_BUDGET_SECONDS,
        metavar="SECONDS",
        help="time for each optional closed form (factored determinant, singular set, "
        "adjugate inverse, symbolic manipulability, readable angle-sum FK and Jacobian of a "
        "long chain); past it symkin says so and the code computes det and manipulability "
        f"numerically, FK and J stay products (default {DEFAULT_BUDGET_SECONDS:g}; "
        "0: no limit)",
    )
    parser.add_argument(
        "--skip",
        type=skip_from_text,
        default=(),
        metavar="LIST",
        help="parts not to derive, comma-separated: determinant (the closed forms above; "
        "numeric det in the code), dynamics",
    )
    parser.add_argument(
        "--kinematics-only", action="store_true", help="same as --skip determinant,dynamics"
    )


def add_robot_argument(parser: argparse.ArgumentParser) -> None:
    """``ROBOT`` and, for a URDF, the links its chain runs between (``--base``, ``--tip``)."""
    parser.add_argument("robot", metavar="ROBOT")
    parser.add_argument(
        "--tip", metavar="LINK", help="URDF: the chain's last link (needed with several leaves)"
    )
    parser.add_argument("--base", metavar="LINK", help="URDF: the chain's first link (its root)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="symkin",
        description="Closed-form kinematics from Denavit-Hartenberg tables.",
        epilog=(
            "ROBOT is a built-in name (see 'symkin list'), a path to a .toml robot file "
            "or a path to a .urdf file."
        ),
    )
    parser.add_argument(
        "--time-limit",
        type=time_limit_from_text,
        default=DEFAULT_TIME_LIMIT,
        metavar="SECONDS",
        help=f"stop with an error after this long (default {DEFAULT_TIME_LIMIT:g}; 0: no limit)",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    add_list(commands)
    add_show(commands)
    add_eval(commands)
    add_derive(commands)
    add_latex(commands)
    add_generate(commands)
    add_ik(commands)
    add_trajopt(commands)
    add_identify(commands)
    add_dh(commands)
    add_urdf(commands)
    add_workspace_commands(commands, add_robot_argument)
    add_check(commands)
    for name, command in commands.choices.items():
        add_run_options(command, cached=name in CACHED_COMMANDS)
    return parser


def add_run_options(command: argparse.ArgumentParser, cached: bool) -> None:
    """``--verbose`` on every command; ``--no-cache`` on those whose results are cached."""
    command.add_argument(
        "--verbose",
        action="store_true",
        help="print the time of each derivation phase and the cache's decisions on stderr",
    )
    if cached:
        command.add_argument(
            "--no-cache",
            action="store_true",
            help="derive afresh: neither read nor write the derivation cache",
        )


def add_dh(commands: Commands) -> None:
    """``symkin dh ROBOT``."""
    dh = commands.add_parser(
        "dh",
        help="the DH table of the chain, by the frame-assignment procedure, with proof",
        description="Assign DH frames from the joint axes (common normals; skew, parallel, "
        "intersecting and coincident axes), print the table with the base and tool transforms "
        "that make it exact, and prove that its FK equals the robot's.",
    )
    add_robot_argument(dh)
    dh.add_argument("--convention", choices=("standard", "modified"), default="standard")
    dh.add_argument("--json", action="store_true", help="print a JSON object (SymPy syntax)")
    dh.add_argument("--toml", metavar="FILE", help="write the DH model as a robot file")
    dh.add_argument("--latex", metavar="FILE", help="write the derivation as a LaTeX document")
    add_set_option(dh)
    dh.set_defaults(run=command_dh)


def add_urdf(commands: Commands) -> None:
    """``symkin urdf ROBOT -o FILE``."""
    urdf = commands.add_parser("urdf", help="write the robot as a URDF file")
    add_robot_argument(urdf)
    urdf.add_argument("-o", "--output", required=True, metavar="FILE", help="the .urdf file")
    add_set_option(urdf)
    urdf.set_defaults(run=command_urdf)


def add_list(commands: Commands) -> None:
    """``symkin list``."""
    listing = commands.add_parser("list", help="list the built-in robots")
    listing.set_defaults(run=command_list)


def add_show(commands: Commands) -> None:
    """``symkin show ROBOT``."""
    show = commands.add_parser(
        "show", help="DH table, transforms, Jacobian determinant and singularities"
    )
    add_robot_argument(show)
    show.add_argument("--json", action="store_true", help="print a JSON object (SymPy syntax)")
    show.add_argument("--task", metavar="ROWS", help=TASK_HELP)
    show.add_argument(
        "--dynamics", action="store_true", help="also print the equations of motion (M, C, G)"
    )
    add_derivation_options(show)
    show.set_defaults(run=command_show)


def add_eval(commands: Commands) -> None:
    """``symkin eval ROBOT --q ...``."""
    evaluate = commands.add_parser(
        "eval",
        help="numbers at one configuration",
        description="Evaluate pose, Jacobian, determinant and point motion at one state. "
        "Values are radians (or metres for prismatic joints); append 'deg' for degrees.",
    )
    add_robot_argument(evaluate)
    evaluate.add_argument("--q", required=True, metavar="V1,V2,...", help="joint positions")
    evaluate.add_argument("--dq", metavar="V1,V2,...", help="joint velocities")
    evaluate.add_argument("--ddq", metavar="V1,V2,...", help="joint accelerations")
    for order in ("d3q", "d4q"):
        evaluate.add_argument(
            f"--{order}",
            metavar="V1,V2,...",
            help=f"{'third' if order == 'd3q' else 'fourth'} time derivatives of q (with "
            "--dynamics, a robot with elastic joints: theta and tau_motor)",
        )
    add_set_option(evaluate)
    evaluate.add_argument(
        "--point",
        action="append",
        default=[],
        metavar="LINK:X,Y,Z",
        help="a point fixed in link LINK (0 = base), coordinates in that link's frame",
    )
    evaluate.add_argument("--task", metavar="ROWS", help=TASK_HELP)
    evaluate.add_argument(
        "--dynamics",
        action="store_true",
        help="add M, c, G, tau and the energies T, V, L (c, T and L need --dq, tau --dq and "
        "--ddq); links without inertial data need --set m1=... --set cx1=... (one --set each)",
    )
    evaluate.add_argument(
        "--wrench",
        metavar="FX,FY,FZ,MX,MY,MZ",
        help="with --dynamics: an external wrench on the tool (N, N m; base frame, at the tool "
        "point): tau includes -J^T w, and the static torque G - J^T w is printed",
    )
    evaluate.add_argument(
        "--derivatives",
        action="store_true",
        help="add dtau_dq, dtau_ddq, dddq_dq, dddq_ddq, dddq_dtau, jacobian_dot and "
        "jacobian_dot_dq (needs --dq and --ddq; row = output index)",
    )
    evaluate.add_argument("--json", action="store_true", help="print a JSON object")
    add_euler_option(
        evaluate,
        "also the tool orientation as intrinsic Euler angles of this "
        "order, or as the rotation vector (rotvec)",
    )
    evaluate.set_defaults(run=command_eval)


def add_derive(commands: Commands) -> None:
    """``symkin derive ROBOT --out DIR``."""
    derive_parser = commands.add_parser(
        "derive", help="write generated code (NumPy, C, CasADi) for one robot"
    )
    add_robot_argument(derive_parser)
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
    derive_parser.add_argument(
        "--numeric-parameters",
        action="store_true",
        help="put the parameter values (file values, or --set) into the code: no p input, "
        "constants folded, and for robots with full inertial data the dynamics run on base "
        "parameters (fewer operations)",
    )
    derive_parser.add_argument(
        "--regressor",
        action="store_true",
        help="also the identification kernels: regressor (tau = Y pi) and base_regressor "
        "(tau = Y_b beta), and mass_matrix_barycentric and inverse_dynamics_barycentric of a "
        "parameter vector delta = pi; see docs/identification.md",
    )
    derive_parser.add_argument(
        "--derivatives",
        action="store_true",
        help="also the derivative kernels: inverse_dynamics_derivatives (tau, dtau/dq, "
        "dtau/ddq), jacobian_derivative (dJ/dt, dJ/dt dq) and forward_dynamics_derivatives",
    )
    add_set_option(derive_parser)
    add_derivation_options(derive_parser)
    derive_parser.set_defaults(run=command_derive)


def add_latex(commands: Commands) -> None:
    """``symkin latex ROBOT``."""
    latex = commands.add_parser(
        "latex",
        help="the derivation as a LaTeX document and snippets (optionally a PDF)",
        description="Write the DH table, transforms, Jacobian, determinant and singularities "
        "as LaTeX: a standalone document plus snippets and macros to \\input into notes.",
    )
    add_robot_argument(latex)
    latex.add_argument("-o", "--output", metavar="FILE", help="document path (default ROBOT.tex)")
    latex.add_argument("--pdf", action="store_true", help="compile with pdflatex as well")
    latex.add_argument("--shorthand", action="store_true", help="c_1, s_12, ... with a legend")
    latex.add_argument("--lang", choices=LANGUAGES, default="en", help="headings (default: en)")
    latex.add_argument("--q", metavar="V1,V2,...", help="also show numbers at this configuration")
    add_set_option(latex)
    latex.add_argument(
        "--sections",
        default=",".join(DEFAULT_SECTIONS),
        metavar="LIST",
        help=f"comma-separated, from {','.join(SECTIONS)} (default: all but dynamics, which "
        "prints M, C and G by Lagrange up to three joints)",
    )
    latex.add_argument(
        "--text-width",
        type=float,
        default=TEXT_WIDTH_CM,
        metavar="CM",
        help=f"text width that decides where matrices split (default {TEXT_WIDTH_CM})",
    )
    add_derivation_options(latex)
    latex.set_defaults(run=command_latex)


def add_generate(commands: Commands) -> None:
    """``symkin generate``."""
    generate = commands.add_parser(
        "generate", help="regenerate generated/<robot>/ for every built-in robot"
    )
    generate.add_argument("--check", action="store_true", help="compare only; exit 2 on a diff")
    generate.add_argument("--root", default="generated", metavar="DIR", help="default: generated")
    generate.set_defaults(run=command_generate)


def add_ik(commands: Commands) -> None:
    """``symkin ik ROBOT --target ...`` or ``--path-from ... --to ... --steps K``."""
    ik = commands.add_parser(
        "ik",
        help="inverse kinematics: joint values for a tool pose, or along a straight path",
        description="Solve for joint values that put the tool at a target (numeric "
        "Levenberg-Marquardt or Newton; --all: every solution, in closed form where the robot "
        "has one), or along a straight path (--path-from, --to, --steps; --table prints the "
        "lecture's Newton path table). A target is x,y,z[,rx,ry,rz]: metres, then Z-Y-X "
        "Euler angles, R = Rz(rz) Ry(ry) Rx(rx), in rad or with 'deg'; x,y matches only the "
        "x and y rows. Exit status 1 when the target is not reached.",
    )
    add_robot_argument(ik)
    ik.add_argument("--target", metavar="X,Y,Z[,RX,RY,RZ]", help="the tool pose to reach")
    add_euler_option(ik, IK_EULER_HELP)
    ik.add_argument(
        "--q0", metavar="V1,V2,...", help="first guess (with --table: joint values at the start)"
    )
    ik.add_argument(
        "--all",
        action="store_true",
        help="every solution: closed form with branch flags, or numeric from many seeds",
    )
    ik.add_argument(
        "--task", metavar="ROWS", help="rows to match, e.g. x,y or xy (default: the robot's)"
    )
    add_ik_solver_options(ik)
    ik.add_argument(
        "--tolerance",
        type=float,
        default=DEFAULT_TOLERANCE,
        metavar="TOL",
        help=f"position error in m and rotation error in rad (default {DEFAULT_TOLERANCE:g})",
    )
    ik.add_argument(
        "--restarts",
        type=int,
        metavar="N",
        help=f"random restarts after a failed attempt (default {DEFAULT_RESTARTS}; along a path 0)",
    )
    ik.add_argument(
        "--seed", type=seed_from_text, default=0, metavar="N", help="seed of the restarts (>= 0)"
    )
    ik.add_argument("--path-from", metavar="X0", help="start of a straight path (as --target)")
    ik.add_argument("--to", metavar="X_END", help="end of the path")
    ik.add_argument("--steps", type=int, metavar="K", help="number of equal steps of the path")
    ik.add_argument(
        "--table",
        action="store_true",
        help="the lecture's scheme: one Newton step per waypoint from (--path-from, --q0)",
    )
    add_table_latex_options(ik)
    add_set_option(ik)
    ik.add_argument("--json", action="store_true", help="print a JSON object")
    ik.add_argument("--plot", metavar="FILE.png", help="draw the arm (and the path) to a PNG")
    ik.set_defaults(run=command_ik)


def add_ik_solver_options(ik: argparse.ArgumentParser) -> None:
    """``--method`` and ``--backend`` of ``symkin ik``."""
    ik.add_argument(
        "--method", choices=METHODS, default="lm", help="lm (default) or newton (Newton-Raphson)"
    )
    ik.add_argument(
        "--backend",
        choices=IK_BACKENDS,
        default="auto",
        help="auto (default): the generated C solver, compiled once, else its NumPy twin, for "
        "lm on all six rows or x,y,z; python: the general solver (docs/ik.md)",
    )


def add_table_latex_options(ik: argparse.ArgumentParser) -> None:
    """``--latex`` and ``--lang`` of ``symkin ik --table``."""
    ik.add_argument(
        "--latex",
        action="store_true",
        help="with --table: print the table as a standalone LaTeX document (the lecture's columns)",
    )
    ik.add_argument(
        "--lang", choices=LANGUAGES, default="en", help="language of --latex (default: en)"
    )


def add_trajopt(commands: Commands) -> None:
    """``symkin trajopt ROBOT --from ... --to ...``."""
    trajopt = commands.add_parser(
        "trajopt",
        help="optimal point-to-point motion on the robot's dynamics (CasADi + IPOPT)",
        description="Plan a rest-to-rest motion from --from to --to (or to the tool position "
        "--cartesian-goal) on the robot's forward dynamics: minimum effort (the integral of "
        "tau^2 over a fixed --time) or minimum time, within the joint limits of the robot file "
        "and the velocity and torque limits given here (default: none). Joint values are "
        "radians (or metres); append 'deg' for degrees.",
    )
    add_robot_argument(trajopt)
    trajopt.add_argument(
        "--from", dest="from_", required=True, metavar="V1,V2,...", help="start configuration"
    )
    trajopt.add_argument(
        "--to", metavar="V1,V2,...", help="goal configuration (with --cartesian-goal: a guess)"
    )
    trajopt.add_argument(
        "--cartesian-goal", metavar="X,Y,Z", help="goal tool position in metres, base frame"
    )
    trajopt.add_argument(
        "--intervals", type=int, default=40, metavar="N", help="time intervals (default 40)"
    )
    duration = trajopt.add_mutually_exclusive_group()
    duration.add_argument("--time", metavar="T", help="fixed final time in seconds (effort)")
    duration.add_argument(
        "--min-time", action="store_true", help="minimise the final time (= --objective time)"
    )
    trajopt.add_argument(
        "--objective", choices=OBJECTIVES, help="effort (the default) or time (= --min-time)"
    )
    add_trajopt_options(trajopt)
    trajopt.add_argument(
        "--velocity-limit",
        metavar="V[,V2,...]",
        help="|dq| limit, one value for all joints or one per joint (rad/s or m/s; deg ok)",
    )
    trajopt.add_argument(
        "--torque-limit",
        metavar="V[,V2,...]",
        help="|tau| limit, one value for all joints or one per joint (N m or N)",
    )
    add_set_option(trajopt)
    trajopt.add_argument(
        "--out", metavar="DIR", help="write trajectory.csv and trajectory.json to DIR"
    )
    trajopt.add_argument("--plot", action="store_true", help="also write DIR/trajectory.png")
    trajopt.add_argument("--json", action="store_true", help="print a JSON object")
    trajopt.set_defaults(run=command_trajopt)


def add_identify(commands: Commands) -> None:
    """``symkin identify ROBOT --data FILE.csv`` or ``--excite --out FILE.csv``."""
    identify = commands.add_parser(
        "identify",
        help="base inertial parameters from logged data, or an exciting trajectory",
        description="Fit the base parameters (least squares on the base regressor) to logged "
        "joint states and torques, or (--excite) design a periodic Fourier-series motion "
        "that makes the fit well conditioned. See docs/identification.md.",
    )
    add_robot_argument(identify)
    identify.add_argument(
        "--data",
        metavar="FILE.csv",
        help="columns q1..qn, dq1..dqn, ddq1..ddqn, tau1..taun by header name, each once (with "
        "--filter: t, q1..qn, tau1..taun); a regular file of at most 256 MiB",
    )
    identify.add_argument(
        "--filter",
        type=float,
        metavar="HZ",
        help="velocities and accelerations from q: 4th-order Butterworth low-pass at HZ, "
        "zero phase (filtfilt), then central differences; tau filtered alike",
    )
    identify.add_argument(
        "--weights",
        metavar="W1,...,Wn|auto",
        help="weighted least squares: one weight per joint, or auto (each joint by the "
        "inverse variance of its residual in a first fit)",
    )
    identify.add_argument("--json", action="store_true", help="print a JSON object")
    identify.add_argument(
        "--excite", action="store_true", help="write an exciting trajectory instead of fitting"
    )
    identify.add_argument(
        "--harmonics", type=int, default=5, help="Fourier harmonics, 1 to 30 (default 5)"
    )
    identify.add_argument(
        "--period", type=float, default=10.0, metavar="SECONDS",
        help="period (default 10; --period x --rate at most 10^6 samples)",
    )  # fmt: skip
    identify.add_argument(
        "--rate", type=float, default=100.0, metavar="HZ",
        help="samples per second (default 100; --period x --rate at most 10^6 samples)",
    )  # fmt: skip
    identify.add_argument(
        "--velocity-limit", metavar="V[,V2,...]",
        help="|dq| limit (default: the robot file's max_velocity, else 1 rad/s or m/s)",
    )  # fmt: skip
    identify.add_argument(
        "--simulate", action="store_true",
        help="also columns tau1..taun from the robot file's model (simulated measurements)",
    )  # fmt: skip
    identify.add_argument(
        "--noise", type=float, default=0.0, metavar="SIGMA",
        help="with --simulate: standard deviation of the torque noise, >= 0 (default 0)",
    )  # fmt: skip
    identify.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    identify.add_argument("--out", metavar="FILE.csv", help="with --excite: the trajectory file")
    add_set_option(identify)
    identify.set_defaults(run=command_identify)

"""The ``symkin`` commands but ``ik`` (:mod:`symkin.cli.commands_ik`): one function per
command, taking the parsed arguments; each parses its values, calls the library and prints.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

from symkin.cache import DiskCache, remembered, user_cache
from symkin.cli.report import (
    dynamics_json,
    dynamics_show_json,
    dynamics_show_text,
    dynamics_text,
    eval_json,
    eval_text,
    json_text,
    progress,
    show_json,
    show_text,
)
from symkin.cli.values import (
    joint_values,
    limit_values,
    parameter_overrides,
    point_from_text,
    robot_from_args,
    seconds_from_text,
    target_from_text,
    task_rows_from_text,
)
from symkin.derive import derive
from symkin.derive.budget import DEFAULT_BUDGET_SECONDS
from symkin.emit.latex import check_sections, latex_files
from symkin.emit.python_ext import extension_name
from symkin.errors import SymkinError
from symkin.generate import check_backends, files_for_robot, generate_catalogue
from symkin.io import catalogue_names, load_robot
from symkin.output_folder import write_folder
from symkin.runtime.extension import build_extension
from symkin.runtime.latex_build import compile_pdf
from symkin.solve.evaluate import dynamic_state, kinematic_state
from symkin.solve.trajopt import (
    TrajectoryProblem,
    check_problem,
    optimal_trajectory,
    summary_text,
    write_trajectory,
)

# Arguments that do not shape a command's text (where it goes, how the run is shown or
# limited); every other argument, present or future, is part of the cache key.
NOT_SHAPING = frozenset(
    {"run", "robot", "out", "output", "no_build", "pdf", "no_cache", "verbose", "time_limit"}
)


def cache_options(args: argparse.Namespace) -> dict[str, object]:
    """The command's options that shape its text, for the cache key (the robot is keyed by
    its content, not by the ROBOT argument)."""
    return {k: v for k, v in sorted(vars(args).items()) if k not in NOT_SHAPING}


def command_cache(args: argparse.Namespace) -> DiskCache | None:
    return None if args.no_cache else user_cache()


def command_list(_: argparse.Namespace) -> None:
    for name in catalogue_names():
        with warnings.catch_warnings():
            # Listing is not the place for data-quality warnings (show and eval give them).
            warnings.simplefilter("ignore")
            robot = load_robot(name)
        print(f"{name:<24} {robot.dof} DOF  {robot.convention:<8}  {robot.title}")


def derivation_options(args: argparse.Namespace) -> tuple[float | None, bool, bool]:
    """``(budget, closed_forms, dynamics)`` from ``--budget``, ``--skip`` and
    ``--kinematics-only`` (a budget of 0 is no limit)."""
    skip = set(args.skip) | ({"determinant", "dynamics"} if args.kinematics_only else set())
    return args.budget or None, "determinant" not in skip, "dynamics" not in skip


def command_show(args: argparse.Namespace) -> None:
    budget, closed_forms, dynamics = derivation_options(args)
    robot = robot_from_args(args)
    rows = task_rows_from_text(args.task)
    dynamics = dynamics and args.dynamics

    def report() -> str:
        model = derive(robot, budget, closed_forms)
        if args.json:
            extra = dynamics_show_json(model) if dynamics else {}
            return json_text(show_json(model, rows) | extra)
        return show_text(model, rows) + (dynamics_show_text(model) if dynamics else "")

    print(remembered(command_cache(args), "show", robot, cache_options(args), report))


def command_eval(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    model = derive(robot)
    overrides = parameter_overrides(args.set)
    if not args.dynamics:
        robot.parameter_values(overrides)  # reject unknown names and missing values first
    dq = joint_values(args.dq, "--dq", robot) if args.dq else None
    ddq = joint_values(args.ddq, "--ddq", robot) if args.ddq else None
    if ddq is not None and dq is None:
        raise SymkinError("--ddq needs --dq as well (acceleration depends on both)")
    q = joint_values(args.q, "--q", robot)
    kinematic_overrides = {k: v for k, v in overrides.items() if k in dict(robot.parameters)}
    points = [point_from_text(p, robot) for p in args.point]
    with np.errstate(all="ignore"):  # an overflow is reported once, by json_text below
        dynamics = dynamic_state(model, q, dq, ddq, overrides) if args.dynamics else None
        state = kinematic_state(
            model, q, dq, ddq, kinematic_overrides, points, task_rows_from_text(args.task)
        )
    data = eval_json(state) | dynamics_json(dynamics)
    if args.json:
        print(json_text(data))
    else:
        json_text(data)  # the same check: no NaN or infinity printed as a result
        print(eval_text(state) + dynamics_text(dynamics))


def derive_flags(args: argparse.Namespace) -> list[str]:
    """The options of a ``derive`` call that shape its files, for their "Regenerate with" line.

    ``--emit`` is not one of them: it chooses which files are written, not what any of them
    holds, so a built-in robot's files from ``derive --emit c`` equal those of ``generate``."""
    flags = ["--precision", args.precision] if args.precision != "double" else []
    flags += ["--numeric-parameters"] if args.numeric_parameters else []
    flags += [word for item in args.set for word in ("--set", item)]
    flags += [word for item in args.point for word in ("--point", item)]
    flags += ["--budget", f"{args.budget:g}"] if args.budget != DEFAULT_BUDGET_SECONDS else []
    flags += ["--skip", ",".join(args.skip)] if args.skip else []
    return flags + (["--kinematics-only"] if args.kinematics_only else [])


def command_derive(args: argparse.Namespace) -> None:
    backends = check_backends(args.emit.split(","))
    robot = robot_from_args(args)
    if args.numeric_parameters:
        robot = robot.with_parameter_values(parameter_overrides(args.set))
    elif args.set:
        raise SymkinError(
            "--set puts parameter values into the code: use it with --numeric-parameters"
        )
    progress(f"deriving {robot.name} and emitting {', '.join(backends)} ...")
    points = [point_from_text(p, robot) for p in args.point]
    budget, closed_forms, dynamics = derivation_options(args)
    files = remembered(
        command_cache(args),
        "derive",
        robot,
        cache_options(args),
        lambda: files_for_robot(
            robot,
            backends,
            args.precision,
            points,
            derive_flags(args),
            budget=budget,
            closed_forms=closed_forms,
            dynamics=dynamics,
        ),
    )
    out = Path(args.out)
    build = "python" in backends and not args.no_build

    def compile_extension(staging: Path) -> list[str]:
        progress("compiling the Python extension ...")
        extension = build_extension(
            staging / "python" / f"{extension_name(robot)}.c", staging / "c" / f"{robot.name}.c"
        )
        return [extension.relative_to(staging).as_posix()]

    written = write_folder(out, files, finish=compile_extension if build else None)
    print(f"wrote {len(files)} file{'s' if len(files) != 1 else ''} to {out}/:")
    for relative in files:
        print(f"  {out / relative}")
    for relative in sorted(set(written) - set(files)):
        print(f"built {out / relative} (import it with symkin.runtime.extension.load_extension)")
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
    robot = robot_from_args(args)
    sections = check_sections(args.sections.split(","))
    q = joint_values(args.q, "--q", robot) if args.q else None
    overrides = parameter_overrides(args.set)
    budget, closed_forms, _ = derivation_options(args)
    files = dict(
        remembered(
            command_cache(args),
            "latex",
            robot,
            cache_options(args),
            lambda: latex_files(
                derive(robot, budget, closed_forms),
                sections=sections,
                shorthand=args.shorthand,
                lang=args.lang,
                q=q,
                overrides=overrides,
                text_width_cm=args.text_width,
            ),
        )
    )
    out = Path(args.output or f"{robot.name}.tex")
    # snippets/ and <robot>-macros.tex beside the document
    write_folder(out.parent, {out.name: files.pop(f"{robot.name}.tex"), **files}, document=out.stem)
    print(f"wrote {out} and {len(files)} snippet and macro files in {out.parent}/")
    if args.pdf:
        print(f"wrote {compile_pdf(out)}")


def command_trajopt(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    if args.to is None and args.cartesian_goal is None:
        raise SymkinError("give the goal: --to V1,V2,... or --cartesian-goal X,Y,Z")
    if args.plot and args.out is None:
        raise SymkinError("--plot needs --out DIR, the folder for trajectory.png")
    if args.min_time and args.objective == "effort":
        raise SymkinError("--min-time means --objective time, not effort")
    objective = "time" if args.min_time else args.objective or "effort"
    cartesian_goal = None
    if args.cartesian_goal is not None:
        cartesian_goal = target_from_text(args.cartesian_goal, "--cartesian-goal")
        if len(cartesian_goal) != 3:
            raise SymkinError(
                f"--cartesian-goal: expected x,y,z (the tool position in metres), "
                f"got {args.cartesian_goal!r}"
            )
    problem = TrajectoryProblem(
        start=joint_values(args.from_, "--from", robot),
        goal=joint_values(args.to, "--to", robot) if args.to is not None else None,
        cartesian_goal=cartesian_goal,
        intervals=args.intervals,
        final_time=None if args.time is None else seconds_from_text(args.time, "--time"),
        objective=objective,
        method=args.method,
        velocity_limits=limit_values(args.velocity_limit, "--velocity-limit", robot, rates=True),
        torque_limits=limit_values(args.torque_limit, "--torque-limit", robot, rates=False),
        overrides=parameter_overrides(args.set),
    )
    model = derive(robot)
    check_problem(model, problem)  # input mistakes before the progress line
    progress(f"setting up and solving the {problem.method} problem with IPOPT ...")
    trajectory = optimal_trajectory(model, problem)
    print(summary_text(trajectory))
    if args.out is not None:
        paths = write_trajectory(trajectory, args.out, plot=args.plot)
        print(f"wrote {', '.join(str(path) for path in paths)}")

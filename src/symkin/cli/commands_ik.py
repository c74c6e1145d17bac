"""``symkin ik``: one target (numeric, or ``--all`` solutions) or a straight path (the path
follower, or ``--table``: the lecture's Newton path table)."""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from symkin.cli.report import (
    branch_text,
    ik_result_json,
    ik_result_text,
    json_text,
    newton_path_text,
    path_follow_json,
    path_follow_text,
    progress,
    solutions_text,
    target_text,
)
from symkin.cli.values import (
    joint_values,
    parameter_overrides,
    robot_from_args,
    target_from_text,
    task_rows_from_text,
)
from symkin.derive import Model, derive
from symkin.errors import SymkinError
from symkin.solve.ik.numeric import DEFAULT_RESTARTS, solve_ik
from symkin.solve.ik.path import (
    follow_path,
    newton_path_table,
    path_table_json,
    path_table_latex,
)
from symkin.solve.ik.plot import plot_path, plot_solutions
from symkin.solve.ik.solutions import all_solutions
from symkin.solve.ik.target import pose_from_target


def ik_problem(
    values: list[float], task_text: str | None, orientation: str | None = None
) -> tuple[np.ndarray, bool, tuple[str, ...] | None]:
    """Pose, position-only flag and task rows of a target: ``x,y`` matches the rows x, y only;
    ``orientation``: how the three rotation values read (``--euler``; default Z-Y-X)."""
    pose = pose_from_target([*values, 0.0] if len(values) == 2 else values, orientation)
    task = task_rows_from_text(task_text) or (("x", "y") if len(values) == 2 else None)
    return pose, len(values) < 6, task


def ik_path(
    model: Model, args: argparse.Namespace, q0: list[float] | None, overrides: dict[str, float]
) -> int:
    """``--path-from``: the lecture's table (``--table``) or the path follower."""
    if args.to is None or args.steps is None:
        raise SymkinError("--path-from needs --to and --steps as well")
    if args.all:
        raise SymkinError("--all solves one target; use it with --target, not --path-from")
    start = target_from_text(args.path_from, "--path-from")
    end = target_from_text(args.to, "--to")
    if len(start) != len(end):
        raise SymkinError(
            f"--path-from and --to need the same number of values, got {len(start)} and {len(end)}"
        )
    if args.table:
        return ik_table(model, args, start, end, q0, overrides)
    if args.latex:
        raise SymkinError("--latex prints the lecture's table: use it with --table")
    return ik_follow(model, args, start, end, q0, overrides)


def ik_follow(
    model: Model,
    args: argparse.Namespace,
    start: list[float],
    end: list[float],
    q0: list[float] | None,
    overrides: dict[str, float],
) -> int:
    """The path follower: every waypoint solved from the previous solution."""
    start_pose, position_only, task = ik_problem(start, args.task, args.euler)
    end_pose = ik_problem(end, args.task, args.euler)[0]
    path = follow_path(
        model,
        start_pose,
        end_pose,
        args.steps,
        q0,
        restarts=args.restarts or 0,
        method=args.method,
        position_only=position_only,
        task=task,
        tolerance=args.tolerance,
        seed=args.seed,
        overrides=overrides,
    )
    robot = model.robot
    if args.json:
        print(json_text({"robot": robot.name, **path_follow_json(path)}))
    else:
        print(
            f"{robot.name}: straight path in {args.steps} steps, each waypoint solved to "
            f"{args.tolerance:g} from the previous solution"
        )
        print(path_follow_text(robot, path))
    if args.plot:
        rows = ("x", "y") if len(start) == 2 else ("x", "y", "z")
        indices = ["xyz".index(r) for r in rows]
        plot_path(
            model,
            np.array([t[indices, 3] for t in path.targets]),
            np.array([r.pose[indices, 3] for r in path.results]),
            np.array([r.q for r in path.results]),
            args.plot,
            task=rows,
            overrides=overrides,
        )
        progress(f"wrote {args.plot}")
    return 0 if path.success else 1


def ik_table(
    model: Model,
    args: argparse.Namespace,
    start: list[float],
    end: list[float],
    q0: list[float] | None,
    overrides: dict[str, float],
) -> int:
    """The lecture's Newton path table."""
    if q0 is None:
        raise SymkinError(
            "--table starts from a known pair: give --q0, the joint values at --path-from"
        )
    if len(start) == 6:
        raise SymkinError(
            "--table interpolates positions: give --path-from and --to as x,y or x,y,z"
        )
    rows = task_rows_from_text(args.task) or ("x", "y", "z")[: len(start)]
    if len(rows) != len(start):
        raise SymkinError(
            f"--task {','.join(rows)}: --path-from and --to need one value per row, "
            f"got {len(start)}"
        )
    path = newton_path_table(
        model, start, q0, end, args.steps, task=rows, tolerance=args.tolerance, overrides=overrides
    )
    robot = model.robot
    if args.json:
        print(json_text({"robot": robot.name, **path_table_json(path)}))
    elif args.latex:
        print(path_table_latex(path, robot.name, args.steps, args.lang), end="")
    else:
        print(newton_path_text(robot, path, start, end, args.steps, args.tolerance))
    if args.plot:
        plot_path(
            model,
            np.array([r.target for r in path.rows]),
            np.array([r.real for r in path.rows]),
            np.array([r.q for r in path.rows]),
            args.plot,
            task=path.task,
            labels=[r.label for r in path.rows],
            overrides=overrides,
        )
        progress(f"wrote {args.plot}")
    return 0 if path.converged else 1


def command_ik(args: argparse.Namespace) -> int:
    """Exit status 0 when the target (or every waypoint) is reached, else 1."""
    robot = robot_from_args(args)
    model = derive(robot)
    overrides = parameter_overrides(args.set, robot)
    robot.parameter_values(overrides)  # reject unknown names and missing values first
    q0 = joint_values(args.q0, "--q0", robot) if args.q0 else None
    if args.restarts is not None and args.restarts < 0:
        raise SymkinError(f"--restarts: expected a count >= 0, got {args.restarts}")
    if (args.target is None) == (args.path_from is None):
        raise SymkinError("give either --target or --path-from (with --to and --steps)")
    if args.path_from is not None:
        return ik_path(model, args, q0, overrides)
    if args.to is not None or args.steps is not None or args.table or args.latex:
        raise SymkinError("--to, --steps, --table and --latex go with --path-from, not --target")
    values = target_from_text(args.target, "--target")
    pose, position_only, task = ik_problem(values, args.task, args.euler)
    rows = task or model.task_rows
    if len(values) == 6 and any(values[3:]) and not {"wx", "wy", "wz"} & set(rows):
        warnings.warn(
            f"the target's rotation is not matched: the task rows are {', '.join(rows)}",
            stacklevel=1,
        )
    options = {
        "position_only": position_only,
        "task": task,
        "tolerance": args.tolerance,
        "seed": args.seed,
        "overrides": overrides,
    }
    if args.all:
        return ik_all(model, args, values, pose, q0, options)
    return ik_one(model, args, values, pose, q0, options)


def ik_all(
    model: Model,
    args: argparse.Namespace,
    values: list[float],
    pose: np.ndarray,
    q0: list[float] | None,
    options: dict,
) -> int:
    """``--all``: every solution (closed form or from many seeds); status 1 when there is none."""
    robot = model.robot
    found = all_solutions(model, pose, q0, **options)
    if args.json:
        solutions = [
            {"q": s.q.tolist(), "branch": dict(s.branch), "within_limits": s.within_limits}
            for s in found.solutions
        ]
        print(
            json_text(
                {
                    "robot": robot.name,
                    "method": found.method,
                    "description": found.description,
                    "complete": found.complete,
                    "solutions": solutions,
                }
            )
        )
    else:
        print(f"{robot.name}: target {target_text(values)}")
        print(solutions_text(robot, found))
    if args.plot and found.solutions:
        labels = [
            f"{k}: {branch_text(dict(s.branch), s.within_limits)}".rstrip(": ")
            for k, s in enumerate(found.solutions, start=1)
        ]
        plot_solutions(
            model,
            [s.q for s in found.solutions],
            args.plot,
            target=pose,
            labels=labels,
            overrides=options["overrides"],
        )
        progress(f"wrote {args.plot}")
    return 0 if found.solutions else 1


def ik_one(
    model: Model,
    args: argparse.Namespace,
    values: list[float],
    pose: np.ndarray,
    q0: list[float] | None,
    options: dict,
) -> int:
    """One numeric solve (with restarts); status 1 when the target is not reached."""
    robot = model.robot
    restarts = DEFAULT_RESTARTS if args.restarts is None else args.restarts
    result = solve_ik(
        model, pose, q0, method=args.method, restarts=restarts, backend=args.backend, **options
    )
    if args.json:
        print(json_text({"robot": robot.name, **ik_result_json(result)}))
    else:
        print(f"{robot.name}: target {target_text(values)}")
        print(ik_result_text(robot, result, args.tolerance))
    if args.plot:
        plot_solutions(
            model,
            [result.q],
            args.plot,
            target=pose,
            labels=["solution" if result.success else "closest pose reached"],
            overrides=options["overrides"],
        )
        progress(f"wrote {args.plot}")
    return 0 if result.success else 1

"""``symkin trajopt``: its own options (transcription, accuracy, waypoints, obstacles, output)
and the command, a thin layer over :func:`symkin.solve.trajopt.optimal_trajectory`."""

from __future__ import annotations

import argparse
from pathlib import Path

from symkin.cli.report import json_text, progress
from symkin.cli.values import (
    joint_values,
    limit_values,
    parameter_overrides,
    robot_from_args,
    sampled_rows,
    seconds_from_text,
    target_from_text,
)
from symkin.derive import derive
from symkin.errors import SymkinError
from symkin.output_folder import check_output_root
from symkin.robot import Robot
from symkin.solve.trajopt import (
    DEFAULT_TOLERANCE,
    Obstacle,
    TrajectoryProblem,
    Waypoint,
    check_problem,
    optimal_trajectory,
    robot_functions,
    summary_text,
    trajectory_json,
    write_trajectory,
)
from symkin.solve.trajopt.problem import DEFAULT_MAX_REFINEMENTS
from symkin.solve.trajopt.report import write_resampled
from symkin.solve.trajopt.resample import resampled

FORWARD_METHODS = ("multiple-shooting", "collocation")


def add_trajopt_options(trajopt: argparse.ArgumentParser) -> None:
    """The options of ``symkin trajopt`` beyond the problem's start, goal, time and limits."""
    trajopt.add_argument(
        "--method",
        choices=FORWARD_METHODS,
        default="multiple-shooting",
        help="forward transcription: multiple-shooting (RK4, default) or collocation (Radau)",
    )
    trajopt.add_argument(
        "--transcription",
        choices=("forward", "inverse"),
        default="forward",
        help="forward: torques are the decisions, the forward dynamics integrated (--method); "
        "inverse: accelerations are the decisions, the torque is the inverse dynamics "
        "(faster; see docs/trajopt.md)",
    )
    trajopt.add_argument(
        "--tolerance",
        type=float,
        default=DEFAULT_TOLERANCE,
        help="largest local defect after re-simulation, joint units "
        f"(default {DEFAULT_TOLERANCE:g})",
    )
    trajopt.add_argument(
        "--max-refinements",
        type=int,
        default=DEFAULT_MAX_REFINEMENTS,
        metavar="K",
        help=f"mesh refinements at most (default {DEFAULT_MAX_REFINEMENTS})",
    )
    _add_path_options(trajopt)


def _add_path_options(trajopt: argparse.ArgumentParser) -> None:
    """Waypoints, obstacles, manipulability margin and the resampled output."""
    trajopt.add_argument(
        "--via",
        action="append",
        default=[],
        metavar="V1,V2,...[@T]",
        help="pass through these joint values (at T seconds, or at a free time); repeatable",
    )
    trajopt.add_argument(
        "--via-tool",
        action="append",
        default=[],
        metavar="X,Y,Z[@T]",
        help="pass the tool through this position in metres (at T s or a free time); repeatable",
    )
    trajopt.add_argument(
        "--obstacle",
        action="append",
        default=[],
        metavar="X,Y,Z,R",
        help="a sphere (centre and radius, metres) the links keep clear of; repeatable",
    )
    trajopt.add_argument(
        "--clearance",
        type=float,
        default=0.05,
        metavar="M",
        help="radius of the capsules around the links for --obstacle (default 0.05 m)",
    )
    trajopt.add_argument(
        "--min-manipulability",
        type=float,
        metavar="W",
        help="keep Yoshikawa's manipulability at least W at every node",
    )
    trajopt.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help="with --out: also write trajectory_resampled.csv and .json at HZ samples per "
        "second (states, accelerations, feedforward torques); T x HZ at most 10^6 samples",
    )


def _waypoint(text: str, option: str, robot: Robot, tool: bool) -> Waypoint:
    """``values[@T]`` as a :class:`Waypoint`."""
    values, _, at = text.partition("@")
    time = seconds_from_text(at, option) if at else None
    if tool:
        position = target_from_text(values, option)
        if len(position) != 3:
            raise SymkinError(f"{option}: expected x,y,z in metres, got {values!r}")
        return Waypoint(position=tuple(position), time=time)
    return Waypoint(q=tuple(joint_values(values, option, robot)), time=time)


def _obstacle(text: str) -> Obstacle:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 4:
        raise SymkinError(f"--obstacle: expected X,Y,Z,R in metres, got {text!r}")
    return Obstacle(tuple(values[:3]), values[3])


def problem_from_args(args: argparse.Namespace, robot: Robot) -> TrajectoryProblem:
    """The :class:`TrajectoryProblem` the options describe."""
    if args.to is None and args.cartesian_goal is None:
        raise SymkinError("give the goal: --to V1,V2,... or --cartesian-goal X,Y,Z")
    if args.min_time and args.objective == "effort":
        raise SymkinError("--min-time means --objective time, not effort")
    if args.transcription == "inverse" and args.method != "multiple-shooting":
        raise SymkinError(
            "--method chooses a forward transcription; drop it with --transcription inverse"
        )
    cartesian_goal = None
    if args.cartesian_goal is not None:
        cartesian_goal = target_from_text(args.cartesian_goal, "--cartesian-goal")
        if len(cartesian_goal) != 3:
            raise SymkinError(
                f"--cartesian-goal: expected x,y,z (the tool position in metres), "
                f"got {args.cartesian_goal!r}"
            )
    waypoints = [_waypoint(v, "--via", robot, tool=False) for v in args.via]
    waypoints += [_waypoint(v, "--via-tool", robot, tool=True) for v in args.via_tool]
    return TrajectoryProblem(
        start=joint_values(args.from_, "--from", robot),
        goal=joint_values(args.to, "--to", robot) if args.to is not None else None,
        cartesian_goal=cartesian_goal,
        intervals=args.intervals,
        final_time=None if args.time is None else seconds_from_text(args.time, "--time"),
        objective="time" if args.min_time else args.objective or "effort",
        method="inverse-dynamics" if args.transcription == "inverse" else args.method,
        velocity_limits=limit_values(args.velocity_limit, "--velocity-limit", robot, rates=True),
        torque_limits=limit_values(args.torque_limit, "--torque-limit", robot, rates=False),
        overrides=parameter_overrides(args.set, robot),
        tolerance=args.tolerance,
        max_refinements=args.max_refinements,
        waypoints=tuple(sorted(waypoints, key=lambda w: (w.time is None, w.time or 0.0))),
        obstacles=tuple(_obstacle(v) for v in args.obstacle),
        min_manipulability=args.min_manipulability,
        clearance=args.clearance,
    )


def command_trajopt(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    if args.plot and args.out is None:
        raise SymkinError("--plot needs --out DIR, the folder for trajectory.png")
    if args.rate is not None and (args.out is None or not args.rate > 0):
        raise SymkinError("--rate needs --out DIR and a positive number of samples per second")
    if args.out is not None:
        check_output_root(Path(args.out))  # before the solve, not after it
    problem = problem_from_args(args, robot)
    if args.rate is not None and problem.final_time is not None:
        sampled_rows(args.rate, problem.final_time, "--rate", "--time")
    model = derive(robot)
    check_problem(model, problem)  # input mistakes before the progress line
    progress(f"setting up and solving the {problem.method} problem with IPOPT ...")
    trajectory = optimal_trajectory(model, problem)
    if args.rate is not None:  # a free time is known now: check before printing or writing
        sampled_rows(args.rate, trajectory.final_time, "--rate", "the optimal time")
    if args.json:
        print(json_text(trajectory_json(trajectory)))
    else:
        print(summary_text(trajectory))
    if args.out is not None:
        functions = robot_functions(
            model, dict(problem.overrides), problem.coulomb_friction, problem.friction_velocity
        )
        paths = write_trajectory(trajectory, args.out, plot=args.plot, functions=functions)
        if args.rate is not None:
            paths += write_resampled(resampled(trajectory, functions, args.rate), args.out)
        if not args.json:
            print(f"wrote {', '.join(str(path) for path in paths)}")

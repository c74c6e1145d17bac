"""The PNGs of an optimal trajectory: joint positions, velocities and torques against time;
and the tool path with the links, waypoints and obstacles.

Each joint has one colour; its limits are dashed lines in that colour.  Torques are drawn as
the steps they are (piecewise constant on each interval).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from symkin.solve.plotting import colour_cycle, new_figure, save_figure
from symkin.solve.trajopt.functions import RobotFunctions
from symkin.solve.trajopt.problem import units
from symkin.solve.trajopt.resample import resampled
from symkin.solve.trajopt.solve import Trajectory


def trajectory_figure(trajectory: Trajectory) -> object:
    """A matplotlib figure with three panels (q, dq, tau) sharing the time axis."""
    robot, problem = trajectory.robot, trajectory.problem
    figure = new_figure(figsize=(8, 8))
    top, middle, bottom = figure.subplots(3, 1, sharex=True)
    colours = colour_cycle()
    t = trajectory.t
    tau = np.vstack([trajectory.tau, trajectory.tau[-1:]])  # the last step drawn to T
    for i, joint in enumerate(robot.joints):
        colour = colours[i % len(colours)]
        label = f"joint {i + 1}"
        top.plot(t, trajectory.q[:, i], color=colour, label=label)
        middle.plot(t, trajectory.dq[:, i], color=colour)
        bottom.step(t, tau[:, i], where="post", color=colour)
        limits = [
            (top, joint.limits),
            (middle, _symmetric(problem.velocity_limits, i)),
            (bottom, _symmetric(problem.torque_limits, i)),
        ]
        for axes, pair in limits:
            for value in pair or ():
                axes.axhline(value, color=colour, linestyle="--", linewidth=0.8, alpha=0.7)
    unit_sets = {units(joint) for joint in robot.joints}
    names = ("position", "velocity", "torque")
    for k, (axes, name) in enumerate(zip((top, middle, bottom), names, strict=True)):
        unit = " / ".join(sorted({u[k] for u in unit_sets}))
        axes.set_ylabel(f"{name} [{unit}]")
        axes.grid(True, alpha=0.3)
    bottom.set_xlabel("time [s]")
    top.legend(loc="best", fontsize="small", ncol=min(robot.dof, 3))
    objective = "minimum effort" if problem.objective == "effort" else "minimum time"
    top.set_title(
        f"{robot.name}: {objective}, {problem.method.replace('-', ' ')}, "
        f"T = {trajectory.final_time:.4g} s (dashed: limits)"
    )
    return figure


def _symmetric(limits: tuple[float, ...] | None, i: int) -> tuple[float, float] | None:
    return None if limits is None else (-limits[i], limits[i])


def plot_trajectory(trajectory: Trajectory, path: str | Path) -> Path:
    """Write :func:`trajectory_figure` as a PNG at ``path``."""
    return save_figure(trajectory_figure(trajectory), path)


# The arm is drawn at this many instants of the tool-path figure.
ARM_POSES = 7


def path_figure(trajectory: Trajectory, functions: RobotFunctions, rate: float = 200.0) -> object:
    """The tool path in the x-y and x-z planes of the base frame, sampled from the
    re-simulation at ``rate`` per second (:func:`~symkin.solve.trajopt.resample.resampled`);
    the links (segments between frame origins) at a few instants, lighter to darker in time;
    the waypoints as crosses; the obstacles as circles (their radius, and dashed, the radius
    plus the links' clearance)."""
    import casadi
    from matplotlib.patches import Circle

    problem = trajectory.problem
    samples = resampled(trajectory, functions, rate)
    q = casadi.SX.sym("q", functions.dof)
    origins = casadi.Function("origins", [q], [casadi.horzcat(*functions.link_origins(q))])
    tool = np.array([np.asarray(functions.tool_position(row)).ravel() for row in samples["q"]])
    figure = new_figure(figsize=(11, 5.2))
    panes = figure.subplots(1, 2)
    instants = np.linspace(0, len(samples["t"]) - 1, ARM_POSES).astype(int)
    for axes, (i, j) in zip(panes, ((0, 1), (0, 2)), strict=True):
        axes.plot(tool[:, i], tool[:, j], color="C0", label="tool path")
        for shade, k in zip(np.linspace(0.25, 0.9, ARM_POSES), instants, strict=True):
            points = np.array(origins(samples["q"][k]))
            axes.plot(points[i], points[j], "-o", color=str(1 - shade), markersize=2.5)
        for obstacle in problem.obstacles:
            centre = (obstacle.centre[i], obstacle.centre[j])
            axes.add_patch(Circle(centre, obstacle.radius, color="C3", alpha=0.35))
            reach = obstacle.radius + problem.clearance
            axes.add_patch(Circle(centre, reach, color="C3", fill=False, linestyle="--"))
        for waypoint in problem.waypoints:
            where = (
                waypoint.position
                or np.asarray(functions.tool_position(np.array(waypoint.q))).ravel()
            )
            axes.plot(where[i], where[j], "x", color="C2", markersize=9, mew=2)
        axes.set_xlabel(f"{'xyz'[i]} [m]")
        axes.set_ylabel(f"{'xyz'[j]} [m]")
        axes.set_aspect("equal", adjustable="datalim")
        axes.grid(True, alpha=0.3)
    panes[0].legend(loc="best", fontsize="small")
    figure.suptitle(f"{trajectory.robot.name}: tool path and links (grey: earlier to later)")
    return figure


def plot_path(trajectory: Trajectory, functions: RobotFunctions, path: str | Path) -> Path:
    """Write :func:`path_figure` as a PNG at ``path``."""
    return save_figure(path_figure(trajectory, functions), path)

"""The PNG of an optimal trajectory: joint positions, velocities and torques against time.

Each joint has one colour; its limits are dashed lines in that colour.  Torques are drawn as
the steps they are (piecewise constant on each interval).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from symkin.solve.plotting import colour_cycle, new_figure, save_figure
from symkin.solve.trajopt.problem import units
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

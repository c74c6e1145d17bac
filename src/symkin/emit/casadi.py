"""CasADi backend: a Python module per robot that builds ``casadi.Function`` objects."""

from __future__ import annotations

from collections.abc import Sequence

from symkin.emit.layout import kernel_layout
from symkin.emit.printers import casadi_code
from symkin.emit.render import (
    forward_dynamics_context,
    parameter_context,
    preamble_lines,
    render,
)
from symkin.kernels import Kernel
from symkin.robot import Robot


def module_name(robot: Robot) -> str:
    return f"{robot.name}_casadi"


def emit_casadi(
    robot: Robot, kernels: tuple[Kernel, ...], flags: Sequence[str] = ()
) -> dict[str, str]:
    """``{"casadi/<robot>_casadi.py": source}``."""
    text = render(
        "casadi/module.py.j2",
        preamble=preamble_lines(robot, kernels, "CasADi kinematics", flags),
        prefix=robot.name,
        dof=robot.dof,
        **parameter_context(robot, lambda v: repr(float(v)), "float('nan')"),
        kernels=[kernel_layout(k, casadi_code) for k in kernels],
        forward=forward_dynamics_context(kernels),
    )
    return {f"casadi/{module_name(robot)}.py": text}

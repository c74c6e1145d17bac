"""CasADi backend: a Python module per robot that builds ``casadi.Function`` objects."""

from __future__ import annotations

from symkin.emit.layout import kernel_layout
from symkin.emit.printers import casadi_code
from symkin.emit.render import preamble_lines, render
from symkin.kernel import Kernel
from symkin.robot import Robot


def module_name(robot: Robot) -> str:
    return f"{robot.name}_casadi"


def emit_casadi(robot: Robot, kernels: tuple[Kernel, ...]) -> dict[str, str]:
    """``{"casadi/<robot>_casadi.py": source}``."""
    text = render(
        "casadi/module.py.j2",
        preamble=preamble_lines(robot, kernels, "CasADi kinematics"),
        prefix=robot.name,
        dof=robot.dof,
        parameter_names=[n for n, _ in robot.parameters],
        parameter_values=[
            repr(float(v)) if v is not None else "float('nan')" for _, v in robot.parameters
        ],
        kernels=[kernel_layout(k, casadi_code) for k in kernels],
    )
    return {f"casadi/{module_name(robot)}.py": text}

"""NumPy backend: one Python module per robot, every function batched over leading axes."""

from __future__ import annotations

from collections.abc import Sequence

from symkin.emit.layout import kernel_layout
from symkin.emit.printers import numpy_code
from symkin.emit.render import (
    forward_dynamics_context,
    parameter_context,
    preamble_lines,
    render,
)
from symkin.kernels import Kernel
from symkin.robot import Robot


def module_name(robot: Robot) -> str:
    return f"{robot.name}_kinematics"


def emit_numpy(
    robot: Robot, kernels: tuple[Kernel, ...], flags: Sequence[str] = ()
) -> dict[str, str]:
    """``{"numpy/<robot>_kinematics.py": source}``."""
    text = render(
        "numpy/module.py.j2",
        preamble=preamble_lines(robot, kernels, "NumPy kinematics", flags),
        dof=robot.dof,
        **parameter_context(robot, lambda v: repr(float(v)), "numpy.nan"),
        kernels=[kernel_layout(k, numpy_code) for k in kernels],
        forward=forward_dynamics_context(kernels),
    )
    return {f"numpy/{module_name(robot)}.py": text}

"""NumPy backend: one Python module per robot, every function batched over leading axes."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from symkin.emit.layout import KernelLayout, kernel_layout
from symkin.emit.numpy_trig import pair_trig
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


def numpy_kernel_layout(kernel: Kernel) -> KernelLayout:
    """The kernel's layout with each angle's sine and cosine as one line,
    ``s, c = _sincos(angle)`` (``emit.numpy_trig``); operation counts are the kernel's."""
    rewritten, pairs = pair_trig(kernel)
    layout = kernel_layout(rewritten, numpy_code, kernel.operation_counts)
    lines = tuple(
        (f"{pairs[i].sin.name}, {pairs[i].cos.name}", f"_sincos({numpy_code(pairs[i].angle)})")
        if i in pairs
        else line
        for i, line in enumerate(layout.assignments)
        if i - 1 not in pairs  # the cosine half of a pair
    )
    return dataclasses.replace(layout, assignments=lines)


def emit_numpy(
    robot: Robot, kernels: tuple[Kernel, ...], flags: Sequence[str] = ()
) -> dict[str, str]:
    """``{"numpy/<robot>_kinematics.py": source}``."""
    text = render(
        "numpy/module.py.j2",
        preamble=preamble_lines(robot, kernels, "NumPy kinematics", flags),
        dof=robot.dof,
        **parameter_context(robot, lambda v: repr(float(v)), "numpy.nan"),
        kernels=[numpy_kernel_layout(k) for k in kernels],
        forward=forward_dynamics_context(kernels),
    )
    return {f"numpy/{module_name(robot)}.py": text}

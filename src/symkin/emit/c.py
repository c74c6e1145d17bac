"""Embedded C backend: one ``.h``/``.c`` pair per robot, an example and a Makefile."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from functools import partial

import sympy as sp

from symkin.emit.c_library import library_files
from symkin.emit.layout import KernelLayout, kernel_layout
from symkin.emit.printers import c_code, c_literal
from symkin.emit.render import (
    dynamics_notes,
    forward_dynamics_context,
    parameter_context,
    preamble_lines,
    render,
)
from symkin.errors import ParameterError
from symkin.kernels import Kernel, units
from symkin.robot import Robot

PRECISIONS = ("double", "float")


# IEEE single precision: the largest finite value and the smallest normal one.
FLOAT_MAX = 3.4028234663852886e38
FLOAT_MIN_NORMAL = 1.1754943508222875e-38


def check_float_range(robot: Robot, kernels: tuple[Kernel, ...]) -> None:
    """Every constant of the code (parameter values, numbers in the formulas) must be a
    ``float`` when the C code is single precision; the compiler would otherwise truncate it
    to zero or infinity (``-Werror=overflow``), and the numbers would be wrong."""
    numbers = [v for _, v in robot.parameters if v is not None]
    for kernel in kernels:
        expressions = [e for _, e in kernel.assignments]
        expressions += [e for output in kernel.outputs for e in output.matrix]
        numbers += [float(n) for e in expressions for n in e.atoms(sp.Number)]
    for number in numbers:
        if abs(number) > FLOAT_MAX or 0 < abs(number) < FLOAT_MIN_NORMAL:
            raise ParameterError(
                f"{{precision}} float: {robot.name} has the constant {number:g}, outside the "
                f"range of float ({FLOAT_MIN_NORMAL:.3g} to {FLOAT_MAX:.3g}); "
                "use {precision} double"
            )


def c_kernel_layout(kernel: Kernel, precision: str) -> KernelLayout:
    """The kernel's layout with ``precision`` literals, without the inputs that hold no
    symbols: the C function of a robot without parameters takes no ``p``."""
    layout = kernel_layout(kernel, partial(c_code, precision=precision))
    empty = {i.name for i in layout.inputs if i.size == 0}
    return replace(
        layout,
        inputs=tuple(i for i in layout.inputs if i.name not in empty),
        unused_inputs=tuple(name for name in layout.unused_inputs if name not in empty),
    )


def _library_parts(kernels: tuple[Kernel, ...]) -> tuple[str, ...]:
    """The C library's parts the source needs: Cholesky for the forward dynamics, and the
    many-column solve for its derivatives (a pasted function is static: never an unused one)."""
    forward = forward_dynamics_context(kernels)
    return ("cholesky", "cholesky_columns") if forward and forward["derivatives"] else ("cholesky",)


def emit_c(
    robot: Robot,
    kernels: tuple[Kernel, ...],
    precision: str = "double",
    flags: Sequence[str] = (),
) -> dict[str, str]:
    """``c/<robot>.h``, ``c/<robot>.c``, ``c/example.c`` and ``c/Makefile``; ``flags`` as for
    :func:`~symkin.emit.render.preamble_lines`."""
    if precision == "float":
        check_float_range(robot, kernels)
    header, source = f"{robot.name}.h", f"{robot.name}.c"
    context = {
        "robot": robot.name,
        "prefix": robot.name,
        "macro": robot.name.upper(),
        "guard": f"{robot.name.upper()}_KINEMATICS_H",
        "real": precision,
        "dof": robot.dof,
        "header": header,
        "source": source,
        **parameter_context(robot, partial(c_literal, precision=precision), "NAN"),
        "has_parameters": bool(robot.parameters),
        "example_q": [round(0.1 * (i + 1), 1) for i in range(robot.dof)],
        "example_q_literals": [
            c_literal(round(0.1 * (i + 1), 1), precision) for i in range(robot.dof)
        ],
        "kernels": [c_kernel_layout(k, precision) for k in kernels],
        "forward": forward_dynamics_context(kernels),
        "joint_units": units.joint_units(robot),
        "notes": dynamics_notes(robot, kernels),
        "force_units": units.generalized_force(robot),
        "acceleration_units": units.joint_acceleration(robot),
        "library": library_files(precision, *_library_parts(kernels)),
    }
    context["preamble"] = preamble_lines(robot, kernels, f"C kinematics ({precision})", flags)
    return {
        f"c/{header}": render("c/header.h.j2", **context),
        f"c/{source}": render("c/source.c.j2", **context),
        "c/example.c": render("c/example.c.j2", **context),
        "c/Makefile": render("c/Makefile.j2", **context),
    }

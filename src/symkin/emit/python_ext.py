"""CPython extension backend: a thin binding of the generated C kernels.

Calling C through ctypes costs 1.5-2.5 us per call whatever the C does; a CPython extension
with ``METH_FASTCALL`` and NumPy's C API costs a fraction of that and offers batched calls.
"""

from __future__ import annotations

from symkin.emit.layout import kernel_layout
from symkin.emit.render import preamble_lines, render
from symkin.kernel import Kernel
from symkin.robot import Robot

NUMPY_TYPES = {"double": "NPY_FLOAT64", "float": "NPY_FLOAT32"}
# The binding covers kernels of (q, p); dynamics kernels (dq, ddq, pi) are planned.
BINDING_INPUTS = ("q", "p")


def extension_name(robot: Robot) -> str:
    return f"{robot.name}_ext"


def emit_python_extension(
    robot: Robot, kernels: tuple[Kernel, ...], precision: str = "double"
) -> dict[str, str]:
    """``{"python/<robot>_ext.c": source}``; it includes ``../c/<robot>.h``."""
    module = extension_name(robot)
    text = render(
        "python/module.c.j2",
        preamble=preamble_lines(robot, kernels, f"Python binding ({precision})"),
        module=module,
        robot=robot.name,
        prefix=robot.name,
        macro=robot.name.upper(),
        header=f"{robot.name}.h",
        real=precision,
        npy_type=NUMPY_TYPES[precision],
        dof=robot.dof,
        parameter_names=[n for n, _ in robot.parameters],
        # Printing is not needed for the binding; the layout only supplies names and shapes.
        kernels=[
            kernel_layout(k, lambda e: "")
            for k in kernels
            if tuple(i.name for i in k.inputs) == BINDING_INPUTS
        ],
    )
    return {f"python/{module}.c": text}

"""CPython extension backend: a thin binding of the generated C kernels.

Calling C through ctypes costs 1.5-5 us per call whatever the C does; a CPython extension
with ``METH_FASTCALL`` and NumPy's C API costs a fraction of that and offers batched calls.
Every kernel is bound (kinematics and dynamics), and forward dynamics when the robot has it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from symkin.emit.layout import InputLayout, kernel_layout
from symkin.emit.render import forward_dynamics_context, preamble_lines, render
from symkin.errors import SymkinError
from symkin.kernels import Kernel
from symkin.robot import Robot

NUMPY_TYPES = {"double": "NPY_FLOAT64", "float": "NPY_FLOAT32"}
# The forward dynamics' derivative matrices, after ddq, as every backend names them.
FD_DERIVATIVES = ("dddq_dq", "dddq_ddq", "dddq_dtau")


@dataclass(frozen=True)
class Binding:
    """One Python function: its per-state inputs, the parameter vector it takes after ``p``
    (``pi``, the file's missing inertial data, or ``delta``, the barycentric parameters of the
    identification kernels; size 0: none), its outputs.

    ``batched`` kernels have a ``<robot>_<name>_batch`` C entry point; forward dynamics has
    none and is looped over the states in the binding.
    """

    name: str
    description: str
    states: tuple[str, ...]
    state_sizes: tuple[int, ...]
    pi_size: int
    outputs: tuple[tuple[str, tuple[int, ...]], ...]
    batched: bool = True
    if_not_finite: str = ""  # the error raised when an output is NaN or infinite
    pi_name: str = "pi"

    @property
    def takes_pi(self) -> bool:
        return self.pi_size > 0

    @property
    def signature(self) -> str:
        extra = f", {self.pi_name}=None" if self.takes_pi else ""
        return f"{self.name}({', '.join(self.states)}, p=None{extra})"


def extension_name(robot: Robot) -> str:
    return f"{robot.name}_ext"


def _vector_after_p(name: str, inputs: Sequence[InputLayout]) -> InputLayout | None:
    """The one shared input besides ``p`` (``pi`` or ``delta``), if any: the binding's
    signature has room for one, so a kernel with two is refused, not half bound."""
    vectors = [i for i in inputs if not i.per_state and i.name != "p"]
    if len(vectors) > 1:
        names = ", ".join(i.name for i in vectors)
        raise SymkinError(
            f"kernel {name} takes {len(vectors)} vectors besides p ({names}); the Python "
            "extension binds one"
        )
    return vectors[0] if vectors else None


def bindings(robot: Robot, kernels: tuple[Kernel, ...]) -> list[Binding]:
    """The functions of the extension, in the order of the kernels."""
    result = []
    for kernel in kernels:
        # Printing is not needed for the binding; the layout only supplies names and shapes.
        layout = kernel_layout(kernel, lambda e: "")
        vector = _vector_after_p(kernel.name, layout.inputs)
        result.append(
            Binding(
                name=layout.name,
                description=layout.description,
                states=tuple(i.name for i in layout.inputs if i.per_state),
                state_sizes=tuple(i.size for i in layout.inputs if i.per_state),
                pi_size=vector.size if vector else 0,
                outputs=tuple((o.name, o.numpy_shape) for o in layout.outputs),
                pi_name=vector.name if vector else "pi",
            )
        )
    forward = forward_dynamics_context(kernels)
    if forward is None:
        return result
    n = robot.dof
    composed = [("forward_dynamics", "forward dynamics ddq = M^-1 (tau - c - G - F)", ())]
    # The forward dynamics' texts are in generated/: keep them as they are.
    if forward["derivatives"]:
        matrices = tuple((name, (n, n)) for name in FD_DERIVATIVES)
        what = "ddq and d ddq/dq, d ddq/ddq, d ddq/dtau = M^-1"
        composed.append(("forward_dynamics_derivatives", what, matrices))
    for name, description, more in composed:
        result.append(
            Binding(
                name=name,
                description=f"{description} (Cholesky)",
                states=("q", "dq", "tau"),
                state_sizes=(robot.dof,) * 3,
                pi_size=forward["pi"],
                outputs=(("ddq", (n,)), *more),
                # forward_dynamics has no batched C entry point: the binding loops over states.
                batched=bool(more),
                if_not_finite="ddq is not finite: M(q) is not positive definite there "
                "(non-physical inertial data?) or an input is not finite",
            )
        )
    if forward["elastic"]:
        result.append(
            Binding(
                name="elastic_forward_dynamics",
                description="elastic-joint forward dynamics (ddq, ddtheta) (Spong's model)",
                states=("q", "dq", "theta", "tau"),
                state_sizes=(robot.dof,) * 4,
                pi_size=forward["pi"],
                outputs=(("ddq", (robot.dof,)), ("ddtheta", (robot.dof,))),
                batched=False,
                if_not_finite="ddq or ddtheta is not finite: M(q) is not positive definite "
                "there or an input is not finite",
            )
        )
    return result


def emit_python_extension(
    robot: Robot,
    kernels: tuple[Kernel, ...],
    precision: str = "double",
    flags: Sequence[str] = (),
    ik: bool = False,
) -> dict[str, str]:
    """``{"python/<robot>_ext.c": source}``; it includes ``../c/<robot>.h``.

    With ``ik``, the module also binds the generated damped-least-squares IK as ``ik(...)``
    (``templates/python/ik_binding.c.j2``); it then includes ``../c/<robot>_ik.h`` and must be
    compiled with ``c/<robot>_ik.c`` (:func:`symkin.emit.ik_c.emit_ik_c`), which needs the
    ``fk_jacobian`` kernel.
    """
    module = extension_name(robot)
    functions = bindings(robot, kernels)
    # Every dynamics kernel takes the same inertial symbols pi (see kernel.dynamics_inputs).
    inertial = next((i for k in kernels for i in k.inputs if i.name == "pi"), None)
    text = render(
        "python/module.c.j2",
        preamble=preamble_lines(robot, kernels, f"Python binding ({precision})", flags),
        module=module,
        robot=robot.name,
        prefix=robot.name,
        macro=robot.name.upper(),
        header=f"{robot.name}.h",
        real=precision,
        npy_type=NUMPY_TYPES[precision],
        dof=robot.dof,
        parameter_names=[n for n, _ in robot.parameters],
        has_parameters=bool(robot.parameters),
        inertial_count=len(inertial.symbols) if inertial else 0,
        barycentric=any(f.pi_name == "delta" for f in functions),
        bindings=functions,
        max_outputs=max(len(f.outputs) for f in functions),
        # At least 3 (q, dq, tau of forward dynamics) so rigid robots' files stay as they were.
        max_states=max(3, *(len(f.states) for f in functions)),
        ik=ik,
        ik_header=f"{robot.name}_ik.h",
    )
    return {f"python/{module}.c": text}

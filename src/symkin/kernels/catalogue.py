"""The catalogue of kernels a robot gets: kinematics, points fixed in links, dynamics.

Each kernel is built from the derived :class:`~symkin.derive.Model`; the backends print them
all the same way.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

import sympy as sp

from symkin.derive import Model
from symkin.derive.budget import NOT_SQUARE, OVER_BUDGET
from symkin.derive.dynamics import link_inertial_data
from symkin.derive.jacobians import rows_from_names
from symkin.kernels import units
from symkin.kernels.elastic import elastic_kernels
from symkin.kernels.numeric_determinant import (
    numeric_determinant_kernels,
    numeric_manipulability_kernel,
)
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel, KernelInput, kernel_from_outputs


def state_inputs(model: Model, *rates: str) -> tuple[KernelInput, ...]:
    """``q``, the chosen rates (``dq``, ``ddq``), then the parameters ``p`` in file order."""
    descriptions = {
        "dq": (model.dq, "joint velocities (rad/s or m/s)"),
        "ddq": (model.ddq, "joint accelerations (rad/s^2 or m/s^2)"),
    }
    inputs = [KernelInput("q", model.q, "joint positions (rad or m)")]
    inputs += [KernelInput(r, *descriptions[r]) for r in rates]
    names = ", ".join(n for n, _ in model.robot.parameters) or "none"
    described = f"parameters ({names}; {units.PARAMETERS})"
    inputs.append(KernelInput("p", model.robot.parameter_symbols, described))
    return tuple(inputs)


def shortest_kernel(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    outputs_by_form: Sequence[Sequence[tuple[str, sp.MatrixBase, str]]],
) -> Kernel:
    """The kernel with the fewest operations among equivalent forms of the same outputs.

    The contracted form wins on short chains (``cos(q1 + q2)``), the raw product form on long
    ones (a 7-DOF Jacobian expanded is ten times longer than its product form after CSE).
    Ties go to the first form.  The last form (the product form, cheapest to build) is built
    first, and a form whose :func:`_products_lower_bound` already exceeds the best count so far
    is not built: on a generic arm the expanded form's CSE costs seconds and cannot win.
    """
    candidates: dict[int, Kernel] = {}
    for index in reversed(range(len(outputs_by_form))):
        outputs = outputs_by_form[index]
        # A form equal to one built already (no readable form was derived) costs no new CSE.
        twin = next((i for i in candidates if _same(outputs_by_form[i], outputs)), None)
        if twin is not None:
            candidates[index] = candidates[twin]
            continue
        best = min((k.operation_counts["total"] for k in candidates.values()), default=None)
        if best is not None and _products_lower_bound(outputs) > best:
            continue
        candidates[index] = kernel_from_outputs(name, description, inputs, outputs)
    return candidates[min(candidates, key=lambda i: (candidates[i].operation_counts["total"], i))]


def _same(
    first: Sequence[tuple[str, sp.MatrixBase, str]],
    second: Sequence[tuple[str, sp.MatrixBase, str]],
) -> bool:
    """Whether two forms' outputs are the same expressions (structural equality)."""
    return all(a[1] == b[1] for a, b in zip(first, second, strict=True))


def _products_lower_bound(outputs: Sequence[tuple[str, sp.MatrixBase, str]]) -> int:
    """Fewest operations any CSE of ``outputs`` can take: one multiplication per distinct
    product among the terms of the entries (coefficients aside).  ``sympy.cse`` shares equal
    subexpressions but never factors, so each distinct product is formed at least once.
    """
    products = {
        term.as_coeff_Mul()[1]
        for _, matrix, *_ in outputs
        for entry in matrix
        for term in sp.Add.make_args(entry)
    }
    return sum(1 for product in products if product.is_Mul)


def kinematics_kernels(model: Model) -> tuple[Kernel, ...]:
    """The kinematics kernels of one robot, in a fixed order: :func:`pose_kernels` and, when
    the task Jacobian is square, ``det`` and ``manipulability`` (a redundant arm:
    ``manipulability`` alone)."""
    kernels = pose_kernels(model)
    jacobian = next(k for k in kernels if k.name == "jacobian")
    return kernels + _determinant_kernels(model, state_inputs(model), jacobian)


def pose_kernels(model: Model, names: Collection[str] | None = None) -> tuple[Kernel, ...]:
    """``fk`` (T), ``position`` (tool position), ``jacobian`` (geometric, 6 x n),
    ``position_jacobian`` (dp/dq, 3 x n) and ``fk_jacobian`` (T and J in one pass, the kernel
    controllers call), or those of them in ``names``; no determinant.

    Each comes from the simplified or the raw product form of the model, whichever is shorter.
    A chain without a readable form (an unsimplified model, or a contraction over its budget)
    gets the link-by-link named form of :mod:`symkin.derive.named_pose` instead, with dp/dq as
    the Jacobian's linear rows (the same values): on a generic 6R its kernels have 252, 288 and
    319 operations (fk, jacobian, fk_jacobian) where the product form's CSE gave 484, 712 and
    879, and a generic 12R's Jacobian kernel takes 0.3 s instead of 34 s of CPU.
    """
    specs = _pose_specs(model)
    kernels = {
        "fk": ("forward kinematics", ("T",)),
        "position": ("tool position", ("p",)),
        "jacobian": ("geometric Jacobian", ("J",)),
        "position_jacobian": ("analytic position Jacobian", ("Jp",)),
        "fk_jacobian": ("forward kinematics and Jacobian", ("T", "J")),
    }
    chosen = [(k, v) for k, v in kernels.items() if names is None or k in names]
    inputs = state_inputs(model)
    if not model.kinematics.simplified:
        pose = model.named_pose
        matrices = {
            "T": pose.forward_kinematics,
            "p": pose.forward_kinematics[:3, 3],
            "J": pose.geometric_jacobian,
            "Jp": pose.geometric_jacobian[:3, :],
        }
        return tuple(
            kernel_from_assignments(
                name,
                description,
                inputs,
                pose.assignments,
                [_output(specs, k, matrices[k]) for k in keys],
            )
            for name, (description, keys) in chosen
        )
    forms = (model,) if model.product_form is model else (model, model.product_form)
    getters = {
        "T": lambda m: m.forward_kinematics,
        "p": lambda m: m.tool_position,
        "J": lambda m: m.geometric_jacobian,
        "Jp": lambda m: m.position_jacobian,
    }
    return tuple(
        shortest_kernel(
            name,
            description,
            inputs,
            [[_output(specs, k, getters[k](form)) for k in keys] for form in forms],
        )
        for name, (description, keys) in chosen
    )


def _pose_specs(model: Model) -> dict[str, tuple[str, str, str, str]]:
    """Name, description, kind and units of the pose kernels' outputs ``T, p, J, Jp``."""
    n = model.robot.dof
    return {
        "T": ("T", "pose of the tool in the base frame (4x4)", "matrix", units.POSE),
        "p": ("p_tool", "tool position in the base frame (3x1)", "vector", units.POSITION),
        "J": (
            "J",
            f"geometric Jacobian (6x{n}, rows x y z wx wy wz, base frame)",
            "matrix",
            units.jacobian(model.robot, angular=True),
        ),
        "Jp": ("Jp", f"dp/dq (3x{n})", "matrix", units.jacobian(model.robot, angular=False)),
    }


def _output(
    specs: dict[str, tuple[str, str, str, str]], key: str, matrix: sp.MatrixBase
) -> tuple[str, sp.MatrixBase, str, str, str]:
    name, description, kind, unit = specs[key]
    return (name, matrix, description, kind, unit)


def _determinant_kernels(
    model: Model, inputs: Sequence[KernelInput], jacobian: Kernel
) -> tuple[Kernel, ...]:
    """``det`` and ``manipulability`` of the task Jacobian when it is square: the closed form,
    or without one (over budget, switched off) the numeric fallback; for a redundant arm
    (fewer task rows than joints) ``manipulability`` alone, computed numerically."""
    form = model.determinant_form()
    if form.status == NOT_SQUARE:
        indices = rows_from_names(model.task_rows)
        if len(indices) > model.robot.dof:
            return ()
        unit = units.manipulability(model.robot, model.task_rows)
        rows_text = ", ".join(model.task_rows)
        return (numeric_manipulability_kernel(jacobian, indices, rows_text, unit),)
    rows = ", ".join(model.task_rows)
    unit = units.determinant(model.robot, model.task_rows)
    if not form.found:
        reason = (
            "no closed form within the budget"
            if form.status == OVER_BUDGET
            else ("closed forms switched off")
        )
        indices = rows_from_names(model.task_rows)
        return numeric_determinant_kernels(jacobian, indices, rows, unit, reason)
    determinant = form.value
    return (
        kernel_from_outputs(
            "det",
            f"determinant of the task Jacobian (rows {rows})",
            inputs,
            [("det", sp.Matrix([[determinant]]), "det J", "scalar", unit)],
        ),
        kernel_from_outputs(
            "manipulability",
            "Yoshikawa manipulability of the task Jacobian (|det J| when square)",
            inputs,
            [("mu", sp.Matrix([[sp.Abs(determinant)]]), "sqrt(det(J J^T))", "scalar", unit)],
        ),
    )


def point_kernels(
    model: Model, points: Sequence[tuple[int, Sequence[float]]]
) -> tuple[Kernel, ...]:
    """``point1, point2, ...``: position, velocity and acceleration of points fixed in links
    (the link-by-link recursion of :class:`~symkin.derive.PointMotion`), each point given as
    ``(link, (x, y, z))`` in the link's frame."""
    kernels = []
    for k, (link, point) in enumerate(points, start=1):
        motion = model.point_motion(link, point)
        position, velocity, acceleration = motion.outputs
        where = f"({', '.join(f'{c:g}' for c in point)}) in frame {link}"
        kernels.append(
            kernel_from_assignments(
                f"point{k}",
                f"motion of the point {where}",
                state_inputs(model, "dq", "ddq"),
                motion.assignments,
                [
                    ("p_point", position, "position, base frame", "vector", units.POSITION),
                    ("v_point", velocity, "velocity, base frame", "vector", units.VELOCITY),
                    (
                        "a_point",
                        acceleration,
                        "acceleration, base frame",
                        "vector",
                        units.ACCELERATION,
                    ),
                ],
            )
        )
    return tuple(kernels)


def cse_engine(model: Model) -> str:
    """Whose CSE the dynamics and statics kernels of ``model`` use (see
    :func:`~symkin.kernels.passes.kernel_from_assignments`): SymPy's for an arm with a readable
    form (every catalogue robot: their operation counts are SymPy's), SymEngine's for an arm
    without one (a generic arm, where SymPy's CSE was half of the derivation: on a generic 6R
    the dynamics and statics kernels take about half the time for 0.5 to 9 % more operations,
    Christoffel C 5,946 -> 5,977)."""
    return "sympy" if model.kinematics.simplified else "symengine"


def inertial_symbols(model: Model) -> tuple[sp.Symbol, ...]:
    """Symbols of the inertial data the robot file leaves out (``m1, cx1, ..., iyz1, m2, ...``)."""
    symbols: list[sp.Symbol] = []
    for i, joint in enumerate(model.robot.joints):
        if joint.link is None:
            link = link_inertial_data(model.robot, i)
            symbols += [link.mass, *link.com, *link.inertia]
    return tuple(symbols)


def dynamics_inputs(model: Model, *rates: str) -> tuple[KernelInput, ...]:
    """:func:`state_inputs`, then the inertial symbols ``pi`` the robot file leaves out."""
    inputs = list(state_inputs(model, *rates))
    inertial = inertial_symbols(model)
    if inertial:
        names = ", ".join(s.name for s in inertial)
        described = f"inertial parameters ({names}; {units.INERTIAL})"
        inputs.append(KernelInput("pi", inertial, described))
    return tuple(inputs)


def _mass_matrix_bias(model: Model, mass_unit: str, force_unit: str) -> Kernel:
    """``M`` and ``bias = tau(q, dq, 0) = C dq + G + F`` in one kernel, for forward dynamics:
    one CSE over the mass-matrix recursion and the torque recursion with its ``ddq`` terms
    dropped, so the two share sin, cos and their common products."""
    n = model.robot.dof
    dynamics = model.newton_euler
    assignments, torque = model.inverse_dynamics_recursion
    at_rest = {a: sp.Integer(0) for a in dynamics.ddq}
    at_rest_assignments = tuple((s, e.xreplace(at_rest)) for s, e in assignments)
    return kernel_from_assignments(
        "mass_matrix_bias",
        "mass matrix and bias torques (forward dynamics)",
        dynamics_inputs(model, "dq"),
        dynamics.assignments + at_rest_assignments,
        [
            ("M", dynamics.mass_matrix, f"M(q) ({n}x{n})", "matrix", mass_unit),
            (
                "bias",
                torque.xreplace(at_rest),
                f"bias = C dq + G + F, the torques at ddq = 0 ({n}x1)",
                "vector",
                force_unit,
            ),
        ],
        cse_engine(model),
    )


def _dynamics_steps(
    model: Model,
) -> list[tuple[str, str, tuple[str, ...], str, sp.MatrixBase, str]]:
    """``(kernel, description, rates, output, matrix, output description)`` of the kernels
    read off the Newton–Euler dynamics."""
    n = model.robot.dof
    dynamics = model.newton_euler
    return [
        ("mass_matrix", "mass matrix", ("",), "M", dynamics.mass_matrix, f"M(q) ({n}x{n})"),
        ("gravity", "gravity torques", ("",), "G", dynamics.gravity_vector, f"G(q) ({n}x1)"),
        (
            "coriolis",
            "Coriolis and centrifugal torques",
            ("dq",),
            "c",
            dynamics.coriolis_vector,
            f"c = C(q, dq) dq ({n}x1)",
        ),
        (
            "coriolis_matrix",
            "Coriolis matrix (Christoffel symbols)",
            ("dq",),
            "C",
            dynamics.coriolis_matrix,
            f"C(q, dq) ({n}x{n}), dM/dt - 2C skew-symmetric",
        ),
    ]


def dynamics_kernels(model: Model, coriolis_matrix: bool = True) -> tuple[Kernel, ...]:
    """``mass_matrix``, ``gravity``, ``coriolis`` (c = C dq), ``coriolis_matrix`` and
    ``inverse_dynamics`` (tau, with friction and rotor inertia) from recursive Newton–Euler;
    ``coriolis_matrix=False`` leaves out ``C``, the longest kernel, which the solvers never use."""
    n = model.robot.dof
    dynamics = model.newton_euler
    torque_assignments, torque = model.inverse_dynamics_recursion
    steps = _dynamics_steps(model)
    force = units.generalized_force(model.robot)
    unit = {"M": units.mass_matrix(model.robot), "G": force, "c": force}
    unit["C"] = units.coriolis_matrix(model.robot)
    engine = cse_engine(model)
    kernels = [
        kernel_from_assignments(
            name,
            description,
            dynamics_inputs(model, *(r for r in rates if r)),
            dynamics.assignments,
            [
                (
                    output,
                    matrix,
                    output_description,
                    "vector" if output in ("G", "c") else "matrix",
                    unit[output],
                )
            ],
            engine,
        )
        for name, description, rates, output, matrix, output_description in steps
        if coriolis_matrix or name != "coriolis_matrix"
    ]
    kernels.append(_mass_matrix_bias(model, unit["M"], force))
    kernels.append(
        kernel_from_assignments(
            "inverse_dynamics",
            "inverse dynamics",
            dynamics_inputs(model, "dq", "ddq"),
            torque_assignments,
            [("tau", torque, f"tau = M ddq + C dq + G + F ({n}x1)", "vector", force)],
            engine,
        )
    )
    return (*kernels, *elastic_kernels(model, dynamics_inputs(model, "dq", "ddq")))

"""Kernels: named inputs, named outputs and one common-subexpression elimination.

A :class:`Kernel` is what every backend prints.  The CSE runs once, here, so the NumPy, C and
CasADi versions of a kernel share the same intermediates and the same operation counts.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from symkin.derive import Model
from symkin.derive.dynamics import link_inertial_data
from symkin.robot import unused_prefix

# Kinds reported in operation counts, from SymPy's count_ops(visual=True) names.
OPERATION_KINDS: Mapping[str, tuple[str, ...]] = {
    "additions": ("ADD", "SUB"),
    "multiplications": ("MUL", "NEG"),
    "divisions": ("DIV",),
    "trig": ("SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ATAN2"),
    "sqrt": ("SQRT",),
    "powers": ("POW",),
}


@dataclass(frozen=True)
class KernelInput:
    """A vector input: its name in generated code and its symbols in order."""

    name: str
    symbols: tuple[sp.Symbol, ...]
    description: str


@dataclass(frozen=True)
class KernelOutput:
    """A matrix output (row-major in C), expressed in the kernel's intermediates."""

    name: str
    matrix: sp.ImmutableMatrix
    description: str
    # "matrix", "vector" or "scalar": how array backends shape it (a 1-DOF mass matrix is a
    # 1x1 matrix, a 1-DOF gravity vector has one entry, a determinant is a scalar).
    kind: str = "matrix"

    @property
    def shape(self) -> tuple[int, int]:
        return self.matrix.shape

    @property
    def size(self) -> int:
        return self.matrix.rows * self.matrix.cols


@dataclass(frozen=True)
class Kernel:
    """One function of generated code: ``outputs = f(inputs)`` after CSE."""

    name: str
    description: str
    inputs: tuple[KernelInput, ...]
    outputs: tuple[KernelOutput, ...]
    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]

    @cached_property
    def operation_counts(self) -> dict[str, int]:
        """Operations by kind over all assignments and outputs, plus ``total``."""
        expressions = [e for _, e in self.assignments]
        expressions += [e for output in self.outputs for e in output.matrix]
        return count_operations(expressions)


def _sqrt_count(expr: sp.Expr) -> int:
    return sum(
        1
        for node in sp.preorder_traversal(expr)
        if node.is_Pow and node.exp in (sp.S.Half, -sp.S.Half)
    )


def count_operations(expressions: Sequence[sp.Expr]) -> dict[str, int]:
    """Arithmetic operations by kind (SymPy's ``count_ops``, square roots split from powers)."""
    raw: Counter[str] = Counter()
    for expr in expressions:
        visual = sp.count_ops(expr, visual=True)
        for term in sp.Add.make_args(visual):
            coefficient, symbol = term.as_coeff_Mul()
            if isinstance(symbol, sp.Symbol):
                raw[symbol.name] += int(coefficient)
        square_roots = _sqrt_count(expr)
        raw["SQRT"] += square_roots
        raw["POW"] -= square_roots
    counts = {kind: sum(raw[name] for name in names) for kind, names in OPERATION_KINDS.items()}
    counts["total"] = sum(counts.values())
    return counts


def _intermediate_prefix(expressions: Sequence[sp.Expr]) -> str:
    """``t`` for intermediates ``t0, t1, ...``, unless an input is already named ``t<k>``."""
    return unused_prefix("t", (s.name for e in expressions for s in e.free_symbols))


def kernel_from_outputs(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    outputs: Sequence[tuple[str, sp.MatrixBase, str]],
) -> Kernel:
    """Run one CSE over all outputs and package the result.

    The intermediates are numbered deterministically in the order SymPy's ``cse`` emits them.
    """
    matrices = [sp.ImmutableMatrix(matrix) for _, matrix, *_ in outputs]
    prefix = _intermediate_prefix([e for m in matrices for e in m])
    assignments, reduced = sp.cse(matrices, symbols=sp.numbered_symbols(prefix, real=True))
    kernel_outputs = tuple(
        KernelOutput(spec[0], sp.ImmutableMatrix(matrix), *spec[2:])
        for spec, matrix in zip(outputs, reduced, strict=True)
    )
    return Kernel(name, description, tuple(inputs), kernel_outputs, tuple(assignments))


def state_inputs(model: Model, *rates: str) -> tuple[KernelInput, ...]:
    """``q``, the chosen rates (``dq``, ``ddq``), then the parameters ``p`` in file order."""
    descriptions = {
        "dq": (model.dq, "joint velocities (rad/s or m/s)"),
        "ddq": (model.ddq, "joint accelerations (rad/s^2 or m/s^2)"),
    }
    inputs = [KernelInput("q", model.q, "joint positions (rad or m)")]
    inputs += [KernelInput(r, *descriptions[r]) for r in rates]
    names = ", ".join(n for n, _ in model.robot.parameters) or "none"
    inputs.append(KernelInput("p", model.robot.parameter_symbols, f"parameters ({names})"))
    return tuple(inputs)


def _shortest_kernel(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    outputs_by_form: Sequence[Sequence[tuple[str, sp.MatrixBase, str]]],
) -> Kernel:
    """The kernel with the fewest operations among equivalent forms of the same outputs.

    The contracted form wins on short chains (``cos(q1 + q2)``), the raw product form on long
    ones (a 7-DOF Jacobian expanded is ten times longer than its product form after CSE).
    Ties go to the first form.
    """
    candidates = [kernel_from_outputs(name, description, inputs, o) for o in outputs_by_form]
    return min(candidates, key=lambda k: k.operation_counts["total"])


def kinematics_kernels(model: Model) -> tuple[Kernel, ...]:
    """The kinematics kernels of one robot, in a fixed order.

    ``fk`` (T), ``position`` (tool position), ``jacobian`` (geometric, 6 x n),
    ``position_jacobian`` (dp/dq, 3 x n), ``fk_jacobian`` (T and J in one pass, the kernel
    controllers call) and, when the task Jacobian is square, ``det`` and ``manipulability``.
    Each comes from the simplified or the raw product form of the model, whichever is shorter.
    """
    inputs = state_inputs(model)
    n = model.robot.dof
    forms = (model, model.product_form)

    def outputs(*keys: str) -> list[list[tuple[str, sp.MatrixBase, str]]]:
        table = {
            "T": lambda m: ("T", m.forward_kinematics, "pose of the tool in the base frame (4x4)"),
            "p": lambda m: (
                "p_tool",
                m.tool_position,
                "tool position in the base frame (3x1)",
                "vector",
            ),
            "J": lambda m: (
                "J",
                m.geometric_jacobian,
                f"geometric Jacobian (6x{n}, rows x y z wx wy wz, base frame)",
            ),
            "Jp": lambda m: ("Jp", m.position_jacobian, f"dp/dq (3x{n})"),
        }
        return [[table[key](form) for key in keys] for form in forms]

    kernels = [
        _shortest_kernel("fk", "forward kinematics", inputs, outputs("T")),
        _shortest_kernel("position", "tool position", inputs, outputs("p")),
        _shortest_kernel("jacobian", "geometric Jacobian", inputs, outputs("J")),
        _shortest_kernel("position_jacobian", "analytic position Jacobian", inputs, outputs("Jp")),
        _shortest_kernel(
            "fk_jacobian", "forward kinematics and Jacobian", inputs, outputs("T", "J")
        ),
    ]
    determinant = model.determinant()
    if determinant is not None:
        rows = ", ".join(model.task_rows)
        kernels.append(
            kernel_from_outputs(
                "det",
                f"determinant of the task Jacobian (rows {rows})",
                inputs,
                [("det", sp.Matrix([[determinant]]), "det J", "scalar")],
            )
        )
        kernels.append(
            kernel_from_outputs(
                "manipulability",
                "Yoshikawa manipulability of the task Jacobian (|det J| when square)",
                inputs,
                [("mu", sp.Matrix([[sp.Abs(determinant)]]), "sqrt(det(J J^T))", "scalar")],
            )
        )
    return tuple(kernels)


def point_kernels(
    model: Model, points: Sequence[tuple[int, Sequence[float]]]
) -> tuple[Kernel, ...]:
    """``point1, point2, ...``: position, velocity and acceleration of points fixed in links
    (U-matrix method), each point given as ``(link, (x, y, z))`` in the link's frame."""
    kernels = []
    for k, (link, point) in enumerate(points, start=1):
        motion = model.point_motion(link, point)
        where = f"({', '.join(f'{c:g}' for c in point)}) in frame {link}"
        kernels.append(
            kernel_from_outputs(
                f"point{k}",
                f"motion of the point {where}",
                state_inputs(model, "dq", "ddq"),
                [
                    ("p_point", motion.position, "position, base frame", "vector"),
                    ("v_point", motion.velocity, "velocity, base frame", "vector"),
                    ("a_point", motion.acceleration, "acceleration, base frame", "vector"),
                ],
            )
        )
    return tuple(kernels)


def kernel_from_assignments(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    outputs: Sequence[tuple[str, sp.MatrixBase, str]],
) -> Kernel:
    """A kernel from named intermediates that already share their subexpressions.

    Keeps only the intermediates the outputs need (in definition order) and renames them
    ``t0, t1, ...`` so the text does not depend on how many were recorded before.
    """
    matrices = [sp.ImmutableMatrix(m) for _, m, *_ in outputs]
    kept, matrices = _shared_subexpressions(_needed(list(assignments), matrices), matrices)
    kept, matrices = _summands_inlined(*_without_aliases(kept, matrices))
    # Factoring makes new sums, some the negatives of others.
    kept, matrices = _without_aliases(*_common_factors_out(kept, matrices))
    kept, matrices = _signs_absorbed(kept, matrices)
    prefix = _intermediate_prefix([e for _, e in kept] + [e for m in matrices for e in m])
    renaming = {old: sp.Symbol(f"{prefix}{k}", real=True) for k, (old, _) in enumerate(kept)}
    renamed = tuple((renaming[s], e.xreplace(renaming)) for s, e in kept)
    kernel_outputs = tuple(
        KernelOutput(spec[0], matrix.xreplace(renaming), *spec[2:])
        for spec, matrix in zip(outputs, matrices, strict=True)
    )
    return Kernel(name, description, tuple(inputs), kernel_outputs, renamed)


def _summands_inlined(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Substitute an intermediate used once, as a plain term of a sum (``tau1 = 0.78*ddq1 +
    t100``), so like terms merge (``t100 = 1.88*ddq1 + ...``).  Nowhere else: a number times
    an inlined sum would be distributed, costing multiplications."""
    uses: Counter[sp.Symbol] = Counter()
    expressions = [e for _, e in assignments] + [e for m in matrices for e in m]
    for expr in expressions:
        uses.update(expr.free_symbols)
    definitions = dict(assignments)

    def inlined(expr: sp.Expr) -> sp.Expr:
        if not expr.is_Add:
            return expr
        terms = [
            definitions[t] if t in definitions and uses[t] == 1 else t
            for t in sp.Add.make_args(expr)
        ]
        return sp.Add(*terms)

    substituted = [(s, inlined(e)) for s, e in assignments]
    matrices = [m.applyfunc(inlined) for m in matrices]
    return _needed(substituted, matrices), matrices


def _signs_absorbed(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Name ``a + b`` instead of ``-a - b`` and ``a*b`` instead of ``-a*b`` (one negation
    fewer) and let the uses take the sign: ``x - t`` costs what ``x + t`` does.  Kept only
    where the whole kernel gets shorter."""
    flipped: dict[sp.Symbol, sp.Expr] = {}
    result = []
    for symbol, expr in assignments:
        expr = expr.xreplace(flipped)
        if (expr.is_Add and all(t.could_extract_minus_sign() for t in expr.args)) or (
            expr.is_Mul and expr.as_coeff_Mul()[0] < 0
        ):
            flipped[symbol] = -symbol
            expr = -expr
        result.append((symbol, expr))
    if not flipped:
        return assignments, matrices
    flipped_matrices = [m.xreplace(flipped) for m in matrices]
    before = [e for _, e in assignments] + [e for m in matrices for e in m]
    after = [e for _, e in result] + [e for m in flipped_matrices for e in m]
    # Only the expressions that changed are counted (xreplace returns the same object else).
    changed = [k for k, (old, new) in enumerate(zip(before, after, strict=True)) if old is not new]
    saving = (
        count_operations([before[k] for k in changed])["total"]
        - count_operations([after[k] for k in changed])["total"]
    )
    return (result, flipped_matrices) if saving > 0 else (assignments, matrices)


def _needed(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> list[tuple[sp.Symbol, sp.Expr]]:
    """The intermediates the outputs need, in definition order (dead ones dropped)."""
    needed: set[sp.Symbol] = set().union(*(m.free_symbols for m in matrices))
    kept = []
    for symbol, expr in reversed(assignments):
        if symbol in needed:
            kept.append((symbol, expr))
            needed |= expr.free_symbols
    return kept[::-1]


def _common_factors_out(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Take a factor shared by terms of a sum out of it: ``a*x + a*y + z`` becomes
    ``a*u + z`` with a new intermediate ``u = x + y``, one multiplication fewer.

    CSE shares whole subexpressions but never factors, and the recursions leave many such
    sums (``0.00288*t45 + 0.00288*t58``).  The inner sum gets a name of its own because
    SymPy would distribute a number over a sum again.
    """
    counter = iter(range(10**9))
    result: list[tuple[sp.Symbol, sp.Expr]] = []

    def factored(expr: sp.Expr) -> sp.Expr:
        if not expr.is_Add:
            return expr
        terms = sp.Add.make_args(expr)
        occurrences: Counter[sp.Expr] = Counter()
        for term in terms:
            occurrences.update(_factors(term))
        if not occurrences:
            return expr
        factor, count = max(occurrences.items(), key=lambda kv: (kv[1], sp.default_sort_key(kv[0])))
        if count < 2:
            return expr
        inside = [_divided(t, factor) for t in terms if factor in _factors(t)]
        outside = [t for t in terms if factor not in _factors(t)]
        inner = factored(sp.Add(*inside))
        if not inner.is_Atom:
            symbol = sp.Symbol(f"_factor{next(counter)}", real=True)
            result.append((symbol, inner))
            inner = symbol
        return factor * inner + factored(sp.Add(*outside))

    for symbol, expr in assignments:
        result.append((symbol, factored(expr)))
    return result, [m.applyfunc(factored) for m in matrices]


def _factors(term: sp.Expr) -> set[sp.Expr]:
    """The factors of one term of a sum, its coefficient's size among them unless it is 1."""
    coefficient, rest = term.as_coeff_Mul()
    factors = set(sp.Mul.make_args(rest)) - {sp.Integer(1)}
    if not _is_unit(coefficient):
        factors.add(abs(coefficient))
    return factors


def _is_unit(number: sp.Number) -> bool:
    # SymPy 1.13+ holds Float(1.0) != Integer(1); both mean no multiplication here.
    return abs(float(number)) == 1.0


def _divided(term: sp.Expr, factor: sp.Expr) -> sp.Expr:
    """``term / factor`` for a factor of the term, without leaving a ``1.0*`` behind."""
    coefficient, rest = term.as_coeff_Mul()
    if factor.is_Number:
        coefficient = coefficient / factor
    else:
        rest = rest / factor
    if _is_unit(coefficient):
        coefficient = sp.Integer(1 if coefficient > 0 else -1)
    return coefficient * rest


def _without_aliases(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Substitute intermediates that copy a symbol or a number, or an earlier intermediate or
    its negative (``t7 = -t3``; ``t9 = t4 - t2`` after ``t8 = t2 - t4``): CSE does not see
    that ``x`` and ``-x`` share their work, and factoring makes sums CSE never saw."""
    aliases: dict[sp.Symbol, sp.Expr] = {}
    defined: dict[frozenset, sp.Symbol] = {}
    kept = []
    for symbol, expr in assignments:
        expr = expr.xreplace(aliases)
        # Terms as (coefficient, rest) pairs: negating them is cheap, unlike -expr in SymPy.
        terms = [t.as_coeff_Mul() for t in sp.Add.make_args(expr)]
        negated = frozenset((-c, rest) for c, rest in terms)
        if expr.is_Atom or (terms[0][0] == -1 and len(terms) == 1 and terms[0][1].is_Atom):
            aliases[symbol] = expr
        elif frozenset(terms) in defined:
            aliases[symbol] = defined[frozenset(terms)]
        elif negated in defined:
            aliases[symbol] = -defined[negated]
        else:
            defined[frozenset(terms)] = symbol
            kept.append((symbol, expr))
    return kept, [m.xreplace(aliases) for m in matrices]


def _shared_subexpressions(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """One CSE over named intermediates and outputs (``sin(q1)`` once, not per quantity).

    Each new subexpression is placed just before its first use, which is after every
    intermediate it refers to, so the order stays a valid evaluation order.
    """
    expressions = [e for _, e in assignments] + list(matrices)
    found, reduced = sp.cse(expressions, symbols=sp.numbered_symbols("_cse", real=True))
    definitions = dict(found)
    placed: set[sp.Symbol] = set()
    ordered: list[tuple[sp.Symbol, sp.Expr]] = []

    def place(expr: sp.Expr) -> None:
        for symbol in sorted(expr.free_symbols & definitions.keys(), key=sp.default_sort_key):
            if symbol not in placed:
                place(definitions[symbol])
                placed.add(symbol)
                ordered.append((symbol, definitions[symbol]))

    for (symbol, _), expr in zip(assignments, reduced, strict=False):
        place(expr)
        ordered.append((symbol, expr))
    outputs = [sp.ImmutableMatrix(m) for m in reduced[len(assignments) :]]
    for matrix in outputs:
        place(matrix)
    return ordered, outputs


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
        inputs.append(KernelInput("pi", inertial, f"inertial parameters ({names})"))
    return tuple(inputs)


def dynamics_kernels(model: Model) -> tuple[Kernel, ...]:
    """``mass_matrix``, ``gravity``, ``coriolis`` (c = C dq), ``coriolis_matrix`` and
    ``inverse_dynamics`` (tau, with friction and rotor inertia) from recursive Newton–Euler."""
    n = model.robot.dof
    dynamics = model.newton_euler
    torque_assignments, torque = model.inverse_dynamics_recursion
    steps = [
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
    kernels = [
        kernel_from_assignments(
            name,
            description,
            dynamics_inputs(model, *(r for r in rates if r)),
            dynamics.assignments,
            [(output, matrix, output_description, "vector" if output in ("G", "c") else "matrix")],
        )
        for name, description, rates, output, matrix, output_description in steps
    ]
    kernels.append(
        kernel_from_assignments(
            "inverse_dynamics",
            "inverse dynamics",
            dynamics_inputs(model, "dq", "ddq"),
            torque_assignments,
            [("tau", torque, f"tau = M ddq + C dq + G + F ({n}x1)", "vector")],
        )
    )
    return tuple(kernels)

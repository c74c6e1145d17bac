"""The closed-form IK solver's constants as SymPy expressions of the robot's parameters.

:mod:`symkin.solve.ik.closed_form` recognises the joint structure from the numeric DH table and
builds one frozen solver per robot and parameter set, with every constant of the formulas as a
float.  Generated C takes the parameter vector ``p`` at run time, so here each of those
constants is built again, by the same formulas, as an expression of the parameter symbols
(``closed_form_constants`` kernel, computed once per call).  Numbers stay numbers: the PUMA
560's shoulder offset becomes ``-d3``, a 90 degree twist's cosine ``0``.

What does not vary with ``p`` is read from the Python solver object: the family, the kind of
arm, twist signs and joint indices.  A parameter set that changes the structure (a twist, or
a link length set to zero) is not solved by this structure; the FK check in C then drops every
candidate.

Each builder below names the Python function it mirrors; ``docs/ik-closed-form.md`` has the
derivations, and ``tests/test_ik_closed_c.py`` compares the generated C with the Python solver,
solution by solution, at the file's parameter values and at others.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.kernels import Kernel, KernelInput, kernel_from_outputs
from symkin.kernels.ik.closed_form_parallel import ParallelAxesSolver
from symkin.kernels.ik.closed_form_planar import PlanarSolver, planar_links
from symkin.kernels.ik.closed_form_table import chain_from_robot, twist_sign
from symkin.kernels.ik.closed_form_wrist import (
    Arm,
    ArticulatedArm,
    CylindricalArm,
    SphericalArm,
    SphericalWristSolver,
    wrist_centre_in_frame2,
)
from symkin.kernels.ik.plan import closed_form_solver
from symkin.robot import Robot
from symkin.spatial import rot_x, transform_from_rotation_translation, transform_inverse

#: Digits kept when numbers such as ``pi/2`` are turned into literals (C99 has no ``M_PI``).
DIGITS = 17

#: A constant: C field name, value (list of expressions), description for the C comment.
Constant = tuple[str, Sequence[sp.Expr], str]


@dataclass(frozen=True)
class SymbolicChain:
    """:class:`symkin.kernels.ik.closed_form_table.NumericChain` with SymPy entries: standard DH,
    ``T = base A_1 .. A_n tool``, a modified table rewritten the same way."""

    kinds: tuple[str, ...]
    theta: tuple[sp.Expr, ...]
    d: tuple[sp.Expr, ...]
    a: tuple[sp.Expr, ...]
    alpha: tuple[sp.Expr, ...]
    base: sp.Matrix
    tool: sp.Matrix

    @property
    def size(self) -> sp.Expr:
        """``NumericChain.size``: ``max(1, sum |a| + |d| + |base offset| + |tool offset|)``."""
        lengths = sum(sp.Abs(x) for x in (*self.a, *self.d))
        offsets = self.base[:3, 3].norm() + self.tool[:3, 3].norm()
        return sp.Max(1, lengths + offsets)


def _translation_rotation(rotation: sp.Matrix, x: sp.Expr = 0) -> sp.Matrix:
    """``Tx(x) R`` as a 4x4 transform (``Tx(a) Rx(alpha)`` for ``R = Rx(alpha)``)."""
    return transform_from_rotation_translation(rotation, sp.Matrix([x, 0, 0]))


def symbolic_chain(robot: Robot) -> SymbolicChain:
    """Mirror of ``closed_form_table.chain_from_robot`` with the parameters kept as symbols."""
    joints = robot.joints
    theta = tuple(sp.sympify(j.theta) for j in joints)
    d = tuple(sp.sympify(j.d) for j in joints)
    base, tool = sp.Matrix(robot.base), sp.Matrix(robot.tool)
    if robot.convention == "modified":
        first = joints[0]
        base = base @ _translation_rotation(rot_x(sp.sympify(first.alpha)), first.a)
        a = (*(sp.sympify(j.a) for j in joints[1:]), sp.S.Zero)
        alpha = (*(sp.sympify(j.alpha) for j in joints[1:]), sp.S.Zero)
    else:
        a = tuple(sp.sympify(j.a) for j in joints)
        alpha = tuple(sp.sympify(j.alpha) for j in joints)
    return SymbolicChain(tuple(j.type for j in joints), theta, d, a, alpha, base, tool)


def _polar(x: sp.Expr, y: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``closed_form_planar.polar``: ``(length, angle)`` of the vector ``(x, y)``."""
    return sp.sqrt(x**2 + y**2), sp.atan2(y, x)


def _frames(chain: SymbolicChain, tail: sp.Matrix | None) -> list[Constant]:
    """``head_inverse`` (and ``tail_inverse``) where they are not the identity, and ``scale``."""
    constants: list[Constant] = [("scale", [chain.size], "length scale of the robot (>= 1 m)")]
    for name, transform, description in (
        ("head_inverse", chain.base, "base^-1, row-major 4x4"),
        ("tail_inverse", tail, "(Tx(a_n) Rx(alpha_n) tool)^-1, row-major 4x4"),
    ):
        if transform is not None and transform != sp.eye(4):
            constants.append((name, list(transform_inverse(transform)), description))
    return constants


def planar_constants(chain: SymbolicChain, solver: PlanarSolver) -> list[Constant]:
    """The constants of ``closed_form_planar.planar_solver`` as expressions in ``p``."""
    tool = _translation_rotation(rot_x(chain.alpha[-1])) @ chain.tool
    start, offsets, links, gamma = planar_links(chain, tool, sp.S.Zero, sp.cos, sp.sin)
    polar = [_polar(*link) for link in links]
    constants: list[Constant] = [
        ("offsets", offsets, "o_k + gamma_{k-1}: angle offset of each revolute joint"),
        ("link_length", [p[0] for p in polar], "|v_k|: planar links after each revolute joint"),
        ("link_angle", [p[1] for p in polar], "atan2 of v_k"),
        ("start", list(start), "v_0: first revolute axis in the plane"),
    ]
    if len(solver.revolute) == 3:
        constants += [
            ("end_angle", [gamma], "gamma_r: turn after the last revolute joint"),
            ("tool_row", list(tool[0, :3]), "first row of the tool rotation (heading)"),
        ]
    if solver.prismatic is not None:
        constants.append(("z_offset", [sum(chain.d) + tool[2, 3]], "tool z at q_prismatic = 0"))
    return constants + _frames(chain, None)


def _arm_constants(chain: SymbolicChain, arm: Arm, twist2: int) -> list[Constant]:
    """Mirror of ``_articulated``, ``_spherical`` and ``_cylindrical`` in
    ``closed_form_wrist``."""
    a, d = chain.a, chain.d
    if isinstance(arm, ArticulatedArm):
        link2 = _polar(a[1], sp.S.Zero)
        link3 = _polar(a[2], -sp.sin(chain.alpha[2]) * d[3])
        height = d[1] + d[2] + sp.cos(chain.alpha[2]) * d[3]
        return [
            ("d1", [d[0]], "d_1"),
            ("a1", [a[0]], "a_1"),
            ("offset", [-arm.twist1 * height], "wrist centre's distance from the arm's plane"),
            ("link2", list(link2), "(a_2, 0) in polar form (length, angle)"),
            ("link3", list(link3), "(a_3, -sin(alpha_3) d_4) in polar form"),
        ]
    cx, cy, cz = wrist_centre_in_frame2(chain, sp.cos, sp.sin)
    if isinstance(arm, SphericalArm):
        return [
            ("d1", [d[0]], "d_1"),
            ("a1", [a[0]], "a_1"),
            ("offset", [-arm.twist1 * (d[1] + arm.twist2 * cy)], "shoulder offset"),
            ("k", [a[1] + cx], "the reach's distance from the shoulder axis"),
            ("reach_offset", [cz], "lambda - q_3"),
        ]
    c, s = sp.cos(chain.theta[1]), sp.sin(chain.theta[1])
    k = a[1] + cx
    return [
        ("height", [d[0] + d[1] + twist2 * cy], "z of the wrist centre minus q_2"),
        ("g", [a[0] + c * k, s * k], "horizontal wrist centre at zero radial reach"),
        ("e", [s * twist2, -c * twist2], "unit direction of the radial reach"),
        ("reach_offset", [cz], "lambda - q_3"),
    ]


def _twists(chain: SymbolicChain) -> list[Constant]:
    return [
        ("twist_cos", [sp.cos(x) for x in chain.alpha[:5]], "cos(alpha_1) .. cos(alpha_5)"),
        ("twist_sin", [sp.sin(x) for x in chain.alpha[:5]], "sin(alpha_1) .. sin(alpha_5)"),
    ]


def _tail(chain: SymbolicChain) -> sp.Matrix:
    """``Tx(a_6) Rx(alpha_6) tool``, taken off the target (``closed_form_wrist.tail_inverse``)."""
    return _translation_rotation(rot_x(chain.alpha[5]), chain.a[5]) @ chain.tool


def wrist_constants(
    chain: SymbolicChain, solver: SphericalWristSolver, twist2: int
) -> list[Constant]:
    """Mirror of ``closed_form_wrist.spherical_wrist_solver``."""
    return [
        *_arm_constants(chain, solver.arm, twist2),
        *_twists(chain),
        ("theta", list(chain.theta), "theta_i - q_i (revolute) or theta_i (prismatic)"),
        ("d6", [chain.d[5]], "d_6: wrist centre to flange along z_6"),
        *_frames(chain, _tail(chain)),
    ]


def parallel_constants(chain: SymbolicChain, solver: ParallelAxesSolver) -> list[Constant]:
    """Mirror of ``closed_form_parallel.parallel_axes_solver``."""
    t1 = solver.twists[0]
    a, d = chain.a, chain.d
    return [
        ("d1", [d[0]], "d_1"),
        ("a1", [a[0]], "a_1"),
        ("offset", [-t1 * (d[1] + d[2] + d[3])], "-t_1 (d_2 + d_3 + d_4)"),
        ("d5", [d[4]], "d_5"),
        ("d6", [d[5]], "d_6"),
        ("link2", list(_polar(a[1], sp.S.Zero)), "(a_2, 0) in polar form (length, angle)"),
        ("link3", list(_polar(a[2], sp.S.Zero)), "(a_3, 0) in polar form"),
        *_twists(chain),
        ("theta", list(chain.theta), "theta_i - q_i"),
        *_frames(chain, _tail(chain)),
    ]


#: Branch flags each family sets (names and values as in ``ClosedFormSolution.branch``).
ARM_FLAGS = {
    "planar": ("elbow",),
    "articulated": ("shoulder", "elbow", "wrist"),
    "spherical": ("shoulder", "extension", "wrist"),
    "cylindrical": ("extension", "wrist"),
    "parallel": ("shoulder", "elbow", "wrist"),
}
#: Solutions per pose at most: 2 per square root (shoulder, elbow or reach, wrist).
MAX_SOLUTIONS = {"planar": 2, "articulated": 8, "spherical": 8, "cylindrical": 4, "parallel": 8}


@dataclass(frozen=True)
class ClosedFormPlan:
    """What the generated closed-form IK of one robot is made of.

    ``family``: the template, ``"planar"``, ``"wrist"`` or ``"parallel"``; ``arm``: the kind of
    arm, a key of :data:`ARM_FLAGS`; ``structure``: what does not vary with ``p`` (twist signs
    +-1, joint indices), from the Python solver recognised at the file's parameter values (a
    parameter without a value counts as a generic length, as in ``has_closed_form``);
    ``constants``: the kernel computing every other constant from ``p``; ``solver``: that
    Python solver (its ``family`` and ``task``).
    """

    family: str
    arm: str
    structure: dict[str, object]
    constants: Kernel
    solver: PlanarSolver | SphericalWristSolver | ParallelAxesSolver

    @property
    def flags(self) -> tuple[str, ...]:
        return ARM_FLAGS[self.arm]

    @property
    def max_solutions(self) -> int:
        return MAX_SOLUTIONS[self.arm]

    def has(self, name: str) -> bool:
        """True if the constant ``name`` is computed (``head_inverse`` only without an
        identity base, for example)."""
        return any(output.name == name for output in self.constants.outputs)


def _literal_numbers(expr: sp.Expr) -> sp.Expr:
    """Irrational numbers (``pi/2``, ``sqrt(2)/2``) as floats, computed once here rather than
    at run time; rationals, exponents included, stay exact."""
    return sp.sympify(expr).replace(
        lambda e: e.is_number and not e.is_Rational, lambda e: e.evalf(DIGITS)
    )


def _kernel(robot: Robot, constants: list[Constant]) -> Kernel:
    names = ", ".join(n for n, _ in robot.parameters) or "none"
    outputs = [
        (
            name,
            sp.ImmutableMatrix([_literal_numbers(v) for v in values]),
            description,
            "scalar" if len(values) == 1 else "vector",
        )
        for name, values, description in constants
    ]
    return kernel_from_outputs(
        "closed_form_constants",
        "constants of the closed-form IK",
        [KernelInput("p", robot.parameter_symbols, f"parameters ({names})")],
        outputs,
    )


def closed_form_plan(robot: Robot) -> ClosedFormPlan | None:
    """The plan of ``robot``'s generated closed form, or None where
    ``has_closed_form(robot)`` is False."""
    solver = closed_form_solver(robot, None, generic=True)
    if solver is None:
        return None
    chain = symbolic_chain(robot)
    if isinstance(solver, PlanarSolver):
        structure = {"revolute": solver.revolute, "prismatic": solver.prismatic}
        return ClosedFormPlan(
            "planar", "planar", structure, _kernel(robot, planar_constants(chain, solver)), solver
        )
    if isinstance(solver, ParallelAxesSolver):
        t1, t4, t5 = solver.twists
        structure = {"twist1": t1, "twist4": t4, "twist5": t5}
        constants = _kernel(robot, parallel_constants(chain, solver))
        return ClosedFormPlan("parallel", "parallel", structure, constants, solver)
    # The cylindrical arm's solver keeps only vectors derived from sin(alpha_2): the sign comes
    # from the same generic numeric table the recogniser read.
    twist2 = twist_sign(chain_from_robot(robot, None, generic=True).alpha[1])
    arm = solver.arm
    kind = {ArticulatedArm: "articulated", SphericalArm: "spherical", CylindricalArm: "cylindrical"}
    structure = {
        "twist1": getattr(arm, "twist1", 0),
        "twist2": twist2,
        "twist4": solver.wrist.twist4,
        "twist5": solver.wrist.twist5,
    }
    return ClosedFormPlan(
        "wrist",
        kind[type(arm)],
        structure,
        _kernel(robot, wrist_constants(chain, solver, twist2)),
        solver,
    )

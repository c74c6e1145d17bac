"""The ``closed_form_constants`` kernel: the plan's constants (:mod:`closed_form_spec`)
computed from the parameter vector ``p``, as generated C does once per call.

The Python solver evaluates the same expressions at the parameter values
(``ClosedFormPlan.values``), so both read one derivation.  Numbers stay numbers: the PUMA
560's shoulder offset becomes ``-d3``, a 90 degree twist's cosine ``0``.
"""

from __future__ import annotations

import sympy as sp

from symkin.kernels import Kernel, KernelInput, kernel_from_outputs
from symkin.kernels.ik.closed_form_spec import ClosedFormPlan
from symkin.robot import Robot

#: Digits kept when numbers such as ``pi/2`` are turned into literals (C99 has no ``M_PI``).
DIGITS = 17


def _literal_numbers(expr: sp.Expr) -> sp.Expr:
    """Irrational numbers (``pi/2``, ``sqrt(2)/2``) as floats, computed once here rather than
    at run time; rationals, exponents included, stay exact."""
    return sp.sympify(expr).replace(
        lambda e: e.is_number and not e.is_Rational, lambda e: e.evalf(DIGITS)
    )


def constants_kernel(robot: Robot, plan: ClosedFormPlan) -> Kernel:
    """The kernel computing every constant of ``plan`` from ``p`` (one output per constant,
    in the plan's order)."""
    names = ", ".join(n for n, _ in robot.parameters) or "none"
    outputs = [
        (
            c.name,
            sp.ImmutableMatrix([_literal_numbers(v) for v in c.entries]),
            c.description,
            "scalar" if len(c.entries) == 1 else "vector",
        )
        for c in plan.constants
    ]
    return kernel_from_outputs(
        "closed_form_constants",
        "constants of the closed-form IK",
        [KernelInput("p", robot.parameter_symbols, f"parameters ({names})")],
        outputs,
    )

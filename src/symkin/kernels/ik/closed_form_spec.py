"""The closed-form IK plan of a robot, read by both the Python solver
(:mod:`symkin.solve.ik.closed_form`) and the C emitter (:mod:`symkin.emit.ik_closed_c`).

A :class:`Shape` is what the recogniser decided from the numeric table: the family, the kind
of arm, the signs and joint indices that select the formulas.  A :class:`ClosedFormPlan` adds
every other number the formulas need as a SymPy expression of the robot's parameters
(:class:`Constant`).  Python evaluates those expressions at the parameter values
(:meth:`ClosedFormPlan.values`); generated C computes them from ``p`` at run time.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from symkin.kernels.ik.closed_form_table import (
    Numbers,
    SymbolicChain,
    number,
    translation_rotation,
)
from symkin.spatial import rot_x, transform_inverse

#: Branch flags each kind of arm sets (names and values as in ``ClosedFormSolution.branch``).
ARM_FLAGS = {
    "planar": ("elbow",),
    "articulated": ("shoulder", "elbow", "wrist"),
    "spherical": ("shoulder", "extension", "wrist"),
    "cylindrical": ("extension", "wrist"),
    "parallel": ("shoulder", "elbow", "wrist"),
}
#: Solutions per pose at most: 2 per square root (shoulder, elbow or reach, wrist).
MAX_SOLUTIONS = {"planar": 2, "articulated": 8, "spherical": 8, "cylindrical": 4, "parallel": 8}

#: Evaluated constants: name -> its values (one for a scalar).
Values = Mapping[str, tuple[float, ...]]


@dataclass(frozen=True)
class Constant:
    """One constant of the formulas: C field name, entries (SymPy, in the parameters), and
    what it is (the C comment)."""

    name: str
    entries: tuple[sp.Expr, ...]
    description: str


@dataclass(frozen=True)
class Shape:
    """What the recogniser read from the numeric table.

    ``family``: the solver, ``"planar"``, ``"wrist"`` or ``"parallel"``; ``arm``: a key of
    :data:`ARM_FLAGS`; ``name``: the family as users read it (``"planar 2R + prismatic z"``);
    ``task``: the target components used (``"pose"``, ``"xy"``, ``"xyz+heading"``, ...);
    ``structure``: ``(name, value)`` pairs that do not vary with the parameters (twist signs
    +-1, joint indices); ``nonzero``: ``(constant, index)`` lengths the formulas divide by,
    which must not be zero at the parameter values.
    """

    family: str
    arm: str
    name: str
    task: str
    structure: tuple[tuple[str, object], ...]
    nonzero: tuple[tuple[str, int], ...] = ()

    def __getitem__(self, name: str) -> object:
        return dict(self.structure)[name]

    @property
    def flags(self) -> tuple[str, ...]:
        return ARM_FLAGS[self.arm]

    @property
    def max_solutions(self) -> int:
        return MAX_SOLUTIONS[self.arm]


@dataclass(frozen=True)
class ClosedFormPlan:
    """A :class:`Shape` and the constants of its formulas (SymPy, in the parameters)."""

    shape: Shape
    constants: tuple[Constant, ...]

    def has(self, name: str) -> bool:
        """True if the constant ``name`` is part of the plan (``head_inverse`` only without an
        identity base, for example)."""
        return any(c.name == name for c in self.constants)

    def values(self, numbers: Numbers) -> dict[str, tuple[float, ...]]:
        """Every constant at the parameter values ``numbers``."""
        return {c.name: tuple(number(e, numbers) for e in c.entries) for c in self.constants}


def polar(x: sp.Expr, y: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``(length, angle)`` of the vector ``(x, y)``."""
    return sp.sqrt(x**2 + y**2), sp.atan2(y, x)


def frame_constants(chain: SymbolicChain, tail: sp.Matrix | None) -> list[Constant]:
    """``scale``, and ``head_inverse`` (``tail_inverse``) where it is not the identity."""
    constants = [Constant("scale", (chain.size,), "length scale of the robot (>= 1 m)")]
    for name, transform, description in (
        ("head_inverse", chain.base, "base^-1, row-major 4x4"),
        ("tail_inverse", tail, "(Tx(a_n) Rx(alpha_n) tool)^-1, row-major 4x4"),
    ):
        if transform is not None and transform != sp.eye(4):
            constants.append(Constant(name, tuple(transform_inverse(transform)), description))
    return constants


def twist_constants(chain: SymbolicChain) -> list[Constant]:
    """Cosines and sines of the twists ``alpha_1 .. alpha_5`` (six-joint families)."""
    return [
        Constant(
            "twist_cos", tuple(sp.cos(x) for x in chain.alpha[:5]), "cos(alpha_1) .. cos(alpha_5)"
        ),
        Constant(
            "twist_sin", tuple(sp.sin(x) for x in chain.alpha[:5]), "sin(alpha_1) .. sin(alpha_5)"
        ),
    ]


def tail(chain: SymbolicChain) -> sp.Matrix:
    """``Tx(a_6) Rx(alpha_6) tool``: what follows ``Rz(th6) Tz(d6)``, taken off a target."""
    return translation_rotation(rot_x(chain.alpha[5]), chain.a[5]) @ chain.tool

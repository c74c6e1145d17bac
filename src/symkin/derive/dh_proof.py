"""Proof that an extracted DH model has the forward kinematics of its source.

Symbolic: each link transform is linear in ``(1, cos q_i, sin q_i)`` (revolute) or
``(1, q_i)`` (prismatic), and each ``q_i`` enters one link only, so ``T(q)`` is a
multilinear trig polynomial, and these products are linearly independent functions: two
chains have the same FK for every ``q`` exactly when the coefficients of ``T`` in that basis
agree.  Both FKs are expanded in it (a tensor of ``16 * 3^n`` numbers at most) and compared
to :data:`TOLERANCE` (the values are floats, so "equal" means to rounding).  When the
expansion is over its budget (size or time), the check falls back to :data:`CONFIGURATIONS`
random configurations, and says so.  The numeric check runs in both cases.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np
import sympy as sp

from symkin.derive.dh_extraction import DhExtraction, dh_matrix, numeric_robot
from symkin.derive.dh_lines import SNAP_TOLERANCE
from symkin.derive.kinematics import link_transform
from symkin.robot import Robot
from symkin.symbols import joint_symbols

TOLERANCE = 1e-12
CONFIGURATIONS = 100
SYMBOLIC_COEFFICIENTS = 4_000_000  # 32 MB of doubles: a 12-joint revolute chain
SYMBOLIC_SECONDS = 20.0


@dataclass(frozen=True)
class FkProof:
    """How the FK equality was shown: ``method`` "symbolic" (coefficients of the expanded FK,
    ``symbolic_error`` their largest difference) or "numeric" (``reason`` says why); the
    numeric check's largest entry difference over ``configurations`` random states always;
    ``snapping`` explains a difference that the snapping of nearly round values caused."""

    method: Literal["symbolic", "numeric"]
    symbolic_error: float | None
    numeric_error: float
    configurations: int
    reason: str = ""
    snapping: str = ""

    def summary(self) -> str:
        note = f"; {self.snapping}" if self.snapping else ""
        return self._methods() + note

    def _methods(self) -> str:
        numeric = (
            f"agreement at {self.configurations} random configurations to "
            f"{self.numeric_error:.1e} (tolerance {TOLERANCE:g})"
        )
        if self.method == "symbolic":
            return (
                "symbolic: both FKs expanded in the basis 1, cos q_i, sin q_i (q_i prismatic) "
                f"agree coefficient by coefficient to {self.symbolic_error:.1e}; numeric: {numeric}"
            )
        return f"numeric only ({self.reason}): {numeric}"


def _link_coefficients(entry: sp.Expr, q: sp.Symbol, revolute: bool) -> list[float] | None:
    """The coefficients of one link-transform entry in ``(1, cos q, sin q)`` or ``(1, q)``;
    None when the entry is not of that form."""
    cosine, sine = sp.Dummy("c"), sp.Dummy("s")
    expanded = sp.expand(sp.expand_trig(entry))
    generators = (cosine, sine) if revolute else (q,)
    if revolute:
        expanded = expanded.xreplace({sp.cos(q): cosine, sp.sin(q): sine})
    if expanded.has(q) and revolute:
        return None
    poly = sp.Poly(expanded, *generators)
    basis = [(0,) * len(generators)] + [
        tuple(int(i == k) for i in range(len(generators))) for k in range(len(generators))
    ]
    terms = dict(poly.terms())
    if set(terms) - set(basis) or any(not c.is_number for c in terms.values()):
        return None
    return [float(terms.get(monomial, 0)) for monomial in basis]


def _chain_tensor(
    robot: Robot, links: tuple[sp.ImmutableMatrix, ...], deadline: float
) -> np.ndarray | str:
    """``T(q)`` as coefficients in the product basis, shape ``(4, 4, b_1, ..., b_n)``; a
    string saying why not when a transform is not of the expected form or time is up."""
    tensor = np.array(robot.base.evalf(), dtype=float)
    symbols = joint_symbols(robot.dof)
    for k, (joint, link, q) in enumerate(zip(robot.joints, links, symbols, strict=True)):
        revolute = joint.type == "revolute"
        entries = [_link_coefficients(e, q, revolute) for e in link]
        if any(c is None for c in entries):
            return f"link transform {k + 1} is not linear in cos q, sin q"
        coefficients = np.array(entries, dtype=float).reshape(4, 4, -1)
        tensor = np.einsum("im...,mjb->ij...b", tensor, coefficients)
        if time.monotonic() > deadline:
            return f"the expansion took over {SYMBOLIC_SECONDS:g} s"
    return np.einsum("im...,mj->ij...", tensor, np.array(robot.tool.evalf(), dtype=float))


def symbolic_difference(source: Robot, model: Robot) -> float | str:
    """Largest coefficient difference of the two expanded FKs, or why it was not computed."""
    size = 16 * math.prod(3 if j.type == "revolute" else 2 for j in model.joints)
    if size > SYMBOLIC_COEFFICIENTS:
        return (
            f"the expanded FK would have {size:,} coefficients, over the budget of "
            f"{SYMBOLIC_COEFFICIENTS:,}"
        )
    deadline = time.monotonic() + SYMBOLIC_SECONDS
    robot = numeric_robot(source)
    tensors = [_chain_tensor(r, link_transforms(r), deadline) for r in (robot, model)]
    for tensor in tensors:
        if isinstance(tensor, str):
            return tensor
    return float(np.max(np.abs(tensors[0] - tensors[1])))


def random_configurations(robot: Robot, count: int, seed: int = 0) -> np.ndarray:
    """Seeded joint values within the limits (else +-pi rad, +-1 m)."""
    rng = np.random.default_rng(seed)
    columns = []
    for joint in robot.joints:
        low, high = joint.limits or ((-math.pi, math.pi) if joint.type == "revolute" else (-1, 1))
        columns.append(rng.uniform(low, high, count))
    return np.array(columns).T


def dh_forward_kinematics(model: Robot, q: np.ndarray) -> np.ndarray:
    """``base * A_1 ... A_n * tool`` of a DH robot with numeric entries, in NumPy."""
    pose = np.array(model.base.evalf(), dtype=float)
    for joint, value in zip(model.joints, q, strict=True):
        theta, d = float(joint.theta), float(joint.d)
        if joint.type == "revolute":
            theta += value
        else:
            d += value
        pose = pose @ dh_matrix(theta, d, float(joint.a), float(joint.alpha), model.convention)
    return pose @ np.array(model.tool.evalf(), dtype=float)


def link_transforms(robot: Robot) -> tuple[sp.ImmutableMatrix, ...]:
    """``A_1(q_1) .. A_n(q_n)`` of any robot (DH or placed), each in its own variable."""
    q = joint_symbols(robot.dof)
    return tuple(
        link_transform(j, qi, robot.convention) for j, qi in zip(robot.joints, q, strict=True)
    )


def numeric_difference(source: Robot, model: Robot, count: int = CONFIGURATIONS) -> float:
    """Largest entry difference of the two FKs over ``count`` random configurations; the
    source's FK is the product of its link transforms, each a small NumPy function."""
    robot = numeric_robot(source)
    functions = [
        sp.lambdify([qi], link, modules="numpy")
        for qi, link in zip(joint_symbols(robot.dof), link_transforms(robot), strict=True)
    ]
    base, tool = (np.array(m.evalf(), dtype=float) for m in (robot.base, robot.tool))

    def source_fk(q: np.ndarray) -> np.ndarray:
        pose = base
        for function, value in zip(functions, q, strict=True):
            pose = pose @ np.asarray(function(value), dtype=float)
        return pose @ tool

    return max(
        float(np.max(np.abs(source_fk(q) - dh_forward_kinematics(model, q))))
        for q in random_configurations(robot, count)
    )


def prove_forward_kinematics(extraction: DhExtraction) -> FkProof:
    """Show ``T_source(q) = T_dh(q)`` for all ``q`` (module docstring).

    Snapping (values within ``SNAP_TOLERANCE`` of round ones made exact) may move the FK of a
    source whose values are nearly but not exactly round, such as a URDF's ``1.57079632679``
    for ``pi/2``: a difference above :data:`TOLERANCE` but within what snapping can cause is
    reported in ``snapping``; a larger one is an ArithmeticError (a bug of the extraction).
    """
    source, model = extraction.source, extraction.robot
    numeric = numeric_difference(source, model)
    symbolic = symbolic_difference(source, model)
    reach = max(1.0, *(float(np.linalg.norm(line.point)) for line in extraction.lines))
    worst = max(numeric, symbolic if isinstance(symbolic, float) else 0.0)
    snapping = ""
    if worst > TOLERANCE * reach:
        if worst > 4 * model.dof * SNAP_TOLERANCE * reach:
            raise ArithmeticError(
                f"{source.name}: the extracted DH model's FK differs from the source's by "
                f"{worst:.1e} (a bug of symkin dh: please report it with the robot file)"
            )
        snapping = (
            f"the difference is above {TOLERANCE:g} because values within {SNAP_TOLERANCE:g} "
            "of round ones were made exact while the source's are not exactly round "
            "(as a URDF's 1.57079632679 for pi/2)"
        )
    if isinstance(symbolic, str):
        return FkProof("numeric", None, numeric, CONFIGURATIONS, symbolic, snapping)
    return FkProof("symbolic", symbolic, numeric, CONFIGURATIONS, snapping=snapping)

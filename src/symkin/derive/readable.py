"""The readable forward kinematics and Jacobian under a budget, with the product form as fallback.

The readable model contracts sums of products of sines and cosines into functions of summed
angles after every product (:func:`~symkin.derive.simplify.contract_product`, Fu's TR10i);
a chain without parallel axes has no angle sums, and its expanded ``T`` and Jacobian are
nested joint by joint instead (:mod:`symkin.derive.nesting`).
Its cost grows with the length of the expanded chain, far faster than the chain: readable
FK + J take 5 to 8 s of CPU at 8 joints with right-angle twists (a random 8R of 386 terms,
load 5 to 8; 15 s before the Jacobian's columns came from local frames) and more than 80 s
at 12 (measured before that change).
The product form has the same values (and the kernels use it anyway when it is shorter), so the
contraction is optional like the closed forms of :mod:`symkin.derive.budget`:

* a cheap size measure comes first: the number of terms of ``T = base A_1 ... A_n tool``
  expanded by SymEngine (:func:`expanded_size`; milliseconds).  At most
  :data:`INLINE_TERMS` terms (every catalogue robot: the Panda has 160) the contraction runs
  in process without a deadline, so catalogue forms never depend on the machine's speed;
* above it, the contraction runs under the model's budget (a forked child, see
  :func:`~symkin.derive.budget.run_within`); past the budget one
  :class:`~symkin.errors.BudgetWarning` names the robot, the result and ``{budget}``, and the
  model keeps the product form;
* past :data:`MAX_TERMS` terms (a random 12R arm: 3,046; a generic-twist 6R: 1,511) it is
  not attempted under a budget: one warning says so at once, where the child would
  only have spent the budget.
"""

from __future__ import annotations

import dataclasses
import warnings

import symengine as se
import sympy as sp

from symkin.derive import jacobians
from symkin.derive.budget import OVER_BUDGET, ClosedForm, closed_form_within
from symkin.derive.kinematics import Kinematics, kinematics_from_robot, link_transform
from symkin.derive.nesting import nest_matrix
from symkin.derive.pythagorean import fold_matrix
from symkin.errors import BudgetWarning
from symkin.robot import Robot
from symkin.symbols import joint_symbols

# Expanded terms of T up to which the contraction runs without a deadline.  Measured
# (symkin's catalogue and bench/random_arms.py): catalogue robots 18..160, a random 6R arm
# with right-angle twists 165 (readable FK + J 1 s), the Jaco-like 6R 198, a random 8R 404
# (9 s), a random 12R 3,046 (over 80 s).
INLINE_TERMS = 200
# Past this many terms the contraction is not attempted under a budget: with parallel axes
# TR10i's search grows about as the square of the terms (404 terms 9 s, 1,000 about a
# minute); without, the "readable" form is the plain expansion (a generic 6R: 1,511 terms),
# unreadable, and as a kernel candidate it about doubled the CPU time of a 6R's derive
# (measured 14.5 s without it).  With no budget (``budget=None``) it is attempted.
MAX_TERMS = 1000
# The size measure stops counting past this many terms of a partial product (twice
# MAX_TERMS: the remaining links would have to cancel half the terms to come back under it).
STOP_COUNTING = 2 * MAX_TERMS

QUANTITY = "angle-sum contraction of the forward kinematics and Jacobian"
FALLBACK = "they keep their product form (same values, longer expressions)"

Readable = tuple[Kinematics, sp.ImmutableMatrix]


def expanded_size(robot: Robot, stop_above: int | None = None) -> int:
    """Number of terms of the 16 entries of ``T`` expanded (the chain multiplied in SymEngine,
    expanded after each link as the contraction does).

    With ``stop_above``, the count of the partial product ``base A_1 ... A_k`` is returned as
    soon as it exceeds ``stop_above``: a generic 12R arm's full expansion has 485,575 terms
    and took about 25 s of CPU only to be refused.  Later links multiply every rotation term
    by a new joint's sine or cosine, so terms do not cancel there; the caller's margin
    (:data:`STOP_COUNTING`) covers the position column, where they could.
    """
    q = joint_symbols(robot.dof)
    transform = _symengine(robot.base)
    for joint, qi in zip(robot.joints, q, strict=True):
        product = transform * _symengine(link_transform(joint, qi, robot.convention))
        transform = product.applyfunc(se.expand)
        if stop_above is not None and _terms(transform) > stop_above:
            return _terms(transform)
    transform = (transform * _symengine(robot.tool)).applyfunc(se.expand)
    return _terms(transform)


def _has_trig_square(matrix: sp.MatrixBase) -> bool:
    """Whether an entry holds ``sin(x)**k`` or ``cos(x)**k``."""
    return any(isinstance(p.base, sp.sin | sp.cos) for p in matrix.atoms(sp.Pow))


def _terms(matrix: se.DenseMatrix) -> int:
    return sum(len(e.args) if isinstance(e, se.Add) else 1 for e in matrix)


def _symengine(matrix: sp.MatrixBase) -> se.DenseMatrix:
    return se.DenseMatrix(matrix.rows, matrix.cols, [se.sympify(e) for e in matrix])


def readable_form(robot: Robot, budget: float | None) -> ClosedForm:
    """The contracted ``(kinematics, geometric Jacobian)`` of ``robot`` as a
    :class:`ClosedForm`: found, or over budget (with one warning) for the caller to fall back
    to the product form."""

    size = expanded_size(robot, None if budget is None else STOP_COUNTING)
    inline = size <= INLINE_TERMS

    def contracted() -> Readable:
        kinematics = kinematics_from_robot(robot)
        jacobian = jacobians.geometric_jacobian(robot, kinematics)
        # The columns R (e_z x p_local) hold no sin^2 + cos^2 (z x (p - o) expanded did: PUMA
        # J(3,2), 258 -> 209 ops once folded); the fold stays as a net, walked only when a
        # square of a sine or cosine is there (a long generic chain keeps it: 1.3 s more at
        # six generic joints).
        if inline and _has_trig_square(jacobian):
            jacobian = fold_matrix(jacobian)
        if kinematics.angle_sums:
            return kinematics, jacobian
        # No angle sums to show: T and J nested joint by joint (half the length, shared
        # groups; see symkin.derive.nesting).
        tool = nest_matrix(kinematics.forward_kinematics, kinematics.q)
        nested = dataclasses.replace(kinematics, forward_kinematics=tool)
        return nested, nest_matrix(jacobian, kinematics.q)

    if budget is not None and size > MAX_TERMS:
        note = (
            f"{robot.name}: the {QUANTITY} was not attempted: T expanded has "
            f"{'more than ' if size > STOP_COUNTING else ''}{min(size, STOP_COUNTING):,} terms "
            f"(more than {MAX_TERMS:,}, minutes of work); {FALLBACK}"
        )
        warnings.warn(BudgetWarning(note), stacklevel=4)
        return ClosedForm(QUANTITY, OVER_BUDGET, None, note)
    within = None if inline else budget
    return closed_form_within(QUANTITY, robot.name, within, contracted, FALLBACK)

"""Closed-form inverse kinematics: every solution, with branch flags, each checked by FK.

The joint structure is recognised from the numeric DH table (never from the robot's name),
after a modified-DH table has been rewritten as a standard one (``closed_form_table``):

======================================  =================================  ======================
family (module)                         recognised by                      catalogue robots
======================================  =================================  ======================
planar 2R / 3R, + prismatic along z     all twists 0 (tool twist aside)    planar_2r, scara,
(``closed_form_planar``)                                                   planar_3r
spherical wrist + RRR / RRP / RPP arm   axes 4, 5, 6 meet in a point       puma560, stanford,
(``closed_form_wrist``, Pieper)                                            cylindrical_rtt_wrist
three parallel axes, UR type            axes 2, 3, 4 parallel; a4 = a5 = 0 ur5
(``closed_form_parallel``)
======================================  =================================  ======================

Anything else (the Panda's seven joints, the RPR arm) has no closed form here: use the numeric
solver.  The derivations, branch flags and singular cases are in ``docs/ik-closed-form.md``.

Per robot (and parameter overrides) one frozen solver is built and cached; per pose the work
is a few ``atan2``/``sqrt`` and 3x3 products, then one batched FK of all candidates
(:func:`batched_forward_kinematics`), an evaluation independent of the closed forms.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.numeric import parameter_substitution
from symkin.errors import SymkinError
from symkin.kernels.ik.closed_form_steps import Candidate
from symkin.kernels.ik.plan import (
    DUPLICATE_TOL,
    RIGID_TOL,
    VERIFY_TOL,
    Solver,
    closed_form_family,
    closed_form_solver,
    has_closed_form,
)
from symkin.robot import Robot

__all__ = [
    "VERIFY_TOL",
    "ClosedFormSolution",
    "batched_forward_kinematics",
    "closed_form_family",
    "closed_form_ik",
    "has_closed_form",
]


@dataclass(frozen=True, eq=False)
class ClosedFormSolution:
    """One inverse-kinematics solution.

    ``q``: joint values (radians / metres), read-only.  Revolute joints are wrapped to
    ``(-pi, pi]``; where that value is outside the joint's limits but ``q + 2 pi k`` is inside
    (PUMA shoulder, limits -45..225 deg), the value inside the limits is given instead.
    ``branch``: read-only mapping of branch flags, e.g. ``{"shoulder": "right", "elbow": "up",
    "wrist": "no_flip"}``; names and meanings in ``docs/ik-closed-form.md``.
    ``within_limits``: False if some joint is outside its limits (such solutions are returned
    and flagged, not dropped).
    """

    q: np.ndarray
    branch: Mapping[str, str] = field(default_factory=dict)
    within_limits: bool = True

    def __post_init__(self) -> None:
        q = np.array(self.q, dtype=float)
        q.flags.writeable = False
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "branch", MappingProxyType(dict(self.branch)))


def batched_forward_kinematics(
    model: Model, overrides: Mapping[str, float] | None = None
) -> Callable[[np.ndarray], np.ndarray]:
    """``fk(qs) -> (k, 4, 4)``: ``T = base A_1 .. A_n tool`` at each row of ``qs`` (k x n).

    Lambdified from the model's unsimplified product form: symkin's derivation of the table as
    written (standard or modified DH), independent of the closed forms and of their
    standard-DH rewriting, and quick to build for any robot.
    """
    form = model.product_form
    entries = list(form.forward_kinematics.xreplace(parameter_substitution(model, overrides)))
    varying = [i for i, entry in enumerate(entries) if entry.free_symbols]
    function = sp.lambdify([list(form.q)], [entries[i] for i in varying], modules="numpy", cse=True)
    # Constant entries (the last row, zeros of a planar arm) are filled in once per call.
    template = np.array([0.0 if i in varying else float(e) for i, e in enumerate(entries)])

    def fk(qs: np.ndarray) -> np.ndarray:
        columns = np.asarray(qs, dtype=float).T
        values = np.repeat(template[:, None], columns.shape[1], axis=1)
        values[varying] = function(columns)
        return values.T.reshape(-1, 4, 4)

    return fk


def _no_closed_form_reason(robot: Robot) -> str:
    if robot.convention == "placement" and robot.parameters:
        return (
            f"{robot.name}: no closed-form inverse kinematics for a robot of placed joints "
            "with parameters (the closed forms read the DH table `symkin dh` finds, which "
            "holds numbers); use the numeric solver"
        )
    table = "its DH form (`symkin dh`) " if robot.convention == "placement" else ""
    return (
        f"{robot.name}: no closed-form inverse kinematics for {table}this {robot.dof}-joint "
        "structure (closed forms: planar 2R/3R arms, six-joint arms with a spherical "
        "wrist, UR-type arms); use the numeric solver"
    )


@dataclass(frozen=True, eq=False)
class _Prepared:
    """Everything per-pose work needs about one model and parameter set."""

    solver: Solver
    fk: Callable[[np.ndarray], np.ndarray]
    revolute: np.ndarray  # bool per joint
    low: np.ndarray  # lower limit per joint, -inf without limits
    high: np.ndarray
    shift: bool  # some revolute joint's limits do not contain (-pi, pi]


#: ``(id(model), overrides) -> (model, prepared)``.  Looked up by identity: hashing a model
#: hashes every SymPy entry of its robot, which would cost more than solving a pose.
_PREPARED: dict[tuple[int, tuple], tuple[Model, _Prepared]] = {}
_PREPARED_SIZE = 32


def _prepared(model: Model, overrides: Mapping[str, float] | None) -> _Prepared:
    key = (id(model), tuple(sorted((overrides or {}).items())))
    entry = _PREPARED.get(key)
    if entry is not None and entry[0] is model:
        return entry[1]
    robot = model.robot
    solver = closed_form_solver(robot, overrides)
    if solver is None:
        raise SymkinError(_no_closed_form_reason(robot))
    prepared = _Prepared(
        solver=solver,
        fk=batched_forward_kinematics(model, overrides),
        revolute=np.array([joint.type == "revolute" for joint in robot.joints]),
        low=np.array([-np.inf if j.limits is None else j.limits[0] for j in robot.joints]),
        high=np.array([np.inf if j.limits is None else j.limits[1] for j in robot.joints]),
        shift=any(
            j.type == "revolute"
            and j.limits is not None
            and not j.limits[0] <= -np.pi < np.pi <= j.limits[1]
            for j in robot.joints
        ),
    )
    if len(_PREPARED) >= _PREPARED_SIZE:
        _PREPARED.pop(next(iter(_PREPARED)))
    _PREPARED[key] = (model, prepared)
    return prepared


def _check_target(target: np.ndarray) -> np.ndarray:
    matrix = np.asarray(target, dtype=float)
    expected = "a 4x4 homogeneous transform [R p; 0 0 0 1] with R a rotation"
    if matrix.shape != (4, 4):
        raise SymkinError(f"the target must be {expected}; got shape {matrix.shape}")
    if not np.all(np.isfinite(matrix)):
        raise SymkinError(f"the target must be {expected}; it holds NaN or inf")
    rotation = matrix[:3, :3]
    rigid = (
        np.abs(matrix[3] - (0.0, 0.0, 0.0, 1.0)).max() <= RIGID_TOL
        and np.abs(rotation.T @ rotation - np.eye(3)).max() <= RIGID_TOL
        and np.dot(np.cross(rotation[0], rotation[1]), rotation[2]) > 0
    )
    if not rigid:
        raise SymkinError(f"the target must be {expected}; its rotation block or last row is not")
    return matrix


def _wrap(angles: np.ndarray) -> np.ndarray:
    """``angles`` mapped to ``(-pi, pi]``."""
    return np.pi - (np.pi - angles) % (2.0 * np.pi)


def _inside(q: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Elementwise: ``q`` within ``[low, high]`` (``-inf, inf`` where a joint has no limits)."""
    return (q >= low - DUPLICATE_TOL) & (q <= high + DUPLICATE_TOL)


def _joint_values(raw: np.ndarray, prepared: _Prepared) -> np.ndarray:
    """Revolute columns wrapped to ``(-pi, pi]``, or shifted by whole turns into the limits."""
    q = np.where(prepared.revolute, _wrap(raw), raw)
    low, high = prepared.low, prepared.high
    if not prepared.shift:
        return q
    for turns in (-1, 1, -2, 2):
        shifted = q + 2.0 * np.pi * turns
        move = prepared.revolute & ~_inside(q, low, high) & _inside(shifted, low, high)
        q = np.where(move, shifted, q)
    return q


def _task_residuals(solver: Solver, reached: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Largest error per candidate in the components the solver's task uses."""
    scale = solver.scale
    if solver.task == "pose":
        position = np.abs(reached[:, :3, 3] - target[:3, 3]).max(axis=1) / scale
        rotation = np.abs(reached[:, :3, :3] - target[:3, :3]).max(axis=(1, 2))
        return np.maximum(position, rotation)
    local = solver.head_inverse @ reached
    wanted = solver.head_inverse @ target
    rows = 3 if "z" in solver.task else 2
    errors = np.abs(local[:, :rows, 3] - wanted[:rows, 3]).max(axis=1) / scale
    if "heading" in solver.task:
        column, goal = local[:, :3, :3] @ solver.tool_row, wanted[:3, :3] @ solver.tool_row
        turn = np.arctan2(column[:, 1], column[:, 0]) - math.atan2(goal[1], goal[0])
        errors = np.maximum(errors, np.abs((turn + np.pi) % (2 * np.pi) - np.pi))
    return errors


def _distinct(q: np.ndarray, revolute: np.ndarray) -> np.ndarray:
    """Mask of the rows of ``q`` that differ from every earlier row (angles modulo 2 pi)."""
    difference = q[:, None, :] - q[None, :, :]
    difference = np.abs(np.where(revolute, _wrap(difference), difference)).max(axis=2)
    earlier = np.tril(difference <= DUPLICATE_TOL, k=-1)
    return ~earlier.any(axis=1)


def closed_form_ik(
    model: Model, target: np.ndarray, overrides: Mapping[str, float] | None = None
) -> tuple[ClosedFormSolution, ...]:
    """All closed-form IK solutions of ``model``'s robot for the tool pose ``target``.

    ``target``: 4x4 homogeneous pose of the tool in the base frame (``T = base A_1 .. A_n
    tool``).  Six-joint arms use all of it.  Planar arms use, in the frame after the base
    transform: ``x, y`` of the tool point (2R), plus ``z`` with a prismatic joint (SCARA),
    plus the heading ``atan2(r21, r11)`` of the last joint frame with three revolute joints;
    the other components are ignored.

    Returns ``()`` when the target is out of reach.  Every returned solution reproduces the
    target through the robot's FK to :data:`VERIFY_TOL`.  Solutions outside the joint limits
    are returned with ``within_limits=False``.  Raises :class:`SymkinError` for a robot
    without a closed form (use the numeric solver) or a target that is not a rigid transform.
    """
    prepared = _prepared(model, overrides)
    matrix = _check_target(target)
    candidates: list[Candidate] = prepared.solver.candidates(matrix)
    if not candidates:
        return ()
    qs = _joint_values(np.array([q for q, _ in candidates]), prepared)
    reached = prepared.fk(qs)
    good = _task_residuals(prepared.solver, reached, matrix) <= VERIFY_TOL
    qs, flags = qs[good], [dict(f) for (_, f), ok in zip(candidates, good, strict=True) if ok]
    keep = _distinct(qs, prepared.revolute)
    inside = _inside(qs, prepared.low, prepared.high).all(axis=1)
    return tuple(
        ClosedFormSolution(q, f, bool(i))
        for q, f, i, k in zip(qs, flags, inside, keep, strict=True)
        if k
    )

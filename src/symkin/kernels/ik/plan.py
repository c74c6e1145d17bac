"""The closed-form IK plan of a robot: which family its numeric DH table belongs to, the
family's constants as SymPy expressions of the parameters (:class:`ClosedFormPlan`), and the
tolerances of the checks.  The Python solver (:mod:`symkin.solve.ik.closed_form`) evaluates
the plan at the parameter values (:func:`closed_form_solver`); the C emitter
(:mod:`symkin.emit.ik_closed_c`) prints it (:func:`closed_form_plan`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import lru_cache

from symkin.derive.dh_extraction import extract_dh
from symkin.errors import SymkinError
from symkin.kernels.ik.closed_form_parallel import (
    ParallelAxesSolver,
    parallel_axes_shape,
    parallel_constants,
)
from symkin.kernels.ik.closed_form_planar import PlanarSolver, planar_constants, planar_shape
from symkin.kernels.ik.closed_form_spec import ClosedFormPlan, Constant, Shape
from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    SymbolicChain,
    parameter_numbers,
    symbolic_chain,
)
from symkin.kernels.ik.closed_form_wrist import (
    SphericalWristSolver,
    spherical_wrist_shape,
    wrist_constants,
)
from symkin.robot import Robot

#: A solution is returned only if its FK reproduces the target to this tolerance: rotation
#: entries absolutely, positions relative to the robot's size (at least 1 m).
VERIFY_TOL = 1e-9
#: Two solutions closer than this in every joint (angles modulo 2 pi) are one solution.
DUPLICATE_TOL = 1e-9
#: A target's rotation block may be off orthonormal by this much (rounding, not a mistake).
RIGID_TOL = 1e-6

Solver = PlanarSolver | SphericalWristSolver | ParallelAxesSolver

#: Per family (in the order they are tried): the recogniser, the constants of its formulas
#: and the Python solver that reads them.
FAMILIES: dict[
    str,
    tuple[
        Callable[[NumericChain], Shape | None],
        Callable[[SymbolicChain, Shape], list[Constant]],
        type[PlanarSolver] | type[SphericalWristSolver] | type[ParallelAxesSolver],
    ],
] = {
    "planar": (planar_shape, planar_constants, PlanarSolver),
    "wrist": (spherical_wrist_shape, wrist_constants, SphericalWristSolver),
    "parallel": (parallel_axes_shape, parallel_constants, ParallelAxesSolver),
}


@lru_cache(maxsize=64)
def _plan(robot: Robot, shape: Shape) -> ClosedFormPlan:
    constants = FAMILIES[shape.family][1]
    return ClosedFormPlan(shape, tuple(constants(symbolic_chain(robot), shape)))


@lru_cache(maxsize=16)
def dh_form(robot: Robot) -> Robot | None:
    """The DH model of a robot of placed joints (URDF-like) without parameters, found by the
    lecture's frame assignment (:func:`~symkin.derive.dh_extraction.extract_dh`): the same
    joint values give the same tool pose (its base and tool transforms make it exact), so a
    closed form of the DH model solves the placed robot.  None for a chain the extraction
    rejects, and for a robot with parameters (the extracted table holds their numbers, and a
    plan must follow the parameters)."""
    if robot.parameters:
        return None
    try:
        return extract_dh(robot).robot
    except SymkinError:
        return None


@lru_cache(maxsize=64)
def _recognised(
    robot: Robot, overrides: tuple, generic: bool
) -> tuple[ClosedFormPlan, Solver] | None:
    """The plan of the first family that accepts the robot's numeric table, with its solver
    at those numbers, or None.  The families' formulas take ``theta_i = q_i + offset``: a
    robot with a flipped joint is left to the numeric solver.  A robot of placed joints
    (URDF-like) is judged by its DH form (:func:`dh_form`)."""
    if robot.convention == "placement":
        table = dh_form(robot)
        return None if table is None else _recognised(table, overrides, generic)
    if any(joint.flip for joint in robot.joints):
        return None
    numbers = parameter_numbers(robot, dict(overrides), generic)
    chain = symbolic_chain(robot).at(numbers)
    for recognise, _, solver_type in FAMILIES.values():
        shape = recognise(chain)
        if shape is None:
            continue
        plan = _plan(robot, shape)
        values = plan.values(numbers)
        if any(chain.is_zero_length(values[name][index]) for name, index in shape.nonzero):
            continue
        return plan, solver_type.from_plan(plan, values, chain.dof)
    return None


def _key(overrides: Mapping[str, float] | None) -> tuple:
    return tuple(sorted((overrides or {}).items()))


def closed_form_solver(
    robot: Robot, overrides: Mapping[str, float] | None, generic: bool = False
) -> Solver | None:
    """The family solver of ``robot`` with its parameter values (``overrides`` first), or
    None.  ``generic``: a parameter without a value counts as a generic non-zero length."""
    found = _recognised(robot, _key(overrides), generic)
    return None if found is None else found[1]


def closed_form_plan(
    robot: Robot, overrides: Mapping[str, float] | None = None
) -> ClosedFormPlan | None:
    """The plan of ``robot``'s closed form, recognised at its parameter values (``overrides``
    first; a parameter without a value counts as a generic non-zero length), or None where
    :func:`has_closed_form` is False.  A parameter vector that changes the structure (a twist,
    or a link length set to zero) is not solved by this plan."""
    found = _recognised(robot, _key(overrides), True)
    return None if found is None else found[0]


def has_closed_form(robot: Robot, overrides: Mapping[str, float] | None = None) -> bool:
    """True if the closed-form solver (:mod:`symkin.solve.ik.closed_form`, its docstring
    lists the families) can solve ``robot``.

    Judged from the DH table with the parameter values (``overrides`` first); a parameter
    without a value counts as a generic non-zero length.
    """
    return closed_form_plan(robot, overrides) is not None


def closed_form_family(robot: Robot, overrides: Mapping[str, float] | None = None) -> str | None:
    """The recognised family, e.g. ``"spherical wrist, articulated RRR arm"``, or None."""
    plan = closed_form_plan(robot, overrides)
    return None if plan is None else plan.shape.name

"""The closed-form IK plan of a robot: which family its numeric DH table belongs to, with the
family's constants, and the tolerances of the checks.  Both the Python solver
(:mod:`symkin.solve.ik.closed_form`) and the C emitter (:mod:`symkin.emit.ik_closed_c`) read it.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache

from symkin.kernels.ik.closed_form_parallel import ParallelAxesSolver, parallel_axes_solver
from symkin.kernels.ik.closed_form_planar import PlanarSolver, planar_solver
from symkin.kernels.ik.closed_form_table import chain_from_robot
from symkin.kernels.ik.closed_form_wrist import SphericalWristSolver, spherical_wrist_solver
from symkin.robot import Robot

#: A solution is returned only if its FK reproduces the target to this tolerance: rotation
#: entries absolutely, positions relative to the robot's size (at least 1 m).
VERIFY_TOL = 1e-9
#: Two solutions closer than this in every joint (angles modulo 2 pi) are one solution.
DUPLICATE_TOL = 1e-9
#: A target's rotation block may be off orthonormal by this much (rounding, not a mistake).
RIGID_TOL = 1e-6

Solver = PlanarSolver | SphericalWristSolver | ParallelAxesSolver


@lru_cache(maxsize=64)
def _cached_solver(robot: Robot, overrides: tuple, generic: bool) -> Solver | None:
    """The first family whose recogniser accepts the robot's numeric table, or None."""
    chain = chain_from_robot(robot, dict(overrides), generic)
    for recognise in (planar_solver, spherical_wrist_solver, parallel_axes_solver):
        solver = recognise(chain)
        if solver is not None:
            return solver
    return None


def closed_form_solver(
    robot: Robot, overrides: Mapping[str, float] | None, generic: bool = False
) -> Solver | None:
    """The family solver of ``robot`` with its parameter values (``overrides`` first), or
    None.  ``generic``: a parameter without a value counts as a generic non-zero length."""
    return _cached_solver(robot, tuple(sorted((overrides or {}).items())), generic)


def has_closed_form(robot: Robot, overrides: Mapping[str, float] | None = None) -> bool:
    """True if the closed-form solver (:mod:`symkin.solve.ik.closed_form`, its docstring
    lists the families) can solve ``robot``.

    Judged from the DH table with the parameter values (``overrides`` first); a parameter
    without a value counts as a generic non-zero length.
    """
    return closed_form_solver(robot, overrides, generic=True) is not None


def closed_form_family(robot: Robot, overrides: Mapping[str, float] | None = None) -> str | None:
    """The recognised family, e.g. ``"spherical wrist, articulated RRR arm"``, or None."""
    solver = closed_form_solver(robot, overrides, generic=True)
    return None if solver is None else solver.family

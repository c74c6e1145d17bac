"""Inverse kinematics: numeric solvers, the path-following scheme and closed forms.

* :func:`solve_ik` (``numeric``): Levenberg–Marquardt or Newton–Raphson on the generated
  forward kinematics and Jacobian, with joint limits, task rows, weights, random restarts and
  a rest posture for redundant arms;
* :func:`pose_from_target` (``target``): a 4x4 target from ``x, y, z[, rx, ry, rz]``;
* :func:`newton_path_table` and :func:`follow_path` (``path``): the lecture's Newton path
  scheme and a path follower that solves every waypoint;
* :func:`all_solutions` (``solutions``): every solution, in closed form where the robot has
  one (``closed_form``), else from many numeric seeds;
* plots in ``symkin.solve.ik.plot`` (matplotlib);
* ``symkin.solve.ik.batch.solve_ik_batch`` (the generated C solver's algorithm on NumPy batches) and
  ``symkin.solve.ik.casadi_ik.solve_ik_casadi`` (IPOPT with joint limits as bounds): imported from
  their modules, so that ``import symkin`` loads neither CasADi nor the code generators.

Conventions and examples: ``docs/ik.md``.
"""

from symkin.solve.ik.numeric import IKResult, solve_ik, task_errors
from symkin.solve.ik.path import CartesianPath, NewtonPath, PathRow, follow_path, newton_path_table
from symkin.solve.ik.solutions import Solution, SolutionSet, all_solutions
from symkin.solve.ik.target import pose_from_target

__all__ = [
    "CartesianPath",
    "IKResult",
    "NewtonPath",
    "PathRow",
    "Solution",
    "SolutionSet",
    "all_solutions",
    "follow_path",
    "newton_path_table",
    "pose_from_target",
    "solve_ik",
    "task_errors",
]

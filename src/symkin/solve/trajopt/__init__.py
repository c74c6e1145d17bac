"""Point-to-point trajectory optimisation on the generated CasADi dynamics, solved with IPOPT.

The optimal control problem (docs/trajopt.md has the equations)::

    minimise     sum_k h |tau_k|^2       (effort: the integral of tau^2, tau piecewise constant)
            or   T                       (minimum time, h = T / N)
    subject to   x = (q, dq),  dx/dt = (dq, FD(q, dq, tau))     the robot's forward dynamics
                 q(0) = q_start, dq(0) = 0, q(T) = q_goal (or tool position = goal), dq(T) = 0
                 q_lo <= q <= q_hi,  |dq| <= dq_max,  |tau| <= tau_max

``FD`` solves ``M(q) ddq = tau - c - G - F`` (the CasADi backend's ``forward_dynamics``, friction
and rotor inertia included).  Two transcriptions on N intervals with piecewise-constant torques:
direct multiple shooting (Bock and Plitt 1984) with classical RK4 substeps, and direct
collocation at the Radau IIA points (Betts, Practical Methods for Optimal Control, 2nd ed.,
SIAM 2010, Sec. 4.5).  Both start from the straight joint-space line between the two
configurations, detoured around the obstacles where it would run a link through one.
Coulomb friction (``sign(dq)``) is not differentiable at rest; robots with it
may converge slowly.

The modules, each importing only those before it: ``problem`` (the problem and its checks),
``transcription`` (the dynamics as ``Opti`` constraints), ``constraints`` (the named constraint
groups), ``initial_guess``, ``detour`` (the first guess around obstacles), ``solve`` (IPOPT
and the :class:`Trajectory`), ``plot`` (the PNG) and ``report`` (summary text, CSV, JSON,
files).
"""

from symkin.solve.trajopt.accuracy import Accuracy
from symkin.solve.trajopt.functions import RobotFunctions, robot_functions
from symkin.solve.trajopt.problem import (
    DEFAULT_TOLERANCE,
    FEASIBILITY_TOLERANCE,
    METHODS,
    OBJECTIVES,
    InfeasibleTrajectoryError,
    Method,
    Objective,
    Obstacle,
    TrajectoryProblem,
    Waypoint,
    check_problem,
    units,
)
from symkin.solve.trajopt.program import Program, transcribed_program
from symkin.solve.trajopt.report import (
    summary_text,
    trajectory_json,
    trajectory_rows,
    write_trajectory,
)
from symkin.solve.trajopt.solve import Round, SolverStats, Trajectory, optimal_trajectory
from symkin.solve.trajopt.transcription import TRANSCRIPTIONS, radau_coefficients

__all__ = [
    "DEFAULT_TOLERANCE",
    "FEASIBILITY_TOLERANCE",
    "METHODS",
    "OBJECTIVES",
    "TRANSCRIPTIONS",
    "Accuracy",
    "InfeasibleTrajectoryError",
    "Method",
    "Objective",
    "Obstacle",
    "Program",
    "RobotFunctions",
    "Round",
    "SolverStats",
    "Trajectory",
    "TrajectoryProblem",
    "Waypoint",
    "check_problem",
    "optimal_trajectory",
    "radau_coefficients",
    "robot_functions",
    "summary_text",
    "trajectory_json",
    "trajectory_rows",
    "transcribed_program",
    "units",
    "write_trajectory",
]

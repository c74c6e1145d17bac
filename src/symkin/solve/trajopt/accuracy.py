"""How far a solution can be trusted: its controls re-simulated with an adaptive integrator on
the generated forward dynamics, and the mesh refined where it falls short.

The **local defect** of interval k is ``|x(t_k+1) - x_k+1|_inf``, ``x`` integrated from node k
under the interval's control by SciPy's ``solve_ivp`` (DOP853, rtol = atol = 1e-10): the error
the transcription made on that interval alone (Betts, Practical Methods for Optimal Control,
2nd ed., SIAM 2010, Sec. 4.7, mesh refinement by local error).  The **end error** integrates
the whole motion from the start without ever resetting to a node, the drift an open-loop
playback would see.  Intervals whose defect exceeds the tolerance are split into as many equal
parts as an error of order ``h^5`` needs (RK4 and three-point Radau both have local error
``O(h^5)`` or better), at most ``MAX_SPLIT``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.solve.trajopt.functions import RobotFunctions
from symkin.solve.trajopt.problem import TrajectoryProblem

RESIMULATION_TOLERANCE = 1e-10  # solve_ivp's rtol and atol
LOCAL_ORDER = 5  # the local error of the transcriptions is O(h^LOCAL_ORDER) or better
MAX_SPLIT = 8  # most parts one interval is split into in one refinement
SAMPLES_PER_INTERVAL = 8  # dense-output samples per interval for the obstacle check


@dataclass(frozen=True)
class Accuracy:
    """The re-simulation of a solution: ``defects`` (N: the local defect of each interval,
    joint units), ``end_error`` (the open-loop end state against the last node) and, with
    obstacles, ``clearance`` (N: the smallest distance between an obstacle's surface and a
    link's capsule surface along each re-simulated interval, metres; negative: penetrated)."""

    defects: np.ndarray
    end_error: float
    clearance: np.ndarray | None = None

    @property
    def max_defect(self) -> float:
        return float(self.defects.max(initial=0.0))

    @property
    def min_clearance(self) -> float | None:
        return None if self.clearance is None else float(self.clearance.min())

    def faulty(self, tolerance: float) -> np.ndarray:
        """The intervals to refine: defect above ``tolerance`` or an obstacle touched."""
        bad = self.defects > tolerance
        if self.clearance is not None:
            bad |= self.clearance < 0
        return bad


def control_function(trajectory: Any, functions: RobotFunctions) -> Callable:
    """``(k, s) -> tau``, the torque ``s`` seconds into interval k: ``tau[k]`` held, or with
    accelerations ``ddq`` (inverse-dynamics transcription) the inverse dynamics along the
    interval's quadratic ``q_k + s dq_k + s^2 a_k / 2``."""
    if getattr(trajectory, "ddq", None) is None:
        return lambda k, s: trajectory.tau[k]

    def torque(k, s):
        a = trajectory.ddq[k]
        q = trajectory.q[k] + s * trajectory.dq[k] + s**2 / 2 * a
        dq = trajectory.dq[k] + s * a
        return np.asarray(functions.inverse_function(q, dq, a)).ravel()

    return torque


def integrate_interval(
    functions: RobotFunctions,
    control: Callable,
    k: int,
    x0: np.ndarray,
    h: float,
    dense: bool = True,
):
    """``solve_ivp`` over interval k from ``x0`` (with ``dense``, the dense output kept), on
    the generated forward dynamics as a CasADi function (half the time of the NumPy kernel
    per call)."""
    # Imported here: SciPy's integrators take half a second to import, which every `symkin`
    # command would pay through the CLI's parser.
    from scipy.integrate import solve_ivp

    n = functions.dof

    def rhs(s, x):
        ddq = functions.forward_function(x[:n], x[n:], control(k, s))
        return np.concatenate([x[n:], np.asarray(ddq).ravel()])

    return solve_ivp(
        rhs,
        (0.0, h),
        x0,
        method="DOP853",
        rtol=RESIMULATION_TOLERANCE,
        atol=RESIMULATION_TOLERANCE,
        dense_output=dense,
    )


def accuracy(trajectory: Any, functions: RobotFunctions, problem: TrajectoryProblem) -> Accuracy:
    """Re-simulate ``trajectory`` (``t``, ``q``, ``dq``, ``tau`` and ``ddq`` as in
    :class:`~symkin.solve.trajopt.Trajectory`) interval by interval and end to end."""
    control = control_function(trajectory, functions)
    nodes = np.hstack([trajectory.q, trajectory.dq])
    h = np.diff(trajectory.t)
    defects = np.zeros(len(h))
    clearance = np.zeros(len(h)) if problem.obstacles else None
    origins = origins_function(functions) if problem.obstacles else None
    x = nodes[0]
    for k, length in enumerate(h):
        local = integrate_interval(functions, control, k, nodes[k], length, origins is not None)
        defects[k] = np.abs(local.y[:, -1] - nodes[k + 1]).max()
        x = integrate_interval(functions, control, k, x, length, dense=False).y[:, -1]
        if origins is not None:
            samples = local.sol(np.linspace(0.0, length, SAMPLES_PER_INTERVAL + 1))
            clearance[k] = configuration_clearance(origins, samples[: functions.dof], problem).min()
    return Accuracy(defects, float(np.abs(x - nodes[-1]).max()), clearance)


def origins_function(functions: RobotFunctions) -> Callable:
    """``q (n x m) -> origins (m x links+1 x 3)``, one CasADi function for the whole set."""
    import casadi

    q = casadi.SX.sym("q", functions.dof)
    stacked = casadi.Function("origins", [q], [casadi.horzcat(*functions.link_origins(q))])

    def origins(states: np.ndarray) -> np.ndarray:
        m = states.shape[1]
        values = np.array(stacked.map(m)(states))  # 3 x (links+1) m
        return values.reshape(3, m, -1).transpose(1, 2, 0)  # column j (links+1) + l

    return origins


def configuration_clearance(
    origins: Callable, q: np.ndarray, problem: TrajectoryProblem, margin: float = 0.0
) -> np.ndarray:
    """For each configuration (column of ``q``, n x m) the smallest
    ``|c - segment| - r - clearance - margin`` over the obstacles and the links (metres;
    negative: a capsule grown by ``margin`` enters a sphere); ``origins`` from
    :func:`origins_function`."""
    points = origins(q)  # m x (links+1) x 3
    a, b = points[:, :-1], points[:, 1:]
    worst = np.full(q.shape[1], math.inf)
    for obstacle in problem.obstacles:
        distance = segment_distance(np.array(obstacle.centre), a, b).min(axis=1)
        worst = np.minimum(worst, distance - obstacle.radius - problem.clearance - margin)
    return worst


def segment_distance(c: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from the point ``c`` to the segments ``a``-``b`` (arrays of 3-vectors along
    the last axis): the nearest point is ``a + t (b - a)``, ``t`` clamped to [0, 1]."""
    ab = b - a
    length = np.maximum(np.sum(ab * ab, axis=-1), 1e-300)
    t = np.clip(np.sum((c - a) * ab, axis=-1) / length, 0.0, 1.0)
    return np.linalg.norm(a + t[..., None] * ab - c, axis=-1)


def refined_mesh(mesh: np.ndarray, report: Accuracy, tolerance: float) -> np.ndarray:
    """``mesh`` with each faulty interval split into ``ceil((defect / tolerance)^(1/5))``
    equal parts (2 to ``MAX_SPLIT``; 2 for an obstacle touched)."""
    nodes = [mesh[0]]
    faulty = report.faulty(tolerance)
    for k in range(len(mesh) - 1):
        parts = 1
        if faulty[k]:
            ratio = max(report.defects[k] / tolerance, 1.0)
            parts = min(MAX_SPLIT, max(2, math.ceil(1.2 * ratio ** (1 / LOCAL_ORDER))))
        nodes.extend(mesh[k] + (mesh[k + 1] - mesh[k]) * np.arange(1, parts + 1) / parts)
    nodes[-1] = 1.0
    return np.array(nodes)


def squared_segment_distance(c, a, b):
    """CasADi: the squared distance from the point ``c`` to the segment ``a``-``b``
    (``fmin``/``fmax`` clamp the nearest point ``a + t (b - a)`` to the segment)."""
    import casadi

    ab = b - a
    t = casadi.dot(c - a, ab) / (casadi.dot(ab, ab) + 1e-12)
    t = casadi.fmin(casadi.fmax(t, 0.0), 1.0)
    gap = a + t * ab - c
    return casadi.dot(gap, gap)

"""The dynamics as constraints of a CasADi ``Opti`` problem on N intervals (lengths ``h_k``, a
1 x N row): with piecewise-constant torques, direct multiple shooting (Bock and Plitt 1984) with
classical RK4 substeps and direct collocation at the Radau IIA points (Betts, Practical Methods
for Optimal Control, 2nd ed., SIAM 2010, Sec. 4.5); with piecewise-constant accelerations, the
inverse-dynamics transcription (Betts 2010, Sec. 6.3: the dynamics as an algebraic equation),
whose states are exact quadratics in time and whose torque is the generated inverse dynamics."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.solve.trajopt.problem import METHODS, TrajectoryProblem


@dataclass(frozen=True)
class Dynamics:
    """The robot's dynamics as CasADi callables: ``forward(x, tau) = dx/dt`` for
    ``x = (q, dq)``, and ``inverse(q, dq, ddq) = tau``."""

    forward: Callable
    inverse: Callable


@dataclass(frozen=True)
class Transcription:
    """Node states ``X`` (2n x N+1) and controls ``U`` (n x N: torques, or for the
    inverse-dynamics transcription accelerations) as decision variables; ``defects`` must
    vanish; ``guesses`` pairs further variables with the fractions of T at which their initial
    guess lies on the straight line.  ``torques`` (n x m) are the torques where the limits
    apply and ``weights`` (1 x m) the quadrature weights of the effort
    ``integral |tau|^2 dt = sum_j weights_j |torques_j|^2``.  Path limits apply at the nodes."""

    X: Any
    U: Any
    defects: Any
    torques: Any
    weights: Any
    guesses: tuple[tuple[Any, np.ndarray], ...] = ()


def rk4_step(dynamics: Callable, n: int, substeps: int):
    """``x_next = F(x, tau, h)``: ``substeps`` classical RK4 steps of length ``h / substeps``
    with ``tau`` held constant."""
    import casadi

    x = casadi.SX.sym("x", 2 * n)
    tau = casadi.SX.sym("tau", n)
    h = casadi.SX.sym("h")
    step = h / substeps
    xk = x
    for _ in range(substeps):
        k1 = dynamics(xk, tau)
        k2 = dynamics(xk + step / 2 * k1, tau)
        k3 = dynamics(xk + step / 2 * k2, tau)
        k4 = dynamics(xk + step * k3, tau)
        xk = xk + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return casadi.Function("rk4", [x, tau, h], [xk])


def radau_coefficients(degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(points, C, D)`` of Radau IIA collocation on the unit interval (Betts 2010, Sec. 4.5).

    ``points = [0, s_1 .. s_d]`` with ``s_d = 1``.  With ``L_j`` the Lagrange polynomials on
    these points, ``C[j, r] = L_j'(s_r)`` (the state's slope at ``s_r`` is
    ``sum_j C[j, r] Z_j / h``) and ``D[j] = L_j(1)`` (the state at the interval's end).
    """
    import casadi

    points = np.append(0.0, casadi.collocation_points(degree, "radau"))
    size = degree + 1
    C = np.zeros((size, size))
    D = np.zeros(size)
    for j in range(size):
        basis = np.poly1d([1.0])
        for r in range(size):
            if r != j:
                basis *= np.poly1d([1.0, -points[r]]) / (points[j] - points[r])
        D[j] = basis(1.0)
        C[j] = np.polyder(basis)(points)
    return points, C, D


def multiple_shooting(
    opti, dynamics: Dynamics, n: int, problem: TrajectoryProblem, h
) -> Transcription:
    """``x_k+1 = RK4(x_k, tau_k, h_k)`` on every interval, as defects ``RK4(...) - x_k+1``."""
    N = problem.intervals
    X = opti.variable(2 * n, N + 1)
    U = opti.variable(n, N)
    step = rk4_step(dynamics.forward, n, problem.substeps).map(N)
    return Transcription(X, U, step(X[:, :-1], U, h) - X[:, 1:], U, h)


def inverse_dynamics(
    opti, dynamics: Dynamics, n: int, problem: TrajectoryProblem, h
) -> Transcription:
    """Accelerations ``a_k`` held on each interval: ``q_k+1 = q_k + h dq_k + h^2 a_k / 2`` and
    ``dq_k+1 = dq_k + h a_k``, exact for a constant acceleration, so the states between the
    nodes are known quadratics and no integration error enters.  The torque is the generated
    inverse dynamics along them, ``tau(t) = ID(q(t), dq(t), a_k)``, sampled at each interval's
    start, middle and end for the limits and for Simpson's rule on the effort."""
    import casadi

    N = problem.intervals
    X = opti.variable(2 * n, N + 1)
    A = opti.variable(n, N)
    q, dq = X[:n, :-1], X[n:, :-1]
    H = casadi.repmat(h, n, 1)
    defects = casadi.vertcat(q + H * dq + H**2 / 2 * A - X[:n, 1:], dq + H * A - X[n:, 1:])
    q_mid, dq_mid = q + H / 2 * dq + H**2 / 8 * A, dq + H / 2 * A
    samples = [
        dynamics.inverse(q, dq, A),
        dynamics.inverse(q_mid, dq_mid, A),
        dynamics.inverse(X[:n, 1:], X[n:, 1:], A),
    ]
    torques = casadi.horzcat(*samples)
    weights = casadi.horzcat(h / 6, 4 * h / 6, h / 6)
    return Transcription(X, A, defects, torques, weights)


def collocation(opti, dynamics: Dynamics, n: int, problem: TrajectoryProblem, h) -> Transcription:
    """On interval k with ``Z = [x_k, x_k1 .. x_kd]``: ``Z C[:, r] = h f(x_kr, tau_k)`` at the
    d Radau points and ``x_k+1 = Z D`` (continuity)."""
    import casadi

    N, d = problem.intervals, problem.degree
    points, C, D = radau_coefficients(d)
    X = opti.variable(2 * n, N + 1)
    U = opti.variable(n, N)
    Xc = opti.variable(2 * n, N * d)  # the collocation states, d per interval, in time order
    x = casadi.SX.sym("x", 2 * n)
    tau = casadi.SX.sym("tau", n)
    slope = casadi.Function("f", [x, tau], [dynamics.forward(x, tau)]).map(N * d)
    slopes = slope(Xc, casadi.repmat(U, d, 1).reshape((n, N * d)))
    defects = []
    for k in range(N):
        Z = casadi.horzcat(X[:, k], Xc[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, C[:, 1:]) - h[k] * slopes[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, D) - X[:, k + 1])
    mesh = problem.fractions
    fractions = (mesh[:-1, None] + np.diff(mesh)[:, None] * points[None, 1:]).ravel()
    return Transcription(X, U, casadi.horzcat(*defects), U, h, ((Xc, fractions),))


# ``TrajectoryProblem.method`` -> its transcription, in the order of ``METHODS``.
TRANSCRIPTIONS: Mapping[str, Callable[..., Transcription]] = dict(
    zip(METHODS, (multiple_shooting, collocation, inverse_dynamics), strict=True)
)

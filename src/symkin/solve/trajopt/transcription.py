"""The dynamics as constraints of a CasADi ``Opti`` problem on N intervals with piecewise-constant
torques: direct multiple shooting (Bock and Plitt 1984) with classical RK4 substeps, and direct
collocation at the Radau IIA points (Betts, Practical Methods for Optimal Control, 2nd ed.,
SIAM 2010, Sec. 4.5)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.solve.trajopt.problem import METHODS, TrajectoryProblem


@dataclass(frozen=True)
class Transcription:
    """Node states ``X`` (2n x N+1) and torques ``U`` (n x N) as decision variables;
    ``defects`` must vanish; ``guesses`` pairs further variables with the fractions of T at
    which their initial guess lies on the straight line.  Path limits apply at the nodes."""

    X: Any
    U: Any
    defects: Any
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
    opti, dynamics: Callable, n: int, problem: TrajectoryProblem, h
) -> Transcription:
    """``x_k+1 = RK4(x_k, tau_k, h)`` on every interval, as defects ``RK4(...) - x_k+1``."""
    N = problem.intervals
    X = opti.variable(2 * n, N + 1)
    U = opti.variable(n, N)
    step = rk4_step(dynamics, n, problem.substeps).map(N)
    return Transcription(X, U, step(X[:, :-1], U, h) - X[:, 1:])


def collocation(opti, dynamics: Callable, n: int, problem: TrajectoryProblem, h) -> Transcription:
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
    slope = casadi.Function("f", [x, tau], [dynamics(x, tau)]).map(N * d)
    slopes = slope(Xc, casadi.repmat(U, d, 1).reshape((n, N * d)))
    defects = []
    for k in range(N):
        Z = casadi.horzcat(X[:, k], Xc[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, C[:, 1:]) - h * slopes[:, k * d : (k + 1) * d])
        defects.append(casadi.mtimes(Z, D) - X[:, k + 1])
    fractions = (np.arange(N)[:, None] + points[None, 1:]).ravel() / N
    return Transcription(X, U, casadi.horzcat(*defects), ((Xc, fractions),))


# ``TrajectoryProblem.method`` -> its transcription, in the order of ``METHODS``.
TRANSCRIPTIONS: Mapping[str, Callable[..., Transcription]] = dict(
    zip(METHODS, (multiple_shooting, collocation), strict=True)
)

"""Exciting trajectories: a periodic Fourier-series motion within the joint position and
velocity limits that minimises the condition number of the stacked base regressor.

Each joint follows a finite Fourier series of base frequency ``w = 2 pi / period`` (Swevers,
Ganseman, Tukel, De Schutter and Van Brussel, "Optimal robot excitation and identification",
IEEE Trans. Robot. Autom. 13(5), 1997, eq. 9)::

    q_i(t) = q0_i + sum_l  a_il / (w l) sin(w l t) - b_il / (w l) cos(w l t)
    dq_i   = sum_l  a_il cos(w l t) + b_il sin(w l t)
    ddq_i  = sum_l -a_il w l sin(w l t) + b_il w l cos(w l t)

so position, velocity and acceleration are periodic and start and end alike (repeatable
measurements, averaging over periods).  The coefficients and offsets are chosen by
``scipy.optimize.minimize`` (SLSQP, finite-difference gradients) on ``log cond(Y_b)`` over
:data:`TIME_SAMPLES` instants of one period, the limits imposed at the same instants.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symkin.derive import Model
from symkin.errors import ParameterError
from symkin.runtime.modules import generated_numpy_module
from symkin.solve.identify import base_regressor_function, condition_number

TIME_SAMPLES = 60
# Harmonics above half the optimiser's instants alias on them: the optimiser cannot see them.
MAX_HARMONICS = TIME_SAMPLES // 2
# Unlimited joints move within +-pi; a margin keeps the motion off the limits themselves.
DEFAULT_RANGE = (-np.pi, np.pi)
MARGIN = 0.05
MAX_ITERATIONS = 100
# The limits are checked again on this many instants of the result.
FINE_SAMPLES = 2000


@dataclass(frozen=True)
class Excitation:
    """The Fourier coefficients (``a``, ``b``: n x harmonics), offsets ``q0``, period, and the
    condition number of the stacked base regressor before (the starting motion) and after."""

    a: np.ndarray
    b: np.ndarray
    q0: np.ndarray
    period: float
    condition_number: float
    initial_condition_number: float

    def states(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``q, dq, ddq`` (each len(t) x n) at times ``t`` (module docstring)."""
        return fourier_states(self.a, self.b, self.q0, self.period, t)


def fourier_states(
    a: np.ndarray, b: np.ndarray, q0: np.ndarray, period: float, t: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    w = 2 * np.pi / period
    harmonics = w * np.arange(1, a.shape[1] + 1)  # w l
    phase = np.outer(t, harmonics)  # (T, L)
    sin, cos = np.sin(phase), np.cos(phase)
    q = q0 + (sin / harmonics) @ a.T - (cos / harmonics) @ b.T
    dq = cos @ a.T + sin @ b.T
    ddq = -(sin * harmonics) @ a.T + (cos * harmonics) @ b.T
    return q, dq, ddq


def check_excitation(harmonics: int, period: float) -> None:
    """A :class:`ParameterError` unless 1 <= ``harmonics`` <= :data:`MAX_HARMONICS` and the
    period is a positive number of seconds (called by :func:`exciting_trajectory`)."""
    if not 1 <= harmonics <= MAX_HARMONICS:
        raise ParameterError(
            f"{{harmonics}}: 1 to {MAX_HARMONICS} (the motion is optimised on {TIME_SAMPLES} "
            f"instants of a period, which resolve {MAX_HARMONICS} harmonics), got {harmonics}"
        )
    if not (np.isfinite(period) and period > 0):
        raise ParameterError(f"{{period}}: a positive number of seconds, got {period:g}")


def check_noise(noise: float) -> None:
    """A :class:`ParameterError` unless the torque noise is a standard deviation >= 0 (called
    by :func:`simulated_torques`)."""
    if not (np.isfinite(noise) and noise >= 0):
        raise ParameterError(f"{{noise}}: a standard deviation >= 0 (N m, N), got {noise:g}")


def exciting_trajectory(
    model: Model,
    harmonics: int = 5,
    period: float = 10.0,
    velocity_limits: np.ndarray | None = None,
    seed: int = 0,
) -> Excitation:
    """The optimised motion (module docstring).  ``velocity_limits`` per joint; by default
    the robot file's ``max_velocity``, else 1 rad/s (or m/s)."""
    from scipy.optimize import minimize  # scipy: only this solver needs it

    robot = model.robot
    n = robot.dof
    check_excitation(harmonics, period)
    lower, upper = (
        np.array([(j.limits or DEFAULT_RANGE)[k] for j in robot.joints]) for k in (0, 1)
    )
    span = upper - lower
    lower, upper = lower + MARGIN * span, upper - MARGIN * span
    if velocity_limits is None:
        velocity_limits = np.array([j.max_velocity or 1.0 for j in robot.joints])
    t = np.linspace(0.0, period, TIME_SAMPLES, endpoint=False)
    stacked = base_regressor_function(model)

    def unpack(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        size = n * harmonics
        return (
            x[:size].reshape(n, harmonics),
            x[size : 2 * size].reshape(n, harmonics),
            x[2 * size :],
        )

    def cost(x: np.ndarray) -> float:
        Y = stacked(*fourier_states(*unpack(x), period, t))
        return float(np.log(condition_number(Y.reshape(-1, Y.shape[-1]))))

    def limits(x: np.ndarray) -> np.ndarray:
        q, dq, _ = fourier_states(*unpack(x), period, t)
        return np.concatenate(
            [
                ((upper - q) / span).ravel(),
                ((q - lower) / span).ravel(),
                (1.0 - (dq / velocity_limits) ** 2).ravel(),
            ]
        )

    x0 = _start(n, harmonics, period, (lower + upper) / 2, span, velocity_limits, seed)
    result = minimize(
        cost,
        x0,
        method="SLSQP",
        constraints=[{"type": "ineq", "fun": limits}],
        options={"maxiter": MAX_ITERATIONS, "ftol": 1e-6},
    )
    a, b, q0 = unpack(result.x)
    ratio = _excess(a, b, q0, period, (lower, upper), velocity_limits)
    x = np.concatenate([(a / ratio).ravel(), (b / ratio).ravel(), q0])
    a, b, q0 = unpack(x)
    return Excitation(a, b, q0, period, float(np.exp(cost(x))), float(np.exp(cost(x0))))


def _excess(
    a: np.ndarray,
    b: np.ndarray,
    q0: np.ndarray,
    period: float,
    bounds: tuple[np.ndarray, np.ndarray],
    velocity_limits: np.ndarray,
) -> float:
    """The factor (at least 1) to shrink the motion about ``q0`` by so that the limits hold
    on a fine grid: the solver imposed them at TIME_SAMPLES instants only, to its tolerance
    (``q - q0`` and ``dq`` scale alike with the coefficients)."""
    lower, upper = bounds
    fine = np.linspace(0.0, period, FINE_SAMPLES, endpoint=False)
    q, dq, _ = fourier_states(a, b, q0, period, fine)
    above = np.where(q > q0, (q - q0) / np.maximum(upper - q0, 1e-12), 0.0)
    below = np.where(q < q0, (q0 - q) / np.maximum(q0 - lower, 1e-12), 0.0)
    return float(max(1.0, above.max(), below.max(), (np.abs(dq) / velocity_limits).max()))


def _start(
    n: int,
    harmonics: int,
    period: float,
    middle: np.ndarray,
    span: np.ndarray,
    velocity_limits: np.ndarray,
    seed: int,
) -> np.ndarray:
    """Random coefficients scaled so that the motion stays within a quarter of each joint's
    range and half its velocity limit (a feasible start)."""
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(2, n, harmonics))
    t = np.linspace(0.0, period, TIME_SAMPLES, endpoint=False)
    q, dq, _ = fourier_states(a, b, np.zeros(n), period, t)
    scale = np.minimum(
        0.25 * span / np.maximum(np.abs(q).max(axis=0), 1e-12),
        0.5 * velocity_limits / np.maximum(np.abs(dq).max(axis=0), 1e-12),
    )
    return np.concatenate([(a * scale[:, None]).ravel(), (b * scale[:, None]).ravel(), middle])


def simulated_torques(
    model: Model,
    q: np.ndarray,
    dq: np.ndarray,
    ddq: np.ndarray,
    noise: float = 0.0,
    seed: int = 0,
) -> np.ndarray:
    """``tau`` of the robot file's model along a motion (N x n), plus Gaussian noise of
    standard deviation ``noise`` (N m or N): simulated measurements to try identification on."""
    check_noise(noise)
    if any(j.link is None for j in model.robot.joints):
        raise ParameterError(
            f"{model.robot.name}: simulating torques needs inertial data for every link"
        )
    tau = generated_numpy_module(model).inverse_dynamics(q, dq, ddq, ())
    rng = np.random.default_rng(seed)
    return tau + noise * rng.standard_normal(tau.shape)
